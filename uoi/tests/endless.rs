//! A request that never ends (a huge `EXEC` with a per-cycle model, in the
//! emulator) is served slice by slice, by the shared handler or by a
//! connection's session: other clients are served meanwhile; a request
//! being served is progress (the idle timeout does not cut it off); once
//! its client closes the connection no further slice of it runs; and a
//! request stopped by the server's shutdown is answered `Stopped` with its
//! own op and id.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

use bytes::BytesMut;
use common::{connect, index_of, local, serve_with};
use uoi::tcp::{Handler, ServerConfig, Session, Slice};
use uoi::wire::{encode_request, Answer, Request};
use uoi::{ObjectAddress, Value, ValueType};

/// Slices run of the endless request, per test (each test its own index).
static SLICES: [AtomicU64; 3] = [AtomicU64::new(0), AtomicU64::new(0), AtomicU64::new(0)];

/// The slot of the endless request the shared handler serves.
const SHARED: usize = 0;
/// The slot of the endless request a session serves.
const SESSION: usize = 1;
/// The slot of the endless request the shared handler serves until the
/// server stops.
const UNTIL_STOP: usize = 2;

/// A READ of index 0, sub 0 never ends in the shared handler: every slice
/// hands back the rest. Any other READ is answered with its index.
struct Endless;

impl Handler for Endless {
    type Session = EndlessSession;
    type Rest = Request;

    fn open_session(&mut self) -> EndlessSession {
        EndlessSession
    }

    fn proceed(&mut self, rest: Request) -> Slice {
        self.serve(rest)
    }

    fn serve(&mut self, req: Request) -> Slice {
        match req {
            Request::Read(a, _) if a.index == 0 => {
                SLICES[usize::from(a.sub)].fetch_add(1, Ordering::Relaxed);
                Slice::More(req)
            }
            other => Slice::Done(index_of(&other)),
        }
    }
}

/// Takes READs of index 0, sub 1, 3 and 4: those of sub 1 never end;
/// those of sub 3 take as many more slices as their device number, then
/// answer 42; those of sub 4 too, each slice taking 20 ms.
struct EndlessSession;

impl Session for EndlessSession {
    fn takes(&self, req: &Request) -> bool {
        matches!(req, Request::Read(a, _) if a.index == 0 && matches!(a.sub, 1 | 3 | 4))
    }

    fn proceed(&mut self, rest: Request) -> Slice {
        self.serve(rest)
    }

    fn serve(&mut self, req: Request) -> Slice {
        match req {
            Request::Read(a, ty) if a.sub == 3 || a.sub == 4 => {
                if a.sub == 4 {
                    std::thread::sleep(Duration::from_millis(20));
                }
                match a.device {
                    0 => Slice::Done(Answer::Value(Value::I32(42))),
                    n => Slice::More(Request::Read(ObjectAddress::new(7, n - 1, 0, a.sub), ty)),
                }
            }
            req => {
                SLICES[SESSION].fetch_add(1, Ordering::Relaxed);
                Slice::More(req)
            }
        }
    }
}

/// A server with the [`Endless`] handler and an idle timeout of 300 ms.
fn serve() -> (SocketAddr, tokio::sync::oneshot::Sender<()>) {
    let cfg = ServerConfig {
        idle_timeout: Duration::from_millis(300),
        ..local()
    };
    serve_with(cfg, Endless)
}

fn read(s: &mut TcpStream, index: u16, sub: u16) {
    read_of(s, 0, index, sub);
}

/// Sends a READ of (7, `device`, `index`, `sub`) as request 1.
fn read_of(s: &mut TcpStream, device: u16, index: u16, sub: u16) {
    let mut f = BytesMut::new();
    let req = Request::Read(ObjectAddress::new(7, device, index, sub), ValueType::I32);
    encode_request(1, &req, &mut f);
    s.write_all(&f).expect("send");
}

/// Whether the count of slices of `slot` comes to rest (it would grow
/// forever if the rest of the request kept running).
fn comes_to_rest(slot: usize) -> bool {
    (0..50).any(|_| {
        let before = SLICES[slot].load(Ordering::Relaxed);
        std::thread::sleep(Duration::from_millis(100));
        SLICES[slot].load(Ordering::Relaxed) == before
    })
}

