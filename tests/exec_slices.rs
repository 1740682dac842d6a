//! A huge `EXEC` with an active per-cycle model does not hold the
//! emulator for its whole length: the server runs it
//! slice by slice, and another connection is answered while it is still
//! under way. No timing: a test model counts its cycles and ends the
//! `EXEC` only when the test says so.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Duration;

use emulator::Emulator;
use emulator::EmulatorService;
use tc_module::NoKey;
use tc_module::{AxisPos, Cycle, CycleModel, CycleTime, Groups, TcExtension, AXES};
use tc_request::{Reply, Request};
use uoi::tcp::BlockingClient;
use uoi::ObjectDesc;

mod common;
use common::{loopback, TestServer};

/// The test model: active until `stop`, counting its cycles.
#[derive(Debug, Default)]
struct Hook {
    cycles: Arc<AtomicU64>,
    stop: Arc<AtomicBool>,
}

impl TcExtension for Hook {
    type Key = NoKey;
    type Group = ();
    type Tool = ();
    type Model<'a> = &'a mut Self;
    const GROUP_OBJECTS: &'static [ObjectDesc<NoKey>] = &[];
    const OBJECTS: &'static [ObjectDesc<NoKey>] = &[];

    fn cycle_model<'a>(&'a mut self, _: Groups<'a, Self>) -> &'a mut Self {
        self
    }
}

impl CycleModel for Hook {
    fn active(&self) -> bool {
        !self.stop.load(Ordering::SeqCst)
    }

    fn cycle(&mut self, _: &Cycle<'_>) -> AxisPos {
        self.cycles.fetch_add(1, Ordering::SeqCst);
        [0.0; AXES]
    }
}

/// Starts a server of an emulator with `hook`; stopped when dropped.
fn serve(hook: Hook) -> TestServer {
    let emu = Emulator::with_extension([0.0; AXES], CycleTime::DEFAULT, hook);
    TestServer::with(loopback(), EmulatorService::with_emulator(emu))
}

fn call(client: &mut BlockingClient, req: &Request) -> Reply {
    let ans = client.call(&req.to_wire()).expect("answer");
    Reply::from_wire(req.wire_op(), &ans).expect("reply")
}

#[test]
fn another_request_is_answered_during_a_huge_exec() {
    let hook = Hook::default();
    let (cycles, stop) = (Arc::clone(&hook.cycles), Arc::clone(&hook.stop));
    let server = serve(hook);
    let addr = server.addr;
    let exec_done = Arc::new(AtomicBool::new(false));
    let done = Arc::clone(&exec_done);
    let long = std::thread::spawn(move || {
        let mut a = BlockingClient::connect(&addr.to_string()).expect("connect");
        let reply = call(&mut a, &Request::Exec(Some(u64::MAX - 1)));
        done.store(true, Ordering::SeqCst);
        reply
    });
    // Hang guard only: wait until the EXEC has stepped cycles.
    for _ in 0..30_000 {
        if cycles.load(Ordering::SeqCst) > 0 {
            break;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    assert!(cycles.load(Ordering::SeqCst) > 0, "the EXEC never started");
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut b = BlockingClient::connect(&addr.to_string()).expect("connect");
        let _ = tx.send((call(&mut b, &Request::Queue), call(&mut b, &Request::Pos)));
    });
    // Hang guard only, far above any real wait.
    let answers = rx.recv_timeout(Duration::from_secs(120));
    let (queue, pos) = answers.expect("another connection was not served during the EXEC");
    assert_eq!(queue, Reply::Queue(0));
    assert_eq!(pos, Reply::Pos([0.0; AXES]));
    // Answered while the EXEC is still under way: it cannot end before
    // the model stops.
    assert!(!exec_done.load(Ordering::SeqCst));
    stop.store(true, Ordering::SeqCst);
    assert_eq!(long.join().expect("exec thread"), Reply::Ok);
    assert!(exec_done.load(Ordering::SeqCst));
}
