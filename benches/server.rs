//! Loopback benchmark of the object server, with a tokio-modbus
//! TCP server answering read-holding-registers as a reference in the same
//! run and with the same client pattern: a raw client that writes request
//! frames and reads fixed-size answers. A third server is the floor: on
//! the same loopback path and runtime, it answers every request frame of
//! our protocol with a fixed answer frame and does nothing else, so ours
//! ÷ floor says how much of the kernel's best our server keeps, and
//! tokio-modbus ÷ floor the same of the reference.
//!
//! Run: `cargo bench --bench server` (results go to docs/performance.md).
//! The server and the clients each run on one current-thread runtime, so
//! the two cores of the machine are split evenly between them. Every
//! figure is measured in several rounds and the tables give the median and
//! the range. Inside a round the servers take turns (sequential: blocks of
//! 1,000 round trips; pipelined: ten turns), so a change of the machine's
//! state during the run (another job, the VM's idle polling) falls on all
//! of them alike; so do the same-thread runs, all servers on the client's
//! thread.
//! Beside the rates, the CPU time the server's thread spent per request
//! (from `/proc/self/task/TID/schedstat`, in nanoseconds): it shows the
//! cost of the server's own path, and moves far less than the rates when
//! the machine is shared.

// Test and bench helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]
#![allow(missing_docs)]

use std::future::Future;
use std::net::SocketAddr;
use std::sync::Arc;
use std::time::{Duration, Instant};

use emulator::EmulatorService;
use tc_objects::TcObject;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};
use tokio_modbus::prelude::{ExceptionCode, Request as MbRequest, Response as MbResponse};
use tokio_modbus::server::tcp::{accept_tcp_connection, Server as MbServer};
use uoi::tcp::{Server, ServerConfig};
use uoi::wire::{encode_answer, encode_request, Answer, Op, Request, PREFIX_LEN};
use uoi::{Value, ValueType};

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
        &Request::Read(TcObject::TcPlane.address(), ValueType::I32),
        &mut request,
    );
    Proto {
        name: "addipos UOI",
        request: request.to_vec(),
        answer_len: 28,
        check: |a| a[12..16] == [0, 0, 0, 0] && a[20] == 17,
    }
}

/// The floor speaks our protocol: the same request, the same answer.
fn floor() -> Proto {
    Proto {
        name: "floor (fixed answer)",
        ..ours()
    }
}

/// The answer the floor sends to every request frame: what our server
/// answers to [`ours`]'s read (PLANE, 17), encoded once.
fn floor_answer() -> Vec<u8> {
    let mut out = bytes::BytesMut::new();
    encode_answer(1, Op::Read.code(), &Answer::Value(Value::I32(17)), &mut out);
    out.to_vec()
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

/// The thread id of the calling thread.
fn this_thread() -> u32 {
    let link = std::fs::read_link("/proc/thread-self").expect("/proc/thread-self");
    let tid = link.file_name().and_then(|n| n.to_str()).expect("tid");
    tid.parse().expect("tid")
}

/// CPU time thread `tid` of this process has had so far, in ns.
fn cpu_ns(tid: u32) -> u64 {
    let stat =
        std::fs::read_to_string(format!("/proc/self/task/{tid}/schedstat")).expect("schedstat");
    let on_cpu = stat.split_whitespace().next().expect("first field");
    on_cpu.parse().expect("ns")
}

/// A server running on its own thread: where it listens, and that
/// thread's id.
#[derive(Clone, Copy)]
struct Running {
    addr: SocketAddr,
    tid: u32,
}

/// Starts a server on its own one-thread runtime.
fn start<F, Fut>(make: F) -> Running
where
    F: FnOnce(std::sync::mpsc::Sender<SocketAddr>) -> Fut + Send + 'static,
    Fut: Future<Output = ()>,
{
    let (tx, rx) = std::sync::mpsc::channel();
    let (tid_tx, tid_rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        tid_tx.send(this_thread()).expect("tid");
        let rt = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .expect("runtime");
        rt.block_on(make(tx));
    });
    let addr = rx.recv_timeout(Duration::from_secs(10)).expect("server up");
    let tid = tid_rx.recv().expect("tid");
    Running { addr, tid }
}

