//! Cost of one interpolation cycle with the OTC wear model on, per
//! processing type, next to the executor alone on the same elements.
//! Every figure runs `EXEC 10000` per iteration on a long
//! spooled contour of a running correction (lines with B moving, half
//! circles CW and CCW, circular transitions, inside corners) at 0.1 per
//! cycle; the spooler is topped up between iterations, outside the timed
//! part. ns per cycle = time per iteration / 10000. Figures go to
//! docs/performance.md.
//!
//! * `OTC off (counted)`: OTC off, so the executor counts the cycles
//!   inside an element and steps only the last (the fast path).
//! * `stepped, no model work`: an extension whose model is always active
//!   and returns no offset: the executor steps every cycle through the
//!   same module path as OTC, the model doing nothing.
//! * `Executor::step, no model work`: the bare executor stepped cycle by
//!   cycle with a trivial always-active `CycleModel`, on the same
//!   elements (without the module around it).
//! * RADIUS, LENGTH, TOOL_DIR, SURF_NORM_DIR: OTC on in AUTO (continuous
//!   wear, the type's PLC units enabled and ramping at AccWeight 1).
//!
//! After criterion, a paired run times every variant once per round,
//! round after round in rotating order, and prints the minimum and
//! median per variant and each type's median per-round difference to
//! the executor alone: on a shared machine a load that comes and goes
//! then hits every variant alike.

#![allow(missing_docs, clippy::expect_used, clippy::unwrap_used, clippy::panic)]

#[path = "../tests/common/mod.rs"]
mod common;

use std::hint::black_box;
use std::time::{Duration, Instant};

use common::{command_all, otc_auto_on, otc_module, run, set_units, Contour, CORRECTION_ON, TYPES};
use criterion::{criterion_group, Criterion, Throughput};
use tc_module::Executor;
use tc_module::{
    AlwaysStepped, AxisPos, Cycle, CycleModel, CycleTime, NoExtension, Spooler, TcExtension,
    TcModule, AXES,
};

/// Cycles per iteration.
const CYCLES: u64 = 10_000;
/// Profiles spooled at a time (about 130 cycles each).
const CHUNK: usize = 1_000;
/// Elements below which the spooler is topped up (comfortably more than
/// one iteration's worth, about 80 profiles with their transitions).
const LOW: usize = 600;

/// A trivial always-active model for the bare executor.
struct Trivial;

impl CycleModel for Trivial {
    fn active(&self) -> bool {
        true
    }

    fn cycle(&mut self, _: &Cycle<'_>) -> AxisPos {
        [0.0; AXES]
    }
}

/// A module running the contour, topped up between iterations.
struct Rig<E: TcExtension> {
    tc: TcModule<E>,
    contour: Contour,
    /// The OTC type whose units are turned around at each top-up.
    proc_type: Option<i32>,
    sign: i32,
}

impl<E: TcExtension> Rig<E> {
    fn new(mut tc: TcModule<E>, proc_type: Option<i32>) -> Self {
        run(&mut tc, CORRECTION_ON);
        let mut rig = Self {
            tc,
            contour: Contour::default(),
            proc_type,
            sign: 1,
        };
        rig.top_up();
        rig
    }

    /// More profiles when the spooler runs low; the PLC command turns
    /// around so the units keep ramping.
    fn top_up(&mut self) {
        if self.tc.queue_len() >= LOW {
            return;
        }
        command_all(&mut self.tc, &self.contour.next_profiles(CHUNK));
        if let Some(t) = self.proc_type {
            self.sign = -self.sign;
            set_units(&mut self.tc, t, self.sign * 1_000_000);
        }
    }

    fn time(&mut self, iters: u64) -> Duration {
        let mut total = Duration::ZERO;
        for _ in 0..iters {
            self.top_up();
            let t = Instant::now();
            self.tc.exec(Some(black_box(CYCLES)));
            total += t.elapsed();
        }
        total
    }
}

/// The bare executor on the same elements, taken from a module's spool
/// log.
struct BareRig {
    source: TcModule<NoExtension>,
    contour: Contour,
    spooler: Spooler,
    executor: Executor,
}

impl BareRig {
    fn new() -> Self {
        let mut source = TcModule::default();
        source.spooler_mut().set_logging(true);
        run(&mut source, CORRECTION_ON);
        let mut rig = Self {
            source,
            contour: Contour::default(),
            spooler: Spooler::default(),
            executor: Executor::new([0.0; AXES], CycleTime::DEFAULT),
        };
        rig.top_up();
        rig
    }

    fn top_up(&mut self) {
        if self.spooler.len() >= LOW {
            return;
        }
        command_all(&mut self.source, &self.contour.next_profiles(CHUNK));
        for e in self.source.spooler_mut().take_log() {
            self.spooler.push(&e.start, &e.end, e.element);
        }
        self.source.spooler_mut().discard();
    }

