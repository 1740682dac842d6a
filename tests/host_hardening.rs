//! The host library under faults on a served target: a wait the server
//! stops, a Clean that lands between the library's look and its write, a
//! server that restarts, a close from another thread during a wait,
//! answers of the wrong shape or duplicated, settings files that never
//! end or hold secrets, and a server that asks for its access token.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;

use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Duration;

use addipos_host::{Descriptor, ErrorCode, Machine};
use bytes::{Bytes, BytesMut};
use common::{loopback, ServeProcess, TestServer};
use emulator::{EmulatorInfo, EmulatorService, INFO_OP, WRITE_IF_OP};
use tc_objects::TcObject;
use uoi::tcp::{Handler, Slice};
use uoi::wire::{decode_request, encode_answer, Answer, ProtocolError, Request as WireRequest};
use uoi::Value;

const PLANE: Descriptor = Descriptor {
    bus_number: 1300,
    device_number: 0,
    index: 3,
    sub_index: 0,
};
const CLEAN: Descriptor = Descriptor {
    bus_number: 1300,
    device_number: 0,
    index: 1,
    sub_index: 0,
};
/// The op code of EXEC.
const EXEC_OP: u8 = 0x20;

fn x(v: f64) -> addipos_host::AxisWords {
    let mut w = [None; 8];
    w[0] = Some(v);
    w
}

fn service() -> EmulatorService {
    EmulatorService::new([0.0; 8], tc_module::CycleTime::DEFAULT)
}

/// The shared emulator, with a twist.
struct Twisted {
    inner: EmulatorService,
    /// Answers every EXEC `Stopped`, as a server shutting down does.
    stop_exec: bool,
    /// Armed: before the next write is served, a Clean is carried out (as
    /// if another connection's Clean came in just before it, after the
    /// writer last looked at the server).
    clean_before_write: Arc<AtomicBool>,
}

impl Handler for Twisted {
    type Session = ();
    type Rest = emulator::ExecRest;

    fn open_session(&mut self) {}

    fn proceed(&mut self, rest: Self::Rest) -> Slice<Self::Rest> {
        self.inner.proceed(rest)
    }

    fn serve(&mut self, req: WireRequest) -> Slice<Self::Rest> {
        let exec = matches!(&req, WireRequest::Ext(EXEC_OP, _));
        if self.stop_exec && exec {
            return Slice::Done(Answer::Protocol(ProtocolError::Stopped));
        }
        let write = matches!(
            &req,
            WireRequest::Write(..) | WireRequest::Ext(WRITE_IF_OP, _)
        );
        if write && self.clean_before_write.swap(false, Ordering::SeqCst) {
            let clean = WireRequest::Write(TcObject::Clean.address(), Value::I32(1));
            assert!(matches!(self.inner.serve(clean), Slice::Done(Answer::Ok)));
        }
        self.inner.serve(req)
    }
}

fn twisted(stop_exec: bool) -> (TestServer, Arc<AtomicBool>) {
    let arm = Arc::new(AtomicBool::new(false));
    let handler = Twisted {
        inner: service(),
        stop_exec,
        clean_before_write: Arc::clone(&arm),
    };
    (TestServer::with(loopback(), handler), arm)
}

#[test]
fn an_exec_the_server_stopped_is_an_error_of_its_own() {
    let (server, _) = twisted(true);
    let m = Machine::open(&server.addr.to_string()).unwrap();
    m.lin(x(10.0), Some(600.0)).unwrap();
    let e = m.exec(None).unwrap_err();
    assert_eq!(e.code(), ErrorCode::Stopped, "{e}");
    assert_eq!(e.code().code(), 0xADD0_000B);
    assert!(e.message().contains("stopped"), "{e}");
    assert_eq!(m.last_failure(), e.message());
}

#[test]
fn a_write_through_a_handle_is_never_carried_out_after_a_clean_with_ok() {
    let (server, arm) = twisted(false);
    let m = Machine::open(&server.addr.to_string()).unwrap();
    let plane = m.handle(&PLANE).unwrap();
    // The Clean comes after the library's last look at the server, just
    // before its write.
    arm.store(true, Ordering::SeqCst);
    let e = m.write_int(plane, 18).unwrap_err();
    assert_eq!(e.code(), ErrorCode::StaleHandle, "{e}");
    assert!(!arm.load(Ordering::SeqCst), "no write reached the server");
    let fresh = m.handle(&PLANE).unwrap();
    assert_ne!(
        m.read_int(fresh).unwrap(),
        18,
        "the stale write was carried out"
    );
}