async fn serve_ours(tx: std::sync::mpsc::Sender<SocketAddr>) {
    let cfg = ServerConfig {
        listen: "127.0.0.1:0".parse().expect("addr"),
        // Every bench connection comes from 127.0.0.1.
        max_connections_per_peer: 256,
        ..ServerConfig::default()
    };
    let server = Server::bind(
        cfg,
        EmulatorService::new([0.0; 8], tc_module::CycleTime::DEFAULT),
    )
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

/// The floor: accepts on loopback and serves each connection by
/// [`floor_connection`], one task each, on the same kind of runtime.
async fn serve_floor(tx: std::sync::mpsc::Sender<SocketAddr>) {
    let listener = TcpListener::bind("127.0.0.1:0").await.expect("bind");
    tx.send(listener.local_addr().expect("addr")).expect("send");
    let answer: Arc<[u8]> = floor_answer().into();
    while let Ok((stream, _)) = listener.accept().await {
        stream.set_nodelay(true).expect("nodelay");
        tokio::spawn(floor_connection(stream, Arc::clone(&answer)));
    }
}

/// Reads what the socket has, answers every whole frame in it (found by
/// its length prefix) with `answer`, and writes the answers in one go:
/// no decoding, no handler, no lock.
async fn floor_connection(mut s: TcpStream, answer: Arc<[u8]>) {
    let mut buf = bytes::BytesMut::with_capacity(64 * 1024);
    let mut out = Vec::with_capacity(64 * 1024);
    loop {
        match s.read_buf(&mut buf).await {
            Ok(0) | Err(_) => return,
            Ok(_) => {}
        }
        while buf.len() >= PREFIX_LEN {
            let prefix: [u8; PREFIX_LEN] = buf[..PREFIX_LEN].try_into().expect("prefix");
            let whole = PREFIX_LEN + u32::from_le_bytes(prefix) as usize;
            if buf.len() < whole {
                break;
            }
            let _ = buf.split_to(whole);
            out.extend_from_slice(&answer);
        }
        if !out.is_empty() {
            if s.write_all(&out).await.is_err() {
                return;
            }
            out.clear();
        }
    }
}

/// Sequential round trips with the servers and the client on one thread:
/// no cross-core wake-up, so this shows the cost of the software itself.
/// `keys`: "ours" and/or "modbus", served side by side and taking turns
/// as in [`sequential`]; (req/s, p50 µs, p99 µs) each.
fn sequential_same_thread(keys: &[&str], n: usize) -> Vec<(f64, f64, f64)> {
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("runtime");
    rt.block_on(async {
        let mut servers = Vec::new();
        for key in keys {
            let (tx, rx) = std::sync::mpsc::channel();
            let proto = match *key {
                "modbus" => {
                    tokio::spawn(serve_modbus(tx));
                    modbus()
                }
                "floor" => {
                    tokio::spawn(serve_floor(tx));
                    floor()
                }
                _ => {
                    tokio::spawn(serve_ours(tx));
                    ours()
                }
            };
            let addr = loop {
                if let Ok(a) = rx.try_recv() {
                    break a;
                }
                tokio::task::yield_now().await;
            };
            let tid = this_thread();
            servers.push((proto, Running { addr, tid }));
        }
        let servers: Vec<(&Proto, Running)> = servers.iter().map(|(p, r)| (p, *r)).collect();
        let got = sequential(&servers, n).await;
        got.into_iter()
            .map(|((r, p50, p99, _), _)| (r, p50, p99))
            .collect()
    })
}

fn start_ours() -> Running {
    start(serve_ours)
}

fn start_modbus() -> Running {
    start(serve_modbus)
}

fn start_floor() -> Running {
    start(serve_floor)
}

async fn connect(addr: SocketAddr) -> TcpStream {
    let s = TcpStream::connect(addr).await.expect("connect");
    s.set_nodelay(true).expect("nodelay");
    s
}

/// Round trips per block of the sequential test: the servers take turns
/// block by block, so a change of the machine's state (another job, the
/// VM's idle polling) falls on all of them alike.
const SEQ_BLOCK: usize = 1_000;

/// Turns each server gets in the pipelined test (per connection count).
const PIPE_TURNS: usize = 10;

/// One connection of the sequential test: write a request, read the answer.
struct SeqClient {
    p: Proto,
    s: TcpStream,
    ans: Vec<u8>,
    lat: Vec<Duration>,
    busy: Duration,
    /// The server's thread, and the CPU time it had during the runs.
    server: u32,
    cpu_ns: u64,
    /// The rate of each block, in req/s, in the order they ran.
    blocks: Vec<f64>,
}

impl SeqClient {
    /// Connects and warms up with 2,000 round trips.
    async fn open(p: &Proto, to: Running) -> Self {
        let mut c = Self {
            p: p.clone(),
            s: connect(to.addr).await,
            ans: vec![0u8; p.answer_len],
            lat: Vec::new(),
            busy: Duration::ZERO,
            server: to.tid,
            cpu_ns: 0,
            blocks: Vec::new(),
        };
        c.run(2_000).await;
        assert!(
            (c.p.check)(&c.ans),
            "{}: wrong answer {:?}",
            c.p.name,
            c.ans
        );
        c.lat.clear();
        c.busy = Duration::ZERO;
        c.cpu_ns = 0;
        c.blocks.clear();
        c
    }

    async fn run(&mut self, n: usize) {
        let cpu0 = cpu_ns(self.server);
        let t0 = Instant::now();
        for _ in 0..n {
            let t = Instant::now();
            self.s.write_all(&self.p.request).await.expect("write");
            self.s.read_exact(&mut self.ans).await.expect("read");
            self.lat.push(t.elapsed());
        }
        let took = t0.elapsed();
        self.busy += took;
        self.blocks.push(n as f64 / took.as_secs_f64());
        self.cpu_ns += cpu_ns(self.server) - cpu0;
    }

    /// (req/s, p50 µs, p99 µs, server CPU ns per request), and the rate
    /// of each block.
    fn figures(mut self) -> SeqFigures {
        let n = self.lat.len();
        self.lat.sort();
        let us = |d: Duration| d.as_secs_f64() * 1e6;
        (
            (
                n as f64 / self.busy.as_secs_f64(),
                us(self.lat[n / 2]),
                us(self.lat[n * 99 / 100]),
                self.cpu_ns as f64 / n as f64,
            ),
            self.blocks,
        )
    }
}

/// One server's sequential figures: (req/s, p50 µs, p99 µs, server CPU
/// ns per request), and the rate of each block.
type SeqFigures = ((f64, f64, f64, f64), Vec<f64>);

/// `n` sequential round trips on one connection to each server, in
/// blocks of [`SEQ_BLOCK`] taking turns: [`SeqFigures`] each.
async fn sequential(servers: &[(&Proto, Running)], n: usize) -> Vec<SeqFigures> {
    let mut clients = Vec::new();
    for (p, to) in servers {
        clients.push(SeqClient::open(p, *to).await);
    }
    let blocks = n.div_ceil(SEQ_BLOCK);
    for b in 0..blocks {
        let len = SEQ_BLOCK.min(n - b * SEQ_BLOCK);
        for i in rotated(clients.len(), b) {
            clients[i].run(len).await;
        }
    }
    clients.into_iter().map(SeqClient::figures).collect()
}

/// The connections of the pipelined test to one server: each sends
/// batches of requests in one write and then reads the batch's answers.
struct PipeClient {
    p: Proto,
    burst: Arc<Vec<u8>>,
    batch: usize,
    streams: Vec<TcpStream>,
    requests: usize,
    busy: Duration,
    /// The server's thread, and the CPU time it had during the runs.
    server: u32,
    cpu_ns: u64,
}

impl PipeClient {
    async fn open(p: &Proto, to: Running, conns: usize, batch: usize) -> Self {
        let burst = p.request.repeat(batch);
        let mut streams = Vec::new();
        for _ in 0..conns {
            streams.push(connect(to.addr).await);
        }
        Self {
            p: p.clone(),
            burst: Arc::new(burst),
            batch,
            streams,
            requests: 0,
            busy: Duration::ZERO,
            server: to.tid,
            cpu_ns: 0,
        }
    }

    /// `batches` batches on every connection at once.
    async fn run(&mut self, batches: usize) {
        let cpu0 = cpu_ns(self.server);
        let t0 = Instant::now();
        let mut tasks = tokio::task::JoinSet::new();
        for mut s in self.streams.drain(..) {
            let (p, burst, batch) = (self.p.clone(), Arc::clone(&self.burst), self.batch);
            tasks.spawn(async move {
                let mut ans = vec![0u8; p.answer_len * batch];
                for _ in 0..batches {
                    s.write_all(&burst).await.expect("write");
                    s.read_exact(&mut ans).await.expect("read");
                    assert!((p.check)(&ans[..p.answer_len]), "{}: wrong answer", p.name);
                }
                s
            });
        }
        while let Some(s) = tasks.join_next().await {
            self.streams.push(s.expect("client"));
        }
        self.busy += t0.elapsed();
        self.cpu_ns += cpu_ns(self.server) - cpu0;
        self.requests += self.streams.len() * batches * self.batch;
    }
}

/// About `total` requests to each server over `conns` connections, in
/// batches of `batch`, the servers taking [`PIPE_TURNS`] turns: req/s and
/// server CPU ns per request, each.
async fn pipelined(
    servers: &[(&Proto, Running)],
    conns: usize,
    total: usize,
    batch: usize,
) -> Vec<(f64, f64)> {
    let mut clients = Vec::new();
    for (p, to) in servers {
        clients.push(PipeClient::open(p, *to, conns, batch).await);
    }
    let batches = (total / conns / batch).max(1);
    let per_turn = batches.div_ceil(PIPE_TURNS);
    let mut done = 0;
    let mut turn = 0;
    while done < batches {
        let now = per_turn.min(batches - done);
        for i in rotated(clients.len(), turn) {
            clients[i].run(now).await;
        }
        done += now;
        turn += 1;
    }
    clients
        .iter()
        .map(|c| {
            let n = c.requests as f64;
            (n / c.busy.as_secs_f64(), c.cpu_ns as f64 / n)
        })
        .collect()
}

/// What to run, from the command line (after `--`): `--quick` (short
/// runs), `--rounds N` (default 5, quick 3), `--only seq|pipe|same` (one
/// section), `--target ours|modbus|floor` (one server; for profiling), `--n N`
/// (sequential round trips per round) and `--total N` (pipelined requests
/// per connection count and round).
struct Args {
    quick: bool,
    n: Option<usize>,
    total: Option<usize>,
    rounds: usize,
    only: Option<String>,
    target: Option<String>,
}

impl Args {
    fn parse() -> Self {
        let argv: Vec<String> = std::env::args().collect();
        let value = |flag: &str| {
            argv.iter()
                .position(|a| a == flag)
                .and_then(|i| argv.get(i + 1).cloned())
        };
        let number = |flag: &str| value(flag).map(|n| n.parse().expect("a number"));
        let quick = argv.iter().any(|a| a == "--quick");
        Self {
            quick,
            n: number("--n"),
            total: number("--total"),
            rounds: number("--rounds").unwrap_or(if quick { 3 } else { 5 }),
            only: value("--only"),
            target: value("--target"),
        }
    }

    fn section(&self, name: &str) -> bool {
        self.only.as_deref().is_none_or(|o| o == name)
    }

    fn target(&self, name: &str) -> bool {
        self.target.as_deref().is_none_or(|t| t == name)
    }
}

/// One server under test: protocol, short name, where it runs.
struct Target {
    proto: Proto,
    key: &'static str,
    running: Running,
}

/// Samples of one figure over the rounds.
#[derive(Default)]
struct Samples(Vec<f64>);

impl Samples {
    fn median(&self) -> f64 {
        let mut v = self.0.clone();
        v.sort_by(f64::total_cmp);
        match v.len() {
            0 => f64::NAN,
            n if n % 2 == 1 => v[n / 2],
            n => (v[n / 2 - 1] + v[n / 2]) / 2.0,
        }
    }

    fn min(&self) -> f64 {
        self.0.iter().copied().fold(f64::INFINITY, f64::min)
    }

    fn max(&self) -> f64 {
        self.0.iter().copied().fold(f64::NEG_INFINITY, f64::max)
    }

    /// `median (min–max)`, rates in k or M.
    fn cell(&self, rate: bool) -> String {
        let f = |x: f64| {
            if !rate {
                format!("{x:.1}")
            } else if x >= 1e6 {
                format!("{:.2}M", x / 1e6)
            } else {
                format!("{:.1}k", x / 1e3)
            }
        };
        if self.0.is_empty() {
            return "–".into();
        }
        format!("{} ({}–{})", f(self.median()), f(self.min()), f(self.max()))
    }
}

/// The figures of one target across threads: sequential rate, p50, p99
/// and server CPU per request; pipelined rate at 1/8/64 connections, then
/// server CPU per request at each.
#[derive(Default)]
struct Figures([Samples; 10]);

/// Where the figures of one target are.
const SEQ_RATE: usize = 0;
const SEQ_CPU: usize = 3;
const PIPE_RATE: usize = 4;
const PIPE_CPU: usize = 7;

const PIPE_CONNS: [usize; 3] = [1, 8, 64];

fn loadavg() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_default()
}

