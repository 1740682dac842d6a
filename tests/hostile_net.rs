//! The command line against servers that do not play along: `call` and
//! `replay --server` give up on a server that never answers, and `serve`
//! with an access token lets in only clients that present it.

// Test and bench helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::path::PathBuf;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

mod common;
use common::{bin, ServeProcess};
use tc_objects::TcObject;

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("addipos-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// Waits for `child` to end by itself; kills it after `guard` (a hang
/// guard, far above the wait the test provokes) and fails.
fn finish(mut child: Child, guard: Duration) -> Output {
    let t0 = Instant::now();
    while child.try_wait().expect("wait").is_none() {
        if t0.elapsed() > guard {
            let _ = child.kill();
            panic!("still waiting after {guard:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().expect("output")
}

fn run(cmd: &mut Command) -> Output {
    let child = cmd
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start");
    finish(child, Duration::from_secs(60))
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// Against a listener that accepts (the
/// kernel does) but never answers, both commands give up after
/// `--timeout` with a message naming the address and the time, and exit 2
/// (no UOI server could be reached).
#[test]
fn call_and_replay_give_up_on_a_server_that_never_answers() {
    let silent = std::net::TcpListener::bind("127.0.0.1:0").expect("bind");
    let addr = silent.local_addr().expect("addr").to_string();
    let reach = format!("could not reach a UOI server at {addr}");
    let want = "got no UOI answer within 1 s";

    let plane = TcObject::TcPlane.address().to_string();
    let out = run(bin().args(["call", &addr, "--timeout", "1", "R", &plane, "i"]));
    assert_eq!(out.status.code(), Some(2));
    let said = text(&out.stderr);
    assert!(said.contains(&reach) && said.contains(want), "{said}");

    let trace = temp_dir("silent").join("one.trace");
    std::fs::write(&trace, "R 1300/0/3/0 i => 17\n").expect("trace");
    let out = run(bin()
        .args(["replay", "--server", &addr, "--timeout", "1"])
        .arg(&trace));
    assert_eq!(out.status.code(), Some(2));
    let said = text(&out.stderr);
    assert!(said.contains(&reach) && said.contains(want), "{said}");
}

/// End to end: `serve` generates the token file
/// (owner only), logs where it is but not the token, and `call` gets in
/// only with the token (file, option or environment).
#[test]
fn serve_with_a_token_lets_in_only_clients_that_present_it() {
    let dir = temp_dir("token-serve");
    let data = dir.join("data");
    let config = dir.join("serve.toml");
    std::fs::write(
        &config,
        format!(
            "listen = \"127.0.0.1:0\"\ntoken_on_loopback = true\ndata_dir = {:?}\n",
            data.display().to_string()
        ),
    )
    .expect("config");
    let server = ServeProcess::start(&["--config", config.to_str().expect("utf-8 path")], &[]);
    let token_file = data.join("access-token");
    let token = std::fs::read_to_string(&token_file).expect("token file");
    let token = token.trim().to_string();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(&token_file)
            .expect("meta")
            .permissions()
            .mode();
        assert_eq!(mode & 0o777, 0o600);
    }
    let plane = TcObject::TcPlane.address().to_string();
    let call = |extra: &[&str], env: Option<&str>| {
        let mut cmd = bin();
        cmd.args(["call", &server.addr])
            .args(extra)
            .args(["R", &plane, "i"]);
        cmd.env_remove("ADDIPOS_TOKEN");
        if let Some(t) = env {
            cmd.env("ADDIPOS_TOKEN", t);
        }
        run(&mut cmd)
    };

    let out = call(&[], None);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("Unauthorized") && err.contains("--token-file"),
        "{err}"
    );

    let file = token_file.to_string_lossy().into_owned();
    let out = call(&["--token-file", &file], None);
    assert_eq!(text(&out.stdout).trim(), "17", "{}", text(&out.stderr));
    let out = call(&["--token", &token], None);
    assert_eq!(text(&out.stdout).trim(), "17", "{}", text(&out.stderr));
    let out = call(&[], Some(&token));
    assert_eq!(text(&out.stdout).trim(), "17", "{}", text(&out.stderr));

    let out = call(&["--token", "0000000000000000000000000000000x"], None);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("Unauthorized"),
        "{}",
        text(&out.stderr)
    );

    let log = server.stop();
    assert!(log.contains(&file), "{log}");
    assert!(!log.contains(&token), "the log shows the token: {log}");
}
