//! `addipos run` and `addipos plot` at the limits of their input: flat
//! chains of 80,000 terms on one line run (they overflowed the stack),
//! nesting too deep and a line too long are errors naming their line, an
//! overlong line and a program from a pipe are read in bounded memory
//! (checked under an address-space limit), and `--help` states the bounds.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// Exit code, standard output and standard error of `addipos args..`.
fn addipos(args: &[&std::ffi::OsStr]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .args(args)
        .output()
        .expect("run addipos");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `script` run by `sh` with the address space limited to `limit_kib`,
/// `$0` the binary and `$1` `arg`.
fn addipos_limited(limit_kib: u64, script: &str, arg: &Path) -> (i32, String) {
    let script = format!("ulimit -v {limit_kib}; {script}");
    let out = Command::new("sh")
        .arg("-c")
        .arg(script)
        .arg(env!("CARGO_BIN_EXE_addipos"))
        .arg(arg)
        .output()
        .expect("run sh");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `text` written to `name` in a fresh folder.
fn program_file(dir: &tempfile::TempDir, name: &str, text: &str) -> PathBuf {
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// `n` operands `first`, `rest`, `rest`, .. joined by `op`.
fn chain(first: &str, op: &str, rest: &str, n: usize) -> String {
    let mut s = first.to_string();
    for _ in 1..n {
        s.push_str(op);
        s.push_str(rest);
    }
    s
}

#[test]
fn run_and_plot_take_flat_chains_of_80000_terms() {
    let dir = tempfile::tempdir().unwrap();
    // A short motion (the plot steps the executed path).
    for (name, expr, x) in [
        ("sum.nc", chain("-79998", "+", "1", 80_001), "2"),
        ("product.nc", chain("2", "*", "1", 80_000), "2"),
        ("and.nc", chain("1", " AND ", "1", 80_000), "1"),
    ] {
        let text = format!("R1 = {expr}\nG1 X[R1] Y1\n");
        let prog = program_file(&dir, name, &text);
        let (code, stdout, stderr) = addipos(&["run".as_ref(), prog.as_os_str()]);
        assert_eq!(code, 0, "{name}: {stderr}");
        assert!(
            stdout.contains(&format!("\nPOS X{x} Y1 ")),
            "{name}: {stdout}"
        );
        let svg = dir.path().join(format!("{name}.svg"));
        let (code, _, stderr) = addipos(&[
            "plot".as_ref(),
            prog.as_os_str(),
            "-o".as_ref(),
            svg.as_os_str(),
        ]);
        assert_eq!(code, 0, "{name}: {stderr}");
        assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));
    }
}

#[test]
fn nesting_too_deep_is_a_parse_error_naming_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let deep = format!(
        "N1 G1 X1\nN2 R1 = {}1{}\n",
        "(".repeat(5000),
        ")".repeat(5000)
    );
    let prog = program_file(&dir, "deep.nc", &deep);
    let (code, stdout, stderr) = addipos(&["run".as_ref(), prog.as_os_str()]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stdout.is_empty(), "{stdout}");
    assert!(stderr.contains("line 2, block N2"), "{stderr}");
    assert!(stderr.contains("nested deeper than 64 levels"), "{stderr}");
}

/// A 16 MB line of `X1 X1 ..` (it took 22 times the file in memory) is
/// refused with the limit named, within 256 MiB of address space.
#[test]
fn an_overlong_line_is_refused_in_bounded_memory() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!("N1 G1 X1\nN2 {}\nN3 G1 X2\n", "X1 ".repeat((16 << 20) / 3));
    let prog = program_file(&dir, "long.nc", &text);
    let (code, stderr) = addipos_limited(256 << 10, r#"exec "$0" run "$1""#, &prog);
    assert_eq!(code, 1, "{stderr}");
    let name = prog.display().to_string();
    assert!(
        stderr.contains(&format!("error: {name}: line 2, block N2, column 1: ")),
        "{stderr}"
    );
    assert!(stderr.contains("longer than 1048576 bytes"), "{stderr}");
}

/// An endless program from a pipe (`yes`) stops at the cap with an error
/// instead of taking all memory.
#[test]
fn a_program_from_a_pipe_is_read_up_to_a_cap() {
    let script = r#"yes "G1 X1" | "$0" run "$1""#;
    let (code, stderr) = addipos_limited(512 << 10, script, Path::new("/dev/stdin"));
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("/dev/stdin: a program from a pipe may hold at most 64 MiB"),
        "{stderr}"
    );
}

#[test]
fn run_help_states_the_bounds() {
    let (code, stdout, _) = addipos(&["run".as_ref(), "--help".as_ref()]);
    assert_eq!(code, 0);
    let text = stdout.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(text.contains("at most 1 MiB"), "{stdout}");
    assert!(text.contains("at most 64 MiB"), "{stdout}");
}
