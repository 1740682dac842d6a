//! The executor: runs spooled elements at their feed, one interpolation
//! cycle at a time, and keeps the executed position
//! (trc-geometry.md "Spooler and execution").

use crate::plane::{AxisPos, AXES};
use crate::spooler::Spooler;

/// Default interpolation cycle: 1 ms.
pub const DEFAULT_CYCLE_S: f64 = 1e-3;

/// The executed position and the progress along the element under way.
#[derive(Debug, Clone, PartialEq)]
pub struct Executor {
    pos: AxisPos,
    /// Path distance already run on the front element.
    done: f64,
    /// Cycle time in minutes (feeds are units/min).
    cycle_min: f64,
    cycles: u64,
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
            pos,
            done: 0.0,
            cycle_min: cycle_s / 60.0,
            cycles: 0,
        }
    }

    /// The executed position.
    pub fn position(&self) -> &AxisPos {
        &self.pos
    }

    /// Cycles run so far.
    pub fn cycles(&self) -> u64 {
        self.cycles
    }

    /// Moves axes at once (a direct command), forgetting the element under way.
    pub fn set_axis(&mut self, axis: usize, value: f64) {
        self.pos[axis] = value;
    }

    /// Forgets progress along the element under way (the spooler was discarded).
    pub fn abandon_element(&mut self) {
        self.done = 0.0;
    }

    /// Runs one interpolation cycle. Distance left over at the end of an
    /// element carries into the next; with nothing spooled the cycle runs
    /// idle. Allocation-free.
    pub fn step(&mut self, spooler: &mut Spooler) {
        self.cycles += 1;
        let Some(front) = spooler.front() else { return };
        let mut budget = front.feed * self.cycle_min;
        while let Some(e) = spooler.front() {
            let left = e.length - self.done;
            if budget < left {
                self.done += budget;
                self.pos = e.point_at(self.done);
                break;
            }
            budget -= left;
            self.pos = e.end;
            self.done = 0.0;
            spooler.pop_front();
        }
    }

    /// Runs `n` cycles. Idle cycles and cycles inside one long element are
    /// counted rather than stepped one by one, so a huge count or a huge
    /// move costs no more than a short one.
    pub fn run(&mut self, spooler: &mut Spooler, n: u64) {
        let mut n = n;
        while n > 0 {
            let Some(e) = spooler.front() else {
                self.cycles = self.cycles.saturating_add(n);
                return;
            };
            let budget = e.feed * self.cycle_min;
            let left = e.length - self.done;
            // Whole cycles that stay strictly inside the element.
            let inside = if budget > 0.0 {
                (left / budget).ceil() - 1.0
            } else {
                0.0
            };
            if inside >= 2.0 {
                let k = (inside as u64).min(n) - 1;
                if k > 0 {
                    self.done += budget * k as f64;
                    self.pos = e.point_at(self.done);
                    self.cycles += k;
                    n -= k;
                    continue;
                }
            }
            self.step(spooler);
            n -= 1;
        }
    }

    /// Runs until the spooler is empty: every element ends exactly on its
    /// end point. Whole elements are jumped over rather than stepped, so a
    /// huge move finishes at once; the cycle count is advanced as stepping
    /// would have (up to the carry of the last partial cycle).
    pub fn run_until_empty(&mut self, spooler: &mut Spooler) {
        let mut time = 0.0;
        while let Some(e) = spooler.pop_front() {
            if e.feed > 0.0 {
                time += (e.length - self.done).max(0.0) / (e.feed * self.cycle_min);
            }
            self.pos = e.end;
            self.done = 0.0;
        }
        if time.is_finite() {
            self.cycles = self.cycles.saturating_add(time.ceil() as u64);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spooler::{Origin, SpoolElement};

    fn pos(x: f64) -> AxisPos {
        let mut p = [0.0; AXES];
        p[0] = x;
        p
    }

    #[test]
    fn steps_at_feed_and_carries_over() {
        let mut sp = Spooler::default();
        // 600 units/min = 0.01 per ms
        sp.push(SpoolElement::line(
            pos(0.0),
            pos(0.015),
            600.0,
            false,
            Origin::Plain,
        ));
        sp.push(SpoolElement::line(
            pos(0.015),
            pos(1.0),
            600.0,
            false,
            Origin::Plain,
        ));
        let mut ex = Executor::default();
        ex.step(&mut sp);
        assert!((ex.position()[0] - 0.01).abs() < 1e-12);
        ex.step(&mut sp);
        assert!((ex.position()[0] - 0.02).abs() < 1e-12);
        assert_eq!(sp.len(), 1);
        ex.run(&mut sp, 10);
        assert!((ex.position()[0] - 0.12).abs() < 1e-12);
        ex.run(&mut sp, u64::MAX / 2);
        assert_eq!(ex.position()[0], 1.0);
        assert!(sp.is_empty());
        sp.push(SpoolElement::line(
            pos(1.0),
            pos(1e12),
            600.0,
            false,
            Origin::Plain,
        ));
        ex.run(&mut sp, 1_000_000_000_000);
        assert!((ex.position()[0] - (1e10 + 1.0)).abs() < 1e-2);
        ex.run_until_empty(&mut sp);
        assert_eq!(ex.position()[0], 1e12);
        assert!(sp.is_empty());
    }
}
