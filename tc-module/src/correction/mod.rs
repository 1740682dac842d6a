//! The correction engine: the one-profile buffer of trc-geometry.md.
//!
//! While a group runs, every profile is first held here. When the next one
//! arrives, the held one is corrected together with the corner to the new
//! one and both are spooled; the new one is held. Everything is computed
//! before anything is spooled, so an error never leaves half a corner in
//! the spooler. Every element it spools carries its origin and its
//! contour normal (otc.md rules 3 and 4).
//!
//! What a profile spools is admitted as a whole or not at all: every end
//! point and arc centre within the coordinate limit (else `Range`) and
//! room in the spooler for it and for the profile then held (else
//! `Full`); a refused profile leaves spooler and buffer as they were.
//! Plane-null profiles waiting with the held one count toward the
//! spooler's capacity.
//!
//! By concept: this module holds the profile, the refusals and the buffer
//! with its corner logic; [`Sink`] admits and writes what is spooled
//! (`sink.rs`); `spool.rs` spools the held profile, the plane-null moves
//! and the transitions.

use uoi::AccessError;

use crate::bits::ErrorBits;
use crate::geometry::full_circle::{keeps_whole_turn, start_shift, whole_turn_end};
use crate::geometry::{
    classify, inside_point, transition, Contour, CornerKind, Offset, OffsetError, Part, Transition,
    V2,
};
use crate::group::TransitionMode;
use crate::limits::check_point;
use crate::plane::AxisPos;

mod sink;
mod spool;

pub use sink::Sink;

use spool::{check_held, spool_held, spool_null, spool_transition};

/// Most elements a transition spools (three lines).
const MAX_TRANSITION: usize = 3;

/// Most elements a held profile spools (an approach line and the arc).
const MAX_HELD: usize = 2;

/// Places plane-null profiles leave free for the corner that will spool
/// them: its transition and the profile held after it. With them free,
/// the next profile in the plane is always admitted once the executor has
/// emptied the spooler.
pub const CORNER_ROOM: usize = MAX_TRANSITION + MAX_HELD;

/// Storage for waiting plane-null profiles kept when they leave.
const KEEP_NULLS: usize = 64;

/// Why the buffer did not take a profile.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refusal {
    /// A TC-level error while running: the ERROR bit to set; the caller
    /// faults the group (the access itself is answered ok).
    Fault(ErrorBits),
    /// Refused with an access error (`Range`, `Full`); nothing changed.
    Access(AccessError),
}

impl From<ErrorBits> for Refusal {
    fn from(bits: ErrorBits) -> Self {
        Refusal::Fault(bits)
    }
}

impl From<AccessError> for Refusal {
    fn from(e: AccessError) -> Self {
        Refusal::Access(e)
    }
}

/// A programmed profile as it enters the correction (rotated, machine axes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Profile {
    /// The element in the group's plane.
    pub contour: Contour,
    /// Programmed start, all axes.
    pub start: AxisPos,
    /// Programmed end, all axes.
    pub end: AxisPos,
    /// Feed, units/min.
    pub feed: f64,
    /// A rapid move.
    pub rapid: bool,
}

/// The held profile (the fields of its `Profile`, kept flat: see `hold`)
/// with its offset.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Held {
    /// The profile's plane element.
    contour: Contour,
    /// Its end point, all axes.
    end: AxisPos,
    /// Its start point, all axes (an approach arc starts its line here).
    start: AxisPos,
    /// Its feed.
    feed: f64,
    /// A rapid move.
    rapid: bool,
    off: Offset,
    /// First profile after start, flush or direct command.
    approach: bool,
    /// Where its corrected element starts; `None` for an approach line.
    from: Option<V2>,
    /// A programmed full circle that keeps its whole turn.
    whole_turn: bool,
}

impl Held {
    /// Places its elements take at most: an approach arc spools a line
    /// and the arc.
    fn reserve(&self) -> usize {
        held_places(self.approach && self.from.is_some())
    }

    /// Its part for an inside corner: from the corrected start to `pa`;
    /// the whole circle for a full circle that keeps its whole turn.
    fn part(&self) -> Part {
        Part {
            path: self.off.path,
            from: self.from,
            to: self.off.end,
            full: self.whole_turn,
        }
    }