/// The endless request of `slot` runs while another client is answered,
/// is not cut off by the idle timeout, and stops for good once its client
/// closes the connection.
fn endless_request_stops_with_its_connection(slot: usize) {
    let (addr, _stop) = serve();
    let mut hog = connect(addr);
    read(&mut hog, 0, slot as u16);
    // Another client is answered while the endless request runs.
    let mut other = connect(addr);
    read(&mut other, 5, 0);
    let mut a = [0u8; 28];
    other
        .read_exact(&mut a)
        .expect("the other client is answered");
    assert_eq!(i32::from_le_bytes([a[20], a[21], a[22], a[23]]), 5);
    assert!(
        SLICES[slot].load(Ordering::Relaxed) > 0,
        "the endless request runs"
    );
    // Served slice by slice, the request is progress: three idle
    // timeouts later the hog is still open and has no answer.
    std::thread::sleep(Duration::from_millis(900));
    hog.set_nonblocking(true).expect("nonblocking");
    let mut b = [0u8; 1];
    let waiting = matches!(hog.read(&mut b), Err(e) if e.kind() == std::io::ErrorKind::WouldBlock);
    assert!(waiting, "the idle timeout cut the request off");
    // The client leaves: its request stops at the next slice boundary.
    drop(hog);
    assert!(
        comes_to_rest(slot),
        "slices still run after the client left"
    );
}

#[test]
fn the_shared_handler_drops_the_rest_of_a_request_of_a_closed_connection() {
    endless_request_stops_with_its_connection(SHARED);
}

#[test]
fn a_session_answers_a_request_of_many_slices() {
    let (addr, _stop) = serve();
    let mut s = connect(addr);
    let mut f = BytesMut::new();
    let req = Request::Read(ObjectAddress::new(7, 5, 0, 3), ValueType::I32);
    encode_request(1, &req, &mut f);
    s.write_all(&f).expect("send");
    let mut a = [0u8; 28];
    s.read_exact(&mut a).expect("answered");
    // Status 0 (ok) and the value of the last slice, not Busy.
    assert_eq!(a[12..16], [0, 0, 0, 0], "{a:?}");
    assert_eq!(i32::from_le_bytes([a[20], a[21], a[22], a[23]]), 42);
}

#[test]
fn a_session_serves_a_long_request_in_slices_and_stops_with_its_connection() {
    endless_request_stops_with_its_connection(SESSION);
}

#[test]
fn a_request_longer_than_the_idle_timeout_is_answered() {
    let (addr, _stop) = serve();
    let mut s = connect(addr);
    // 40 slices of 20 ms: 800 ms, beyond the idle timeout of 300 ms.
    read_of(&mut s, 40, 0, 4);
    let mut a = [0u8; 28];
    s.read_exact(&mut a).expect("answered");
    assert_eq!(a[12..16], [0, 0, 0, 0], "status {a:?}");
    assert_eq!(i32::from_le_bytes([a[20], a[21], a[22], a[23]]), 42);
}

#[test]
fn a_request_stopped_by_shutdown_is_answered_stopped_with_its_op_and_id() {
    let cfg = ServerConfig {
        idle_timeout: Duration::from_secs(3600),
        ..local()
    };
    let (addr, stop) = serve_with(cfg, Endless);
    let mut s = connect(addr);
    let mut f = BytesMut::new();
    let req = Request::Read(
        ObjectAddress::new(7, 0, 0, UNTIL_STOP as u16),
        ValueType::I32,
    );
    encode_request(77, &req, &mut f);
    s.write_all(&f).expect("send");
    while SLICES[UNTIL_STOP].load(Ordering::Relaxed) == 0 {
        std::thread::sleep(Duration::from_millis(5));
    }
    drop(stop);
    let (id, op, status) = common::read_head(&mut s);
    assert_eq!((id, op), (77, 0x01));
    assert_eq!(status, uoi::wire::ProtocolError::Stopped.code());
    assert!(common::is_closed(&mut s));
}