/// Round `r` visits the targets starting at `r % n`: no server is always
/// measured first or last.
fn rotated(n: usize, r: usize) -> impl Iterator<Item = usize> {
    (0..n).map(move |k| (k + r) % n)
}

/// The ratio a/b of the same round, over the rounds: median (min–max).
fn ratio(a: &Samples, b: &Samples) -> String {
    let r = Samples(a.0.iter().zip(&b.0).map(|(a, b)| a / b).collect());
    if r.0.is_empty() {
        return "–".into();
    }
    format!("{:.3} ({:.3}–{:.3})", r.median(), r.min(), r.max())
}

/// Starts the servers `args` asks for (each on its own thread).
fn start_targets(args: &Args) -> Vec<Target> {
    TARGETS
        .into_iter()
        .filter(|key| args.target(key))
        .map(|key| {
            let (proto, running) = match key {
                "ours" => (ours(), start_ours()),
                "floor" => (floor(), start_floor()),
                _ => (modbus(), start_modbus()),
            };
            Target {
                proto,
                key,
                running,
            }
        })
        .collect()
}

/// The servers of a full run, by key.
const TARGETS: [&str; 3] = ["ours", "modbus", "floor"];

/// The figures of every round.
struct Results {
    /// Per target: across threads.
    figs: Vec<Figures>,
    /// Per same-thread key: rate, p50, p99.
    same: Vec<[Samples; 3]>,
    same_keys: Vec<&'static str>,
    /// Per target: the rate of every sequential block of every round,
    /// block k of one target run right beside block k of the others.
    seq_blocks: Vec<Vec<f64>>,
}