    /// Where its corrected element ends when its corner asks for `x`: a
    /// whole turn that would end just past its start (`here`) ends on it.
    fn end_at(&self, here: V2, x: V2) -> V2 {
        if !self.whole_turn {
            return x;
        }
        let shift = start_shift(&self.off, here);
        whole_turn_end(&self.off, here, shift, x)
    }
}

/// Whether the profile `contour` (offset `off`) whose corrected element
/// starts at `from` is a full circle that keeps its whole turn;
/// `continued` when it continues from the previous element's end (corner
/// case 1).
fn whole_turn(contour: &Contour, off: &Offset, from: V2, continued: bool) -> bool {
    contour.is_full_circle() && keeps_whole_turn(start_shift(off, from), continued)
}

/// A plane-null profile waiting with the held one.
#[derive(Debug, Clone, Copy, PartialEq)]
struct NullMove {
    end: AxisPos,
    feed: f64,
    rapid: bool,
}

/// How a corner joins the held element `a` to the next `b`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Join {
    /// Where a's corrected element ends.
    a_end: V2,
    /// What is inserted between them.
    transition: Option<Transition>,
    /// Where b's corrected element starts.
    b_from: V2,
    /// b continues from a's end (case 1).
    continued: bool,
}

/// The one-profile buffer of a group. Empty means the next profile is an
/// approach.
#[derive(Debug, Clone, Default)]
pub struct Buffer {
    held: Option<Held>,
    nulls: Vec<NullMove>,
    /// The contour normal at the end of the last element spooled.
    last_normal: Option<V2>,
}

fn offset_error(e: OffsetError) -> ErrorBits {
    match e {
        OffsetError::Calc => ErrorBits::CALC_ERROR,
        OffsetError::Center => ErrorBits::CENTER_ERROR,
    }
}

/// The corner between the held `a` and the next profile's offset `b`
/// (trc-geometry.md "Corner").
fn corner(a: &Held, b: &Offset, b_full: bool, mode: TransitionMode) -> Result<Join, ErrorBits> {
    let k = a.contour.ends().1;
    let pa = a.off.end;
    match classify(a.off.t_end, b.t_start, b.d, &a.off.path, &b.path) {
        CornerKind::Smooth => Ok(Join {
            a_end: pa,
            transition: None,
            b_from: pa,
            continued: true,
        }),
        CornerKind::Outside => {
            let linear = mode == TransitionMode::Linear;
            let t = transition(linear, k, pa, b.start, a.off.t_end, b.t_start, b.d);
            Ok(Join {
                a_end: pa,
                transition: Some(t),
                b_from: b.start,
                continued: false,
            })
        }
        CornerKind::Inside => {
            let part_b = Part {
                path: b.path,
                from: Some(b.start),
                to: b.end,
                full: b_full,
            };
            let x = inside_point(&a.part(), &part_b, k).ok_or(ErrorBits::KORR_ERROR)?;
            Ok(Join {
                a_end: x,
                transition: None,
                b_from: x,
                continued: false,
            })
        }
    }
}

impl Buffer {
    /// Whether a profile is held (STATUS bit ProfMarked).
    pub fn is_marked(&self) -> bool {
        self.held.is_some()
    }

    /// The contour normal at the end of the last element the correction
    /// spooled: what a departure leaves (otc.md rule 4).
    pub fn last_normal(&self) -> Option<[f64; 2]> {
        self.last_normal.map(|n| [n.x, n.y])
    }

    /// Plane-null profiles waiting with the held one.
    pub fn waiting_nulls(&self) -> usize {
        self.nulls.len()
    }

    /// Places the buffer will take in the spooler when it is flushed: the
    /// held profile's elements (at most) and the waiting plane-null ones.
    pub fn pending(&self) -> usize {
        self.held.as_ref().map_or(0, Held::reserve) + self.nulls.len()
    }

    /// Drops the held profile without spooling it (ReInit, direct command,
    /// RESET, fault, start).
    pub fn clear(&mut self) {
        self.held = None;
        self.clear_nulls();
        self.last_normal = None;
    }

    /// Forgets the waiting plane-null profiles, giving back large storage.
    fn clear_nulls(&mut self) {
        self.nulls.clear();
        if self.nulls.capacity() > KEEP_NULLS {
            self.nulls.shrink_to(KEEP_NULLS);
        }
    }