#[test]
fn handles_voided_by_a_clean_stay_void_after_the_server_restarts() {
    let first = TestServer::with(loopback(), service());
    let addr = first.addr;
    let m = Machine::open(&addr.to_string()).unwrap();
    let plane = m.handle(&PLANE).unwrap();
    let clean = m.handle(&CLEAN).unwrap();
    m.write_int(clean, 1).unwrap();
    assert_eq!(
        m.write_int(plane, 17).unwrap_err().code(),
        ErrorCode::StaleHandle
    );
    drop(first);
    let cfg = uoi::tcp::ServerConfig {
        listen: addr,
        ..loopback()
    };
    let _second = TestServer::with(cfg, service());
    // The connection to the first server is gone: this call finds it out.
    let e = m.position().unwrap_err();
    assert_eq!(e.code(), ErrorCode::Connection, "{e}");
    let e = m.write_int(plane, 17).unwrap_err();
    assert_eq!(e.code(), ErrorCode::StaleHandle, "{e}");
    let e = m.read_int(plane).unwrap_err();
    assert_eq!(e.code(), ErrorCode::StaleHandle, "{e}");
    // A handle of the restarted server works.
    let again = m.handle(&PLANE).unwrap();
    assert_eq!(m.read_int(again).unwrap(), 17);
}

#[test]
fn close_from_another_thread_ends_a_served_wait_with_connection() {
    let mut svc = service();
    svc.set_realtime(emulator::RealTimeFactor::ONE);
    let server = TestServer::with(loopback(), svc);
    let m = Arc::new(
        Machine::served_within(&server.addr.to_string(), Duration::from_secs(20)).unwrap(),
    );
    // 1000 mm at F600: 100 s of motion, far beyond the timeout.
    m.lin(x(1000.0), Some(600.0)).unwrap();
    let waiter = {
        let m = Arc::clone(&m);
        std::thread::spawn(move || m.exec(None))
    };
    std::thread::sleep(Duration::from_millis(300));
    m.close();
    let e = waiter.join().unwrap().unwrap_err();
    // Not the timeout: the close ended the wait.
    assert_eq!(e.code(), ErrorCode::Connection, "{e}");
    assert!(e.message().contains("closed"), "{e}");
}

#[test]
fn an_interrupted_served_wait_ends_and_the_next_call_connects_again() {
    let mut svc = service();
    svc.set_realtime(emulator::RealTimeFactor::ONE);
    let server = TestServer::with(loopback(), svc);
    let m = Arc::new(
        Machine::served_within(&server.addr.to_string(), Duration::from_secs(20)).unwrap(),
    );
    m.lin(x(1000.0), Some(600.0)).unwrap();
    let stop = Arc::new(AtomicBool::new(false));
    let waiter = {
        let (m, stop) = (Arc::clone(&m), Arc::clone(&stop));
        std::thread::spawn(move || m.exec_until(None, &stop))
    };
    std::thread::sleep(Duration::from_millis(300));
    stop.store(true, Ordering::SeqCst);
    let e = waiter.join().unwrap().unwrap_err();
    assert_eq!(e.code(), ErrorCode::Timeout, "{e}");
    assert!(e.message().contains("given up"), "{e}");
    let q = m.queue().unwrap();
    assert_eq!(q, 1, "the line still runs");
}

/// How a fake server misbehaves.
#[derive(Clone, Copy)]
enum Fault {
    /// A READ is answered with a value of the other type.
    OtherType,
    /// The first READ is answered twice.
    Duplicate,
}

/// A fake server speaking the wire by hand: INFO as a fresh server
/// answers it, READ as `fault` says, anything else `Ok`. Counts the
/// connections it accepted.
fn fake_server(fault: Fault) -> (String, Arc<AtomicUsize>) {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap().to_string();
    let accepted = Arc::new(AtomicUsize::new(0));
    let count = Arc::clone(&accepted);
    let duplicated = Arc::new(AtomicBool::new(false));
    // One server: one identity for all its connections.
    let info = service().info().to_wire();
    std::thread::spawn(move || {
        for stream in listener.incoming().flatten() {
            count.fetch_add(1, Ordering::SeqCst);
            let (duplicated, info) = (Arc::clone(&duplicated), info.clone());
            std::thread::spawn(move || serve_fake(stream, fault, &duplicated, &info));
        }
    });
    (addr, accepted)
}

