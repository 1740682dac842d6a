//! The sink of the correction: builds the end points of what a profile
//! spools (the plane point, the tool length on the third axis), writes the
//! elements with their contour normals into the spooler, and admits them
//! as a whole or not at all.
//!
//! Every point the sink builds is checked against the coordinate limit as
//! it is built: only the plane coordinates and the third axis (tool
//! length added) can leave it, the other axes are copied from programmed
//! or spooled points, which were checked when they came in.

use uoi::AccessError;

use crate::element::{ContourNormal, NormalRule, Origin, SpoolElement};
use crate::geometry::V2;
use crate::limits::within_limit;
use crate::plane::{AxisPos, PlaneAxes};
use crate::spooler::{Mark, Spooler};

/// Where elements go: the spooler, with the current tool position and the
/// group's plane and tool length.
#[derive(Debug)]
pub struct Sink<'a> {
    spooler: &'a mut Spooler,
    /// The current tool position (end of the last spooled element).
    q: AxisPos,
    plane: PlaneAxes,
    /// Tool length added on the third main axis of every end point.
    len: f64,
    /// The third axis, where it is not one of the plane's (else the length
    /// goes nowhere).
    third: Option<usize>,
    /// Where spooler and tool stood when the profile came in.
    mark: Mark,
    q_mark: AxisPos,
    /// Whether every point built since the profile came in is within the
    /// coordinate limit.
    in_range: bool,
}

impl<'a> Sink<'a> {
    /// Elements go to `spooler`; the tool stands at `q` (the end of the
    /// last element waiting there, or where the executor stands); `plane`
    /// and tool length `len` are the group's.
    pub fn new(spooler: &'a mut Spooler, q: AxisPos, plane: PlaneAxes, len: f64) -> Self {
        let mark = spooler.mark();
        let outside = plane.third != plane.h && plane.third != plane.v;
        Self {
            spooler,
            q,
            plane,
            len,
            third: outside.then_some(usize::from(plane.third)),
            mark,
            q_mark: q,
            in_range: true,
        }
    }

    /// The spooler the elements go to.
    pub fn spooler(&mut self) -> &mut Spooler {
        self.spooler
    }

    /// A profile comes in: what it spools is admitted or taken back as a
    /// whole.
    pub(super) fn begin(&mut self) {
        self.mark = self.spooler.mark();
        self.q_mark = self.q;
        self.in_range = true;
    }

    /// Admits what was spooled since the profile came in, with `reserve`
    /// places kept for what the buffer then holds: every point built
    /// within the limit (else `Range`) and room left (else `Full`).
    /// Otherwise the one rollback: spooler and tool position as they were.
    pub(super) fn admit(&mut self, reserve: usize) -> Result<(), AccessError> {
        let verdict = if !self.in_range {
            Err(AccessError::Range)
        } else if !self.spooler.has_room(reserve) {
            Err(AccessError::Full)
        } else {
            Ok(())
        };
        if verdict.is_err() {
            self.spooler.rollback(self.mark);
            self.q = self.q_mark;
        }
        verdict
    }

    /// The spooler's capacity.
    pub(super) fn capacity(&self) -> usize {
        self.spooler.capacity()
    }

    fn check_plane_point(&mut self, p: V2) {
        self.in_range &= within_limit(p.x) & within_limit(p.y);
    }

    /// End point: plane point `p`, the other axes from `prog` with the
    /// tool length on the third axis. Checked against the limit.
    #[inline]
    pub(super) fn end_point(&mut self, p: V2, prog: &AxisPos) -> AxisPos {
        let mut e = *prog;
        if let Some(t) = self.third {
            e[t] += self.len;
            self.in_range &= within_limit(e[t]);
        }
        self.plane.set_point(&mut e, p);
        self.check_plane_point(p);
        e
    }

    /// End point that moves only the plane axes from the tool position
    /// (transitions: the other axes stay where the corner left them).
    #[inline]
    pub(super) fn in_plane(&mut self, p: V2) -> AxisPos {
        let mut e = self.q;
        self.plane.set_point(&mut e, p);
        self.check_plane_point(p);
        e
    }

    /// Where the tool stands, in the plane.
    #[inline]
    pub(super) fn here(&self) -> V2 {
        self.plane.point(&self.q)
    }

    /// Spools a line to `end`.
    #[inline]
    pub(super) fn line(
        &mut self,
        end: AxisPos,
        feed: f64,
        rapid: bool,
        origin: Origin,
        rule: Option<NormalRule>,
    ) {
        let normal = rule.map(|rule| ContourNormal {
            plane: self.plane,
            rule,
        });
        let e = SpoolElement::line(&self.q, end, feed, rapid, origin).with_normal(normal);
        self.spooler.push(&self.q, e);
        self.q = end;
    }

    /// Spools an arc to `end` about `centre` (checked against the limit).
    #[inline]
    pub(super) fn arc(
        &mut self,
        end: AxisPos,
        centre: V2,
        ccw: bool,
        feed: f64,
        origin: Origin,
        rule: NormalRule,
    ) {
        self.check_plane_point(centre);
        let normal = ContourNormal {
            plane: self.plane,
            rule,
        };
        let e = SpoolElement::arc(&self.q, end, self.plane, centre, ccw, feed, origin)
            .with_normal(Some(normal));
        self.spooler.push(&self.q, e);
        self.q = end;
    }
}
