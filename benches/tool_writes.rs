//! Durable tool writes: acknowledged tool writes per second
//! with 1, 8 and 64 pipelining clients, the disk's fdatasync latency
//! measured in the same run, and reads and non-tool writes with
//! persistence on and off (they must not wait for the disk).
//!
//! Run: `cargo bench --bench tool_writes` (results go to
//! docs/performance.md); `-- --quick` for a short run, `--rounds N`,
//! `--extra-sync-ms X` to simulate a slower disk (X ms slept after each
//! journal fdatasync).
//!
//! The server is the one `serve --data-dir` builds (emulator service, tool
//! store on the file system, journal writer with group commit, durable
//! tool writes), in-process on its own one-thread runtime, with its data
//! directory in a temporary folder. The only difference: the store's
//! storage is [`FsStorage`] wrapped in [`Counting`], which counts the
//! journal syncs and the tool files written (compactions), so the bench
//! can give the mean batch size (acknowledged writes per fdatasync).
//!
//! Every round: the disk's latency of appending ~40 bytes and fdatasync
//! (a file in the same folder), then tool writes with 1, 8 and 64 clients,
//! then reads and non-tool writes against a server with persistence and
//! one without (taking turns), then reads alone and reads beside 8 tool
//! writers.

// Test and bench helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]
#![allow(missing_docs)]

use std::io::{self, Write as _};
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use bytes::BytesMut;
use emulator::tools::durable::Durable;
use emulator::EmulatorService;
use tc_objects::{TcObject, TC_BUS};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;
use tokio_util::codec::Decoder;
use tool_store::Writer;
use tool_store::{FsStorage, Storage, Strictness, ToolStore};
use uoi::tcp::{Server, ServerConfig};
use uoi::wire::{decode_answer, encode_request, Answer, ClientCodec, Op, Request};
use uoi::{Value, ValueType};

/// [`FsStorage`] that counts journal syncs and tool files written.
#[derive(Debug)]
struct Counting {
    fs: FsStorage,
    counts: Arc<Counts>,
}

#[derive(Debug, Default)]
struct Counts {
    syncs: AtomicU64,
    files: AtomicU64,
    /// Every journal sync's duration, ms (taken by the bench).
    sync_ms: Mutex<Vec<f64>>,
    /// Added to every journal sync, to see how a slower disk bounds the
    /// figures (`--extra-sync-ms`).
    extra: Duration,
}

impl Counts {
    fn get(&self) -> (u64, u64) {
        (
            self.syncs.load(Ordering::Relaxed),
            self.files.load(Ordering::Relaxed),
        )
    }

    fn take_sync_ms(&self) -> Vec<f64> {
        std::mem::take(&mut *self.sync_ms.lock().expect("sync times"))
    }
}

impl Storage for Counting {
    fn read_file(&mut self, name: &str) -> io::Result<Option<Vec<u8>>> {
        self.fs.read_file(name)
    }
    fn write_file_atomic(&mut self, name: &str, bytes: &[u8]) -> io::Result<()> {
        self.counts.files.fetch_add(1, Ordering::Relaxed);
        self.fs.write_file_atomic(name, bytes)
    }
    fn read_journal(&mut self) -> io::Result<Vec<u8>> {
        self.fs.read_journal()
    }
    fn append_journal(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.fs.append_journal(bytes)
    }
    fn sync_journal(&mut self) -> io::Result<()> {
        self.counts.syncs.fetch_add(1, Ordering::Relaxed);
        let t = Instant::now();
        let r = self.fs.sync_journal();
        if !self.counts.extra.is_zero() {
            std::thread::sleep(self.counts.extra);
        }
        let took = ms(&t.elapsed());
        self.counts.sync_ms.lock().expect("sync times").push(took);
        r
    }
    fn truncate_journal(&mut self, len: u64) -> io::Result<()> {
        self.fs.truncate_journal(len)
    }
    fn journal_in_place(&mut self) -> io::Result<bool> {
        self.fs.journal_in_place()
    }
    fn available_space(&mut self) -> io::Result<Option<u64>> {
        self.fs.available_space()
    }
    fn remove_temporaries(&mut self) -> io::Result<Vec<String>> {
        self.fs.remove_temporaries()
    }
}

