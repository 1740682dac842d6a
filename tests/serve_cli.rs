//! `addipos serve` with the built-in settings, `addipos call` against it,
//! and a graceful stop on SIGTERM.

// Test and bench helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_addipos"))
}

#[test]
fn serve_call_and_stop() {
    let mut server = bin()
        .args(["serve", "--listen", "127.0.0.1:0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("start serve");
    let stdout = server.stdout.take().expect("stdout");
    let mut line = String::new();
    BufReader::new(stdout).read_line(&mut line).expect("banner");
    let addr = line
        .split_whitespace()
        .find(|w| w.starts_with("127.0.0.1:"))
        .unwrap_or_else(|| panic!("no address in {line:?}"))
        .to_string();

    let out = bin()
        .args(["call", &addr, "R", "1300/0/3/0", "i"])
        .output()
        .expect("call");
    assert_eq!(String::from_utf8_lossy(&out.stdout).trim(), "17");
    assert!(out.status.success());

    let out = bin()
        .args(["call", &addr, "W", "1300/1/1/8", "i", "1024"])
        .output()
        .expect("call");
    assert_eq!(String::from_utf8_lossy(&out.stdout).trim(), "err Range");
    assert!(!out.status.success());

    let out = bin().args(["call", &addr, "FROB"]).output().expect("call");
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown request"));

    let killed = Command::new("kill")
        .args(["-TERM", &server.id().to_string()])
        .status()
        .expect("kill");
    assert!(killed.success());
    let t0 = Instant::now();
    loop {
        if let Some(status) = server.try_wait().expect("wait") {
            assert!(status.success(), "serve exited with {status}");
            break;
        }
        assert!(
            t0.elapsed() < Duration::from_secs(10),
            "serve did not stop on SIGTERM"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[test]
fn serve_refuses_bad_settings_clearly() {
    let dir = std::env::temp_dir().join(format!("addipos-cfg-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let f = dir.join("bad.toml");
    std::fs::write(&f, "core = \"fast\"\n").expect("write");
    let out = bin()
        .args(["serve", "--config"])
        .arg(&f)
        .output()
        .expect("serve");
    assert!(!out.status.success());
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("core"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    let out = bin()
        .args(["serve", "--listen", "0.0.0.0:0"])
        .output()
        .expect("serve");
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--allow-remote"));

    let out = bin()
        .args(["serve", "--print-default-config"])
        .output()
        .expect("serve");
    assert!(String::from_utf8_lossy(&out.stdout).contains("listen = \"127.0.0.1:1300\""));
}
