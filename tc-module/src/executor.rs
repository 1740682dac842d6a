//! The executor: runs spooled elements at their feed, one interpolation
//! cycle at a time (trc-geometry.md "Spooler and execution"). It keeps the
//! nominal path position apart from the executed one: executed = nominal
//! + the offset a per-cycle model (OTC) adds.

use crate::cycle::{Cycle, CycleModel, PathPart, PathParts};
use crate::element::SpoolElement;
use crate::plane::{AxisPos, AXES};
use crate::spooler::Spooler;

/// Default interpolation cycle: 1 ms.
pub const DEFAULT_CYCLE_S: f64 = 1e-3;

/// Where a cycle ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stand {
    /// Inside the spooler's front element.
    OnFront,
    /// At the end of the element that ended last (or nowhere yet).
    OnEnded,
}

/// The nominal and executed positions and the progress along the element
/// under way.
#[derive(Debug, Clone)]
pub struct Executor {
    nominal: AxisPos,
    /// The offset of an active model, from its last cycle.
    offset: Option<AxisPos>,
    /// Path distance already run on the front element.
    done: f64,
    /// Cycle time in minutes (feeds are units/min).
    cycle_min: f64,
    cycles: u64,
    /// The element that ended last (otc.md rule 2); `None` before the
    /// first and after a direct command.
    ended: Option<SpoolElement>,
    /// The path of the current cycle, per element (kept between cycles
    /// only to reuse its storage).
    parts: PathParts,
}

impl Default for Executor {
    fn default() -> Self {
        Self::new([0.0; AXES], DEFAULT_CYCLE_S)
    }
}

impl Executor {
    /// An executor standing at `pos` with a cycle of `cycle_s` seconds.
    pub fn new(pos: AxisPos, cycle_s: f64) -> Self {
        Self {
            nominal: pos,
            offset: None,
            done: 0.0,
            cycle_min: cycle_s / 60.0,
            cycles: 0,
            ended: None,
            parts: PathParts::default(),
        }
    }

    /// The executed position: the nominal one plus the model's offset.
    pub fn position(&self) -> AxisPos {
        match &self.offset {
            None => self.nominal,
            Some(o) => std::array::from_fn(|i| self.nominal[i] + o[i]),
        }
    }

    /// The nominal path position (what the spooled elements describe).
    pub fn nominal(&self) -> &AxisPos {
        &self.nominal
    }

    /// The offset an active model added in the last cycle.
    pub fn offset(&self) -> Option<&AxisPos> {
        self.offset.as_ref()
    }

    /// Cycles run so far.
    pub fn cycles(&self) -> u64 {
        self.cycles
    }

    /// Drops the model's offset (the model stopped acting).
    pub fn clear_offset(&mut self) {
        self.offset = None;
    }

    /// Moves an axis at once (a direct command).
    pub fn set_axis(&mut self, axis: usize, value: f64) {
        self.nominal[axis] = value;
    }

    /// Forgets the element under way and the one that ended (the spooler
    /// was discarded by a direct command: the executor stands on none).
    pub fn abandon_element(&mut self) {
        self.done = 0.0;
        self.ended = None;
    }

    /// Moves along the spooler for one cycle: distance left over at the
    /// end of an element carries into the next; elements without length
    /// are passed; with nothing spooled the cycle runs idle. A cycle that
    /// ends exactly on an end point stands on the element that ended
    /// there (otc.md rule 2), though the next one is already entered.
    /// With `track`, the path per element is kept for a model.
    fn advance(&mut self, spooler: &mut Spooler, track: bool) -> Stand {
        if track {
            self.parts.clear();
        }
        let Some(front) = spooler.front() else {
            return Stand::OnEnded;
        };
        let mut budget = front.feed * self.cycle_min;
        while let Some(e) = spooler.front() {
            let left = e.length - self.done;
            if budget < left {
                self.done += budget;
                self.nominal = e.point_at(self.done);
                if budget > 0.0 {
                    if track {
                        self.parts.push(part(e, budget));
                    }
                    return Stand::OnFront;
                }
                return Stand::OnEnded;
            }
            budget -= left;
            if track {
                self.parts.push(part(e, left));
            }
            self.nominal = e.end;
            self.done = 0.0;
            self.ended = spooler.pop_front();
        }
        Stand::OnEnded
    }