fn serve_fake(mut s: TcpStream, fault: Fault, duplicated: &AtomicBool, info: &Answer) {
    loop {
        let mut len = [0u8; 4];
        if s.read_exact(&mut len).is_err() {
            return;
        }
        let mut body = vec![0u8; u32::from_le_bytes(len) as usize];
        if s.read_exact(&mut body).is_err() {
            return;
        }
        let Ok((id, req)) = decode_request(Bytes::from(body)) else {
            return;
        };
        let (answer, times) = match (&req, fault) {
            (WireRequest::Ext(INFO_OP, _), _) => (info.clone(), 1),
            (WireRequest::Read(..), Fault::OtherType) => (Answer::Value(Value::F64(17.0)), 1),
            (WireRequest::Read(..), Fault::Duplicate) => {
                let twice = !duplicated.swap(true, Ordering::SeqCst);
                (Answer::Value(Value::I32(17)), if twice { 2 } else { 1 })
            }
            _ => (Answer::Ok, 1),
        };
        let mut out = BytesMut::new();
        for _ in 0..times {
            encode_answer(id, req.op().code(), &answer, &mut out);
        }
        if s.write_all(&out).is_err() {
            return;
        }
    }
}

#[test]
fn a_value_of_the_other_type_is_never_a_value() {
    let (addr, accepted) = fake_server(Fault::OtherType);
    let m = Machine::served_within(&addr, Duration::from_secs(10)).unwrap();
    let plane = m.handle(&PLANE).unwrap();
    let e = m.read_int(plane).unwrap_err();
    assert_eq!(e.code(), ErrorCode::Protocol, "{e}");
    // The connection was dropped: the next call made a new one.
    let before = accepted.load(Ordering::SeqCst);
    let _ = m.read_int(plane);
    assert_eq!(accepted.load(Ordering::SeqCst), before + 1);
}

#[test]
fn after_a_duplicated_answer_the_ids_do_not_drift() {
    let (addr, _) = fake_server(Fault::Duplicate);
    let m = Machine::served_within(&addr, Duration::from_secs(10)).unwrap();
    let plane = m.handle(&PLANE).unwrap();
    assert_eq!(m.read_int(plane).unwrap(), 17);
    // The duplicate arrives where the next answer is awaited.
    let e = m.read_int(plane).unwrap_err();
    assert_eq!(e.code(), ErrorCode::Protocol, "{e}");
    assert!(e.message().contains("connects again"), "{e}");
    for _ in 0..5 {
        assert_eq!(m.read_int(plane).unwrap(), 17);
    }
}

#[test]
fn a_settings_file_that_never_ends_or_is_no_file_is_refused() {
    let e = Machine::open("embedded:config=/dev/zero").unwrap_err();
    assert_eq!(e.code(), ErrorCode::Argument, "{e}");
    assert!(e.message().contains("not a regular file"), "{e}");
    let dir = tempfile::tempdir().unwrap();
    let big = dir.path().join("big.toml");
    std::fs::write(&big, vec![b'#'; 2 << 20]).unwrap();
    let e = Machine::open(&format!("embedded:config={}", big.display())).unwrap_err();
    assert!(e.message().contains("larger than 1 MiB"), "{e}");
    // A FIFO nobody writes to is refused before it is opened (an open
    // would wait for a writer).
    let fifo = dir.path().join("fifo");
    if std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success())
    {
        let e = Machine::open(&format!("embedded:config={}", fifo.display())).unwrap_err();
        assert!(e.message().contains("not a regular file"), "{e}");
    }

    let out = common::bin()
        .args(["serve", "--no-persist", "--config", "/dev/zero"])
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(said.contains("not a regular file"), "{said}");
}

#[test]
fn a_settings_file_that_does_not_parse_is_not_quoted() {
    let dir = tempfile::tempdir().unwrap();
    let secret = dir.path().join("shadow");
    std::fs::write(
        &secret,
        "root:$6$SECRETSALT$SECRETHASH:19000:0:99999:7:::\n",
    )
    .unwrap();
    let e = Machine::open(&format!("embedded:config={}", secret.display())).unwrap_err();
    assert!(!e.message().contains("SECRET"), "{e}");
    assert!(e.message().contains("line 1"), "{e}");
    let typed = dir.path().join("typed.toml");
    std::fs::write(&typed, "cycle_ms = \"SECRET\"\n").unwrap();
    let e = Machine::open(&format!("embedded:config={}", typed.display())).unwrap_err();
    assert!(!e.message().contains("SECRET"), "{e}");

    let out = common::bin()
        .args(["serve", "--no-persist", "--config"])
        .arg(&secret)
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(!said.contains("SECRET"), "{said}");
}

