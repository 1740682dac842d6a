//! The spooler: a FIFO of elements waiting for the executor, with a fixed
//! capacity like a real controller's, plus the spool log that traces
//! check (docs/objects.md "Limits of motion commands"). The elements form
//! a chain: each starts where the one before it ends, and ends where it
//! starts on the axes outside its plane unless it moves them; only for
//! those elements does the spooler keep the end of every axis.

use std::collections::VecDeque;

use tc_request::SpoolRecord;

use crate::element::SpoolElement;
use crate::plane::{AxisPos, AXES};

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
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Mark {
    queue: usize,
    ends: usize,
    log: usize,
    tail: AxisPos,
}

/// An element as the spool log keeps it: with where it starts and ends
/// on every axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Logged {
    /// Where the element starts (the end of the one before it, or where
    /// the executor stood).
    pub start: AxisPos,
    /// Where it ends.
    pub end: AxisPos,
    /// The element.
    pub element: SpoolElement,
}

impl Logged {
    /// The element as it is reported (spool log, wire).
    pub fn record(&self) -> SpoolRecord {
        self.element.record(&self.start, &self.end)
    }
}

/// The spooler queue and its log.
#[derive(Debug, Clone)]
pub struct Spooler {
    queue: VecDeque<SpoolElement>,
    /// The ends (every axis) of the waiting elements that move an axis
    /// outside their plane, in the queue's order.
    ends: VecDeque<AxisPos>,
    /// Where the last waiting element ends: where the next one starts
    /// (set by [`Spooler::start_at`] while nothing waits).
    tail: AxisPos,
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
            ends: VecDeque::new(),
            tail: [0.0; AXES],
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

