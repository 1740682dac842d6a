//! The `addipos replay` command: output, exit code, and the line it names.

// Test and bench helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::process::Command;

fn write_trace(name: &str, text: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("addipos-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let p = dir.join(name);
    std::fs::write(&p, text).expect("write trace");
    p
}

fn replay(args: &[&std::path::Path]) -> (i32, String) {
    let (code, out, _) = replay_with_stderr(args);
    (code, out)
}

fn replay_with_stderr(args: &[&std::path::Path]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .arg("replay")
        .args(args)
        .output()
        .expect("run addipos");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A fresh folder of its own for one test.
fn empty_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("addipos-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

#[test]
fn passing_trace_exits_zero() {
    let p = write_trace("good.trace", "R 1300/0/3/0 i => 17\n");
    let (code, out) = replay(&[&p]);
    assert_eq!(code, 0, "{out}");
    assert!(out.lines().any(|l| l == "1 passed, 0 failed"), "{out}");
}

#[test]
fn wrong_expectation_exits_non_zero_and_names_the_line() {
    let good = write_trace("ok2.trace", "R 1300/0/3/0 i => 17\n");
    let bad = write_trace(
        "bad.trace",
        "# comment\nR 1300/0/3/0 i => 17\nR 1300/0/3/0 i => 18\n",
    );
    let (code, out) = replay(&[&good, &bad]);
    assert_ne!(code, 0);
    assert!(out.contains("bad.trace:3:"), "{out}");
    assert!(out.contains("expected 18, got 17"), "{out}");
    assert!(out.lines().any(|l| l == "1 passed, 1 failed"), "{out}");
}

#[test]
fn malformed_trace_names_file_and_line() {
    let bad = write_trace("malformed.trace", "R 1300/0/3/0 i\nFROB 1\n");
    let (code, out) = replay(&[&bad]);
    assert_ne!(code, 0);
    assert!(
        out.contains("malformed.trace:2: unknown request `FROB`"),
        "{out}"
    );
}

#[test]
fn missing_path_is_an_error_naming_it() {
    let good = write_trace("ok3.trace", "R 1300/0/3/0 i => 17\n");
    let p = std::path::Path::new("/nonexistent/nothing.trace");
    let (code, out, err) = replay_with_stderr(&[&good, p]);
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        err.contains("/nonexistent/nothing.trace: no such file or folder"),
        "{err}"
    );
    assert!(!out.contains("passed"), "{out}");
}

#[test]
fn folder_without_traces_is_an_error() {
    let empty = empty_dir("empty");
    let (code, out, err) = replay_with_stderr(&[&empty]);
    assert_eq!(code, 2, "{out}{err}");
    assert!(err.contains("no traces found"), "{err}");
    assert!(err.contains(&*empty.to_string_lossy()), "{err}");
    assert!(!out.contains("0 passed, 0 failed"), "{out}");

    let other = empty_dir("other");
    std::fs::write(other.join("notes.txt"), "R 1300/0/3/0 i => 17\n").expect("write");
    let (code, _, err) = replay_with_stderr(&[&other]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("no traces found"), "{err}");
}

#[test]
fn exit_codes_are_in_the_help() {
    let out = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .args(["replay", "--help"])
        .output()
        .expect("run addipos");
    let help = String::from_utf8_lossy(&out.stdout);
    assert!(help.contains("Exit status: 0 every trace passed"), "{help}");
    assert!(help.contains("1 a trace differs"), "{help}");
    assert!(help.contains("2 nothing could be replayed"), "{help}");
}

#[test]
fn invalid_utf8_names_file_and_line() {
    let dir = empty_dir("utf8");
    let p = dir.join("latin1.trace");
    std::fs::write(&p, b"R 1300/0/3/0 i => 17\n# r\xe9glage\nR 1300/0/3/0 i\n").expect("write");
    let (code, out) = replay(&[&p]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("latin1.trace:2: not UTF-8"), "{out}");
}

#[test]
fn long_request_is_echoed_short() {
    let request = format!("W 1300/1/1/6 d 1.{}", "0".repeat(500));
    let p = write_trace("long.trace", &format!("{request} => err Range\n"));
    let (code, out) = replay(&[&p]);
    assert_eq!(code, 1, "{out}");
    let line = out.lines().next().unwrap_or_default();
    assert!(
        line.contains("long.trace:1: `W 1300/1/1/6 d 1.000"),
        "{line}"
    );
    assert!(
        line.ends_with("…` (517 characters): expected err Range, got ok"),
        "{line}"
    );
    assert!(line.len() < 250, "{line}");
}

#[test]
fn lines_are_replayed_as_they_are_read() {
    // Mismatches before a malformed line are still reported, the step
    // just before it too: the trace is replayed while it is read, not
    // parsed whole first.
    let p = write_trace(
        "late-error.trace",
        "R 1300/0/3/0 i => 18\nR 1300/0/3/0 i => 19\nFROB\n",
    );
    let (code, out) = replay(&[&p]);
    assert_eq!(code, 1, "{out}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 4, "{out}");
    assert!(lines[0].ends_with("late-error.trace:1: `R 1300/0/3/0 i`: expected 18, got 17"));
    assert!(lines[1].ends_with("late-error.trace:2: `R 1300/0/3/0 i`: expected 19, got 17"));
    assert!(lines[2].ends_with("late-error.trace:3: unknown request `FROB`"));
    assert_eq!(lines[3], "0 passed, 1 failed");
}

#[test]
fn large_trace_replays_line_by_line() {
    // 200 000 requests, replayed one step at a time (the peak memory of
    // this is measured by hand, not asserted).
    let dir = empty_dir("large");
    let p = dir.join("large.trace");
    let block = "W 1300/1/1/8 i 3\nR 1300/1/1/8 i => 3\nR 1300/0/3/0 i => 17\nW 1300/1/1/8 i 0\n";
    std::fs::write(&p, block.repeat(50_000)).expect("write");
    let out = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .args(["replay", "-v"])
        .arg(&p)
        .output()
        .expect("run addipos");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    assert!(text.contains("large.trace: ok (200000 requests)"), "{text}");
}
