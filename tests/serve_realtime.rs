//! `serve --realtime --record` over the wire: the clock's idle cycles are
//! one `EXEC n` per stretch between requests, and a stop answers the
//! `EXEC` a client waits on with `Stopped` at once (not after the
//! shutdown grace, without an answer).

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;

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
