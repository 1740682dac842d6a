//! The spooler: a FIFO of elements waiting for the executor, with a fixed
//! capacity like a real controller's, plus the spool log that traces
//! check (trc-geometry.md "Spooler and execution").

use std::collections::VecDeque;

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
pub struct Mark {
    queue: usize,
    log: usize,
}

/// The spooler queue and its log.
#[derive(Debug, Clone)]
pub struct Spooler {
    queue: VecDeque<SpoolElement>,
    capacity: usize,
    log: Vec<SpoolElement>,
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

    /// Elements the queue's storage could hold without growing (memory
    /// actually kept; it shrinks when the queue empties).
    pub fn allocated(&self) -> usize {
        self.queue.capacity()
    }

    /// Whether every spooled element is also kept in the log.
    pub fn set_logging(&mut self, on: bool) {
        self.logging = on;
    }

    /// Appends an element. Callers check [`Spooler::free`] first (or push
    /// tentatively and [`Spooler::rollback`]).
    #[inline]
    pub fn push(&mut self, e: SpoolElement) {
        if self.logging {
            self.log.push(e);
        }
        self.queue.push_back(e);
    }

    /// Where the spooler stands now, to undo pushes made after it.
    pub fn mark(&self) -> Mark {
        Mark {
            queue: self.queue.len(),
            log: self.log.len(),
        }
    }

    /// The elements pushed since `mark`.
    pub fn since(&self, mark: Mark) -> impl Iterator<Item = &SpoolElement> {
        self.queue.range(mark.queue.min(self.queue.len())..)
    }

    /// Drops the elements pushed since `mark` (nothing may have left the
    /// queue in between).
    pub fn rollback(&mut self, mark: Mark) {
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
        self.queue.back().map(|e| e.end)
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
    pub fn take_log(&mut self) -> Vec<SpoolElement> {
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

    fn line(x: f64) -> SpoolElement {
        let mut end = [0.0; AXES];
        end[0] = x;
        SpoolElement::line([0.0; AXES], end, 600.0, false, Origin::Uncorrected)
    }

    #[test]
    fn storage_comes_back_when_the_queue_empties() {
        let mut sp = Spooler::with_capacity(MAX_SPOOL_CAPACITY);
        for k in 0..50_000 {
            sp.push(line(f64::from(k)));
        }
        assert!(sp.allocated() >= 50_000);
        while sp.pop_front().is_some() {}
        assert!(sp.allocated() <= KEEP_WHEN_EMPTY, "{}", sp.allocated());
        for k in 0..20_000 {
            sp.push(line(f64::from(k)));
        }
        sp.discard();
        assert!(sp.allocated() <= KEEP_WHEN_EMPTY);
    }

    #[test]
    fn rollback_undoes_tentative_pushes_and_their_log() {
        let mut sp = Spooler::with_capacity(8);
        sp.set_logging(true);
        sp.push(line(1.0));
        let m = sp.mark();
        sp.push(line(2.0));
        sp.push(line(3.0));
        assert_eq!(sp.since(m).count(), 2);
        sp.rollback(m);
        assert_eq!(sp.len(), 1);
        assert_eq!(sp.take_log().len(), 1);
        assert_eq!(sp.free(), 7);
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
