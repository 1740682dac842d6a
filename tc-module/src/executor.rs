//! The executor: runs spooled elements at their feed, one interpolation
//! cycle at a time. It keeps the
//! nominal path position apart from the executed one: executed = nominal
//! + the offset a per-cycle model (OTC) adds.

use crate::cycle::{Cycle, CycleModel, PathPart, PathParts};
use crate::element::SpoolElement;
use crate::limits::CycleTime;
use crate::plane::{AxisPos, AXES};
use crate::spooler::Spooler;

/// A cycle whose step reaches an element's end point to within this
/// fraction of the step ends exactly on it: the distance run is a sum of
/// steps, and its rounding (a few ulps) must not carry the executor a hair
/// past the end point into the next element, nor leave it a hair short
/// for one more cycle (decision 112; docs/otc.md "Processing types and
/// their directions": a cycle that ends exactly on an end point stands on
/// the element that just ended).
pub const END_POINT_SNAP: f64 = 1e-6;

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
    /// Where the front element starts: the end of the element that ended
    /// last, or where the executor was put (the spooler is a chain).
    entry: AxisPos,
    /// Where the front element ends (kept for the cycle's view of it).
    front_end: AxisPos,
    /// The offset of an active model, from its last cycle.
    offset: Option<AxisPos>,
    /// Path distance already run on the front element.
    done: f64,
    /// Cycle time in minutes (feeds are units/min).
    cycle_min: f64,
    cycles: u64,
    /// The element that ended last (docs/otc.md "What happens in each
    /// interpolation cycle"), with its start; `None` before the first and
    /// after a direct command.
    ended: Option<Ran>,
    /// The path of the current cycle, per element (kept between cycles
    /// only to reuse its storage).
    parts: PathParts,
}

impl Default for Executor {
    fn default() -> Self {
        Self::new([0.0; AXES], CycleTime::DEFAULT)
    }
}