/// Starts a server on its own one-thread runtime, with durable tool data
/// in `tools` when given; returns its address.
fn start_server(tools: Option<(PathBuf, Arc<Counts>)>) -> SocketAddr {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let rt = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .expect("runtime");
        rt.block_on(async move {
            let mut service = EmulatorService::new([0.0; 8], tc_module::CycleTime::DEFAULT);
            if let Some((dir, counts)) = tools {
                let storage = Counting {
                    fs: FsStorage::new(dir),
                    counts,
                };
                let (store, _) = ToolStore::open(storage, Strictness::Strict).expect("store");
                let writer = Writer::start(store).expect("writer");
                service.set_tools(Box::new(Durable::new(writer)));
            }
            let cfg = ServerConfig {
                listen: "127.0.0.1:0".parse().expect("addr"),
                max_connections_per_peer: 256,
                ..ServerConfig::default()
            };
            let server = Server::bind(cfg, service).await.expect("bind");
            tx.send(server.local_addr().expect("addr")).expect("send");
            let _ = server.run(std::future::pending()).await;
        });
    });
    rx.recv_timeout(Duration::from_secs(10)).expect("server up")
}

/// What a client sends.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Kind {
    /// RADIUS (1300/1/g/6) or, for clients 33..64, WkzLen (1300/1/g/12)
    /// of the client's own group.
    Tool,
    /// TransitionMode 1300/2/g/1 of the client's group, 0 and 1 in turn.
    NonTool,
    /// 1300/0/3/0 (i).
    Read,
}

/// The `k`-th request of client `c`.
fn request(kind: Kind, c: usize, k: u64) -> Request {
    let group = (c % 32) as u16 + 1;
    match kind {
        Kind::Tool => {
            let field = if c < 32 {
                TcObject::Radius
            } else {
                TcObject::WkzLen
            };
            let v = 1.0 + (k % 100_000) as f64 * 1e-3;
            Request::Write(field.of(group), Value::F64(v))
        }
        Kind::NonTool => Request::Write(
            TcObject::TransitionMode.of(group),
            Value::I32((k & 1) as i32),
        ),
        Kind::Read => Request::Read(TcObject::TcPlane.address(), ValueType::I32),
    }
}

/// A per-group object as the table of results names it: `1300/2/g/1`.
fn every_group(key: TcObject) -> String {
    let row = key.row();
    format!("{}/{}/g/{}", TC_BUS, row.device, row.sub.start())
}

fn op(kind: Kind) -> Op {
    if kind == Kind::Read {
        Op::Read
    } else {
        Op::Write
    }
}

/// Checks one answer: `Ok` for a write, 17 for the read.
fn check(kind: Kind, body: bytes::Bytes) {
    let (_, ans) = decode_answer(body, op(kind)).expect("an answer frame");
    let good = match kind {
        Kind::Read => ans == Answer::Value(Value::I32(17)),
        _ => ans == Answer::Ok,
    };
    assert!(good, "{kind:?}: answer {ans:?}");
}

async fn connect(addr: SocketAddr) -> TcpStream {
    let s = TcpStream::connect(addr).await.expect("connect");
    s.set_nodelay(true).expect("nodelay");
    s
}

/// One client: sends bursts of `burst` requests in one write and reads
/// and checks their answers, until `until`. Returns the answers counted
/// and, per burst, the time to its last answer.
async fn client(
    mut s: TcpStream,
    kind: Kind,
    c: usize,
    burst: usize,
    until: Instant,
) -> (TcpStream, u64, Vec<Duration>) {
    let mut out = BytesMut::new();
    let mut inb = BytesMut::with_capacity(64 * 1024);
    let (mut k, mut acked, mut lat) = (0u64, 0u64, Vec::new());
    while Instant::now() < until {
        out.clear();
        for _ in 0..burst {
            k += 1;
            encode_request(k as u32, &request(kind, c, k), &mut out);
        }
        let t = Instant::now();
        s.write_all(&out).await.expect("write");
        let mut got = 0;
        while got < burst {
            match ClientCodec.decode(&mut inb).expect("frame") {
                Some(body) => {
                    check(kind, body);
                    got += 1;
                }
                None => {
                    let n = s.read_buf(&mut inb).await.expect("read");
                    assert!(n > 0, "server closed");
                }
            }
        }
        lat.push(t.elapsed());
        acked += burst as u64;
    }
    (s, acked, lat)
}

/// What one load phase gave.
struct Load {
    rate: f64,
    /// Per client kind: burst round-trip times.
    lat: Vec<(Kind, Vec<Duration>)>,
    elapsed: Duration,
    acked: u64,
}