fn push(into: &mut [Samples], got: &[f64]) {
    for (k, x) in got.iter().enumerate() {
        into[k].0.push(*x);
    }
}

fn run_rounds(args: &Args, targets: &[Target], seq_n: usize, total: usize) -> Results {
    let client = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("runtime");
    let servers: Vec<(&Proto, Running)> = targets.iter().map(|t| (&t.proto, t.running)).collect();
    let same_keys: Vec<&'static str> = TARGETS.into_iter().filter(|k| args.target(k)).collect();
    let mut res = Results {
        figs: targets.iter().map(|_| Figures::default()).collect(),
        same: same_keys.iter().map(|_| Default::default()).collect(),
        same_keys,
        seq_blocks: targets.iter().map(|_| Vec::new()).collect(),
    };
    for round in 0..args.rounds {
        if args.section("seq") {
            let got = client.block_on(sequential(&servers, seq_n));
            for (i, ((rate, p50, p99, cpu), blocks)) in got.into_iter().enumerate() {
                push(&mut res.figs[i].0[SEQ_RATE..], &[rate, p50, p99, cpu]);
                res.seq_blocks[i].extend(blocks);
            }
        }
        if args.section("pipe") {
            for (c, conns) in PIPE_CONNS.into_iter().enumerate() {
                let got = client.block_on(pipelined(&servers, conns, total, 128));
                for (i, (rate, cpu)) in got.into_iter().enumerate() {
                    res.figs[i].0[PIPE_RATE + c].0.push(rate);
                    res.figs[i].0[PIPE_CPU + c].0.push(cpu);
                }
            }
        }
        if args.section("same") {
            let got = sequential_same_thread(&res.same_keys, seq_n);
            for (i, (rate, p50, p99)) in got.into_iter().enumerate() {
                push(&mut res.same[i], &[rate, p50, p99]);
            }
        }
        eprintln!("round {} done, load average {}", round + 1, loadavg());
    }
    res
}

