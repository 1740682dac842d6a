//! Conformance sessions over TCP: `SETUP` gives a connection its own
//! emulator, which no other connection sees and which ends with the
//! connection; the shared emulator is never reset or logged by a client.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::net::SocketAddr;
use std::path::Path;

use tc_objects::TcObject;
use tc_request::text::parse_request;
use tc_request::{Reply, Request};
use uoi::tcp::{BlockingClient, Client};
use uoi::{AccessError, Value};

mod common;
use common::{bin, ServeProcess, TestServer};

/// A server of a fresh emulator; stopped when dropped.
fn serve() -> (SocketAddr, TestServer) {
    let s = TestServer::local();
    (s.addr, s)
}

/// A request in trace syntax, on the wire, its reply decoded.
fn call(c: &mut BlockingClient, text: &str) -> Reply {
    let req = parse_request(text).expect("request");
    request(c, &req)
}

fn request(c: &mut BlockingClient, req: &Request) -> Reply {
    let ans = c.call(&req.to_wire()).expect("answered");
    Reply::from_wire(req.wire_op(), &ans).expect("a TC reply")
}

fn setup(c: &mut BlockingClient) -> Reply {
    request(
        c,
        &Request::Setup {
            start: [0.0; 8],
            cycle_s: 1e-3,
            spool_capacity: 0,
        },
    )
}

fn spool_log(c: &mut BlockingClient, logging: bool) -> Reply {
    request(c, &Request::SpoolLog { logging })
}

const RADIUS: &str = "R 1300/1/1/6 d";

#[test]
fn a_session_is_private_and_ends_with_its_connection() {
    let (addr, _stop) = serve();
    let a = addr.to_string();
    let mut shared = BlockingClient::connect(&a).expect("connect");
    assert_eq!(call(&mut shared, "W 1300/1/1/6 d 7.25"), Reply::Ok);

    let mut own = BlockingClient::connect(&a).expect("connect");
    assert_eq!(setup(&mut own), Reply::Ok);
    // The session starts fresh: it does not see the shared radius.
    assert_eq!(call(&mut own, RADIUS), Reply::Value(Value::F64(0.0)));
    assert_eq!(call(&mut own, "W 1300/1/1/6 d 1.5"), Reply::Ok);
    assert_eq!(call(&mut own, "LIN X5"), Reply::Ok);
    assert_eq!(call(&mut own, "QUEUE"), Reply::Queue(1));
    // Nothing of it reaches the shared emulator, and back.
    assert_eq!(call(&mut shared, RADIUS), Reply::Value(Value::F64(7.25)));
    assert_eq!(call(&mut shared, "QUEUE"), Reply::Queue(0));
    assert_eq!(call(&mut shared, "W 1300/1/1/6 d 3"), Reply::Ok);
    assert_eq!(call(&mut own, RADIUS), Reply::Value(Value::F64(1.5)));

    // A second SETUP on the same connection starts the session afresh.
    assert_eq!(setup(&mut own), Reply::Ok);
    assert_eq!(call(&mut own, "QUEUE"), Reply::Queue(0));
    assert_eq!(call(&mut own, "W 1300/1/1/6 d 1.5"), Reply::Ok);

    // The session ends with its connection: a new one is on the shared emulator.
    drop(own);
    let mut next = BlockingClient::connect(&a).expect("connect");
    assert_eq!(call(&mut next, RADIUS), Reply::Value(Value::F64(3.0)));
}

#[test]
fn a_refused_setup_leaves_the_connection_where_it_was() {
    let (addr, _stop) = serve();
    let mut c = BlockingClient::connect(&addr.to_string()).expect("connect");
    assert_eq!(call(&mut c, "W 1300/1/1/6 d 2"), Reply::Ok);
    let bad = Request::Setup {
        start: [0.0; 8],
        cycle_s: 2.0,
        spool_capacity: 0,
    };
    assert_eq!(request(&mut c, &bad), Reply::Access(AccessError::Range));
    assert_eq!(call(&mut c, RADIUS), Reply::Value(Value::F64(2.0)));
    assert_eq!(spool_log(&mut c, true), Reply::Access(AccessError::State));
}