    /// The one capacity rule: whether the elements waiting (those just
    /// spooled by a profile not yet admitted included) and `places` more
    /// fit. Not `places <= free()`: `free` saturates at 0, so a queue
    /// already past its capacity would still have room for nothing more.
    #[inline]
    pub fn has_room(&self, places: usize) -> bool {
        self.queue.len().saturating_add(places) <= self.capacity
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

    /// Appends an element that runs from `start` (the end of the last
    /// waiting element, or where the executor stands when none waits) to
    /// `end`. Callers check [`Spooler::has_room`] first (the correction
    /// pushes tentatively and takes back what it does not admit).
    #[inline]
    pub fn push(&mut self, start: &AxisPos, end: &AxisPos, element: SpoolElement) {
        debug_assert!(self.last_end().is_none_or(|tail| tail == *start));
        debug_assert!(element.plane().point(end) == element.to());
        if self.logging {
            self.log.push(Logged {
                start: *start,
                end: *end,
                element,
            });
        }
        if element.moves_off_plane() {
            self.ends.push_back(*end);
        }
        self.queue.push_back(element);
        self.tail = *end;
    }

    /// The next element starts at `q`: where the executor stands when
    /// nothing waits (else the end of the last waiting element, which `q`
    /// then is).
    #[inline]
    pub(crate) fn start_at(&mut self, q: &AxisPos) {
        debug_assert!(self.last_end().is_none_or(|tail| tail == *q));
        self.tail = *q;
    }

    /// Where the next element starts (see [`Spooler::start_at`]).
    #[inline]
    pub(crate) fn tail(&self) -> &AxisPos {
        &self.tail
    }

    /// Appends an element that moves no axis outside its plane, from where
    /// the next element starts ([`Spooler::start_at`]).
    #[inline]
    pub(crate) fn push_in_plane(&mut self, element: SpoolElement) {
        debug_assert!(!element.moves_off_plane());
        if self.logging {
            let start = self.tail;
            let mut end = start;
            element.plane().set_point(&mut end, element.to());
            self.log.push(Logged {
                start,
                end,
                element,
            });
        }
        self.queue.push_back(element);
        element.plane().set_point(&mut self.tail, element.to());
    }

    /// Where the front element ends, when it starts at `start` (where the
    /// executor entered it).
    #[inline]
    pub fn front_end(&self, start: &AxisPos) -> Option<AxisPos> {
        let e = self.queue.front()?;
        if e.moves_off_plane() {
            return self.ends.front().copied();
        }
        let mut end = *start;
        e.plane().set_point(&mut end, e.to());
        Some(end)
    }

    /// Where the spooler stands now, to undo pushes made after it.
    pub(crate) fn mark(&self) -> Mark {
        Mark {
            queue: self.queue.len(),
            ends: self.ends.len(),
            log: self.log.len(),
            tail: self.tail,
        }
    }

    /// Drops the elements pushed since `mark` (nothing may have left the
    /// queue in between).
    pub(crate) fn rollback(&mut self, mark: Mark) {
        self.queue.truncate(mark.queue);
        self.ends.truncate(mark.ends);
        self.log.truncate(mark.log);
        self.tail = mark.tail;
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
        (!self.queue.is_empty()).then_some(self.tail)
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
        let e = self.queue.pop_front()?;
        if e.moves_off_plane() {
            self.ends.pop_front();
        }
        if self.queue.is_empty() {
            self.give_back();
        }
        Some(e)
    }

    /// Discards every waiting element (direct commands).
    pub fn discard(&mut self) {
        self.queue.clear();
        self.ends.clear();
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
        if self.ends.capacity() > KEEP_WHEN_EMPTY {
            self.ends.shrink_to(KEEP_WHEN_EMPTY);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::Origin;
    use crate::plane::PlaneAxes;

    fn at(x: f64) -> AxisPos {
        let mut p = [0.0; AXES];
        p[0] = x;
        p
    }

    const XY: PlaneAxes = PlaneAxes {
        h: 0,
        v: 1,
        third: 2,
    };

    /// Pushes a line along X to `x`, from the last end (or 0).
    fn push_line(sp: &mut Spooler, x: f64) {
        let start = sp.last_end().unwrap_or([0.0; AXES]);
        let end = at(x);
        let e = SpoolElement::line(&start, &end, XY, 600.0, false, Origin::Uncorrected);
        sp.push(&start, &end, e);
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
    fn a_queue_pushed_past_its_capacity_has_no_room_even_for_nothing() {
        let mut sp = Spooler::with_capacity(8);
        for i in 0..8 {
            push_line(&mut sp, f64::from(i));
        }
        assert!(sp.has_room(0) && !sp.has_room(1));
        // A profile spools tentatively before it is admitted.
        push_line(&mut sp, 9.0);
        assert_eq!(sp.free(), 0);
        assert!(!sp.has_room(0));
    }

    #[test]
    fn whole_ends_are_kept_only_where_axes_outside_the_plane_move() {
        let mut sp = Spooler::with_capacity(8);
        let start = [0.0; AXES];
        let (flat, mut plunge) = (at(1.0), at(1.0));
        plunge[2] = -2.0;
        let e = SpoolElement::line(&start, &flat, XY, 600.0, false, Origin::Uncorrected);
        assert!(!e.moves_off_plane());
        sp.push(&start, &flat, e);
        let m = sp.mark();
        let e = SpoolElement::line(&flat, &plunge, XY, 600.0, false, Origin::Uncorrected);
        assert!(e.moves_off_plane());
        sp.push(&flat, &plunge, e);
        assert_eq!((sp.ends.len(), sp.last_end()), (1, Some(plunge)));
        sp.rollback(m);
        assert_eq!((sp.ends.len(), sp.last_end()), (0, Some(flat)));
        sp.push(&flat, &plunge, e);
        assert_eq!(sp.front_end(&start), Some(flat));
        sp.pop_front();
        assert_eq!(sp.front_end(&flat), Some(plunge));
        sp.pop_front();
        assert_eq!((sp.ends.len(), sp.front_end(&plunge)), (0, None));
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
