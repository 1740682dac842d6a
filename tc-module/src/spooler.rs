//! The spooler: a FIFO of elements waiting for the executor, with a fixed
//! capacity like a real controller's, plus the spool log that traces
//! check (docs/objects.md "Limits of motion commands"). The elements form
//! a chain: each starts where the one before it ends.

use std::collections::VecDeque;

use tc_request::SpoolRecord;

use crate::element::SpoolElement;
use crate::plane::AxisPos;

/// Default capacity: elements the spooler holds.
pub const DEFAULT_SPOOL_CAPACITY: usize = 100_000;

/// Smallest capacity allowed: one corrected profile spools at most 5
/// elements at once (held profile 2, transition 3) and keeps 2 in
/// reserve for the profile it holds next.
pub const MIN_SPOOL_CAPACITY: usize = 8;

/// Largest capacity allowed (about 250 MB of elements).
pub const MAX_SPOOL_CAPACITY: usize = 1_000_000;

/// Storage kept when the queue empties; more is given back.
pub const KEEP_WHEN_EMPTY: usize = 1024;

/// A spooler capacity outside
/// [`MIN_SPOOL_CAPACITY`]..=[`MAX_SPOOL_CAPACITY`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error(
    "spooler capacity {0}: it must lie in {MIN_SPOOL_CAPACITY}..={MAX_SPOOL_CAPACITY} elements"
)]
pub struct CapacityError(pub u64);

/// The one check of a spooler capacity (settings, `SETUP`, trace header).
pub fn check_capacity(n: u64) -> Result<usize, CapacityError> {
    usize::try_from(n)
        .ok()
        .filter(|c| (MIN_SPOOL_CAPACITY..=MAX_SPOOL_CAPACITY).contains(c))
        .ok_or(CapacityError(n))
}

/// Where the spooler stood before a tentative push ([`Spooler::mark`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Mark {
    queue: usize,
    log: usize,
}

/// An element as the spool log keeps it: with the position it starts
/// from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Logged {
    /// Where the element starts (the end of the one before it, or where
    /// the executor stood).
    pub start: AxisPos,
    /// The element.
    pub element: SpoolElement,
}

impl Logged {
    /// The element as it is reported (spool log, wire).
    pub fn record(&self) -> SpoolRecord {
        self.element.record(&self.start)
    }
}

/// The spooler queue and its log.
#[derive(Debug, Clone)]
pub struct Spooler {
    queue: VecDeque<SpoolElement>,
    capacity: usize,
    log: Vec<Logged>,
    logging: bool,
}

impl Default for Spooler {
    fn default() -> Self {
        Self::with_capacity(DEFAULT_SPOOL_CAPACITY)
    }
}

impl Spooler {
    /// An empty spooler holding at most `capacity` elements (checked by
    /// [`check_capacity`] where it comes from outside).
    pub fn with_capacity(capacity: usize) -> Self {
        Self {
            queue: VecDeque::new(),
            capacity,
            log: Vec::new(),
            logging: false,
        }
    }

    /// Elements it holds at most.
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// Places free.
    pub fn free(&self) -> usize {
        self.capacity.saturating_sub(self.queue.len())
    }

    /// The one capacity rule: whether `places` more elements fit.
    #[inline]
    pub fn has_room(&self, places: usize) -> bool {
        places <= self.free()
    }

    /// Elements the queue's storage could hold without growing (memory
    /// actually kept; it shrinks when the queue empties).
    pub fn allocated(&self) -> usize {
        self.queue.capacity()
    }

    /// Whether every spooled element is also kept in the log.
    pub fn set_logging(&mut self, on: bool) {
        self.logging = on;
    }

    /// Appends an element that starts at `start`: the end of the last
    /// waiting element, or where the executor stands when none waits.
    /// Callers check [`Spooler::has_room`] first (the correction pushes
    /// tentatively and takes back what it does not admit).
    #[inline]
    pub fn push(&mut self, start: &AxisPos, element: SpoolElement) {
        debug_assert!(self.last_end().is_none_or(|end| end == *start));
        if self.logging {
            self.log.push(Logged {
                start: *start,
                element,
            });
        }
        self.queue.push_back(element);
    }

