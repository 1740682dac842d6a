//! The per-cycle seam, one trait ([`CycleModel`]) with one set of names
//! from the executor to the extension: what a model that acts on every
//! interpolation cycle (OTC's wear model) is told, and what it answers —
//! an offset added to the nominal path position to give the executed
//! position. An extension hands its model to the module over the groups
//! ([`TcExtension::cycle_model`](crate::TcExtension::cycle_model)).

use crate::element::{Origin, SpoolElement};
use crate::plane::{AxisPos, AXES};

/// Path travelled in one cycle on one element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathPart {
    /// The element's origin tag.
    pub origin: Origin,
    /// Whether the element is a rapid move.
    pub rapid: bool,
    /// Distance travelled on it in this cycle.
    pub length: f64,
}

// Merging by tag must free room.
const _: () = assert!(2 * Origin::ALL.len() < MAX_PARTS);

/// Most parts one cycle reports one by one. A cycle that crosses more
/// elements than this (tiny elements at a high feed) has its parts merged
/// by tag, so the distance per tag stays exact and memory stays bounded.
pub const MAX_PARTS: usize = 16;

/// The parts of one cycle, in the order travelled; allocation-free.
#[derive(Debug, Clone, Copy)]
pub struct PathParts {
    parts: [PathPart; MAX_PARTS],
    len: usize,
}

impl Default for PathParts {
    fn default() -> Self {
        Self {
            parts: [PathPart {
                origin: Origin::Uncorrected,
                rapid: false,
                length: 0.0,
            }; MAX_PARTS],
            len: 0,
        }
    }
}

impl PathParts {
    /// Forgets the parts of the previous cycle.
    pub fn clear(&mut self) {
        self.len = 0;
    }

    /// Adds a part; when full, merges the parts by tag first.
    pub fn push(&mut self, part: PathPart) {
        if self.len == MAX_PARTS {
            self.merge_by_tag();
        }
        self.parts[self.len] = part;
        self.len += 1;
    }

    /// Merges parts with the same tag, keeping the order of first travel.
    /// There are fewer tags (5 origins × rapid or not) than [`MAX_PARTS`],
    /// so this always frees room.
    fn merge_by_tag(&mut self) {
        let mut n = 0;
        for k in 0..self.len {
            let p = self.parts[k];
            match self.parts[..n].iter_mut().find(|q| same_tag(q, &p)) {
                Some(q) => q.length += p.length,
                None => {
                    self.parts[n] = p;
                    n += 1;
                }
            }
        }
        self.len = n;
    }

    /// The parts, in order.
    pub fn as_slice(&self) -> &[PathPart] {
        &self.parts[..self.len]
    }
}

fn same_tag(a: &PathPart, b: &PathPart) -> bool {
    a.origin == b.origin && a.rapid == b.rapid
}

/// What a model is told about one interpolation cycle.
#[derive(Debug, Clone, Copy)]
pub struct Cycle<'a> {
    /// The path travelled in this cycle, per element, in order (empty when
    /// nothing moved).
    pub parts: &'a [PathPart],
    /// The current element at the cycle's end (docs/otc.md "What happens
    /// in each interpolation cycle"): the one the executor stands on, or
    /// the one that just ended when the cycle ended exactly on its end
    /// point (or nothing follows it). `None` before the first element.
    pub current: Option<&'a SpoolElement>,
    /// Where the current element starts (all axes; the nominal position
    /// when there is none).
    pub start: &'a AxisPos,
    /// Where it ends (all axes; the nominal position when there is none).
    pub end: &'a AxisPos,
    /// Path distance run on the current element.
    pub done: f64,
    /// The element that ended before the current one, while the executor
    /// stands inside the current one (`None` when the current element has
    /// just ended, before the first element and after a direct command).
    pub previous: Option<&'a SpoolElement>,
    /// The nominal path position of all axes at the cycle's end.
    pub nominal: &'a AxisPos,
}