impl Executor {
    /// An executor standing at `pos` with interpolation cycle `cycle`.
    pub fn new(pos: AxisPos, cycle: CycleTime) -> Self {
        Self {
            nominal: pos,
            entry: pos,
            front_end: pos,
            offset: None,
            done: 0.0,
            cycle_min: cycle.minutes(),
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

    /// Moves an axis at once (a direct command; nothing is spooled).
    pub fn set_axis(&mut self, axis: usize, value: f64) {
        self.nominal[axis] = value;
        self.entry[axis] = value;
    }

    /// Forgets the element under way and the one that ended (the spooler
    /// was discarded by a direct command: the executor stands on none, and
    /// the next element starts where it stands).
    pub fn abandon_element(&mut self) {
        self.done = 0.0;
        self.ended = None;
        self.entry = self.nominal;
    }

    /// Moves along the spooler for one cycle: distance left over at the
    /// end of an element carries into the next; elements without length
    /// are passed; with nothing spooled the cycle runs idle. A cycle that
    /// ends exactly on an end point (to within [`END_POINT_SNAP`] of its
    /// step) stands on the element that ended there (decisions 44, 112),
    /// though the next one is already entered.
    /// With `track`, the path per element is kept for a model.
    fn advance(&mut self, spooler: &mut Spooler, track: bool) -> Stand {
        if track {
            self.parts.clear();
        }
        let Some(front) = spooler.front() else {
            return Stand::OnEnded;
        };
        let step = self.step_at(front.feed());
        let snap = step * END_POINT_SNAP;
        let mut budget = step;
        while let Some(e) = spooler.front() {
            let left = e.length() - self.done;
            if budget < left - snap {
                self.done += budget;
                let end = spooler.front_end(&self.entry).unwrap_or(self.entry);
                self.nominal = e.point_at(&self.entry, &end, self.done);
                if budget > 0.0 {
                    if track {
                        self.parts.push(part(e, budget));
                    }
                    return Stand::OnFront;
                }
                return Stand::OnEnded;
            }
            // Within the snap the cycle ends exactly on the end point.
            budget = if budget - left <= snap {
                0.0
            } else {
                budget - left
            };
            if track {
                self.parts.push(part(e, left));
            }
            self.end_front(spooler);
        }
        Stand::OnEnded
    }

    /// The front element ends: the executor stands on its end point, where
    /// the next one starts.
    fn end_front(&mut self, spooler: &mut Spooler) {
        let end = spooler.front_end(&self.entry);
        if let (Some(end), Some(element)) = (end, spooler.pop_front()) {
            self.ended = Some(Ran {
                start: self.entry,
                end,
                element,
            });
            self.nominal = end;
        }
        self.entry = self.nominal;
        self.done = 0.0;
    }

    /// Runs one interpolation cycle; an active model is told of it and its
    /// offset applies from this cycle on (an inactive one has none).
    /// Allocation-free.
    pub fn step<M: CycleModel>(&mut self, spooler: &mut Spooler, model: &mut M) {
        self.cycles = self.cycles.saturating_add(1);
        let active = model.active();
        let stand = self.advance(spooler, active);
        if !active {
            self.offset = None;
            return;
        }
        let on_front = stand == Stand::OnFront;
        self.see_front(spooler);
        let cycle = self.cycle_view(spooler, on_front, self.parts.as_slice());
        self.offset = Some(model.cycle(&cycle));
    }

    /// What a model is told: standing `on_front` (inside the spooler's
    /// front element), the front is current and the element that ended
    /// before it is the previous one; otherwise the element that ended is
    /// current, run to its end.
    /// Keeps where the front element ends, for [`Executor::cycle_view`].
    fn see_front(&mut self, spooler: &Spooler) {
        self.front_end = spooler.front_end(&self.entry).unwrap_or(self.entry);
    }

    fn cycle_view<'a>(
        &'a self,
        spooler: &'a Spooler,
        on_front: bool,
        parts: &'a [PathPart],
    ) -> Cycle<'a> {
        let ended = self.ended.as_ref();
        let (current, (start, end), done, previous) = match spooler.front() {
            Some(front) if on_front => (
                Some(front),
                (&self.entry, &self.front_end),
                self.done,
                ended.map(|e| &e.element),
            ),
            _ => (
                ended.map(|e| &e.element),
                ended.map_or((&self.nominal, &self.nominal), |e| (&e.start, &e.end)),
                ended.map_or(0.0, |e| e.element.length()),
                None,
            ),
        };
        Cycle {
            parts,
            current,
            start,
            end,
            done,
            previous,
            nominal: &self.nominal,
        }
    }

    /// Re-evaluates an active model's offset where the executor stands,
    /// no cycle passing (a direct command moved it at once); drops it when
    /// the model is not active.
    pub fn refresh_offset<M: CycleModel>(&mut self, spooler: &Spooler, model: &mut M) {
        if !model.active() {
            self.offset = None;
            return;
        }
        let inside = self.done > 0.0;
        self.see_front(spooler);
        let cycle = self.cycle_view(spooler, inside, &[]);
        self.offset = Some(model.offset_now(&cycle));
    }

    /// The path step per cycle at `feed` (units/min).
    pub fn step_at(&self, feed: f64) -> f64 {
        feed * self.cycle_min
    }

    /// Whether the executor cannot move on element `e`: its step per
    /// cycle is zero or too small to change the distance run (a feed the
    /// module refuses; elements built by hand may have one).
    fn stuck_on(&self, e: &SpoolElement) -> bool {
        let step = self.step_at(e.feed());
        e.length() > self.done && self.done + step <= self.done
    }

    /// Whether a cycle would move nothing: the spooler is empty or the
    /// executor is stuck on its front element.
    fn stands_still(&self, spooler: &Spooler) -> bool {
        spooler.front().is_none_or(|e| self.stuck_on(e))
    }

    /// Runs `n` cycles. An active model sees every one (but idle cycles
    /// once it is at rest); without one, idle cycles and cycles inside one
    /// long element are counted rather than stepped, so a huge count or a
    /// huge move costs no more than a short one.
    pub fn run<M: CycleModel>(&mut self, spooler: &mut Spooler, n: u64, model: &mut M) {
        self.run_for(spooler, n, model, u64::MAX);
    }