fn print_tables(targets: &[Target], res: &Results) {
    println!("| server | sequential req/s | p50 µs | p99 µs | pipelined 1 conn req/s | 8 conns | 64 conns |");
    println!("|---|---|---|---|---|---|---|");
    for (t, f) in targets.iter().zip(&res.figs) {
        let s = &f.0;
        println!(
            "| {} | {} | {} | {} | {} | {} | {} |",
            t.proto.name,
            s[SEQ_RATE].cell(true),
            s[SEQ_RATE + 1].cell(false),
            s[SEQ_RATE + 2].cell(false),
            s[PIPE_RATE].cell(true),
            s[PIPE_RATE + 1].cell(true),
            s[PIPE_RATE + 2].cell(true)
        );
    }
    println!();
    println!("| server thread's CPU, ns per request | sequential | pipelined 1 conn | 8 conns | 64 conns |");
    println!("|---|---|---|---|---|");
    for (t, f) in targets.iter().zip(&res.figs) {
        let s = &f.0;
        println!(
            "| {} | {} | {} | {} | {} |",
            t.proto.name,
            s[SEQ_CPU].cell(false),
            s[PIPE_CPU].cell(false),
            s[PIPE_CPU + 1].cell(false),
            s[PIPE_CPU + 2].cell(false)
        );
    }
    println!();
    println!("| server, client on the same thread | sequential req/s | p50 µs | p99 µs |");
    println!("|---|---|---|---|");
    for (key, s) in res.same_keys.iter().zip(&res.same) {
        let name = match *key {
            "modbus" => modbus().name,
            "floor" => floor().name,
            _ => ours().name,
        };
        println!(
            "| {name} | {} | {} | {} |",
            s[0].cell(true),
            s[1].cell(false),
            s[2].cell(false)
        );
    }
}

