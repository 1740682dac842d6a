//! Loopback benchmark of the object server (issue 4), with a tokio-modbus
//! TCP server answering read-holding-registers as a reference in the same
//! run and with the same client pattern: a raw client that writes request
//! frames and reads fixed-size answers.
//!
//! Run: `cargo bench --bench server` (results go to docs/performance.md).
//! The server and the clients each run on one current-thread runtime, so
//! the two cores of the machine are split evenly between them.

// Test and bench helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]
#![allow(missing_docs)]

use std::future::Future;
use std::net::SocketAddr;
use std::time::{Duration, Instant};

use addipos::service::EmulatorService;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};
use tokio_modbus::prelude::{ExceptionCode, Request as MbRequest, Response as MbResponse};
use tokio_modbus::server::tcp::{accept_tcp_connection, Server as MbServer};
use uoi::tcp::{Core, Server, ServerConfig};
use uoi::wire::{encode_request, Request};
use uoi::{ObjectAddress, ValueType};

/// One protocol as the raw client sees it.
#[derive(Clone)]
struct Proto {
    name: &'static str,
    request: Vec<u8>,
    answer_len: usize,
    /// Checks one answer.
    check: fn(&[u8]) -> bool,
}

fn ours() -> Proto {
    let mut request = bytes::BytesMut::new();
    encode_request(
        1,
        &Request::Read(ObjectAddress::new(1300, 0, 3, 0), ValueType::I32),
        &mut request,
    );
    Proto {
        name: "addipos UOI",
        request: request.to_vec(),
        answer_len: 28,
        check: |a| a[12..16] == [0, 0, 0, 0] && a[20] == 17,
    }
}

fn modbus() -> Proto {
    // MBAP: transaction 1, protocol 0, length 6, unit 1; PDU: fc 3, address 0, count 1.
    Proto {
        name: "tokio-modbus",
        request: vec![0, 1, 0, 0, 0, 6, 1, 3, 0, 0, 0, 1],
        answer_len: 11,
        check: |a| a[7] == 3 && a[8] == 2 && a[10] == 17,
    }
}

#[derive(Clone)]
struct HoldingRegisters;

impl tokio_modbus::server::Service for HoldingRegisters {
    type Request = MbRequest<'static>;
    type Response = MbResponse;
    type Exception = ExceptionCode;
    type Future = std::future::Ready<Result<MbResponse, ExceptionCode>>;

    fn call(&self, req: Self::Request) -> Self::Future {
        std::future::ready(match req {
            MbRequest::ReadHoldingRegisters(_, n) => {
                Ok(MbResponse::ReadHoldingRegisters(vec![17; usize::from(n)]))
            }
            _ => Err(ExceptionCode::IllegalFunction),
        })
    }
}

/// Starts a server on its own one-thread runtime; returns its address.
fn start<F, Fut>(make: F) -> SocketAddr
where
    F: FnOnce(std::sync::mpsc::Sender<SocketAddr>) -> Fut + Send + 'static,
    Fut: Future<Output = ()>,
{
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let rt = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .expect("runtime");
        rt.block_on(make(tx));
    });
    rx.recv_timeout(Duration::from_secs(10)).expect("server up")
}

async fn serve_ours(core: Core, tx: std::sync::mpsc::Sender<SocketAddr>) {
    let cfg = ServerConfig {
        listen: "127.0.0.1:0".parse().expect("addr"),
        core,
        ..ServerConfig::default()
    };
    let server = Server::bind(cfg, EmulatorService::new([0.0; 8], 1e-3))
        .await
        .expect("bind");
    tx.send(server.local_addr().expect("addr")).expect("send");
    let _ = server.run(std::future::pending()).await;
}

async fn serve_modbus(tx: std::sync::mpsc::Sender<SocketAddr>) {
    let listener = TcpListener::bind("127.0.0.1:0").await.expect("bind");
    tx.send(listener.local_addr().expect("addr")).expect("send");
    let server = MbServer::new(listener);
    let new_service = |_addr| Ok(Some(HoldingRegisters));
    // Same socket setting as our server: no Nagle delay on answers.
    let on_connected = |stream: TcpStream, addr| async move {
        stream.set_nodelay(true)?;
        accept_tcp_connection(stream, addr, new_service)
    };
    let _ = server.serve(&on_connected, |_e| {}).await;
}

