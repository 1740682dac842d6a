//! The sink of the correction: builds the end points of what a profile
//! spools (the plane point, the other axes from the programmed point with
//! the tool length on the third axis, or from where the tool stands),
//! writes the elements with their contour normals into the spooler, and
//! admits them as a whole or not at all.
//!
//! Every point the sink builds is checked against the coordinate limit as
//! it is built: only the plane coordinates and the third axis (tool
//! length added) can leave it, the other axes are copied from programmed
//! or spooled points, which were checked when they came in. An element
//! that moves no axis outside the plane is built from plane points alone.

use uoi::AccessError;

use crate::element::{ArcGeometry, ContourNormal, NormalRule, Origin, SpoolElement};
use crate::geometry::V2;
use crate::limits::within_limit;
use crate::plane::{AxisPos, PlaneAxes};
use crate::spooler::{Mark, Spooler};

/// Where the axes outside the plane of an end point come from.
#[derive(Debug, Clone, Copy)]
pub(super) enum Axes<'p> {
    /// They stay where the tool is (a transition).
    Stay,
    /// The programmed point's, with the tool length on the third axis.
    Programmed(&'p AxisPos),
}

/// How an element moves: feed, rapid, origin tag and contour normal.
#[derive(Debug, Clone, Copy)]
struct Motion {
    feed: f64,
    rapid: bool,
    origin: Origin,
    normal: Option<ContourNormal>,
}

/// Where elements go: the spooler, with the group's plane and tool length.
/// The tool stands where the next element starts (the spooler's tail).
#[derive(Debug)]
pub struct Sink<'a> {
    spooler: &'a mut Spooler,
    plane: PlaneAxes,
    /// Tool length added on the third main axis of every end point.
    len: f64,
    /// The third axis, where it is not one of the plane's (else the length
    /// goes nowhere).
    third: Option<usize>,
    /// Where spooler and tool stood when the profile came in.
    mark: Mark,
    /// Whether every point built since the profile came in is within the
    /// coordinate limit.
    in_range: bool,
}

impl<'a> Sink<'a> {
    /// Elements go to `spooler`; the tool stands at `q` (the end of the
    /// last element waiting there, or where the executor stands); `plane`
    /// and tool length `len` are the group's.
    pub fn new(spooler: &'a mut Spooler, q: AxisPos, plane: PlaneAxes, len: f64) -> Self {
        spooler.start_at(&q);
        let mark = spooler.mark();
        let outside = plane.third != plane.h && plane.third != plane.v;
        Self {
            spooler,
            plane,
            len,
            third: outside.then_some(usize::from(plane.third)),
            mark,
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

    /// Checks the end point at plane point `p` with the other axes from
    /// `prog` (see [`Axes::Programmed`]) without building it: the plane
    /// point and the third axis.
    #[inline]
    pub(super) fn check_end(&mut self, p: V2, prog: &AxisPos) {
        if let Some(t) = self.third {
            self.in_range &= within_limit(prog[t] + self.len);
        }
        self.check_plane_point(p);
    }

    /// Where the tool stands, in the plane.
    #[inline]
    pub(super) fn here(&self) -> V2 {
        self.plane.point(self.spooler.tail())
    }

    /// The end point at plane point `p` with the other axes from `prog`
    /// (tool length on the third), when it moves an axis outside the
    /// plane from where the tool stands; `None` when it moves none.
    #[inline]
    fn moved_end(&mut self, p: V2, axes: Axes) -> Option<AxisPos> {
        let Axes::Programmed(prog) = axes else {
            return None;
        };
        let q = self.spooler.tail();
        let mut end = *prog;
        if let Some(t) = self.third {
            end[t] += self.len;
        }
        // Compared to the bit with the plane coordinates left as they are.
        self.plane.set_point(&mut end, self.plane.point(q));
        let differ = (0..end.len()).fold(0, |acc, i| acc | (end[i].to_bits() ^ q[i].to_bits()));
        if differ == 0 {
            return None;
        }
        if let Some(t) = self.third {
            self.in_range &= within_limit(end[t]);
        }
        self.plane.set_point(&mut end, p);
        Some(end)
    }

    /// Spools a line or (with `arc`: centre and direction) an arc to plane
    /// point `p`, the other axes from `axes`.
    #[inline]
    fn spool(&mut self, p: V2, axes: Axes, arc: Option<(V2, bool)>, m: Motion) {
        self.check_plane_point(p);
        let plane = self.plane;
        if let Some(end) = self.moved_end(p, axes) {
            let start = *self.spooler.tail();
            let (feed, origin) = (m.feed, m.origin);
            let e = match arc {
                None => SpoolElement::line(&start, &end, plane, feed, m.rapid, origin),
                Some((c, ccw)) => SpoolElement::arc(&start, &end, plane, c, ccw, feed, origin),
            };
            self.spooler.push(&start, &end, e.with_normal(m.normal));
            return;
        }
        // Only the plane axes move: the lengths over every axis add exact
        // zeros for the others, so they are taken in the plane.
        let from = plane.point(self.spooler.tail());
        let (arc, length) = match arc {
            None => {
                let d = p - from;
                (None, (d.x * d.x + d.y * d.y).sqrt())
            }
            Some((c, ccw)) => {
                let (a, plane_len) = ArcGeometry::of(from, p, c, ccw);
                (Some(a), (plane_len * plane_len).sqrt())
            }
        };
        let e = SpoolElement::in_plane(plane, p, length, arc).moving(m.feed, m.rapid, m.origin);
        self.spooler.push_in_plane(e.with_normal(m.normal));
    }

    /// The contour normal of `rule` in the group's plane.
    fn normal(&self, rule: Option<NormalRule>) -> Option<ContourNormal> {
        let plane = self.plane;
        rule.map(|rule| ContourNormal { plane, rule })
    }

    /// Spools a line to plane point `p`, the other axes from `axes`.
    #[inline]
    pub(super) fn line(
        &mut self,
        p: V2,
        axes: Axes,
        (feed, rapid): (f64, bool),
        origin: Origin,
        rule: Option<NormalRule>,
    ) {
        let normal = self.normal(rule);
        let m = Motion {
            feed,
            rapid,
            origin,
            normal,
        };
        self.spool(p, axes, None, m);
    }

    /// Spools an arc about `centre` (checked against the limit) to plane
    /// point `p`, the other axes from `axes`.
    #[inline]
    pub(super) fn arc(
        &mut self,
        p: V2,
        axes: Axes,
        (centre, ccw): (V2, bool),
        feed: f64,
        origin: Origin,
        rule: NormalRule,
    ) {
        self.check_plane_point(centre);
        let normal = self.normal(Some(rule));
        let m = Motion {
            feed,
            rapid: false,
            origin,
            normal,
        };
        self.spool(p, axes, Some((centre, ccw)), m);
    }
}
