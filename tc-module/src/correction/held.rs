//! What the one-profile buffer holds: the held profile with its offset
//! and how it entered, and the plane-null profiles waiting with it. The
//! held profile spools itself once its corner is known.

use super::profile::Profile;
use super::sink::{Axes, Sink};
use crate::element::{NormalRule, Origin};
use crate::geometry::full_circle::{keeps_whole_turn, start_shift, whole_turn_end, TurnEnd};
use crate::geometry::tolerance::ZERO_ARC;
use crate::geometry::{Contour, Offset, Part, V2};
use crate::plane::AxisPos;

/// Most elements a held profile spools: an approach line and the arc, or
/// a full circle's whole turn and the arc on to its end (decision 330).
pub(super) const MAX_HELD: usize = 2;

/// How a profile entered the buffer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Entry {
    /// The first profile after start, flush, direct command or a radius
    /// change: an approach.
    Approach,
    /// Joined to the profile held before it at a corner: its corrected
    /// element starts at `from`; `continued` when it continues from the
    /// previous end (corner case 1).
    Corner {
        /// Where its corrected element starts.
        from: V2,
        /// It continues from the previous element's end.
        continued: bool,
    },
}

/// What follows for a profile from how it entered the buffer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Hold {
    /// An approach (see [`Entry::Approach`]).
    approach: bool,
    /// Where its corrected element starts; `None` for an approach line.
    from: Option<V2>,
    /// A programmed full circle that keeps its whole turn.
    whole_turn: bool,
    /// A programmed full circle (it counts two places, decision 331).
    full: bool,
}

impl Hold {
    /// How `prof` (offset `off`) is held after entering as `entry`.
    #[inline]
    pub fn of(prof: &Profile, off: &Offset, entry: Entry) -> Self {
        let full = prof.contour.is_full_circle();
        match entry {
            Entry::Approach => Self {
                approach: true,
                from: matches!(prof.contour, Contour::Arc { .. }).then_some(off.start),
                whole_turn: full,
                full,
            },
            Entry::Corner { from, continued } => Self {
                approach: false,
                from: Some(from),
                whole_turn: full && keeps_whole_turn(start_shift(off, from), continued),
                full,
            },
        }
    }

    /// Whether it spools an approach line before its arc.
    fn arc_approach(&self) -> bool {
        self.approach && self.from.is_some()
    }

    /// Places its elements take at most: an approach arc spools a line
    /// and the arc; a full circle counts two places however it entered (a
    /// whole turn and the arc on to its end, decisions 330 and 331).
    pub fn reserve(&self) -> usize {
        if self.arc_approach() || self.full {
            MAX_HELD
        } else {
            1
        }
    }

    /// Checks against the limit the points the profile will spool at
    /// least: its corrected end, and an approach arc's corrected start,
    /// tool length included.
    pub fn check_points(&self, prof: &Profile, off: &Offset, sink: &mut Sink) {
        sink.check_end(off.end, &prof.end);
        if self.arc_approach() {
            sink.check_end(off.start, &prof.start);
        }
    }
}

/// The held profile with its offset and how it is held.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Held {
    /// The programmed profile.
    pub prof: Profile,
    /// Its offset.
    pub off: Offset,
    /// How it entered.
    pub hold: Hold,
}

/// A plane-null profile waiting with the held one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct NullMove {
    pub end: AxisPos,
    pub feed: f64,
    pub rapid: bool,
}

impl NullMove {
    /// The plane-null part of `prof`.
    pub fn of(prof: &Profile) -> Self {
        Self {
            end: prof.end,
            feed: prof.feed,
            rapid: prof.rapid,
        }
    }

    /// Spools it at the current tool position; it keeps the normal the
    /// tool has there.
    pub fn spool(&self, normal: Option<V2>, sink: &mut Sink) {
        let (axes, rule) = (Axes::Programmed(&self.end), normal.map(NormalRule::Fixed));
        let here = sink.here();
        sink.line(here, axes, (self.feed, self.rapid), Origin::Corrected, rule);
    }
}

impl Held {
    /// Places its elements take at most (see [`Hold::reserve`]).
    pub fn reserve(&self) -> usize {
        self.hold.reserve()
    }

    /// Its feed and whether it is a rapid move.
    fn motion(&self) -> (f64, bool) {
        (self.prof.feed, self.prof.rapid)
    }

    /// The programmed corner at its end.
    pub fn corner(&self) -> V2 {
        self.prof.contour.ends().1
    }

    /// Its part for an inside corner: from the corrected start to its
    /// offset end; the whole circle for a full circle that keeps its
    /// whole turn.
    pub fn part(&self) -> Part {
        Part {
            path: self.off.path,
            from: self.hold.from,
            to: self.off.end,
            full: self.hold.whole_turn,
        }
    }

    /// Spools its corrected element(s) up to `x`, then the plane-null
    /// profiles waiting with it; returns the contour normal where it ends.
    pub fn spool(&self, x: V2, nulls: &[NullMove], sink: &mut Sink) -> V2 {
        let n_end = match self.prof.contour {
            Contour::Line { .. } => {
                let origin = if self.hold.approach {
                    Origin::Approach
                } else {
                    Origin::Corrected
                };
                let n_end = self.off.normal_at(x);
                let (axes, motion) = (Axes::Programmed(&self.prof.end), self.motion());
                sink.line(x, axes, motion, origin, Some(NormalRule::Fixed(n_end)));
                n_end
            }
            Contour::Arc { centre, sigma, .. } => {
                self.off.normal_at(self.spool_arc(centre, sigma, x, sink))
            }
        };
        for n in nulls {
            n.spool(Some(n_end), sink);
        }
        n_end
    }

    /// Spools the held arc (after its approach line, for an approach) up
    /// to `x`, or where its whole turn ends; an arc cut to zero length is
    /// not spooled, a full circle always is. Returns where it ends.
    fn spool_arc(&self, centre: V2, sigma: f64, x: V2, sink: &mut Sink) -> V2 {
        if self.hold.approach {
            let (s, axes) = (self.off.start, Axes::Programmed(&self.prof.start));
            let n = NormalRule::Fixed(self.off.normal_at(s));
            sink.line(s, axes, self.motion(), Origin::Approach, Some(n));
        }
        let here = sink.here();
        let arc = |p: V2, axes: Axes, sink: &mut Sink| {
            let rule = NormalRule::Radial {
                centre,
                outward: self.off.tool_outside_arc(sigma),
            };
            let (ccw, feed) = (sigma > 0.0, self.prof.arc_feed);
            sink.arc(p, axes, (centre, ccw), feed, Origin::Corrected, rule);
        };
        let all_axes = Axes::Programmed(&self.prof.end);
        match self.end_at(here, x) {
            // The whole turn makes the whole change outside the plane.
            TurnEnd::TurnThen(x) => {
                arc(here, all_axes, sink);
                arc(x, Axes::Stay, sink);
                x
            }
            TurnEnd::Arc(x) => {
                let zero = (here - x).norm() <= ZERO_ARC;
                if !zero || self.prof.contour.is_full_circle() {
                    arc(x, all_axes, sink);
                }
                x
            }
        }
    }

    /// Where its corrected element ends when its corner asks for `x`: a
    /// whole turn ends on its start (`here`), and runs on from there to an
    /// end within its overlap (decision 330).
    fn end_at(&self, here: V2, x: V2) -> TurnEnd {
        if !self.hold.whole_turn {
            return TurnEnd::Arc(x);
        }
        let shift = start_shift(&self.off, here);
        whole_turn_end(&self.off, here, shift, x)
    }
}