#[test]
fn a_server_that_asks_for_its_token_is_opened_with_it() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("serve.toml");
    std::fs::write(&config, "token_on_loopback = true\n").unwrap();
    let data = dir.path().join("data");
    let server = ServeProcess::start(
        &[
            "--listen",
            "127.0.0.1:0",
            "--config",
            config.to_str().unwrap(),
            "--data-dir",
            data.to_str().unwrap(),
        ],
        &[],
    );
    let e = Machine::open(&server.addr).unwrap_err();
    assert!(e.message().contains("token"), "{e}");
    let file = data.join("access-token");
    let m = Machine::open(&format!("{},token_file={}", server.addr, file.display())).unwrap();
    let plane = m.handle(&PLANE).unwrap();
    assert_eq!(m.read_int(plane).unwrap(), 17);
    let token = std::fs::read_to_string(&file).unwrap();
    let m = Machine::open(&format!("{}, token={}", server.addr, token.trim())).unwrap();
    assert_eq!(m.read_int(m.handle(&PLANE).unwrap()).unwrap(), 17);
    let e = Machine::open(&format!("{},token=wrong-token-of-16-chars", server.addr)).unwrap_err();
    assert!(!e.message().contains("wrong-token"), "{e}");
    server.stop();
}

/// The info a fresh service answers carries an identity of its own.
#[test]
fn every_server_start_has_an_identity_of_its_own() {
    let a = EmulatorInfo::from_wire(&service().info().to_wire()).unwrap();
    let b = service().info();
    assert_ne!(a.server, 0);
    assert_ne!(a.server, b.server);
}

fn group1(sub: i32) -> Descriptor {
    Descriptor {
        bus_number: 1300,
        device_number: 1,
        index: 1,
        sub_index: sub,
    }
}

#[test]
fn a_range_error_says_the_range_and_a_slow_feed_the_smallest_feed() {
    let m = Machine::open("embedded").unwrap();
    let radius = m.handle(&group1(6)).unwrap();
    let e = m.write_double(radius, 5e9).unwrap_err();
    assert_eq!(e.code(), ErrorCode::Range);
    assert!(e.message().contains("RADIUS takes"), "{e}");
    let e = m.lin(x(1.0), Some(0.1)).unwrap_err();
    assert_eq!(e.code(), ErrorCode::Range);
    assert!(
        e.message()
            .contains("the feed F0.1 is below the smallest feed, F0.6"),
        "{e}"
    );
    let e = m.lin(x(1.0), Some(-5.0)).unwrap_err();
    assert_eq!(e.code(), ErrorCode::Range);
    assert!(e.message().contains("the feed F-5 is negative"), "{e}");
}

#[test]
fn a_state_error_after_a_gouge_says_which_group_which_bit_and_how_to_clear_it() {
    let m = Machine::open("embedded").unwrap();
    let w = |sub: i32, v: i32| m.write_int(m.handle(&group1(sub)).unwrap(), v).unwrap();
    w(2, 0);
    w(8, 1);
    m.write_double(m.handle(&group1(6)).unwrap(), 2.0).unwrap();
    w(9, 0);
    w(3, 1);
    let mut p = x(10.0);
    m.lin(p, None).unwrap();
    p[1] = Some(1.0);
    m.lin(p, None).unwrap();
    p[0] = Some(20.0);
    let e = m.lin(p, None).unwrap_err();
    assert_eq!(e.code(), ErrorCode::State, "{e}");
    for part in ["group 1 is faulted", "KorrError", "writing ERROR"] {
        assert!(e.message().contains(part), "{e}");
    }
}

#[test]
fn a_failed_open_does_not_promise_a_next_call() {
    let free = TcpListener::bind("127.0.0.1:0").unwrap();
    let gone = free.local_addr().unwrap().to_string();
    drop(free);
    let e = Machine::open(&gone).unwrap_err();
    assert_eq!(e.code(), ErrorCode::Connection, "{e}");
    assert!(!e.message().contains("next call"), "{e}");
}