    /// Runs up to `n` cycles, stepping at most `budget` of them for an
    /// active model; returns the cycles left to run (0 when all ran). An
    /// active model at rest on a standing executor has its idle cycles
    /// counted after one stepped cycle. Without an active model the work
    /// is bounded by the elements passed, whatever `n`, and all cycles run.
    pub fn run_for<M: CycleModel>(
        &mut self,
        spooler: &mut Spooler,
        n: u64,
        model: &mut M,
        budget: u64,
    ) -> u64 {
        if model.active() {
            return self.run_stepped(spooler, n, model, budget);
        }
        self.offset = None;
        let mut n = n;
        while n > 0 {
            let Some(e) = spooler.front().filter(|e| !self.stuck_on(e)) else {
                self.cycles = self.cycles.saturating_add(n);
                return 0;
            };
            // Jump all but one of the whole cycles that stay inside; the
            // last is stepped.
            let k = self.whole_cycles_inside(e).min(n).saturating_sub(1);
            if k > 0 {
                self.done += self.step_at(e.feed()) * k as f64;
                let end = spooler.front_end(&self.entry).unwrap_or(self.entry);
                self.nominal = e.point_at(&self.entry, &end, self.done);
                self.cycles = self.cycles.saturating_add(k);
                n -= k;
                continue;
            }
            self.step(spooler, model);
            n -= 1;
        }
        0
    }

    /// Steps up to `n` cycles of an active model, at most `budget`; idle
    /// cycles at rest are counted. Returns the cycles left.
    fn run_stepped<M: CycleModel>(
        &mut self,
        spooler: &mut Spooler,
        n: u64,
        model: &mut M,
        budget: u64,
    ) -> u64 {
        let mut left = n;
        let mut stepped = 0u64;
        while left > 0 {
            if stepped > 0 && self.stands_still(spooler) && model.at_rest() {
                self.cycles = self.cycles.saturating_add(left);
                return 0;
            }
            if stepped == budget {
                return left;
            }
            self.step(spooler, model);
            stepped += 1;
            left -= 1;
        }
        0
    }

    /// Whole cycles that stay strictly inside element `e` from where the
    /// executor stands (0 when fewer than two).
    fn whole_cycles_inside(&self, e: &SpoolElement) -> u64 {
        let budget = self.step_at(e.feed());
        let left = e.length() - self.done;
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
        while !self.run_until_empty_for(spooler, model, u64::MAX) {}
    }

    /// As [`Executor::run_until_empty`], stepping at most `budget` cycles
    /// of an active model; `true` when the spooler is empty. Without an
    /// active model the work is bounded by the elements passed.
    pub fn run_until_empty_for<M: CycleModel>(
        &mut self,
        spooler: &mut Spooler,
        model: &mut M,
        budget: u64,
    ) -> bool {
        if model.active() {
            let mut stepped = 0u64;
            while !spooler.is_empty() {
                if stepped == budget {
                    return false;
                }
                self.step(spooler, model);
                stepped += 1;
            }
            return true;
        }
        self.offset = None;
        let mut time = 0.0;
        while let Some(e) = spooler.front() {
            if e.feed() > 0.0 {
                time += (e.length() - self.done).max(0.0) / self.step_at(e.feed());
            }
            self.end_front(spooler);
        }
        if time.is_finite() {
            self.cycles = self.cycles.saturating_add(time.ceil() as u64);
        }
        true
    }
}

fn part(e: &SpoolElement, length: f64) -> PathPart {
    PathPart {
        origin: e.origin(),
        rapid: e.rapid(),
        length,
    }
}

/// An element that ended, with where it started and ended.
#[derive(Debug, Clone, Copy)]
struct Ran {
    start: AxisPos,
    end: AxisPos,
    element: SpoolElement,
}

#[cfg(test)]
mod tests;
