//! `addipos run` streamed: what it prints and the trace it writes as the
//! run goes are exactly what the collected run (`run_nc`) gives; a program
//! with parse errors runs nothing and writes no trace.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::path::{Path, PathBuf};
use std::process::Command;

use nc::nc_run::{axis_text, NcRun};
use trace::{fresh_emulator, parse_trace, replay, Header};

/// A run on the emulator a trace without header options replays on.
fn run_nc(text: &str) -> NcRun {
    let Ok(run) = nc::nc_run::run_nc(&mut fresh_emulator(&Header::new("nc")), text);
    run
}

/// A program of lines and half circles with TRC on, a loop and a
/// condition, `n` moves in the loop's body.
fn program(n: usize) -> String {
    let mut text = String::from(
        "%STREAM\nN1 G17 G90 #set ToolParam(1; 4; 1)#\nN2 D1 G41 G1 X10 Y0 F6000\n\
         $FOR P1 = 1, 3, 1\n",
    );
    for k in 0..n {
        let x = 10 * (k + 2);
        if k % 2 == 0 {
            text.push_str(&format!("G1 X[{x} + P1 * 1000] Y0\n"));
        } else {
            text.push_str(&format!("G2 X[{x} + P1 * 1000] Y0 I5 J0\n"));
        }
    }
    text.push_str("$IF P1 < 3\nG1 X[P1 * 1000 + 5000] Y0\n$ENDIF\n$ENDFOR\n");
    text.push_str("N9 G40 G1 X0 Y-10\nM30\n");
    text
}

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("addipos-nc-stream-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn addipos_run(prog: &Path, trace: &Path) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .arg("run")
        .arg(prog)
        .arg("--trace")
        .arg(trace)
        .output()
        .expect("run addipos");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn streamed_output_and_trace_are_those_of_the_collected_run() {
    let text = program(200);
    let d = dir();
    let prog = d.join("stream.nc");
    let trace = d.join("stream.trace");
    std::fs::write(&prog, &text).unwrap();
    let (code, stdout, stderr) = addipos_run(&prog, &trace);
    assert_eq!(code, 0, "{stderr}");

    let run = run_nc(&text);
    assert!(!run.failed(), "{:?} {:?}", run.error, run.report);
    let mut expected: Vec<String> = run.spool_lines();
    assert!(expected.len() > 600, "{}", expected.len());
    expected.push(format!("POS {}", axis_text(&run.position.unwrap())));
    expected.extend(run.wear.iter().map(|(n, v)| format!("{n} = {v}")));
    assert_eq!(stdout.lines().collect::<Vec<_>>(), expected);

    let name = prog.display().to_string();
    let written = std::fs::read_to_string(&trace).unwrap();
    assert_eq!(written, run.trace(&name));
    let parsed = parse_trace(&name, &written).unwrap();
    let mismatches = replay(&parsed);
    assert!(mismatches.is_empty(), "{mismatches:?}");
}

#[test]
fn a_program_with_parse_errors_runs_nothing_and_writes_no_trace() {
    let mut text = program(50);
    // Two errors, one near the end: every error is reported, nothing runs.
    text = text.replacen("G2 X[30", "G2 Q1 X[30", 1);
    text.push_str("N99 G240\n");
    let d = dir();
    let prog = d.join("bad.nc");
    let trace = d.join("bad.trace");
    std::fs::write(&prog, &text).unwrap();
    let (code, stdout, stderr) = addipos_run(&prog, &trace);
    assert_eq!(code, 1, "{stderr}");
    assert!(stdout.is_empty(), "{stdout}");
    assert_eq!(stderr.lines().count(), 2, "{stderr}");
    assert!(stderr.contains("block N99"), "{stderr}");
    assert!(!trace.exists());
}

/// `addipos run` on `prog` with `stdin` fed in and stdout as `stdout`.
fn run_with(prog: &str, stdin: &str, stdout: std::process::Stdio) -> std::process::Child {
    use std::io::Write;
    let mut child = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .arg("run")
        .arg(prog)
        .stdin(std::process::Stdio::piped())
        .stdout(stdout)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run addipos");
    let mut input = child.stdin.take().unwrap();
    input.write_all(stdin.as_bytes()).unwrap();
    drop(input);
    child
}

/// A program from a pipe is read once into memory: both passes see it.
#[test]
fn a_program_from_a_pipe_runs() {
    let child = run_with(
        "/dev/stdin",
        "G1 F1000 X10\nX20 Y5\nM30\n",
        std::process::Stdio::piped(),
    );
    let out = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    assert!(stdout.contains("LIN X20 Y5"), "{stdout}");
    assert!(stdout.contains("POS X20 Y5"), "{stdout}");
}

/// A directory is not a program: "cannot read", exit 2.
#[test]
fn a_directory_cannot_be_read() {
    let child = run_with(
        &dir().display().to_string(),
        "",
        std::process::Stdio::piped(),
    );
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("cannot read"), "{stderr}");
}

/// When standard output goes away the run stops and says so (exit 2),
/// rather than running the rest of a long program for nothing.
#[test]
fn a_closed_standard_output_stops_the_run() {
    let path = dir().join("closed-stdout.nc");
    std::fs::write(&path, program(20_000)).unwrap();
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let child = run_with(&path.display().to_string(), "", writer.into());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("standard output"), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
}
