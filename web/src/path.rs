//! The path the page draws, kept while a page is open: the spooled
//! (corrected) elements as they entered the spooler and the executed
//! trail, both in the main plane. Bounded: past [`MAX_KEPT`] the oldest
//! entries go. Every entry has a sequence number, so each page asks for
//! what came after the last one it got.

use std::collections::VecDeque;

use serde::Serialize;
use tc_request::SpoolRecord;

use crate::snapshot::Plane;

/// Most spooled elements, and most executed points, kept.
pub const MAX_KEPT: usize = 500_000;

/// Most entries of each kind one update carries; a page that is behind
/// gets the rest in the next ones.
pub const MAX_PER_UPDATE: usize = 20_000;

/// A spooled element in the main plane.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Element {
    /// Start `[h, v]`.
    pub from: [f64; 2],
    /// End `[h, v]`.
    pub to: [f64; 2],
    /// An arc in the main plane: centre `[h, v]` and counter-clockwise.
    pub arc: Option<([f64; 2], bool)>,
    /// A rapid move (drawn dashed).
    pub rapid: bool,
}

impl Element {
    /// `r` seen in `plane`; an arc in another plane is drawn as its chord.
    pub fn of(r: &SpoolRecord, plane: Plane) -> Self {
        let (h, v) = (usize::from(plane.h), usize::from(plane.v));
        let at = |p: &tc_request::AxisPos| [p[h], p[v]];
        let arc = r
            .arc
            .filter(|a| a.plane[0] == plane.h && a.plane[1] == plane.v)
            .map(|a| (a.centre, a.ccw));
        Self {
            from: at(&r.start),
            to: at(&r.end),
            arc,
            rapid: r.rapid,
        }
    }
}

/// Entries of one kind with sequence numbers.
#[derive(Debug, Clone)]
struct Numbered<T> {
    /// The sequence number of the first entry kept.
    first: u64,
    items: VecDeque<T>,
}

impl<T: Clone> Numbered<T> {
    fn new() -> Self {
        Self {
            first: 0,
            items: VecDeque::new(),
        }
    }

    /// The sequence number the next entry gets.
    fn next(&self) -> u64 {
        self.first + self.items.len() as u64
    }

    fn push(&mut self, item: T) {
        if self.items.len() >= MAX_KEPT {
            self.items.pop_front();
            self.first += 1;
        }
        self.items.push_back(item);
    }

    /// The entries from sequence number `from` (or the oldest kept), at
    /// most [`MAX_PER_UPDATE`], and the number after them.
    fn since(&self, from: u64) -> (Vec<T>, u64) {
        let start = from.max(self.first);
        let skip = usize::try_from(start - self.first).unwrap_or(usize::MAX);
        let items: Vec<T> = self
            .items
            .iter()
            .skip(skip)
            .take(MAX_PER_UPDATE)
            .cloned()
            .collect();
        let end = start + items.len() as u64;
        (items, end)
    }
}

/// The spooled elements and the executed trail.
#[derive(Debug, Clone)]
pub struct PathLog {
    spooled: Numbered<Element>,
    executed: Numbered<[f64; 2]>,
    /// Spooled elements that were not kept for the view.
    pub missed: u64,
}

impl Default for PathLog {
    fn default() -> Self {
        Self {
            spooled: Numbered::new(),
            executed: Numbered::new(),
            missed: 0,
        }
    }
}

/// Where a page stands in the log: the next entry of each kind it needs.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Cursor {
    /// The next spooled element.
    pub spooled: u64,
    /// The next executed point.
    pub executed: u64,
}

/// What a page gets of the path in one update.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PathUpdate {
    /// New spooled elements.
    pub spooled: Vec<Element>,
    /// New executed points `[h, v]`.
    pub executed: Vec<[f64; 2]>,
}

impl PathUpdate {
    /// Whether it carries nothing.
    pub fn is_empty(&self) -> bool {
        self.spooled.is_empty() && self.executed.is_empty()
    }
}

impl PathLog {
    /// Appends a spooled element.
    pub fn spooled(&mut self, e: Element) {
        self.spooled.push(e);
    }

    /// Appends an executed position, unless it is where the trail stands.
    pub fn executed(&mut self, at: [f64; 2]) {
        if self.executed.items.back() != Some(&at) {
            self.executed.push(at);
        }
    }

    /// The cursor after everything kept.
    pub fn end(&self) -> Cursor {
        Cursor {
            spooled: self.spooled.next(),
            executed: self.executed.next(),
        }
    }

    /// What came after `c`, and the cursor after it.
    pub fn since(&self, c: Cursor) -> (PathUpdate, Cursor) {
        let (spooled, s) = self.spooled.since(c.spooled);
        let (executed, x) = self.executed.since(c.executed);
        (
            PathUpdate { spooled, executed },
            Cursor {
                spooled: s,
                executed: x,
            },
        )
    }

    /// Elements kept (spooled, executed points).
    pub fn len(&self) -> (usize, usize) {
        (self.spooled.items.len(), self.executed.items.len())
    }

    /// Whether nothing is kept.
    pub fn is_empty(&self) -> bool {
        self.len() == (0, 0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_page_gets_each_entry_once_and_a_late_one_the_oldest_kept() {
        let mut log = PathLog::default();
        for i in 0..3 {
            log.executed([f64::from(i), 0.0]);
        }
        log.executed([2.0, 0.0]);
        let (u, c) = log.since(Cursor::default());
        assert_eq!(u.executed.len(), 3, "a repeated position is not kept");
        let (again, c2) = log.since(c);
        assert!(again.is_empty());
        assert_eq!(c, c2);
        for i in 0..MAX_KEPT {
            log.executed([i as f64 + 10.0, 1.0]);
        }
        let (u, c3) = log.since(c);
        assert_eq!(u.executed.len(), MAX_PER_UPDATE);
        assert_eq!(u.executed[0], [10.0, 1.0]);
        assert_eq!(c3.executed, c.executed + MAX_PER_UPDATE as u64);
        assert_eq!(log.len().1, MAX_KEPT);
    }
}
