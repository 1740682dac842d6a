//! The OPC UA face next to the UOI face, on one `addipos serve
//! --opcua` process: sequential reads (one object per request), batched
//! reads (100 objects per OPC UA Read, 100 pipelined UOI READs), the
//! server's CPU time per read, and the latency of a subscription seeing a
//! UOI write.
//!
//! Run: `cargo bench --bench opcua` (`-- --quick` for a short run); the
//! figures go to docs/performance.md. The server is the release binary in
//! a process of its own, so its CPU time (utime + stime from
//! /proc/PID/stat) is the server's alone; the clients run on one
//! current-thread runtime of the bench.

// Test and bench helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]
#![allow(missing_docs)]

#[path = "../opcua-face/tests/ua/mod.rs"]
mod ua;

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use opcua::types::{NodeId, Variant};
use tc_objects::TcObject;
use tokio::runtime::Runtime;
use ua::{until, Ua};
use uoi::tcp::Client;
use uoi::wire::Request;
use uoi::{ObjectAddress, Value, ValueType};

/// Objects per batch.
const BATCH: usize = 100;

/// A running `addipos serve --opcua`, killed when dropped.
struct Serve {
    child: Child,
    uoi: String,
    url: String,
    _dir: tempfile::TempDir,
}

impl Serve {
    fn start() -> Serve {
        let dir = tempfile::tempdir().expect("dir");
        let mut child = Command::new(env!("CARGO_BIN_EXE_addipos"))
            .current_dir(dir.path())
            .args([
                "serve",
                "--listen",
                "127.0.0.1:0",
                "--opcua",
                "127.0.0.1:0",
                "--no-persist",
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("serve");
        let mut err = BufReader::new(child.stderr.take().expect("stderr"));
        let (mut uoi, mut url) = (None, None);
        let mut line = String::new();
        while uoi.is_none() || url.is_none() {
            line.clear();
            assert!(err.read_line(&mut line).expect("log") > 0, "serve ended");
            let field = |key: &str| {
                line.split_whitespace()
                    .find_map(|w| w.strip_prefix(key))
                    .map(str::to_string)
            };
            uoi = uoi.or_else(|| field("listen="));
            url = url.or_else(|| field("endpoint="));
        }
        std::thread::spawn(move || std::io::copy(&mut err, &mut std::io::sink()));
        Serve {
            child,
            uoi: uoi.unwrap(),
            url: url.unwrap(),
            _dir: dir,
        }
    }

    /// The server's CPU time so far (user + system).
    fn cpu(&self) -> Duration {
        let stat =
            std::fs::read_to_string(format!("/proc/{}/stat", self.child.id())).expect("stat");
        // Fields after the command's closing parenthesis; utime and stime
        // are the 14th and 15th of the line.
        let rest = &stat[stat.rfind(')').expect("comm") + 2..];
        let f: Vec<u64> = rest
            .split_whitespace()
            .skip(11)
            .take(2)
            .map(|v| v.parse().unwrap())
            .collect();
        Duration::from_secs_f64((f[0] + f[1]) as f64 / 100.0)
    }
}

impl Drop for Serve {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The objects read: RADIUS, WKZINDEX, STATUS, ... of groups 1..=10.
fn objects() -> Vec<ObjectAddress> {
    use TcObject as O;
    let keys = [
        O::Error,
        O::Status,
        O::XAxis,
        O::YAxis,
        O::Radius,
        O::WkzIndex,
        O::ZAxis,
        O::WkzLen,
        O::Status,
        O::Error,
    ];
    (1..=10u16)
        .flat_map(|g| keys.iter().map(move |k| k.of(g)))
        .take(BATCH)
        .collect()
}

fn ty(a: ObjectAddress) -> ValueType {
    if matches!(a.sub, 6 | 12) {
        ValueType::F64
    } else {
        ValueType::I32
    }
}

struct Rig {
    rt: Runtime,
    serve: Serve,
    uoi: Client,
    ua: Ua,
    nodes: Vec<NodeId>,
    reads: Vec<Request>,
}

impl Rig {
    fn start() -> Rig {
        let serve = Serve::start();
        let rt = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .unwrap();
        let uoi = rt
            .block_on(Client::connect(serve.uoi.as_str()))
            .expect("uoi");
        let ua = rt.block_on(Ua::open(&serve.url));
        let nodes = objects().iter().map(|a| ua.node(&a.to_string())).collect();
        let reads = objects()
            .into_iter()
            .map(|a| Request::Read(a, ty(a)))
            .collect();
        Rig {
            rt,
            serve,
            uoi,
            ua,
            nodes,
            reads,
        }
    }

    fn uoi_one(&mut self) {
        let v = self
            .rt
            .block_on(self.uoi.read(TcObject::Radius.of(1), ValueType::F64));
        assert!(v.is_ok());
    }

    fn uoi_batch(&mut self) {
        let v = self
            .rt
            .block_on(self.uoi.pipeline(&self.reads))
            .expect("pipeline");
        assert_eq!(v.len(), BATCH);
    }

    fn ua_one(&mut self) {
        let v = self.rt.block_on(self.ua.read_many(&self.nodes[4..5]));
        assert!(v[0].status().is_good());
    }

    fn ua_batch(&mut self) {
        let v = self.rt.block_on(self.ua.read_many(&self.nodes));
        assert!(v.iter().all(|d| d.status().is_good()));
    }

    /// Server CPU per object read over `n` requests of `per` objects.
    fn cpu_per_read(
        &mut self,
        n: usize,
        per: usize,
        mut one: impl FnMut(&mut Rig),
    ) -> (Duration, Duration) {
        let (cpu, t) = (self.serve.cpu(), Instant::now());
        for _ in 0..n {
            one(self);
        }
        let reads = (n * per) as u32;
        (t.elapsed() / reads, (self.serve.cpu() - cpu) / reads)
    }
}

/// A CPU run: its name, requests, objects per request, one request.
type Run = (&'static str, usize, usize, fn(&mut Rig));

fn reads(c: &mut Criterion) {
    let mut rig = Rig::start();
    let mut g = c.benchmark_group("read");
    g.throughput(Throughput::Elements(1));
    g.bench_function("UOI sequential", |b| b.iter(|| rig.uoi_one()));
    g.bench_function("OPC UA sequential", |b| b.iter(|| rig.ua_one()));
    g.throughput(Throughput::Elements(BATCH as u64));
    g.bench_function("UOI pipelined 100", |b| b.iter(|| rig.uoi_batch()));
    g.bench_function("OPC UA batched 100", |b| b.iter(|| rig.ua_batch()));
    g.finish();
    // Server CPU per object read, from the process's own accounting.
    let runs: [Run; 4] = [
        ("UOI sequential", 20_000, 1, Rig::uoi_one),
        ("OPC UA sequential", 5_000, 1, Rig::ua_one),
        ("UOI pipelined 100", 2_000, BATCH, Rig::uoi_batch),
        ("OPC UA batched 100", 500, BATCH, Rig::ua_batch),
    ];
    for (name, n, per, one) in runs {
        let (wall, cpu) = rig.cpu_per_read(n, per, one);
        println!(
            "cpu/{name}: {:.2} µs server CPU per object read ({:.2} µs wall, {} objects)",
            us(cpu),
            us(wall),
            n * per
        );
    }
    latency(&mut rig);
}

fn us(d: Duration) -> f64 {
    d.as_secs_f64() * 1e6
}

/// A UOI write seen by a monitored item sampled every 10 ms: milliseconds
/// from the write's answer to the notification, 100 times.
fn latency(rig: &mut Rig) {
    let mut ms: Vec<f64> = rig.rt.block_on(async {
        let addr = TcObject::Radius.of(2);
        let mut seen = rig.ua.watch(&addr.to_string(), 10.0).await;
        until(&mut seen, &Variant::Double(0.0)).await;
        let mut out = Vec::new();
        for k in 1..=100u32 {
            let v = f64::from(k);
            rig.uoi.write(addr, Value::F64(v)).await.expect("write");
            let written = Instant::now();
            let at = until(&mut seen, &Variant::Double(v)).await;
            out.push(at.saturating_duration_since(written).as_secs_f64() * 1e3);
            // Writes at no fixed phase to the sampler's ticks.
            tokio::time::sleep(Duration::from_millis(u64::from(3 + k % 7))).await;
        }
        out
    });
    ms.sort_by(f64::total_cmp);
    let pct = |p: usize| ms[(ms.len() - 1) * p / 100];
    println!(
        "latency/UOI write to OPC UA notification (10 ms sampling): median {:.1} ms, 90% {:.1} ms, max {:.1} ms, min {:.1} ms",
        pct(50),
        pct(90),
        pct(100),
        pct(0)
    );
}

criterion_group!(benches, reads);
criterion_main!(benches);
