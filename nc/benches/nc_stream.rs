//! Throughput and memory of a streamed NC run: a generated
//! program of 1,000,000 lines and arcs with TRC on goes through the two
//! passes of a run (check, then parse + interpretation) into the
//! correction of `tc-module`; the same requests, built once beforehand, are
//! fed to a fresh module directly. Both sides drain the spooler the same
//! way (no executor cycles). Then the peak RSS of a streamed run of
//! 100,000 and of 1,000,000 blocks, each in a process of its own.
//!
//! `cargo bench -p nc --bench nc_stream` (about two minutes; with
//! `NC_STREAM_QUICK=1` only the RSS, the breakdown and the alternating
//! ratio; `NC_STREAM_PROFILE=<part>` runs one part 5 times for a profiler,
//! see [`profile`]); figures go to docs/performance.md.

#![allow(missing_docs, clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::hint::black_box;
use std::io::{BufReader, Read};
use std::time::{Duration, Instant};

use criterion::{BatchSize, Criterion, Throughput};
use nc::run::{run_reader, At, Controller, Report};
use nc::{check_program, Blocks};
use tc_module::TcModule;
use tc_request::{Reply, Request};
use uoi::ObjectBus;

/// Motion blocks of the benchmark's program.
const N: usize = 1_000_000;

/// Environment variable that makes the bench binary a child measuring the
/// peak RSS of one streamed run of that many blocks.
const RSS_CHILD: &str = "NC_STREAM_RSS_BLOCKS";

/// The text of a program with `n` motion blocks, made as it is read: a
/// header that sets up the tool (D1, radius 1) and the plane, TRC left
/// (G41) with the first motion, then lines and half circles (G2 and G3
/// with I J) advancing along X, TRC off (G40) with the last motion, M30.
/// Block `k` is `N<k+1>` and ends at X = 10 k; both numbers are kept as
/// decimal digits and counted up in place, so making the text costs about
/// what reading a file does.
struct ProgramText {
    n: usize,
    next: usize,
    buf: Vec<u8>,
    at: usize,
    /// Digits of `next` and of `next + 1`.
    k: Vec<u8>,
    k1: Vec<u8>,
}

/// Adds one to a number held as decimal digits.
fn count_up(digits: &mut Vec<u8>) {
    for d in digits.iter_mut().rev() {
        if *d == b'9' {
            *d = b'0';
        } else {
            *d += 1;
            return;
        }
    }
    digits.insert(0, b'1');
}

impl ProgramText {
    fn new(n: usize) -> Self {
        ProgramText {
            n,
            next: 0,
            buf: Vec::with_capacity(64 * 1024),
            at: 0,
            k: b"0".to_vec(),
            k1: b"1".to_vec(),
        }
    }

    /// The next line of the program (0 = header) appended to `out`; false
    /// past the end.
    fn line(&mut self, out: &mut Vec<u8>) -> bool {
        let k = self.next;
        match k {
            0 => out.extend_from_slice(b"%NCBENCH\nN1 G17 G90 G26\n#set ToolParam(1; 4; 1)#\n"),
            1 => out.extend_from_slice(b"N2 D1 G41 G1 X10 Y0 F6000\n"),
            k if k > self.n => return false,
            k => {
                let (head, tail): (&[u8], &[u8]) = match k % 4 {
                    _ if k == self.n => (b" G40 G1 X", b"0 Y-10\nM30\n"),
                    1 | 3 => (b" G1 X", b"0 Y0\n"),
                    2 => (b" G2 X", b"0 Y0 I5 J0\n"),
                    _ => (b" G3 X", b"0.5 Y0 I5.25 J0\n"),
                };
                out.push(b'N');
                out.extend_from_slice(&self.k1);
                out.extend_from_slice(head);
                out.extend_from_slice(&self.k);
                out.extend_from_slice(tail);
            }
        }
        self.next += 1;
        count_up(&mut self.k);
        count_up(&mut self.k1);
        true
    }
}

impl Read for ProgramText {
    fn read(&mut self, dst: &mut [u8]) -> std::io::Result<usize> {
        if self.at == self.buf.len() {
            let mut buf = std::mem::take(&mut self.buf);
            buf.clear();
            self.at = 0;
            while buf.len() < 60 * 1024 && self.line(&mut buf) {}
            self.buf = buf;
        }
        let k = dst.len().min(self.buf.len() - self.at);
        dst[..k].copy_from_slice(&self.buf[self.at..self.at + k]);
        self.at += k;
        Ok(k)
    }
}