    /// Runs one interpolation cycle; an active model is told of it and its
    /// offset applies from this cycle on (an inactive one has none).
    /// Allocation-free.
    pub fn step<M: CycleModel>(&mut self, spooler: &mut Spooler, model: &mut M) {
        self.cycles += 1;
        let active = model.active();
        let stand = self.advance(spooler, active);
        if !active {
            self.offset = None;
            return;
        }
        let (current, done) = match stand {
            Stand::OnFront => (spooler.front(), self.done),
            Stand::OnEnded => (self.ended.as_ref(), self.ended.map_or(0.0, |e| e.length)),
        };
        self.offset = Some(model.cycle(&Cycle {
            parts: self.parts.as_slice(),
            current,
            done,
            nominal: &self.nominal,
        }));
    }

    /// Runs `n` cycles. An active model sees every one; without one, idle
    /// cycles and cycles inside one long element are counted rather than
    /// stepped, so a huge count or a huge move costs no more than a short
    /// one.
    pub fn run<M: CycleModel>(&mut self, spooler: &mut Spooler, n: u64, model: &mut M) {
        if model.active() {
            for _ in 0..n {
                self.step(spooler, model);
            }
            return;
        }
        self.offset = None;
        let mut n = n;
        while n > 0 {
            let Some(e) = spooler.front() else {
                self.cycles = self.cycles.saturating_add(n);
                return;
            };
            // Jump all but one of the whole cycles that stay inside; the
            // last is stepped.
            let k = self.whole_cycles_inside(e).min(n).saturating_sub(1);
            if k > 0 {
                self.done += e.feed * self.cycle_min * k as f64;
                self.nominal = e.point_at(self.done);
                self.cycles += k;
                n -= k;
                continue;
            }
            self.step(spooler, model);
            n -= 1;
        }
    }

    /// Whole cycles that stay strictly inside element `e` from where the
    /// executor stands (0 when fewer than two).
    fn whole_cycles_inside(&self, e: &SpoolElement) -> u64 {
        let budget = e.feed * self.cycle_min;
        let left = e.length - self.done;
        let inside = if budget > 0.0 {
            (left / budget).ceil() - 1.0
        } else {
            0.0
        };
        if inside >= 2.0 {
            // Saturating float-to-int conversion.
            inside as u64
        } else {
            0
        }
    }

    /// Runs until the spooler is empty: every element ends exactly on its
    /// end point. An active model sees every cycle; without one, whole
    /// elements are jumped over and the cycle count advanced as stepping
    /// would have (up to the carry of the last partial cycle).
    pub fn run_until_empty<M: CycleModel>(&mut self, spooler: &mut Spooler, model: &mut M) {
        if model.active() {
            while !spooler.is_empty() {
                self.step(spooler, model);
            }
            return;
        }
        self.offset = None;
        let mut time = 0.0;
        while let Some(e) = spooler.pop_front() {
            if e.feed > 0.0 {
                time += (e.length - self.done).max(0.0) / (e.feed * self.cycle_min);
            }
            self.nominal = e.end;
            self.done = 0.0;
            self.ended = Some(e);
        }
        if time.is_finite() {
            self.cycles = self.cycles.saturating_add(time.ceil() as u64);
        }
    }
}

fn part(e: &SpoolElement, length: f64) -> PathPart {
    PathPart {
        origin: e.origin,
        rapid: e.rapid,
        length,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cycle::NoModel;
    use crate::element::Origin;

    fn pos(x: f64) -> AxisPos {
        let mut p = [0.0; AXES];
        p[0] = x;
        p
    }

    fn line(a: f64, b: f64) -> SpoolElement {
        SpoolElement::line(pos(a), pos(b), 600.0, false, Origin::Uncorrected)
    }

    #[test]
    fn steps_at_feed_and_carries_over() {
        let mut sp = Spooler::default();
        // 600 units/min = 0.01 per ms
        sp.push(line(0.0, 0.015));
        sp.push(line(0.015, 1.0));
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
        sp.push(line(1.0, 1e12));
        ex.run(&mut sp, 1_000_000_000_000, &mut NoModel);
        assert!((ex.position()[0] - (1e10 + 1.0)).abs() < 1e-2);
        ex.run_until_empty(&mut sp, &mut NoModel);
        assert_eq!(ex.position()[0], 1e12);
        assert!(sp.is_empty());
    }
}