/// `clients` (kind, burst) clients at once for `dur`; the rate counts the
/// answers of the first kind only.
async fn load(addr: SocketAddr, clients: &[(Kind, usize)], dur: Duration) -> Load {
    let mut streams = Vec::new();
    for _ in clients {
        streams.push(connect(addr).await);
    }
    let t0 = Instant::now();
    let until = t0 + dur;
    let mut tasks = tokio::task::JoinSet::new();
    for (c, (s, &(kind, burst))) in streams.into_iter().zip(clients).enumerate() {
        tasks.spawn(async move {
            let (_s, n, lat) = client(s, kind, c, burst, until).await;
            (kind, n, lat)
        });
    }
    let first = clients[0].0;
    let (mut acked, mut lat) = (0, Vec::new());
    while let Some(r) = tasks.join_next().await {
        let (kind, n, l) = r.expect("client");
        if kind == first {
            acked += n;
        }
        lat.push((kind, l));
    }
    let elapsed = t0.elapsed();
    Load {
        rate: acked as f64 / elapsed.as_secs_f64(),
        lat,
        elapsed,
        acked,
    }
}

/// `n` times: append a ~40-byte line to a file in `dir` and fdatasync it,
/// as the journal does. The latencies.
fn fsync_probe(dir: &Path, n: usize) -> Vec<Duration> {
    let path = dir.join("fsync-probe.txt");
    let mut f = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(&path)
        .expect("probe file");
    let line = b"1 wz[12].radius 12345.6789 *0123abcd\n";
    (0..n)
        .map(|_| {
            let t = Instant::now();
            f.write_all(line).expect("append");
            f.sync_data().expect("fdatasync");
            t.elapsed()
        })
        .collect()
}

/// Samples of one figure over the rounds.
#[derive(Default, Clone)]
struct Samples(Vec<f64>);

impl Samples {
    fn sorted(&self) -> Vec<f64> {
        let mut v = self.0.clone();
        v.sort_by(f64::total_cmp);
        v
    }

    fn median(&self) -> f64 {
        let v = self.sorted();
        match v.len() {
            0 => f64::NAN,
            n if n % 2 == 1 => v[n / 2],
            n => (v[n / 2 - 1] + v[n / 2]) / 2.0,
        }
    }

    fn pct(&self, p: usize) -> f64 {
        let v = self.sorted();
        v.get((v.len() * p / 100).min(v.len().saturating_sub(1)))
            .copied()
            .unwrap_or(f64::NAN)
    }

    fn min(&self) -> f64 {
        self.0.iter().copied().fold(f64::INFINITY, f64::min)
    }

    fn max(&self) -> f64 {
        self.0.iter().copied().fold(f64::NEG_INFINITY, f64::max)
    }

    /// `median (min–max)` with `digits` decimals.
    fn cell(&self, digits: usize) -> String {
        if self.0.is_empty() {
            return "–".into();
        }
        format!(
            "{:.d$} ({:.d$}–{:.d$})",
            self.median(),
            self.min(),
            self.max(),
            d = digits
        )
    }
}

fn ms(d: &Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn us(d: &Duration) -> f64 {
    d.as_secs_f64() * 1e6
}

fn loadavg() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_default()
}

/// What to run: `--quick` (short phases, 2 rounds), `--rounds N`,
/// `--extra-sync-ms X` (a slower disk: X ms added to each journal sync).
struct Args {
    extra_sync: Duration,
    rounds: usize,
    /// Length of one tool-write phase.
    write_phase: Duration,
    /// Length of one read / non-tool write phase.
    fast_phase: Duration,
    /// fdatasync probes before each tool-write phase.
    probes: usize,
}

impl Args {
    fn parse() -> Self {
        let argv: Vec<String> = std::env::args().collect();
        let quick = argv.iter().any(|a| a == "--quick");
        let rounds = argv
            .iter()
            .position(|a| a == "--rounds")
            .and_then(|i| argv.get(i + 1))
            .map(|r| r.parse().expect("--rounds N"))
            .unwrap_or(if quick { 2 } else { 5 });
        let (w, f) = if quick { (400, 200) } else { (1500, 600) };
        let extra_ms: f64 = argv
            .iter()
            .position(|a| a == "--extra-sync-ms")
            .and_then(|i| argv.get(i + 1))
            .map_or(0.0, |x| x.parse().expect("--extra-sync-ms X"));
        Self {
            extra_sync: Duration::from_secs_f64(extra_ms / 1e3),
            rounds,
            write_phase: Duration::from_millis(w),
            fast_phase: Duration::from_millis(f),
            probes: if quick { 20 } else { 40 },
        }
    }
}

