//! `serve --record` and `serve --realtime` over the wire: the clock's
//! idle cycles are one `EXEC n` per stretch between requests, a stop
//! answers the `EXEC` a client waits on with `Stopped` at once (not after
//! the shutdown grace, without an answer), and a FIFO nobody reads holds
//! neither the start nor the stop.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;

use std::process::Command;
use std::time::Duration;

use common::ServeProcess;
use tc_request::{Reply, Request};
use uoi::tcp::BlockingClient;
use uoi::wire::{Answer, ProtocolError};

fn call(client: &mut BlockingClient, req: &Request) -> Reply {
    let ans = client.call(&req.to_wire()).expect("answer");
    Reply::from_wire(req.wire_op(), &ans).expect("reply")
}

#[test]
fn idle_cycles_are_merged_and_a_stop_answers_a_waiting_exec_stopped() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("rt.trace");
    let f = file.to_str().unwrap();
    let args = ["--listen", "127.0.0.1:0", "--realtime", "1", "--record", f];
    let server = ServeProcess::start(&args, &[]);
    let addr = server.addr.clone();
    let mut c = BlockingClient::connect(&addr).unwrap();
    assert_eq!(call(&mut c, &Request::Queue), Reply::Queue(0));
    // A stretch of idle clock: about 150 ticks of the server.
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(call(&mut c, &Request::Queue), Reply::Queue(0));
    // 10^9 cycles of 1 ms: a wait no test outlives.
    let waiter = std::thread::spawn(move || c.call(&Request::Exec(Some(1_000_000_000)).to_wire()));
    // Settle only (no assertion on time): the EXEC reaches the server.
    std::thread::sleep(Duration::from_millis(300));
    let (status, log) = server.terminate(Duration::from_secs(30));
    assert!(status.success(), "{log}");
    let answer = waiter.join().unwrap();
    assert!(
        matches!(answer, Ok(Answer::Protocol(ProtocolError::Stopped))),
        "the waiting EXEC: {answer:?}\n{log}"
    );
    let text = std::fs::read_to_string(&file).unwrap();
    let lines: Vec<&str> = text
        .lines()
        .filter(|l| !l.starts_with(['#', '@']))
        .collect();
    let queues: Vec<usize> = (0..lines.len())
        .filter(|&i| lines[i] == "QUEUE => 0")
        .collect();
    assert_eq!(queues.len(), 2, "{text}");
    let between = &lines[queues[0] + 1..queues[1]];
    assert!(
        between.len() <= 1 && between.iter().all(|l| l.starts_with("EXEC ")),
        "idle cycles between two requests are one EXEC: {between:?}"
    );
}

/// `serve --record FIFO` with nobody reading the FIFO: the server starts
/// and answers (a FIFO's open waits for a reader, so the recorder opens
/// it on its own thread), and SIGTERM stops it.
#[cfg(unix)]
#[test]
fn a_record_fifo_without_a_reader_holds_neither_the_start_nor_the_stop() {
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("record.fifo");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let mut child = common::bin()
        .args([
            "serve",
            "--no-persist",
            "--listen",
            "127.0.0.1:0",
            "--record",
        ])
        .arg(&fifo)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let err = child.stderr.take().unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(err).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                return;
            }
        }
    });
    // Hang guard: the start line within 30 s (it never came before).
    let started = (0..200)
        .map_while(|_| rx.recv_timeout(Duration::from_secs(30)).ok())
        .find(|l| l.contains("serving"));
    let Some(line) = started else {
        let _ = child.kill();
        panic!("serve --record FIFO did not start");
    };
    let addr = line
        .split_whitespace()
        .find_map(|w| w.strip_prefix("listen="))
        .unwrap()
        .to_string();
    let mut c = BlockingClient::connect(&addr).unwrap();
    assert_eq!(call(&mut c, &Request::Queue), Reply::Queue(0));
    drop(c);
    let term = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(term.success());
    // Hang guard only: the stop within 30 s.
    let status = (0..1500).find_map(|_| {
        std::thread::sleep(Duration::from_millis(20));
        child.try_wait().unwrap()
    });
    let _ = child.kill();
    assert!(
        status.is_some_and(|s| s.success()),
        "SIGTERM stopped it: {status:?}"
    );
}
