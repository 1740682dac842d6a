//! `addipos serve` with the built-in settings, `addipos call` against it,
//! and a graceful stop on SIGTERM.

// Test and bench helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::io::{BufRead, BufReader, Read};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use tc_objects::TcObject;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_addipos"))
}

#[test]
fn serve_call_and_stop() {
    let mut server = bin()
        .args(["serve", "--no-persist", "--listen", "127.0.0.1:0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start serve");
    // The start line is a log line on stderr, naming the address bound.
    let mut log = BufReader::new(server.stderr.take().expect("stderr"));
    let mut start = String::new();
    while !start.contains("serving") {
        start.clear();
        let n = log.read_line(&mut start).expect("start line");
        assert!(n > 0, "serve ended without a start line");
    }
    let addr = start
        .split_whitespace()
        .find_map(|w| w.strip_prefix("listen="))
        .unwrap_or_else(|| panic!("no address in {start:?}"))
        .to_string();
    let port = addr.rsplit_once(':').expect("port").1.to_string();

    // The same server by a bare port and by localhost.
    let plane = TcObject::TcPlane.address().to_string();
    for a in [port.clone(), format!("localhost:{port}")] {
        let out = bin()
            .args(["call", &a, "R", &plane, "i"])
            .output()
            .expect("call");
        assert_eq!(String::from_utf8_lossy(&out.stdout).trim(), "17", "{a}");
    }

    let out = bin()
        .args(["call", &addr, "R", &plane, "i"])
        .output()
        .expect("call");
    assert_eq!(String::from_utf8_lossy(&out.stdout).trim(), "17");
    assert!(out.status.success());

    let out = bin()
        .args([
            "call",
            &addr,
            "W",
            &TcObject::WkzIndex.of(1).to_string(),
            "i",
            "1024",
        ])
        .output()
        .expect("call");
    assert!(String::from_utf8_lossy(&out.stdout)
        .trim()
        .starts_with("err Range: "));
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
    let mut rest = String::new();
    log.read_to_string(&mut rest).expect("log");
    let mut stdout = String::new();
    server
        .stdout
        .take()
        .expect("stdout")
        .read_to_string(&mut stdout)
        .expect("stdout");
    let all = format!("{start}{rest}{stdout}");
    assert_eq!(all.matches("serving").count(), 1, "{all}");
    assert!(!all.contains('\x1b'), "colour escapes in a pipe: {all:?}");
}

/// Runs `serve` with `args` (expected not to start): exit code, stderr.
fn serve_fails(args: &[&str]) -> (i32, String) {
    let out = bin()
        .args(["serve", "--no-persist"])
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("serve");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn port_in_use_names_the_address_and_the_way_out() {
    let taken = std::net::TcpListener::bind("127.0.0.1:0").expect("bind");
    let port = taken.local_addr().expect("addr").port();
    for listen in [
        format!("127.0.0.1:{port}"),
        port.to_string(),
        format!("localhost:{port}"),
    ] {
        let (code, err) = serve_fails(&["--listen", &listen]);
        assert_eq!(code, 2, "{listen}: {err}");
        let want = format!("error: cannot listen on 127.0.0.1:{port}: address already in use");
        assert!(err.contains(&want), "{listen}: {err}");
        assert!(err.contains("--listen"), "{err}");
        assert!(!err.contains('\x1b'), "{err:?}");
    }
}

#[test]
fn every_cannot_start_has_the_same_exit_code() {
    let (code, err) = serve_fails(&["--listen", "nowhere"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--listen"), "{err}");
    assert!(err.contains("nowhere"), "{err}");
    let (code, err) = serve_fails(&["--listen", "0.0.0.0:0"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--allow-remote"), "{err}");
}

#[test]
fn settings_errors_name_the_file() {
    let dir = std::env::temp_dir().join(format!("addipos-cfg2-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    for (name, text, setting) in [
        ("core.toml", "core = \"fast\"\n", "core"),
        ("cycle.toml", "cycle_ms = 0\n", "cycle_ms"),
        ("listen.toml", "listen = \"nowhere\"\n", "listen"),
        ("key.toml", "listn = \"x\"\n", "listn"),
    ] {
        let f = dir.join(name);
        std::fs::write(&f, text).expect("write");
        let (code, err) = serve_fails(&["--config", &f.to_string_lossy()]);
        assert_eq!(code, 2, "{name}: {err}");
        let want = format!("error: {}: ", f.display());
        assert!(err.starts_with(&want), "{name}: {err}");
        assert!(err.contains(setting), "{name}: {err}");
    }
}

#[test]
fn serve_refuses_bad_settings_clearly() {
    let dir = std::env::temp_dir().join(format!("addipos-cfg-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let f = dir.join("bad.toml");
    std::fs::write(&f, "core = \"fast\"\n").expect("write");
    let out = bin()
        .args(["serve", "--no-persist", "--config"])
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
        .args(["serve", "--no-persist", "--listen", "0.0.0.0:0"])
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