    /// Where the spooler stands now, to undo pushes made after it.
    pub(crate) fn mark(&self) -> Mark {
        Mark {
            queue: self.queue.len(),
            log: self.log.len(),
        }
    }

    /// Drops the elements pushed since `mark` (nothing may have left the
    /// queue in between).
    pub(crate) fn rollback(&mut self, mark: Mark) {
        self.queue.truncate(mark.queue);
        self.log.truncate(mark.log);
    }

    /// Elements waiting (the one under way included).
    #[inline]
    pub fn len(&self) -> usize {
        self.queue.len()
    }

    /// Whether nothing waits.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.queue.is_empty()
    }

    /// The end of the last waiting element.
    #[inline]
    pub fn last_end(&self) -> Option<AxisPos> {
        self.queue.back().map(|e| *e.end())
    }

    /// The element under way.
    #[inline]
    pub fn front(&self) -> Option<&SpoolElement> {
        self.queue.front()
    }

    /// Removes the element under way; an emptied queue gives back large
    /// storage.
    #[inline]
    pub fn pop_front(&mut self) -> Option<SpoolElement> {
        let e = self.queue.pop_front();
        if self.queue.is_empty() {
            self.give_back();
        }
        e
    }

    /// Discards every waiting element (direct commands).
    pub fn discard(&mut self) {
        self.queue.clear();
        self.give_back();
    }

    /// Takes the log collected so far.
    pub fn take_log(&mut self) -> Vec<Logged> {
        std::mem::take(&mut self.log)
    }

    /// Shrinks the storage of an empty queue that grew large.
    fn give_back(&mut self) {
        if self.queue.capacity() > KEEP_WHEN_EMPTY {
            self.queue.shrink_to(KEEP_WHEN_EMPTY);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::Origin;
    use crate::plane::AXES;

    fn at(x: f64) -> AxisPos {
        let mut p = [0.0; AXES];
        p[0] = x;
        p
    }

    /// Pushes a line along X to `x`, from the last end (or 0).
    fn push_line(sp: &mut Spooler, x: f64) {
        let start = sp.last_end().unwrap_or([0.0; AXES]);
        let e = SpoolElement::line(&start, at(x), 600.0, false, Origin::Uncorrected);
        sp.push(&start, e);
    }

    #[test]
    fn storage_comes_back_when_the_queue_empties() {
        let mut sp = Spooler::with_capacity(MAX_SPOOL_CAPACITY);
        for k in 0..50_000 {
            push_line(&mut sp, f64::from(k));
        }
        assert!(sp.allocated() >= 50_000);
        while sp.pop_front().is_some() {}
        assert!(sp.allocated() <= KEEP_WHEN_EMPTY, "{}", sp.allocated());
        for k in 0..20_000 {
            push_line(&mut sp, f64::from(k));
        }
        sp.discard();
        assert!(sp.allocated() <= KEEP_WHEN_EMPTY);
    }

    #[test]
    fn rollback_undoes_tentative_pushes_and_their_log() {
        let mut sp = Spooler::with_capacity(8);
        sp.set_logging(true);
        push_line(&mut sp, 1.0);
        let m = sp.mark();
        push_line(&mut sp, 2.0);
        push_line(&mut sp, 3.0);
        assert_eq!(sp.len(), 3);
        sp.rollback(m);
        assert_eq!(sp.len(), 1);
        let log = sp.take_log();
        assert_eq!(log.len(), 1);
        assert_eq!(log[0].record().end[0], 1.0);
        assert_eq!(sp.free(), 7);
        assert!(sp.has_room(7) && !sp.has_room(8));
    }

    #[test]
    fn capacities_are_checked() {
        assert_eq!(check_capacity(8), Ok(8));
        assert_eq!(check_capacity(100_000), Ok(100_000));
        assert!(check_capacity(7).is_err());
        assert!(check_capacity(0).is_err());
        assert!(check_capacity(u64::MAX).is_err());
    }
}
