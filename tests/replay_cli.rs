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
    let out = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .arg("replay")
        .args(args)
        .output()
        .expect("run addipos");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
    )
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
fn missing_file_is_a_failure_not_a_crash() {
    let p = std::path::Path::new("/nonexistent/nothing.trace");
    let (code, out) = replay(&[p]);
    assert_ne!(code, 0);
    assert!(out.contains("cannot read"), "{out}");
}