/// Carries out a request on the module; the spooled elements are drained
/// (all but the last, which the correction starts the next profile from)
/// every 1024 motions and at `EXEC`, without executor cycles.
fn feed(tc: &mut TcModule, req: &Request, motions: &mut u64) -> Reply {
    match req {
        Request::Motion(m) => {
            let r = tc.command(m).into();
            *motions += 1;
            if motions.is_multiple_of(1024) {
                drain(tc);
            }
            r
        }
        Request::Write(a, v) => tc.write_checked(*a, *v).into(),
        Request::Read(a, t) => tc.read_checked(*a, *t).into(),
        Request::Exec(_) => {
            drain(tc);
            Reply::Ok
        }
        Request::Pos => Reply::Pos(tc.position()),
        _ => Reply::Ok,
    }
}

fn drain(tc: &mut TcModule) {
    let sp = tc.spooler_mut();
    while sp.len() > 1 {
        sp.pop_front();
    }
}

/// The module as the interpreter's controller.
struct Engine {
    tc: TcModule,
    motions: u64,
    /// Every request, when recording.
    record: Option<Vec<Request>>,
}

impl Controller for Engine {
    fn call(&mut self, req: &Request, _at: At) -> Reply {
        if let Some(r) = &mut self.record {
            r.push(req.clone());
        }
        feed(&mut self.tc, req, &mut self.motions)
    }
}

/// One streamed run of `n` blocks as `addipos run` does it: the check
/// pass, then the run pass into the module.
fn nc_run(n: usize, engine: &mut Engine) -> Report {
    let errors = check_program(BufReader::new(ProgramText::new(n)));
    assert!(errors.is_empty(), "{errors:?}");
    run_pass(n, engine)
}

/// The run pass alone.
fn run_pass(n: usize, engine: &mut Engine) -> Report {
    let mut report = Report::default();
    let mut blocks = Blocks::new(BufReader::new(ProgramText::new(n)));
    run_reader(&mut blocks, engine, &mut report).expect("the program runs");
    report
}

fn fresh(record: bool) -> Engine {
    Engine {
        tc: TcModule::default(),
        motions: 0,
        record: record.then(Vec::new),
    }
}

fn check_clean(e: &Engine) {
    assert_eq!(e.motions, N as u64);
    assert_eq!(e.tc.group_at(1).map(|g| g.error.bits()), Some(0));
}

fn engine_direct(requests: &[Request]) -> Engine {
    let mut e = fresh(false);
    for r in requests {
        black_box(feed(&mut e.tc, black_box(r), &mut e.motions));
    }
    e
}

fn throughput(c: &mut Criterion, requests: &[Request]) {
    let mut g = c.benchmark_group("nc_stream");
    g.throughput(Throughput::Elements(N as u64));
    g.sample_size(10);
    g.warm_up_time(Duration::from_secs(1));
    g.measurement_time(Duration::from_secs(10));
    g.bench_function("NC check + run, 1M blocks", |b| {
        b.iter_batched(
            || fresh(false),
            |mut e| {
                nc_run(N, &mut e);
                check_clean(&e);
                e
            },
            BatchSize::PerIteration,
        )
    });
    g.bench_function("NC run pass only, 1M blocks", |b| {
        b.iter_batched(
            || fresh(false),
            |mut e| {
                run_pass(N, &mut e);
                check_clean(&e);
                e
            },
            BatchSize::PerIteration,
        )
    });
    g.bench_function("engine fed the same requests, 1M profiles", |b| {
        b.iter_batched(
            || (),
            |()| {
                let e = engine_direct(requests);
                check_clean(&e);
                e
            },
            BatchSize::PerIteration,
        )
    });
    g.finish();
}

/// Median seconds of `rounds` runs of `f`.
fn median_secs(rounds: usize, mut f: impl FnMut()) -> f64 {
    let mut t: Vec<f64> = (0..rounds)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64()
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[rounds / 2]
}

/// NC against engine in alternating rounds, printed as profiles/s and
/// their ratios: both passes (what `addipos run` does), and the run pass
/// alone (the program parsed, interpreted and corrected once).
fn ratio(requests: &[Request]) {
    const ROUNDS: usize = 5;
    let mut t = [Vec::new(), Vec::new(), Vec::new()];
    for _ in 0..ROUNDS {
        t[0].push(median_secs(1, || {
            let mut e = fresh(false);
            nc_run(N, &mut e);
            check_clean(&e);
        }));
        t[1].push(median_secs(1, || {
            let mut e = fresh(false);
            run_pass(N, &mut e);
            check_clean(&e);
        }));
        t[2].push(median_secs(1, || check_clean(&engine_direct(requests))));
    }
    let [nc, run, direct] = t.map(|mut v| {
        v.sort_by(f64::total_cmp);
        v[ROUNDS / 2]
    });
    let rate = |s: f64| N as f64 / s / 1e6;
    println!(
        "alternating, median of {ROUNDS}: NC both passes {nc:.3} s = {:.3} M profiles/s; \
         NC run pass {run:.3} s = {:.3} M profiles/s; engine {direct:.3} s = {:.3} M \
         profiles/s; NC / engine = {:.3} (both passes), {:.3} (run pass)",
        rate(nc),
        rate(run),
        rate(direct),
        direct / nc,
        direct / run
    );
}