/// Ours / tokio-modbus, round by round (the servers take turns inside a
/// round, so a round's ratio compares like with like); for the CPU per
/// request, tokio-modbus / ours (above 1: ours takes less).
fn print_ratios(targets: &[Target], res: &Results) {
    let (Some(o), Some(m)) = (
        targets.iter().position(|t| t.key == "ours"),
        targets.iter().position(|t| t.key == "modbus"),
    ) else {
        return;
    };
    let same = match (
        res.same_keys.iter().position(|k| *k == "ours"),
        res.same_keys.iter().position(|k| *k == "modbus"),
    ) {
        (Some(i), Some(j)) => ratio(&res.same[i][0], &res.same[j][0]),
        _ => "–".into(),
    };
    let (l, r) = (&res.figs[o].0, &res.figs[m].0);
    println!();
    println!("| per round | sequential | pipelined 1 conn | 8 conns | 64 conns | same thread |");
    println!("|---|---|---|---|---|---|");
    println!(
        "| ours / tokio-modbus, req/s | {} | {} | {} | {} | {same} |",
        ratio(&l[SEQ_RATE], &r[SEQ_RATE]),
        ratio(&l[PIPE_RATE], &r[PIPE_RATE]),
        ratio(&l[PIPE_RATE + 1], &r[PIPE_RATE + 1]),
        ratio(&l[PIPE_RATE + 2], &r[PIPE_RATE + 2]),
    );
    println!(
        "| tokio-modbus / ours, server CPU per request | {} | {} | {} | {} | – |",
        ratio(&r[SEQ_CPU], &l[SEQ_CPU]),
        ratio(&r[PIPE_CPU], &l[PIPE_CPU]),
        ratio(&r[PIPE_CPU + 1], &l[PIPE_CPU + 1]),
        ratio(&r[PIPE_CPU + 2], &l[PIPE_CPU + 2]),
    );
}