#[test]
fn the_shared_emulator_cannot_be_logged() {
    let (addr, _stop) = serve();
    let mut c = BlockingClient::connect(&addr.to_string()).expect("connect");
    assert_eq!(spool_log(&mut c, true), Reply::Access(AccessError::State));
    assert_eq!(call(&mut c, "LIN X1"), Reply::Ok);
    assert_eq!(spool_log(&mut c, false), Reply::Access(AccessError::State));
}

/// Spools `n` lines on a connection in pipelined batches.
fn spool_lines(addr: SocketAddr, session: bool, n: usize) -> Vec<Reply> {
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("rt");
    rt.block_on(async move {
        let mut c = Client::connect(addr).await.expect("connect");
        let mut reqs = Vec::new();
        if session {
            reqs.push(Request::Setup {
                start: [0.0; 8],
                cycle_s: 1e-3,
                spool_capacity: 0,
            });
            reqs.push(Request::SpoolLog { logging: true });
        }
        reqs.extend((0..n).map(|k| parse_request(&format!("LIN X{}", k % 2)).expect("LIN")));
        reqs.push(Request::SpoolLog { logging: true });
        reqs.push(Request::Setup {
            start: [0.0; 8],
            cycle_s: 1e-3,
            spool_capacity: 0,
        });
        reqs.push(Request::SpoolLog { logging: true });
        let wire: Vec<_> = reqs.iter().map(Request::to_wire).collect();
        let answers = c.pipeline(&wire).await.expect("pipeline");
        reqs.iter()
            .zip(&answers)
            .map(|(r, a)| Reply::from_wire(r.wire_op(), a).expect("a TC reply"))
            .collect()
    })
}

/// A reply, a spool log shown by its length only.
fn short(r: &Reply) -> String {
    match r {
        Reply::Spool(els, more) => format!("Spool({} elements, more {more})", els.len()),
        other => format!("{other:?}"),
    }
}

#[test]
fn a_full_session_log_is_reported_until_the_next_setup() {
    let (addr, _stop) = serve();
    let cap = emulator::LOG_CAPACITY;
    let replies = spool_lines(addr, true, cap + 1);
    let n = replies.len();
    // The log overflowed: SPOOL_LOG says so instead of a partial log...
    assert_eq!(short(&replies[n - 3]), "Access(State)");
    // ...until SETUP starts afresh, with an empty log.
    assert_eq!(replies[n - 2], Reply::Ok);
    assert_eq!(replies[n - 1], Reply::Spool(Vec::new(), false));
    // Exactly full is still a whole log.
    let replies = spool_lines(addr, true, cap);
    let Reply::Spool(els, more) = &replies[replies.len() - 3] else {
        panic!("{}", short(&replies[replies.len() - 3]));
    };
    assert_eq!((els.len(), *more), (tc_request::wire::SPOOL_BATCH, true));
}

/// `addipos serve` on a free port; killed on drop.
fn cli(args: &[&str]) -> (bool, String) {
    let out = bin().args(args).output().expect("run addipos");
    let text = String::from_utf8_lossy(&out.stdout).trim().to_string();
    (out.status.success(), text)
}

/// The new user's steps: a radius written with `call`, then the README's
/// `replay --server` command; the radius is still there.
#[test]
fn replay_over_the_wire_leaves_the_shared_emulator_alone() {
    let server = ServeProcess::start(&["--listen", "127.0.0.1:0"], &[]);
    let a = server.addr.as_str();
    let radius = TcObject::Radius.of(1).to_string();
    assert_eq!(
        cli(&["call", a, "W", &radius, "d", "7.25"]),
        (true, "ok".into())
    );
    let traces = Path::new(env!("CARGO_MANIFEST_DIR")).join("traces");
    let trace = traces.join("d0-reinit.trace");
    let trace = trace.to_str().expect("utf-8 path");
    let (passed, out) = cli(&["replay", "--server", a, trace]);
    assert!(passed, "{out}");
    assert!(out.contains("1 passed, 0 failed"), "{out}");
    assert_eq!(cli(&["call", a, "R", &radius, "d"]), (true, "7.25".into()));
}
