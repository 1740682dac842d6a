//! Unit tests of `executor`.

use super::*;
use crate::cycle::{Cycle, CycleModel, NoModel};
use crate::element::Origin;
use crate::plane::PlaneAxes;

fn pos(x: f64) -> AxisPos {
    let mut p = [0.0; AXES];
    p[0] = x;
    p
}

const XY: PlaneAxes = PlaneAxes {
    h: 0,
    v: 1,
    third: 2,
};

/// Pushes a line along X from `a` to `b` (`a` the end of the last one) at
/// `feed`.
fn push_at(sp: &mut Spooler, a: f64, b: f64, feed: f64, origin: Origin) {
    let e = SpoolElement::line(&pos(a), &pos(b), XY, feed, false, origin);
    sp.push(&pos(a), &pos(b), e);
}

fn push(sp: &mut Spooler, a: f64, b: f64, origin: Origin) {
    push_at(sp, a, b, 600.0, origin);
}

#[test]
fn steps_at_feed_and_carries_over() {
    let mut sp = Spooler::default();
    // 600 units/min = 0.01 per ms
    push(&mut sp, 0.0, 0.015, Origin::Uncorrected);
    push(&mut sp, 0.015, 1.0, Origin::Uncorrected);
    let mut ex = Executor::default();
    ex.step(&mut sp, &mut NoModel);
    assert!((ex.position()[0] - 0.01).abs() < 1e-12);
    ex.step(&mut sp, &mut NoModel);
    assert!((ex.position()[0] - 0.02).abs() < 1e-12);
    assert_eq!(sp.len(), 1);
    ex.run(&mut sp, 10, &mut NoModel);
    assert!((ex.position()[0] - 0.12).abs() < 1e-12);
    ex.run(&mut sp, u64::MAX / 2, &mut NoModel);
    assert_eq!(ex.position()[0], 1.0);
    assert!(sp.is_empty());
    push(&mut sp, 1.0, 1e12, Origin::Uncorrected);
    ex.run(&mut sp, 1_000_000_000_000, &mut NoModel);
    assert!((ex.position()[0] - (1e10 + 1.0)).abs() < 1e-2);
    ex.run_until_empty(&mut sp, &mut NoModel);
    assert_eq!(ex.position()[0], 1e12);
    assert!(sp.is_empty());
}

/// Records the origin of the current element and the cycle's parts.
#[derive(Default)]
struct Current(Option<Origin>, f64);

impl CycleModel for Current {
    fn active(&self) -> bool {
        true
    }
    fn cycle(&mut self, c: &Cycle<'_>) -> AxisPos {
        self.0 = c.current.map(|e| e.origin());
        self.1 = c.parts.iter().map(|p| p.length).sum();
        [0.0; AXES]
    }
}

#[test]
fn a_cycle_that_ends_on_an_end_point_stands_on_the_element_that_ended() {
    // 0.3, 0.7, 1.1 summed in steps of 0.01 round a few ulps past (or
    // short of) their length; the cycle that reaches it ends exactly.
    for len in [0.3, 0.7, 1.1, 10.0] {
        let mut sp = Spooler::default();
        push(&mut sp, 0.0, len, Origin::Corrected);
        push(&mut sp, len, 5.0 * len, Origin::Transition);
        let (mut ex, mut m) = (Executor::default(), Current::default());
        let cycles = (len / 0.01).round() as u64;
        ex.run(&mut sp, cycles, &mut m);
        assert_eq!(m.0, Some(Origin::Corrected), "{len}");
        assert_eq!(ex.nominal()[0], len, "{len}");
        assert_eq!(sp.len(), 1, "{len}");
        ex.step(&mut sp, &mut m);
        assert_eq!(m.0, Some(Origin::Transition), "{len}");
        assert!((m.1 - 0.01).abs() < 1e-15);
    }
}

#[test]
fn a_stuck_element_costs_nothing_per_cycle() {
    // Hand-built elements the module would refuse: no feed, and a step
    // that vanishes against the distance already run.
    for feed in [0.0, 5e-324] {
        let mut sp = Spooler::default();
        push_at(&mut sp, 0.0, 1.0, feed, Origin::Uncorrected);
        let mut ex = Executor::default();
        ex.run(&mut sp, u64::MAX - 1, &mut NoModel);
        assert_eq!(ex.cycles(), u64::MAX - 1);
        assert_eq!(sp.len(), 1);
        assert_eq!(ex.position()[0], 0.0);
    }
}

#[test]
fn an_element_that_moves_other_axes_runs_to_its_whole_end() {
    // A plunge of 0.02 along Z (kept whole by the spooler), then a line
    // along X that leaves Z where the plunge put it; 0.01 a cycle.
    let mut sp = Spooler::default();
    let (top, mut bottom) = (pos(0.0), pos(0.0));
    bottom[2] = -0.02;
    let mut along = bottom;
    along[0] = 0.02;
    let plunge = SpoolElement::line(&top, &bottom, XY, 600.0, false, Origin::Uncorrected);
    let flat = SpoolElement::line(&bottom, &along, XY, 600.0, false, Origin::Uncorrected);
    assert!(plunge.moves_off_plane() && !flat.moves_off_plane());
    sp.push(&top, &bottom, plunge);
    sp.push(&bottom, &along, flat);
    let mut ex = Executor::default();
    ex.step(&mut sp, &mut NoModel);
    assert!((ex.nominal()[2] + 0.01).abs() < 1e-15, "{:?}", ex.nominal());
    ex.step(&mut sp, &mut NoModel);
    assert_eq!(*ex.nominal(), bottom);
    ex.step(&mut sp, &mut NoModel);
    assert!((ex.nominal()[0] - 0.01).abs() < 1e-15 && ex.nominal()[2] == -0.02);
    ex.run_until_empty(&mut sp, &mut NoModel);
    assert_eq!(*ex.nominal(), along);
}