/// The ratio a/b of blocks run side by side (block k of one server
/// against block k of the other, a few milliseconds apart): median and
/// quartiles, and the count of pairs. Pairing by block keeps the
/// machine's changes of state (the VM's slow wake-ups that turn a 5 µs
/// round trip into 70 µs for a while) on both sides of each ratio.
fn paired(a: &[f64], b: &[f64]) -> String {
    let mut r: Vec<f64> = a.iter().zip(b).map(|(x, y)| x / y).collect();
    if r.is_empty() {
        return "–".into();
    }
    r.sort_by(f64::total_cmp);
    let q = |f: f64| r[((r.len() - 1) as f64 * f).round() as usize];
    format!(
        "{:.3} (quartiles {:.3}–{:.3}, {} pairs)",
        q(0.5),
        q(0.25),
        q(0.75),
        r.len()
    )
}

/// Each server ÷ the floor, round by round, in req/s: how much of the
/// loopback path's best each keeps (1 is the floor itself).
fn print_floor_ratios(targets: &[Target], res: &Results) {
    let Some(f) = targets.iter().position(|t| t.key == "floor") else {
        return;
    };
    let same_floor = res.same_keys.iter().position(|k| *k == "floor");
    let floor = &res.figs[f].0;
    println!();
    println!("| ÷ floor, req/s per round | sequential | pipelined 1 conn | 8 conns | 64 conns | same thread |");
    println!("|---|---|---|---|---|---|");
    for (t, figs) in targets.iter().zip(&res.figs) {
        if t.key == "floor" {
            continue;
        }
        let same = match (res.same_keys.iter().position(|k| *k == t.key), same_floor) {
            (Some(i), Some(j)) => ratio(&res.same[i][0], &res.same[j][0]),
            _ => "–".into(),
        };
        let l = &figs.0;
        println!(
            "| {} ÷ floor | {} | {} | {} | {} | {same} |",
            t.proto.name,
            ratio(&l[SEQ_RATE], &floor[SEQ_RATE]),
            ratio(&l[PIPE_RATE], &floor[PIPE_RATE]),
            ratio(&l[PIPE_RATE + 1], &floor[PIPE_RATE + 1]),
            ratio(&l[PIPE_RATE + 2], &floor[PIPE_RATE + 2]),
        );
    }
    println!();
    println!(
        "| ÷ floor, sequential, blocks of {SEQ_BLOCK} side by side | median of the block ratios |"
    );
    println!("|---|---|");
    for (i, t) in targets.iter().enumerate() {
        if t.key != "floor" {
            println!(
                "| {} ÷ floor | {} |",
                t.proto.name,
                paired(&res.seq_blocks[i], &res.seq_blocks[f])
            );
        }
    }
}

fn main() {
    let args = Args::parse();
    let (seq_n, total) = if args.quick {
        (5_000, 100_000)
    } else {
        (50_000, 1_000_000)
    };
    let seq_n = args.n.unwrap_or(seq_n);
    let total = args.total.unwrap_or(total);
    println!(
        "rounds: {}, sequential {} round trips, pipelined {} requests; load average at start: {}",
        args.rounds,
        seq_n,
        total,
        loadavg()
    );
    let targets = start_targets(&args);
    let res = run_rounds(&args, &targets, seq_n, total);
    println!("load average at end: {}", loadavg());
    println!();
    println!("Median (min–max) over {} rounds.", args.rounds);
    println!();
    print_tables(&targets, &res);
    print_ratios(&targets, &res);
    print_floor_ratios(&targets, &res);
}
