//! `addipos serve --web`: the view served beside the UOI face, its
//! address read as `--listen` reads one, and anything but loopback
//! refused without `--allow-remote`.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_addipos"))
}

/// Stops the server when the test ends, passed or not.
struct Running(Child);

impl Drop for Running {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// GET `path` at `addr`: the whole answer.
fn get(addr: &str, path: &str) -> String {
    let mut s = TcpStream::connect(addr).expect("connect");
    s.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    write!(s, "GET {path} HTTP/1.1\r\nHost: {addr}\r\n\r\n").unwrap();
    let mut out = String::new();
    s.read_to_string(&mut out).expect("answer");
    out
}

#[test]
fn serve_web_shows_the_served_emulator() {
    let mut child = bin()
        .args(["serve", "--no-persist", "--listen", "127.0.0.1:0"])
        .args(["--web", "127.0.0.1:0"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start serve");
    let log = BufReader::new(child.stderr.take().expect("stderr"));
    let server = Running(child);
    let mut web = None;
    for line in log.lines().take(100) {
        let line = line.expect("log line");
        if let Some(at) = line.split("http://").nth(1) {
            web = Some(at.trim_end_matches('/').to_string());
            break;
        }
    }
    let web = web.expect("the web view's start line names its address");
    let state = get(&web, "/state");
    assert!(state.starts_with("HTTP/1.1 200"), "{state}");
    assert!(state.contains("\"mode\": \"stepped\""), "{state}");
    assert!(state.contains("\"capacity\": 100000"), "{state}");
    let page = get(&web, "/");
    assert!(page.contains("id=\"pos-X\""), "{page}");
    drop(server);
}

#[test]
fn serve_web_elsewhere_than_loopback_needs_leave() {
    let out = bin()
        .args(["serve", "--no-persist", "--listen", "127.0.0.1:0"])
        .args(["--web", "0.0.0.0:0"])
        .stdin(Stdio::null())
        .output()
        .expect("serve");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("--allow-remote"), "{err}");
    let out = bin()
        .args(["serve", "--no-persist", "--web", "nowhere"])
        .stdin(Stdio::null())
        .output()
        .expect("serve");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("--web"), "{err}");
}