const WRITERS: [usize; 3] = [1, 8, 64];

/// Requests per burst: tool writes are answered one at a time per
/// connection (each waits for its sync), so a short burst suffices.
const TOOL_BURST: usize = 16;
/// As the server bench.
const FAST_BURST: usize = 128;

/// Everything measured, per round.
#[derive(Default)]
struct Results {
    /// Probe fdatasync latency, ms, every probe.
    fsync: Samples,
    /// Per writer count: writes/s, mean batch, ms per batch, the writer's
    /// fdatasync median, its share of the time, the limit (clients / the
    /// writer's fdatasync median), writes/s without persistence, the
    /// probe's median just before.
    tool: [[Samples; 8]; 3],
    /// The writer's fdatasync times, ms, every one.
    writer_sync: Samples,
    compactions: u64,
    /// Reads, non-tool writes: [persist on, off], req/s.
    fast: [[Samples; 2]; 2],
    /// Per-round ratio on/off: reads, non-tool writes.
    fast_ratio: [Samples; 2],
    /// Sequential read round trip µs: alone, beside 8 tool writers.
    read_alone: Samples,
    read_beside: Samples,
    /// Tool writes/s with the reader beside.
    beside_rate: Samples,
}

/// Tool writes with `n` clients: writes/s, mean batch, ms per batch,
/// the writer's fdatasync median (ms), the share of the time the writer
/// spent in fdatasync; and every fdatasync time of the phase.
async fn tool_phase(
    addr: SocketAddr,
    counts: &Counts,
    n: usize,
    dur: Duration,
) -> ([f64; 5], Vec<f64>) {
    let clients = vec![(Kind::Tool, TOOL_BURST); n];
    let (s0, _) = counts.get();
    counts.take_sync_ms();
    let l = load(addr, &clients, dur).await;
    let syncs = (counts.get().0 - s0).max(1) as f64;
    let sync_ms = counts.take_sync_ms();
    let elapsed = l.elapsed.as_secs_f64() * 1e3;
    let figures = [
        l.rate,
        l.acked as f64 / syncs,
        elapsed / syncs,
        Samples(sync_ms.clone()).median(),
        sync_ms.iter().sum::<f64>() / elapsed,
    ];
    (figures, sync_ms)
}

/// Reads with one sequential client (burst 1), alone or beside 8 tool
/// writers: (read round trip µs, every one; tool writes/s).
async fn read_probe(addr: SocketAddr, writers: usize, dur: Duration) -> (Vec<f64>, f64) {
    let mut clients = vec![(Kind::Tool, TOOL_BURST); writers];
    clients.push((Kind::Read, 1));
    let l = load(addr, &clients, dur).await;
    let reads = l
        .lat
        .iter()
        .filter(|(k, _)| *k == Kind::Read)
        .flat_map(|(_, v)| v.iter().map(us))
        .collect();
    let rate = if writers > 0 { l.rate } else { 0.0 };
    (reads, rate)
}

struct Setup {
    dir: PathBuf,
    counts: Arc<Counts>,
    on: SocketAddr,
    off: SocketAddr,
}

fn round(rt: &tokio::runtime::Runtime, s: &Setup, args: &Args, r: usize, res: &mut Results) {
    for (i, n) in WRITERS.into_iter().enumerate() {
        let probe: Vec<f64> = fsync_probe(&s.dir, args.probes).iter().map(ms).collect();
        let t = &mut res.tool[i];
        t[7].0.push(Samples(probe.clone()).median());
        res.fsync.0.extend(probe);
        let (got, sync_ms) = rt.block_on(tool_phase(s.on, &s.counts, n, args.write_phase));
        for (k, x) in got.into_iter().enumerate() {
            t[k].0.push(x);
        }
        t[5].0.push(n as f64 / got[3] * 1e3);
        res.writer_sync.0.extend(sync_ms);
        let clients = vec![(Kind::Tool, TOOL_BURST); n];
        t[6].0
            .push(rt.block_on(load(s.off, &clients, args.fast_phase)).rate);
    }
    for (f, kind) in [Kind::Read, Kind::NonTool].into_iter().enumerate() {
        let clients = vec![(kind, FAST_BURST); 8];
        let mut rates = [0.0; 2];
        for side in [r % 2, 1 - r % 2] {
            let addr = if side == 0 { s.on } else { s.off };
            rates[side] = rt.block_on(load(addr, &clients, args.fast_phase)).rate;
            res.fast[f][side].0.push(rates[side]);
        }
        res.fast_ratio[f].0.push(rates[0] / rates[1]);
    }
    let (alone, _) = rt.block_on(read_probe(s.on, 0, args.fast_phase));
    res.read_alone.0.extend(alone);
    let (beside, rate) = rt.block_on(read_probe(s.on, 8, args.write_phase));
    res.read_beside.0.extend(beside);
    res.beside_rate.0.push(rate);
    eprintln!("round {} done, load average {}", r + 1, loadavg());
}

