//! Cost of one interpolation cycle with the OTC wear model on, per
//! processing type, next to the executor alone on the same elements
//! (issue 9). Every figure runs `EXEC 10000` per iteration on a long
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

#![allow(missing_docs, clippy::expect_used, clippy::unwrap_used, clippy::panic)]

#[path = "../tests/common/mod.rs"]
mod common;

use std::hint::black_box;
use std::time::{Duration, Instant};

use common::{command_all, otc_auto_on, otc_module, run, set_units, Contour, CORRECTION_ON, TYPES};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use tc_module::executor::Executor;
use tc_module::extension::NoKey;
use tc_module::{
    AxisPos, Cycle, CycleModel, CycleTime, Groups, NoExtension, Spooler, TcExtension, TcModule,
    AXES,
};
use uoi::ObjectDesc;

/// Cycles per iteration.
const CYCLES: u64 = 10_000;
/// Profiles spooled at a time (about 130 cycles each).
const CHUNK: usize = 1_000;
/// Elements below which the spooler is topped up (comfortably more than
/// one iteration's worth, about 80 profiles with their transitions).
const LOW: usize = 600;

/// An extension whose per-cycle model is always active and adds nothing.
#[derive(Debug, Default)]
struct Stepped;

impl TcExtension for Stepped {
    type Key = NoKey;
    type Group = ();
    type Tool = ();
    const GROUP_OBJECTS: &'static [ObjectDesc<NoKey>] = &[];
    const OBJECTS: &'static [ObjectDesc<NoKey>] = &[];

    fn cycle_active(&mut self, _: Groups<'_, Self>) -> bool {
        true
    }

    fn cycle(&mut self, _: &Cycle<'_>, _: Groups<'_, Self>) -> AxisPos {
        [0.0; AXES]
    }
}

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
            self.spooler.push(e);
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
            TcModule::new([0.0; AXES], CycleTime::DEFAULT, Stepped),
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
            let mut rig = Rig::new(otc_module(), Some(code));
            otc_auto_on(&mut rig.tc, code, 1_000_000);
            rig.tc.exec(Some(10));
            assert!(
                rig.tc.executor().offset().is_some(),
                "{name}: the wear model does not act per cycle"
            );
            b.iter_custom(|iters| rig.time(iters));
        });
    }
    g.finish();
}

criterion_group!(benches, wear_cycle);
criterion_main!(benches);
