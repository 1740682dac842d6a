//! A request that never ends (a huge `EXEC` with a per-cycle model, in the
//! emulator) is served slice by slice, by the shared handler or by a
//! connection's session: other clients are served meanwhile, and
//! once its connection is closed (here by the idle timeout) no further
//! slice of it runs.

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
static SLICES: [AtomicU64; 2] = [AtomicU64::new(0), AtomicU64::new(0)];

/// The slot of the endless request the shared handler serves.
const SHARED: usize = 0;
/// The slot of the endless request a session serves.
const SESSION: usize = 1;

/// A READ of index 0, sub 0 never ends in the shared handler: every slice
/// hands back the rest. Any other READ is answered with its index.
struct Endless;

impl Handler for Endless {
    type Session = EndlessSession;

    fn open_session(&mut self) -> EndlessSession {
        EndlessSession
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

/// Takes READs of index 0, sub 1 and 3: those of sub 1 never end; those
/// of sub 3 take as many more slices as their device number, then answer
/// 42.
struct EndlessSession;

impl Session for EndlessSession {
    fn takes(&self, req: &Request) -> bool {
        matches!(req, Request::Read(a, _) if a.index == 0 && (a.sub == 1 || a.sub == 3))
    }

    fn serve(&mut self, req: Request) -> Slice {
        match req {
            Request::Read(a, ty) if a.sub == 3 => match a.device {
                0 => Slice::Done(Answer::Value(Value::I32(42))),
                n => Slice::More(Request::Read(ObjectAddress::new(7, n - 1, 0, 3), ty)),
            },
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
    let mut f = BytesMut::new();
    let req = Request::Read(ObjectAddress::new(7, 0, index, sub), ValueType::I32);
    encode_request(1, &req, &mut f);
    s.write_all(&f).expect("send");
}

/// The endless request of `slot` runs while another client is answered,
/// and stops for good once its connection is closed.
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
    // The idle timeout closes the hog (no complete request for 300 ms).
    let mut rest = Vec::new();
    let _ = hog.read_to_end(&mut rest);
    // Then its request stops: the count of slices comes to rest (it
    // would grow forever if the rest of the request kept running).
    let stopped = (0..50).any(|_| {
        let before = SLICES[slot].load(Ordering::Relaxed);
        std::thread::sleep(Duration::from_millis(100));
        SLICES[slot].load(Ordering::Relaxed) == before
    });
    assert!(stopped, "slices still run after the connection closed");
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