fn print_results(res: &Results, files: u64) {
    for (name, f) in [
        ("probe: append ~40 bytes + fdatasync", &res.fsync),
        ("the journal writer's fdatasync", &res.writer_sync),
    ] {
        println!(
            "{name}, {} times: median {:.3} ms, p90 {:.3} ms, p99 {:.3} ms, min {:.3} ms, max {:.3} ms",
            f.0.len(),
            f.median(),
            f.pct(90),
            f.pct(99),
            f.min(),
            f.max(),
        );
    }
    println!("tool files written (compactions × groups): {files}");
    println!();
    println!("| clients | acknowledged durable writes/s | mean batch (writes per fdatasync) | ms per batch | writer's fdatasync median, ms | writer's time in fdatasync | limit: clients / writer's fdatasync median, writes/s | probe fdatasync median just before, ms | without persistence, writes/s |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for (i, n) in WRITERS.into_iter().enumerate() {
        let t = &res.tool[i];
        let share = Samples(t[4].0.iter().map(|x| x * 100.0).collect());
        println!(
            "| {n} | {} | {} | {} | {} | {} % | {} | {} | {} |",
            t[0].cell(0),
            t[1].cell(1),
            t[2].cell(3),
            t[3].cell(3),
            share.cell(0),
            t[5].cell(0),
            t[7].cell(3),
            t[6].cell(0),
        );
    }
    println!();
    println!("| 8 clients, pipelined 128 | persistence on, M req/s | off, M req/s | on / off, per round |");
    println!("|---|---|---|---|");
    let names = [
        format!("reads {}", TcObject::TcPlane.address()),
        format!("non-tool writes {}", every_group(TcObject::TransitionMode)),
    ];
    for (i, name) in names.into_iter().enumerate() {
        let k = |x: &Samples| Samples(x.0.iter().map(|v| v / 1e6).collect()).cell(2);
        println!(
            "| {name} | {} | {} | {} |",
            k(&res.fast[i][0]),
            k(&res.fast[i][1]),
            res.fast_ratio[i].cell(3)
        );
    }
    println!();
    println!("| one sequential reader, persistence on | read p50 µs | p99 µs | max µs | tool writes/s beside |");
    println!("|---|---|---|---|---|");
    for (name, s, rate) in [
        ("alone", &res.read_alone, None),
        (
            "beside 8 tool writers",
            &res.read_beside,
            Some(&res.beside_rate),
        ),
    ] {
        println!(
            "| {name} | {:.1} | {:.1} | {:.0} | {} |",
            s.median(),
            s.pct(99),
            s.max(),
            rate.map_or("–".into(), |r| r.cell(0))
        );
    }
}

fn main() {
    let args = Args::parse();
    let dir = std::env::temp_dir().join(format!("addipos-tool-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    println!(
        "rounds: {}, extra per journal sync {:?}, data directory {}, load average at start: {}",
        args.rounds,
        args.extra_sync,
        dir.display(),
        loadavg()
    );
    let counts = Arc::new(Counts {
        extra: args.extra_sync,
        ..Counts::default()
    });
    let setup = Setup {
        on: start_server(Some((dir.join("tools"), Arc::clone(&counts)))),
        off: start_server(None),
        dir: dir.clone(),
        counts,
    };
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("runtime");
    let mut res = Results::default();
    for r in 0..args.rounds {
        round(&rt, &setup, &args, r, &mut res);
    }
    res.compactions = setup.counts.get().1;
    println!("load average at end: {}", loadavg());
    println!("Median (min–max) over {} rounds.", args.rounds);
    println!();
    print_results(&res, res.compactions);
    let _ = std::fs::remove_dir_all(&dir);
}