    fn time(&mut self, iters: u64) -> Duration {
        let mut total = Duration::ZERO;
        for _ in 0..iters {
            self.top_up();
            let t = Instant::now();
            for _ in 0..black_box(CYCLES) {
                self.executor.step(&mut self.spooler, &mut Trivial);
            }
            total += t.elapsed();
        }
        total
    }
}

fn wear_cycle(c: &mut Criterion) {
    let mut g = c.benchmark_group("wear_cycle");
    g.throughput(Throughput::Elements(CYCLES));
    g.bench_function("OTC off (counted)", |b| {
        let mut rig = Rig::new(otc_module(), None);
        b.iter_custom(|iters| rig.time(iters));
    });
    g.bench_function("stepped, no model work", |b| {
        let mut rig = Rig::new(
            TcModule::new([0.0; AXES], CycleTime::DEFAULT, AlwaysStepped),
            None,
        );
        b.iter_custom(|iters| rig.time(iters));
    });
    g.bench_function("Executor::step, no model work", |b| {
        let mut rig = BareRig::new();
        b.iter_custom(|iters| rig.time(iters));
    });
    for (code, name) in TYPES {
        g.bench_function(name, |b| {
            let mut rig = otc_rig(code, name);
            b.iter_custom(|iters| rig.time(iters));
        });
    }
    g.finish();
}

/// A rig with OTC on in AUTO with `code`, checked to act per cycle.
fn otc_rig(code: i32, name: &str) -> Rig<otc_ext::OtcExtension> {
    let mut rig = Rig::new(otc_module(), Some(code));
    otc_auto_on(&mut rig.tc, code, 1_000_000);
    rig.tc.exec(Some(10));
    assert!(
        rig.tc.executor().offset().is_some(),
        "{name}: the wear model does not act per cycle"
    );
    rig
}

/// Rounds of the paired run.
const ROUNDS: usize = 300;

/// A variant of the paired run: its name and one timed iteration.
type Variant = (&'static str, Box<dyn FnMut() -> Duration>);

/// The paired run, for a shared machine: every variant runs one
/// iteration per round, round after round, in rotating order, so a load
/// that comes and goes hits all of them alike. Prints per variant the
/// minimum and median ns per cycle over the rounds and, per OTC type,
/// the median of its per-round difference to and ratio over `stepped, no
/// model work` (the executor alone, stepping every cycle).
fn paired() {
    let mut variants: Vec<Variant> = Vec::new();
    let mut off = Rig::new(otc_module(), None);
    variants.push(("OTC off (counted)", Box::new(move || off.time(1))));
    let stepped = TcModule::new([0.0; AXES], CycleTime::DEFAULT, AlwaysStepped);
    let mut stepped = Rig::new(stepped, None);
    variants.push(("stepped, no model work", Box::new(move || stepped.time(1))));
    let mut bare = BareRig::new();
    variants.push((
        "Executor::step, no model work",
        Box::new(move || bare.time(1)),
    ));
    for (code, name) in TYPES {
        let mut rig = otc_rig(code, name);
        variants.push((name, Box::new(move || rig.time(1))));
    }
    let n = variants.len();
    let mut ns = vec![Vec::with_capacity(ROUNDS); n];
    for round in 0..ROUNDS {
        for k in 0..n {
            let i = (k + round) % n;
            let t = (variants[i].1)();
            ns[i].push(t.as_secs_f64() * 1e9 / CYCLES as f64);
        }
    }
    println!("\npaired run: {ROUNDS} rounds of EXEC {CYCLES} per variant, ns per cycle");
    println!("| variant | min | median | added (median of per-round differences) | ratio |");
    println!("|---|---|---|---|---|");
    let base = ns[1].clone();
    for (i, (name, _)) in variants.iter().enumerate() {
        let (min, med) = (min_of(&ns[i]), median(&ns[i]));
        if i < 3 {
            println!("| {name} | {min:.1} | {med:.1} | | |");
            continue;
        }
        let diff: Vec<f64> = ns[i].iter().zip(&base).map(|(a, b)| a - b).collect();
        let ratio: Vec<f64> = ns[i].iter().zip(&base).map(|(a, b)| a / b).collect();
        println!(
            "| {name} | {min:.1} | {med:.1} | {:+.1} | {:.2} |",
            median(&diff),
            median(&ratio)
        );
    }
}

fn min_of(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, f64::min)
}

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s[s.len() / 2]
}

criterion_group!(benches, wear_cycle);

fn main() {
    benches();
    Criterion::default().configure_from_args().final_summary();
    // Not in test mode (`cargo test --benches` runs each bench once).
    if std::env::args().any(|a| a == "--bench") {
        paired();
    }
}