/// Answers every request `ok` (`POS`: the origin): the interpreter
/// without the engine.
struct Null;

impl Controller for Null {
    fn call(&mut self, req: &Request, _at: At) -> Reply {
        match req {
            Request::Pos => Reply::Pos([0.0; tc_module::AXES]),
            _ => Reply::Ok,
        }
    }
}

/// Where the NC side's time goes, median of 3 each: making the text, the
/// check pass, the run pass without the engine.
fn breakdown() {
    let text = median_secs(3, || {
        let mut sink = std::io::sink();
        std::io::copy(&mut ProgramText::new(N), &mut sink).expect("copied");
    });
    let check = median_secs(3, || {
        let errors = check_program(BufReader::new(ProgramText::new(N)));
        assert!(errors.is_empty());
    });
    let run = median_secs(3, || {
        let mut report = Report::default();
        let mut blocks = Blocks::new(BufReader::new(ProgramText::new(N)));
        run_reader(&mut blocks, &mut Null, &mut report).expect("runs");
    });
    println!(
        "NC side, median of 3: making the text {text:.3} s, check pass {check:.3} s (text \
         included), run pass without the engine {run:.3} s (text included)"
    );
}

/// `VmHWM` of this process in kB.
fn peak_rss_kb() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .unwrap_or(0)
}

/// The child: one streamed run of `n` blocks, then its peak RSS.
fn rss_child(n: usize) {
    let before = peak_rss_kb();
    let mut e = fresh(false);
    let report = if n > 0 {
        nc_run(n, &mut e)
    } else {
        Report::default()
    };
    println!(
        "{n} {before} {} {} {}",
        peak_rss_kb(),
        report.peak_held_blocks,
        e.motions
    );
}

/// Peak RSS of streamed runs of 0, 100,000 and 1,000,000 blocks, each in
/// a child process.
fn rss() {
    let exe = std::env::current_exe().expect("own path");
    for n in [0, 100_000, 1_000_000] {
        let out = std::process::Command::new(&exe)
            .env(RSS_CHILD, n.to_string())
            .output()
            .expect("child runs");
        let text = String::from_utf8_lossy(&out.stdout);
        let f: Vec<&str> = text.split_whitespace().collect();
        match f.as_slice() {
            [n, start, peak, held, motions] => println!(
                "peak RSS, streamed run of {n} blocks: {peak} kB (at start {start} kB), \
                 blocks held at most {held}, motions {motions}"
            ),
            _ => println!("rss child for {n} blocks: {text} {}", out.status),
        }
    }
}

/// One part run 5 times on its own, for `perf record` / `perf stat`:
/// `gen` (making the text), `check` (the check pass), `run` (the run pass
/// without the engine), `nc` (both passes into the engine), `record` (one
/// NC run, recording its requests), `engine` (`record`, then the engine
/// fed them 5 times); `head` prints the start of the program.
fn profile(part: &str) {
    if part == "record" {
        recorded();
        return;
    }
    if part == "engine" {
        let requests = recorded();
        for _ in 0..5 {
            check_clean(&engine_direct(&requests));
        }
        return;
    }
    for _ in 0..5 {
        match part {
            "head" => {
                let mut t = ProgramText::new(8);
                let mut s = String::new();
                t.read_to_string(&mut s).expect("text");
                print!("{s}");
                return;
            }
            "gen" => {
                std::io::copy(&mut ProgramText::new(N), &mut std::io::sink()).expect("copied");
            }
            "check" => assert!(check_program(BufReader::new(ProgramText::new(N))).is_empty()),
            "run" => {
                let mut blocks = Blocks::new(BufReader::new(ProgramText::new(N)));
                run_reader(&mut blocks, &mut Null, &mut Report::default()).expect("runs");
            }
            _ => check_clean(&{
                let mut e = fresh(false);
                nc_run(N, &mut e);
                e
            }),
        }
    }
}

/// The requests of the NC run, recorded once, outside any timing.
fn recorded() -> Vec<Request> {
    let mut rec = fresh(true);
    nc_run(N, &mut rec);
    check_clean(&rec);
    rec.record.take().unwrap_or_default()
}

fn main() {
    if let Ok(n) = std::env::var(RSS_CHILD) {
        rss_child(n.parse().expect("a number of blocks"));
        return;
    }
    if let Ok(part) = std::env::var("NC_STREAM_PROFILE") {
        profile(&part);
        return;
    }
    rss();
    let requests = recorded();
    println!("requests of the program: {}", requests.len());
    // NC_STREAM_QUICK=1: the alternating ratio only (while profiling).
    if std::env::var_os("NC_STREAM_QUICK").is_none() {
        let mut c = Criterion::default().configure_from_args();
        throughput(&mut c, &requests);
        c.final_summary();
    }
    breakdown();
    ratio(&requests);
}
