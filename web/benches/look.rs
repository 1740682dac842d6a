//! How long the view holds the emulator: one look of the sampler (the
//! position and the elements spooled since the last look, every 10 ms)
//! and one whole state (every 50 ms), on an emulator with OTC on in
//! group 1 and tool entries in two groups (docs/performance.md).

// Bench setup may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]
// criterion_group! makes an undocumented function.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion};
use emulator::EmulatorService;
use tc_module::CycleTime;
use tc_request::text::parse_request;
use uoi::tcp::Handler;

fn service() -> EmulatorService {
    let mut s = EmulatorService::new([0.0; 8], CycleTime::DEFAULT);
    for text in [
        "W 1300/1/1/8 i 1",
        "W 1300/1/1/6 d 2",
        "W 1300/3/1/30 i 2",
        "W 1300/3/1/4 d 20000",
        "W 1300/1/1/9 i 0",
        "W 1300/1/1/3 i 1",
        "W 1300/3/1/1 i 1",
        "W 1300/1/2/6 d 5",
        "W 1300/1/2/8 i 7",
        "W 1300/1/2/6 d 3",
        "CIR CCW X0 Y20 I0 J10 F600",
        "EXEC 500",
    ] {
        let _ = s.serve(parse_request(text).unwrap().to_wire());
    }
    s.watch_spool(true);
    s
}

fn look(c: &mut Criterion) {
    let mut s = service();
    c.bench_function("web look: position and spooled elements", |b| {
        b.iter(|| {
            let spooled = s.take_watched_spool();
            let pos = s.emulator_mut().position();
            std::hint::black_box((spooled, pos))
        })
    });
    c.bench_function("web look: the whole state", |b| {
        b.iter(|| std::hint::black_box(web_view::snapshot::take(&mut s, 1)))
    });
    let snap = web_view::snapshot::take(&mut s, 1);
    c.bench_function("web: the state as JSON", |b| {
        b.iter(|| std::hint::black_box(serde_json::to_string(&snap).unwrap()))
    });
}

criterion_group!(benches, look);
criterion_main!(benches);
