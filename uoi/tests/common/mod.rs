//! Helpers the server's integration tests share: a trivial handler, a
//! server on its own thread, clients with a hang guard, READ frames and
//! the reading of answers.

// Each test file uses only some of them.
#![allow(dead_code)]

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::Duration;

use bytes::BytesMut;
use uoi::tcp::{Handler, Server, ServerConfig, Slice};
use uoi::wire::{encode_request, Answer, Request};
use uoi::{ObjectAddress, Value, ValueType};

/// Answers a READ with the object's index.
pub struct Index;

impl Handler for Index {
    type Session = ();
    type Rest = Request;

    fn open_session(&mut self) {}

    fn serve(&mut self, req: Request) -> Slice {
        Slice::Done(index_of(&req))
    }
}

/// The object's index for a READ, `Ok` for anything else.
pub fn index_of(req: &Request) -> Answer {
    match req {
        Request::Read(a, _) => Answer::Value(Value::I32(i32::from(a.index))),
        _ => Answer::Ok,
    }
}

/// A server with the [`Index`] handler on its own thread; stopped when
/// the sender is dropped.
pub fn serve(cfg: ServerConfig) -> (SocketAddr, tokio::sync::oneshot::Sender<()>) {
    serve_with(cfg, Index)
}

/// A server with `handler` on its own thread; stopped when the sender is
/// dropped.
pub fn serve_with<H: Handler>(
    cfg: ServerConfig,
    handler: H,
) -> (SocketAddr, tokio::sync::oneshot::Sender<()>) {
    let (addr_tx, addr_rx) = std::sync::mpsc::channel();
    let (stop_tx, stop_rx) = tokio::sync::oneshot::channel::<()>();
    std::thread::spawn(move || {
        let rt = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .expect("runtime");
        rt.block_on(async move {
            let server = Server::bind(cfg, handler).await.expect("bind");
            addr_tx
                .send(server.local_addr().expect("addr"))
                .expect("send");
            let _ = server
                .run(async {
                    let _ = stop_rx.await;
                })
                .await;
        });
    });
    (addr_rx.recv().expect("server started"), stop_tx)
}

/// The default settings, listening on a free loopback port.
pub fn local() -> ServerConfig {
    ServerConfig {
        listen: "127.0.0.1:0".parse().expect("addr"),
        ..ServerConfig::default()
    }
}

/// `s` with a read timeout of 60 s.
pub fn guarded(s: TcpStream) -> TcpStream {
    // Only a guard against a hung test, far above any real wait.
    s.set_read_timeout(Some(Duration::from_secs(60)))
        .expect("timeout");
    s
}

/// A guarded connection to `addr`.
pub fn connect(addr: SocketAddr) -> TcpStream {
    guarded(TcpStream::connect(addr).expect("connect"))
}

/// A guarded connection to `addr` from the local address `from` (any of
/// 127.0.0.0/8 on Linux): another peer address on the same machine.
pub fn connect_from(from: [u8; 4], addr: SocketAddr) -> TcpStream {
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("runtime");
    let s = rt.block_on(async {
        let sock = tokio::net::TcpSocket::new_v4().expect("socket");
        sock.bind(SocketAddr::from((from, 0))).expect("bind");
        sock.connect(addr).await.expect("connect")
    });
    let s = s.into_std().expect("std");
    s.set_nonblocking(false).expect("blocking");
    guarded(s)
}

/// A READ of object (7, 0, `index`, 0) with the request id `index`.
pub fn read_frame(index: u16) -> Vec<u8> {
    let mut f = BytesMut::new();
    let req = Request::Read(ObjectAddress::new(7, 0, index, 0), ValueType::I32);
    encode_request(u32::from(index), &req, &mut f);
    f.to_vec()
}

/// Reads one READ answer: (id, value).
pub fn read_answer(s: &mut TcpStream) -> (u32, i32) {
    let mut a = [0u8; 28];
    s.read_exact(&mut a).expect("answer");
    let id = u32::from_le_bytes([a[8], a[9], a[10], a[11]]);
    let v = i32::from_le_bytes([a[20], a[21], a[22], a[23]]);
    (id, v)
}

/// Reads one answer frame: (id, op, status).
pub fn read_head(s: &mut TcpStream) -> (u32, u8, u32) {
    let mut pre = [0u8; 4];
    s.read_exact(&mut pre).expect("prefix");
    let mut body = vec![0u8; u32::from_le_bytes(pre) as usize];
    s.read_exact(&mut body).expect("body");
    let word = |at: usize| u32::from_le_bytes([body[at], body[at + 1], body[at + 2], body[at + 3]]);
    (word(4), body[3], word(8))
}

/// Reads one answer frame: (id, op, status); `None` if the connection
/// ends first.
pub fn try_read_head(s: &mut TcpStream) -> Option<(u32, u8, u32)> {
    let mut pre = [0u8; 4];
    s.read_exact(&mut pre).ok()?;
    let mut body = vec![0u8; u32::from_le_bytes(pre) as usize];
    s.read_exact(&mut body).ok()?;
    let word = |at: usize| u32::from_le_bytes([body[at], body[at + 1], body[at + 2], body[at + 3]]);
    Some((word(4), body[3], word(8)))
}

/// Waits for the server to close `s`: end of stream or a reset, not the
/// guard timeout.
pub fn is_closed(s: &mut TcpStream) -> bool {
    let mut b = [0u8; 1];
    match s.read(&mut b) {
        Ok(n) => n == 0,
        Err(e) => !matches!(
            e.kind(),
            std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
        ),
    }
}

/// Pipelines requests and never reads an answer, until the server's
/// writes to it block (its socket buffers are full).
pub fn flood_until_blocked(s: &mut TcpStream) {
    s.set_write_timeout(Some(Duration::from_millis(200)))
        .expect("timeout");
    let burst: Vec<u8> = (0..4096).flat_map(|i| read_frame(i as u16)).collect();
    while s.write_all(&burst).is_ok() {}
}
