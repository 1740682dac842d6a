//! Object reads per second through the C ABI on an embedded emulator
//! (goal: at least 5 M/s), beside the Rust API's, and the cost of
//! recording them (goal: at most 1.5 times the time without). The
//! recording goes to `/dev/null`: what is measured is the library's work
//! (formatting, buffering, writing), not the disk's speed.
//!
//! Group `served`: reads through the library to a server (an in-process
//! `addipos serve` on loopback) beside the Rust client's own sequential
//! reads (`uoi::tcp::BlockingClient::read`) to the same server, in the
//! same run (goal: at least 0.9 times the client's rate).

// The bench calls the C ABI as a C program does: its functions are
// `unsafe extern "C"` (they write through the pointers they are given).
#![allow(unsafe_code)]
#![allow(missing_docs, clippy::unwrap_used, clippy::expect_used)]

use std::ffi::CString;
use std::hint::black_box;
use std::time::Duration;

use addipos_host::{Descriptor, Machine};
use c_abi::{addipos_close, addipos_open, addipos_record, uoi_init, uoi_read_int, Addipos};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use tc_objects::TcObject;

// The C ABI compiled into the bench, as a C program links it: the crate
// has no Rust library (it is `libaddipos` for C), so its source comes in
// as a module (decision 511).
// Built as a test too, where the module's own tests and the constants a
// C program uses are not reached.
#[path = "../src/lib.rs"]
#[allow(dead_code, unused_imports)]
mod c_abi;

/// TcPlane, an i32 object (reads 17).
fn plane() -> Descriptor {
    Descriptor::of(TcObject::TcPlane.address())
}

/// Reads per iteration.
const BATCH: u64 = 1000;

/// An embedded connection through the C ABI and a handle to TcPlane,
/// recorded into `/dev/null` when `record`.
fn open(record: bool) -> (*mut Addipos, u32) {
    let target = CString::new("embedded").unwrap();
    // SAFETY: a NUL-terminated string.
    let a = unsafe { addipos_open(target.as_ptr()) };
    assert!(!a.is_null());
    if record {
        let null = CString::new("/dev/null").unwrap();
        // SAFETY: a NUL-terminated string.
        assert_eq!(unsafe { addipos_record(a, null.as_ptr()) }, 0);
    }
    let mut h = 0u32;
    // SAFETY: a descriptor and a handle of ours.
    assert_eq!(unsafe { uoi_init(a, &plane(), &mut h) }, 0);
    (a, h)
}

fn reads(a: *mut Addipos, h: u32) {
    let mut v = 0i32;
    for _ in 0..BATCH {
        // SAFETY: `v` is ours and writable.
        let rc = unsafe { uoi_read_int(a, h, &mut v) };
        black_box((rc, v));
    }
}

fn c_abi(c: &mut Criterion) {
    let mut g = c.benchmark_group("reads");
    g.throughput(Throughput::Elements(BATCH));
    g.measurement_time(Duration::from_secs(4));
    let (plain, hp) = open(false);
    let (recorded, hr) = open(true);
    let m = Machine::open("embedded").unwrap();
    let hm = m.handle(&plane()).unwrap();
    // Alternated in one run: plain, recorded, Rust API.
    g.bench_function("c_abi", |b| b.iter(|| reads(plain, hp)));
    g.bench_function("c_abi_recorded", |b| b.iter(|| reads(recorded, hr)));
    g.bench_function("rust_api", |b| {
        b.iter(|| {
            for _ in 0..BATCH {
                black_box(m.read_int(hm).unwrap());
            }
        })
    });
    g.finish();
    addipos_close(plain);
    addipos_close(recorded);
}

/// An `addipos serve` in this process, on a loopback port of its own.
fn serve() -> String {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let rt = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .enable_all()
            .build()
            .unwrap();
        rt.block_on(async move {
            let cfg = uoi::tcp::ServerConfig {
                listen: "127.0.0.1:0".parse().unwrap(),
                ..uoi::tcp::ServerConfig::default()
            };
            let service = emulator::EmulatorService::new([0.0; 8], tc_module::CycleTime::DEFAULT);
            let server = uoi::tcp::Server::bind(cfg, service).await.unwrap();
            tx.send(server.local_addr().unwrap().to_string()).unwrap();
            let _ = server.run(std::future::pending()).await;
        });
    });
    rx.recv_timeout(Duration::from_secs(10)).unwrap()
}

/// Reads per iteration over the wire.
const SERVED_BATCH: u64 = 100;

fn served(c: &mut Criterion) {
    let addr = serve();
    let m = Machine::open(&addr).unwrap();
    let h = m.handle(&plane()).unwrap();
    let mut client = uoi::tcp::BlockingClient::connect(&addr).unwrap();
    let plane = TcObject::TcPlane.address();
    let mut g = c.benchmark_group("served");
    g.throughput(Throughput::Elements(SERVED_BATCH));
    g.measurement_time(Duration::from_secs(4));
    g.bench_function("library", |b| {
        b.iter(|| {
            for _ in 0..SERVED_BATCH {
                black_box(m.read_int(h).unwrap());
            }
        })
    });
    g.bench_function("rust_client", |b| {
        b.iter(|| {
            for _ in 0..SERVED_BATCH {
                black_box(client.read(plane, uoi::ValueType::I32).unwrap());
            }
        })
    });
    g.finish();
}

criterion_group!(benches, c_abi, served);
criterion_main!(benches);