impl Cycle<'_> {
    /// The unit path tangent of the current element at the cycle's end.
    #[inline]
    pub fn tangent(&self) -> Option<AxisPos> {
        self.current
            .map(|e| e.tangent_through(self.start, self.end, self.done, self.nominal))
    }

    /// The path direction of the current element at the cycle's end, not
    /// normalised: the tangent times the element's length (see
    /// [`SpoolElement::direction_through`]), for models that normalise only
    /// the axes they need.
    #[inline]
    pub fn direction(&self) -> Option<AxisPos> {
        self.current
            .map(|e| e.direction_through(self.start, self.end, self.done, self.nominal))
    }

    /// The contour normal at the cycle's end (side normal of a corrected
    /// line, radial on an arc, from the programmed corner on a
    /// transition; the normal an approach leads onto or a departure
    /// leaves), or `None` on elements the correction did not spool.
    #[inline]
    pub fn normal(&self) -> Option<AxisPos> {
        self.current.and_then(|e| e.normal_at(self.nominal))
    }
}

/// A model evaluated once per interpolation cycle. It allocates nothing.
pub trait CycleModel {
    /// Whether the model needs every cycle now. While it does not, the
    /// executor may count idle cycles and jump along elements.
    fn active(&self) -> bool;

    /// One cycle: returns the offset to add to the nominal position.
    fn cycle(&mut self, cycle: &Cycle<'_>) -> AxisPos;

    /// Whether the model is at rest: a cycle in which nothing moves would
    /// change neither its state nor its offset. Asked after a stepped
    /// cycle while the executor stands still; when it is, the remaining
    /// idle cycles of an `EXEC n` are counted, not stepped. The
    /// conservative default says no.
    fn at_rest(&mut self) -> bool {
        false
    }

    /// The offset for the model's state as it stands, no cycle passing:
    /// asked when a direct command has moved the executor at once
    /// (`cycle.parts` is empty). Default: no offset.
    fn offset_now(&mut self, _cycle: &Cycle<'_>) -> AxisPos {
        [0.0; AXES]
    }
}

/// A model lent for a while (an extension lends itself as its own model,
/// [`TcExtension::cycle_model`](crate::TcExtension::cycle_model)).
impl<M: CycleModel + ?Sized> CycleModel for &mut M {
    fn active(&self) -> bool {
        (**self).active()
    }

    fn cycle(&mut self, cycle: &Cycle<'_>) -> AxisPos {
        (**self).cycle(cycle)
    }

    fn at_rest(&mut self) -> bool {
        (**self).at_rest()
    }

    fn offset_now(&mut self, cycle: &Cycle<'_>) -> AxisPos {
        (**self).offset_now(cycle)
    }
}

/// No model: the executed position is the nominal one.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoModel;

impl CycleModel for NoModel {
    fn active(&self) -> bool {
        false
    }

    fn cycle(&mut self, _: &Cycle<'_>) -> AxisPos {
        [0.0; AXES]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn part(origin: Origin, length: f64) -> PathPart {
        PathPart {
            origin,
            rapid: false,
            length,
        }
    }

    #[test]
    fn parts_keep_order_and_merge_by_tag_when_full() {
        let mut p = PathParts::default();
        p.push(part(Origin::Approach, 1.0));
        p.push(part(Origin::Corrected, 2.0));
        assert_eq!(p.as_slice().len(), 2);
        for k in 0..100 {
            let o = if k % 2 == 0 {
                Origin::Transition
            } else {
                Origin::Corrected
            };
            p.push(part(o, 1.0));
        }
        let s = p.as_slice();
        assert!(s.len() <= MAX_PARTS);
        let total = |o| {
            s.iter()
                .filter(|x| x.origin == o)
                .map(|x| x.length)
                .sum::<f64>()
        };
        assert_eq!(total(Origin::Approach), 1.0);
        assert_eq!(total(Origin::Corrected), 52.0);
        assert_eq!(total(Origin::Transition), 50.0);
        assert_eq!(s[0].origin, Origin::Approach);
        p.clear();
        assert!(p.as_slice().is_empty());
    }
}
