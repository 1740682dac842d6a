//! Throughput of the correction (profiles/s through the one-profile buffer)
//! and cost of one executor cycle. Figures go to docs/performance.md.

#![allow(missing_docs, clippy::expect_used)]

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use tc_module::Executor;
use tc_module::{ArcDir, Motion, Origin, SpoolElement, Spooler, TcModule, AXES};
use tc_module::{Cycle, CycleModel, CycleTime, NoModel, Path};
use tc_objects::TcObject;
use uoi::{ObjectBus, Value};

/// A contour of `n` mixed profiles advancing along X: line, half circle
/// above (CW), line, half circle below (CCW), ... so the corrected path
/// has inside and outside corners of lines and arcs.
fn contour(n: usize) -> Vec<Motion> {
    let mut out = Vec::with_capacity(n);
    let mut x = 0.0;
    for i in 0..n {
        let mut w = [None; AXES];
        w[1] = Some(0.0);
        match i % 4 {
            0 | 2 => {
                x += 10.0;
                w[0] = Some(x);
                out.push(Motion::Lin {
                    words: w,
                    feed: Some(6000.0),
                });
            }
            k => {
                x += 10.0;
                w[0] = Some(x);
                out.push(Motion::Cir {
                    dir: if k == 1 { ArcDir::Cw } else { ArcDir::Ccw },
                    words: w,
                    centre: [Some(5.0), Some(0.0), None],
                    feed: None,
                });
            }
        }
    }
    out
}

fn running_module() -> TcModule {
    let mut tc = TcModule::default();
    for (addr, v) in [
        (TcObject::WkzIndex.of(1), Value::I32(1)),
        (TcObject::Radius.of(1), Value::F64(1.0)),
        (TcObject::Left.of(1), Value::I32(0)),
        (TcObject::Status.of(1), Value::I32(1)),
    ] {
        tc.write_checked(addr, v).expect("setup write");
    }
    tc
}

fn correction(c: &mut Criterion) {
    const N: usize = 1_000_000;
    let profiles = contour(N);
    let mut g = c.benchmark_group("correction");
    g.throughput(Throughput::Elements(N as u64));
    g.sample_size(10);
    g.bench_function("1M mixed line/arc profiles", |b| {
        b.iter_batched(
            running_module,
            |mut tc| {
                for (i, m) in profiles.iter().enumerate() {
                    let _ = tc.command(black_box(m));
                    if i % 1024 == 0 {
                        // What the executor would have consumed meanwhile.
                        tc.spooler_mut().discard();
                    }
                }
                assert_eq!(tc.group_at(1).map(|g| g.error.bits()), Some(0));
                tc
            },
            BatchSize::PerIteration,
        )
    });
    g.finish();
}

fn executor(c: &mut Criterion) {
    let mut far = [0.0; AXES];
    far[0] = 1e8;
    far[1] = 1e8;
    let mut g = c.benchmark_group("executor");
    g.throughput(Throughput::Elements(1));
    g.bench_function("step on a line", |b| {
        let mut sp = Spooler::default();
        let start = [0.0; AXES];
        let xy = tc_module::TcPlane::Xy.pick([0, 1, 2]);
        let e = SpoolElement::line(&start, &far, xy, 1000.0, false, Origin::Uncorrected);
        sp.push(&start, &far, e);
        let mut ex = Executor::default();
        b.iter(|| ex.step(black_box(&mut sp), &mut NoModel));
    });
    g.bench_function("step on an arc", |b| {
        let mut sp = Spooler::default();
        sp.push(
            &CIRCLE_START,
            &CIRCLE_START,
            big_circle(Origin::Uncorrected),
        );
        let mut ex = Executor::new(CIRCLE_START, CycleTime::DEFAULT);
        b.iter(|| ex.step(black_box(&mut sp), &mut NoModel));
    });
    g.bench_function("step on a corrected arc, with a model", |b| {
        let mut sp = Spooler::default();
        let e = big_circle(Origin::Corrected);
        let Path::Arc(a) = e.path() else {
            unreachable!()
        };
        let normal = tc_module::ContourNormal {
            plane: a.plane,
            rule: tc_module::NormalRule::Radial {
                centre: a.centre,
                outward: true,
            },
        };
        sp.push(&CIRCLE_START, &CIRCLE_START, e.with_normal(Some(normal)));
        let mut ex = Executor::new(CIRCLE_START, CycleTime::DEFAULT);
        let mut model = AlongNormal;
        b.iter(|| ex.step(black_box(&mut sp), &mut model));
    });
    g.finish();
}

/// Where [`big_circle`] starts and ends.
const CIRCLE_START: [f64; AXES] = [1e6, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];

/// A full circle of radius 1e6 at 1000 units/min: never finishes within a
/// run.
fn big_circle(origin: Origin) -> SpoolElement {
    let plane = tc_module::TcPlane::Xy.pick([0, 1, 2]);
    let centre = tc_module::V2::zeros();
    SpoolElement::arc(
        &CIRCLE_START,
        &CIRCLE_START,
        plane,
        centre,
        true,
        1000.0,
        origin,
    )
}

/// A model that offsets by the path travelled along the contour normal:
/// it reads the parts and the normal every cycle, as a wear model does.
struct AlongNormal;

impl CycleModel for AlongNormal {
    fn active(&self) -> bool {
        true
    }

    fn cycle(&mut self, c: &Cycle<'_>) -> [f64; AXES] {
        let ds: f64 = c.parts.iter().map(|p| p.length).sum();
        c.normal().map_or([0.0; AXES], |n| n.map(|v| v * ds))
    }
}

criterion_group!(benches, correction, executor);
criterion_main!(benches);