    /// A new profile enters with offset `d` (side × radius). On a
    /// TC-level error the bit to set is returned and nothing was spooled
    /// (the caller faults the group); on an access error nothing changed.
    pub fn push(
        &mut self,
        prof: &Profile,
        d: f64,
        mode: TransitionMode,
        sink: &mut Sink,
    ) -> Result<(), Refusal> {
        sink.begin();
        if prof.contour.is_plane_null() {
            return self.push_plane_null(prof, sink);
        }
        let off = prof.contour.offset(d).map_err(offset_error)?;
        // The held profile is read in place (no copy of it); nothing of
        // the buffer changes before the spooled elements are admitted.
        let (approach, from, whole, spooled) = match &self.held {
            Some(a) if a.off.d == d => {
                let join = corner(a, &off, prof.contour.is_full_circle(), mode)?;
                let n = spool_held(a, join.a_end, &self.nulls, sink);
                if let Some(t) = join.transition {
                    spool_transition(t, a.contour.ends().1, prof, sink);
                }
                let whole = whole_turn(&prof.contour, &off, join.b_from, join.continued);
                (false, Some(join.b_from), whole, Some(n))
            }
            held => {
                // Radius changed while running: finish as at SSF 2001.
                let n = held
                    .as_ref()
                    .map(|a| spool_held(a, a.off.end, &self.nulls, sink));
                let from = matches!(prof.contour, Contour::Arc { .. }).then_some(off.start);
                (true, from, prof.contour.is_full_circle(), n)
            }
        };
        let arc_approach = approach && from.is_some();
        let admitted = check_held(prof, &off, arc_approach, sink)
            .and_then(|()| sink.check(held_places(arc_approach)));
        if let Err(e) = admitted {
            sink.spooler.rollback(sink.mark);
            return Err(e.into());
        }
        if let Some(n) = spooled {
            self.clear_nulls();
            self.last_normal = Some(n);
        }
        self.hold(prof, off, approach, from, whole);
        Ok(())
    }

    fn hold(
        &mut self,
        prof: &Profile,
        off: Offset,
        approach: bool,
        from: Option<V2>,
        whole_turn: bool,
    ) {
        // Copied field by field from the borrowed profile: built in place,
        // this saves a whole-`Profile` temporary (208 bytes) per profile
        // on the hot path (callgrind, saw-tooth bench).
        self.held = Some(Held {
            contour: prof.contour,
            end: prof.end,
            start: prof.start,
            feed: prof.feed,
            rapid: prof.rapid,
            off,
            approach,
            from,
            whole_turn,
        });
    }

    /// A plane-null profile waits with the held one, or is spooled at once
    /// at the current tool position when nothing is held. Waiting, it
    /// takes a place of the spooler's capacity and leaves
    /// [`CORNER_ROOM`] free for the corner that will spool it.
    fn push_plane_null(&mut self, prof: &Profile, sink: &mut Sink) -> Result<(), Refusal> {
        let null = NullMove {
            end: prof.end,
            feed: prof.feed,
            rapid: prof.rapid,
        };
        if self.held.is_none() {
            spool_null(&null, self.last_normal, sink);
            return Ok(sink.admit(0)?);
        }
        check_point(&sink.end_point(sink.here(), &prof.end))?;
        let pending = self.pending() + 1;
        let cap = sink.spooler.capacity();
        if sink.spooler.len() + pending > cap || pending + CORNER_ROOM > cap {
            return Err(AccessError::Full.into());
        }
        self.nulls.push(null);
        Ok(())
    }

    /// Spools the held profile with its own offset end, then the plane-null
    /// profiles waiting with it (STATUS=0, SSF 2001). The buffer is empty
    /// afterwards: the next profile is an approach. Its places were kept,
    /// its points checked as it came in.
    pub fn flush(&mut self, sink: &mut Sink) {
        if let Some(a) = &self.held {
            self.last_normal = Some(spool_held(a, a.off.end, &self.nulls, sink));
        }
        self.held = None;
        self.clear_nulls();
    }
}

/// Places a held profile takes at most once spooled: an approach arc
/// spools a line and the arc, anything else one element.
fn held_places(arc_approach: bool) -> usize {
    if arc_approach {
        MAX_HELD
    } else {
        1
    }
}