/// Sequential round trips with server and client on one thread: no
/// cross-core wake-up, so this shows the cost of the software itself.
fn sequential_same_thread(p: &Proto, modbus: bool, n: usize) -> (f64, f64, f64) {
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("runtime");
    rt.block_on(async {
        let (tx, rx) = std::sync::mpsc::channel();
        if modbus {
            tokio::spawn(serve_modbus(tx));
        } else {
            tokio::spawn(serve_ours(Core::Lock, tx));
        }
        let addr = loop {
            if let Ok(a) = rx.try_recv() {
                break a;
            }
            tokio::task::yield_now().await;
        };
        sequential(p, addr, n).await
    })
}

fn start_ours(core: Core) -> SocketAddr {
    start(move |tx| serve_ours(core, tx))
}

fn start_modbus() -> SocketAddr {
    start(serve_modbus)
}

async fn connect(addr: SocketAddr) -> TcpStream {
    let s = TcpStream::connect(addr).await.expect("connect");
    s.set_nodelay(true).expect("nodelay");
    s
}

/// Sequential round trips on one connection: (req/s, p50 µs, p99 µs).
async fn sequential(p: &Proto, addr: SocketAddr, n: usize) -> (f64, f64, f64) {
    let mut s = connect(addr).await;
    let mut ans = vec![0u8; p.answer_len];
    for _ in 0..2_000 {
        s.write_all(&p.request).await.expect("write");
        s.read_exact(&mut ans).await.expect("read");
    }
    assert!((p.check)(&ans), "{}: wrong answer {ans:?}", p.name);
    let mut lat = Vec::with_capacity(n);
    let t0 = Instant::now();
    for _ in 0..n {
        let t = Instant::now();
        s.write_all(&p.request).await.expect("write");
        s.read_exact(&mut ans).await.expect("read");
        lat.push(t.elapsed());
    }
    let total = t0.elapsed();
    lat.sort();
    let us = |d: Duration| d.as_secs_f64() * 1e6;
    (
        n as f64 / total.as_secs_f64(),
        us(lat[n / 2]),
        us(lat[n * 99 / 100]),
    )
}

/// `conns` connections, each sending `per_conn` requests in batches of
/// `batch` before reading the batch's answers: total req/s.
async fn pipelined(
    p: &Proto,
    addr: SocketAddr,
    conns: usize,
    per_conn: usize,
    batch: usize,
) -> f64 {
    let burst: Vec<u8> = p
        .request
        .iter()
        .copied()
        .cycle()
        .take(p.request.len() * batch)
        .collect();
    let mut streams = Vec::new();
    for _ in 0..conns {
        streams.push(connect(addr).await);
    }
    let t0 = Instant::now();
    let mut tasks = tokio::task::JoinSet::new();
    for mut s in streams {
        let burst = burst.clone();
        let p = p.clone();
        tasks.spawn(async move {
            let mut ans = vec![0u8; p.answer_len * batch];
            for _ in 0..per_conn / batch {
                s.write_all(&burst).await.expect("write");
                s.read_exact(&mut ans).await.expect("read");
                assert!((p.check)(&ans[..p.answer_len]), "{}: wrong answer", p.name);
            }
        });
    }
    while let Some(r) = tasks.join_next().await {
        r.expect("client");
    }
    (conns * (per_conn / batch) * batch) as f64 / t0.elapsed().as_secs_f64()
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let (seq_n, total) = if quick {
        (5_000, 100_000)
    } else {
        (50_000, 1_000_000)
    };
    let targets = [
        (ours(), start_ours(Core::Lock), "lock"),
        (ours(), start_ours(Core::Owner), "owner task"),
        (modbus(), start_modbus(), "reference"),
    ];
    let client = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("runtime");
    println!("| server | core | sequential req/s | p50 µs | p99 µs | pipelined 1 conn req/s | 8 conns | 64 conns |");
    println!("|---|---|---|---|---|---|---|---|");
    for (p, addr, core) in &targets {
        let (rate, p50, p99) = client.block_on(sequential(p, *addr, seq_n));
        let mut pipes = Vec::new();
        for conns in [1usize, 8, 64] {
            pipes.push(client.block_on(pipelined(p, *addr, conns, total / conns, 128)));
        }
        println!(
            "| {} | {} | {:.0} | {:.1} | {:.1} | {:.0} | {:.0} | {:.0} |",
            p.name, core, rate, p50, p99, pipes[0], pipes[1], pipes[2]
        );
    }
    println!();
    println!("| server, client on the same thread | sequential req/s | p50 µs | p99 µs |");
    println!("|---|---|---|---|");
    for (p, modbus) in [(ours(), false), (modbus(), true)] {
        let (rate, p50, p99) = sequential_same_thread(&p, modbus, seq_n);
        println!("| {} | {:.0} | {:.1} | {:.1} |", p.name, rate, p50, p99);
    }
}
