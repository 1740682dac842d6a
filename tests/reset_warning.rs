//! A group RESET sent to a server that keeps tool data clears the group's
//! persisted tool table (the legacy meaning) and says so in the log.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;

use common::{bin, ServeProcess};

fn call(addr: &str, request: &str) -> String {
    let out = bin()
        .arg("call")
        .arg(addr)
        .args(request.split_whitespace())
        .output()
        .expect("run addipos call");
    assert!(
        out.status.success(),
        "{request}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).trim().to_owned()
}

#[test]
fn a_group_reset_logs_the_group_and_the_entries_cleared() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().to_str().unwrap();
    let server = ServeProcess::start(&["--data-dir", data, "--listen", "127.0.0.1:0"], &[]);
    let addr = server.addr.clone();
    for (entry, radius) in [(3, "2.5"), (4, "4"), (7, "1")] {
        call(&addr, &format!("W 1300/1/2/8 i {entry}"));
        call(&addr, &format!("W 1300/1/2/6 d {radius}"));
    }
    call(&addr, "W 1300/1/1/8 i 5");
    call(&addr, "W 1300/1/1/6 d 3");
    call(&addr, "W 1300/1/2/2 i 0");
    call(&addr, "W 1300/1/2/8 i 4");
    assert_eq!(call(&addr, "R 1300/1/2/6 d"), "0");
    call(&addr, "W 1300/1/1/8 i 5");
    assert_eq!(call(&addr, "R 1300/1/1/6 d"), "3", "group 1 is kept");
    let log = server.stop();
    let warning = log
        .lines()
        .find(|l| l.contains("group RESET"))
        .unwrap_or_else(|| panic!("{log}"));
    assert!(warning.contains("WARN"), "{warning}");
    assert!(
        warning.contains("tool table of group 2 is cleared, 3 entries"),
        "{warning}"
    );
    assert_eq!(log.matches("group RESET").count(), 1, "{log}");
}
