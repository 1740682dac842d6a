//! The server's connection handling with a trivial handler: answers in
//! order, batches only over complete requests, idle and shutdown closes.

// Test and bench helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::Duration;

use bytes::BytesMut;
use uoi::tcp::{Handler, Server, ServerConfig};
use uoi::wire::{encode_request, Answer, Request};
use uoi::{ObjectAddress, Value, ValueType};

/// Answers a READ with the object's index.
struct Index;

impl Handler for Index {
    type Session = ();

    fn handle(&mut self, req: Request) -> Answer {
        match req {
            Request::Read(a, _) => Answer::Value(Value::I32(i32::from(a.index))),
            _ => Answer::Ok,
        }
    }
}

/// A server on its own thread; stopped when the sender is dropped.
fn serve(cfg: ServerConfig) -> (SocketAddr, tokio::sync::oneshot::Sender<()>) {
    let (addr_tx, addr_rx) = std::sync::mpsc::channel();
    let (stop_tx, stop_rx) = tokio::sync::oneshot::channel::<()>();
    std::thread::spawn(move || {
        let rt = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .expect("runtime");
        rt.block_on(async move {
            let server = Server::bind(cfg, Index).await.expect("bind");
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
    let addr = addr_rx.recv().expect("server started");
    (addr, stop_tx)
}

fn local() -> ServerConfig {
    ServerConfig {
        listen: "127.0.0.1:0".parse().expect("addr"),
        ..ServerConfig::default()
    }
}

fn read_frame(index: u16) -> Vec<u8> {
    let mut f = BytesMut::new();
    let req = Request::Read(ObjectAddress::new(7, 0, index, 0), ValueType::I32);
    encode_request(u32::from(index), &req, &mut f);
    f.to_vec()
}

/// Reads one READ answer: (id, value).
fn read_answer(s: &mut TcpStream) -> (u32, i32) {
    let mut a = [0u8; 28];
    s.read_exact(&mut a).expect("answer");
    let id = u32::from_le_bytes([a[8], a[9], a[10], a[11]]);
    let v = i32::from_le_bytes([a[20], a[21], a[22], a[23]]);
    (id, v)
}

fn connect(addr: SocketAddr) -> TcpStream {
    let s = TcpStream::connect(addr).expect("connect");
    // Only a guard against a hung test, far above any real wait.
    s.set_read_timeout(Some(Duration::from_secs(60)))
        .expect("timeout");
    s
}

/// Waits for the server to close `s`: end of stream or a reset, not the
/// guard timeout.
fn is_closed(s: &mut TcpStream) -> bool {
    let mut b = [0u8; 1];
    match s.read(&mut b) {
        Ok(n) => n == 0,
        Err(e) => !matches!(
            e.kind(),
            std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
        ),
    }
}

#[test]
fn pipelined_requests_are_answered_in_order() {
    let (addr, _stop) = serve(local());
    let mut s = connect(addr);
    let burst: Vec<u8> = (1..=200).flat_map(read_frame).collect();
    s.write_all(&burst).expect("write");
    for k in 1..=200 {
        assert_eq!(read_answer(&mut s), (k, k as i32));
    }
}

/// The answer to a complete request is not held back for a request of
/// which only a part has arrived.
#[test]
fn a_partial_next_request_does_not_hold_back_the_answer() {
    let (addr, _stop) = serve(local());
    let mut s = connect(addr);
    let second = read_frame(2);
    let mut first = read_frame(1);
    first.extend_from_slice(&second[..10]);
    s.write_all(&first).expect("write");
    assert_eq!(read_answer(&mut s), (1, 1));
    s.write_all(&second[10..]).expect("write");
    assert_eq!(read_answer(&mut s), (2, 2));
}

#[test]
fn a_silent_connection_is_closed_an_active_one_answered() {
    let (addr, _stop) = serve(ServerConfig {
        idle_timeout: Duration::from_millis(200),
        ..local()
    });
    let mut silent = connect(addr);
    // Blocks until the server closes the connection.
    assert!(is_closed(&mut silent));
    let mut s = connect(addr);
    s.write_all(&read_frame(3)).expect("write");
    assert_eq!(read_answer(&mut s), (3, 3));
}

#[test]
fn shutdown_closes_a_waiting_connection() {
    let (addr, stop) = serve(local());
    let mut s = connect(addr);
    s.write_all(&read_frame(4)).expect("write");
    assert_eq!(read_answer(&mut s), (4, 4));
    drop(stop);
    assert!(is_closed(&mut s));
}

#[test]
fn a_client_that_never_reads_is_closed_when_idle_and_frees_its_place() {
    let (addr, _stop) = serve(ServerConfig {
        idle_timeout: Duration::from_millis(300),
        max_connections: 1,
        ..local()
    });
    // Pipeline requests and never read an answer: the server's writes
    // block once the socket buffers are full.
    let mut hog = connect(addr);
    hog.set_write_timeout(Some(Duration::from_millis(200)))
        .expect("timeout");
    let burst: Vec<u8> = (0..4096).flat_map(|i| read_frame(i as u16)).collect();
    while hog.write_all(&burst).is_ok() {}
    // The blocked connection is closed by the idle timeout: a new client
    // gets in (a guard of 60 s, not a timed assertion).
    let deadline = std::time::Instant::now() + Duration::from_secs(60);
    loop {
        let mut c = connect(addr);
        c.write_all(&read_frame(5)).expect("write");
        let mut head = [0u8; 16];
        c.read_exact(&mut head).expect("an answer");
        let status = u32::from_le_bytes([head[12], head[13], head[14], head[15]]);
        if status == 0 {
            break;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "the blocked client kept its place"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}
