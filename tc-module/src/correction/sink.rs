//! The sink of the correction: admits what a profile spools as a whole or
//! not at all, and writes the spooled elements (end points with the tool
//! length, contour normals) into the spooler.

use uoi::AccessError;

use crate::element::{ContourNormal, NormalRule, Origin, Path, SpoolElement};
use crate::geometry::V2;
use crate::limits::check_point;
use crate::plane::{AxisPos, PlaneAxes};
use crate::spooler::{Mark, Spooler};

/// Where elements go: the spooler, with the current tool position and the
/// group's plane and tool length.
#[derive(Debug)]
pub struct Sink<'a> {
    /// The spooler.
    pub spooler: &'a mut Spooler,
    /// The current tool position (end of the last spooled element).
    pub q: AxisPos,
    /// The group's plane axes.
    pub plane: PlaneAxes,
    /// Tool length added on the third main axis of every end point.
    pub len: f64,
    /// Where the spooler stood when the profile came in.
    pub(super) mark: Mark,
}

pub(super) fn rule_of(n: V2) -> NormalRule {
    NormalRule::Fixed([n.x, n.y])
}

/// `base` with the plane point `p` on the plane axes (`v` written last,
/// as [`PlaneAxes::set_point`] does) and `third_add` added on the third
/// axis when it is not a plane axis. Axis by axis, so the position is
/// built in registers (no single-axis store read back as a whole).
fn with_plane_point(plane: PlaneAxes, base: &AxisPos, p: V2, third_add: Option<f64>) -> AxisPos {
    let (h, v, third) = (plane.h as usize, plane.v as usize, plane.third as usize);
    std::array::from_fn(|i| match third_add {
        _ if i == v => p.y,
        _ if i == h => p.x,
        Some(add) if i == third => base[i] + add,
        _ => base[i],
    })
}

impl<'a> Sink<'a> {
    /// Elements go to `spooler`; the tool stands at `q`; `plane` and tool
    /// length `len` are the group's.
    pub fn new(spooler: &'a mut Spooler, q: AxisPos, plane: PlaneAxes, len: f64) -> Self {
        let mark = spooler.mark();
        Self {
            spooler,
            q,
            plane,
            len,
            mark,
        }
    }

    /// A profile comes in: what it spools is admitted or taken back as a
    /// whole.
    pub(super) fn begin(&mut self) {
        self.mark = self.spooler.mark();
    }

    /// Admits what was spooled since the profile came in, with `reserve`
    /// places kept for what the buffer then holds; otherwise takes it back
    /// and answers why (`Range` for a point beyond the limit, `Full`).
    pub(super) fn admit(&mut self, reserve: usize) -> Result<(), AccessError> {
        let r = self.check(reserve);
        if r.is_err() {
            self.spooler.rollback(self.mark);
        }
        r
    }

    /// Whether what was spooled since the profile came in may stay, with
    /// `reserve` places kept: every point within the limit (`Range`) and
    /// room left (`Full`).
    pub(super) fn check(&self, reserve: usize) -> Result<(), AccessError> {
        for e in self.spooler.since(self.mark) {
            check_point(&e.end)?;
            if let Path::Arc(a) = &e.path {
                check_point(&a.centre)?;
            }
        }
        if self.spooler.len() + reserve > self.spooler.capacity() {
            return Err(AccessError::Full);
        }
        Ok(())
    }

    /// End point: plane point `p`, other axes from `prog` with the tool
    /// length on the third axis.
    pub(super) fn end_point(&self, p: V2, prog: &AxisPos) -> AxisPos {
        with_plane_point(self.plane, prog, p, Some(self.len))
    }

    /// End point that moves only the plane axes from the tool position
    /// (transitions: the other axes stay where the corner left them).
    pub(super) fn in_plane(&self, p: V2) -> AxisPos {
        with_plane_point(self.plane, &self.q, p, None)
    }

    fn normal(&self, rule: Option<NormalRule>) -> Option<ContourNormal> {
        rule.map(|rule| ContourNormal {
            plane: self.plane,
            rule,
        })
    }

    pub(super) fn line(
        &mut self,
        end: AxisPos,
        feed: f64,
        rapid: bool,
        origin: Origin,
        n: Option<NormalRule>,
    ) {
        let e = SpoolElement::line(self.q, end, feed, rapid, origin).with_normal(self.normal(n));
        self.spooler.push(e);
        self.q = end;
    }

    pub(super) fn arc(
        &mut self,
        end: AxisPos,
        centre: V2,
        ccw: bool,
        feed: f64,
        origin: Origin,
        n: NormalRule,
    ) {
        let c = [centre.x, centre.y];
        let e = SpoolElement::arc(self.q, end, self.plane, c, ccw, feed, origin)
            .with_normal(self.normal(Some(n)));
        self.spooler.push(e);
        self.q = end;
    }

    pub(super) fn here(&self) -> V2 {
        let p = self.plane.point(&self.q);
        V2::new(p[0], p[1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plane::AXES;

    /// The old way: copy, write h then v, add on a distinct third axis.
    fn by_set_point(plane: PlaneAxes, base: &AxisPos, p: V2, add: Option<f64>) -> AxisPos {
        let mut e = *base;
        plane.set_point(&mut e, [p.x, p.y]);
        let third = plane.third as usize;
        if let Some(add) = add {
            if third != plane.h as usize && third != plane.v as usize {
                e[third] += add;
            }
        }
        e
    }

    #[test]
    fn plane_point_written_as_set_point_does() {
        let base: AxisPos = std::array::from_fn(|i| i as f64 - 2.0);
        let p = V2::new(10.5, -20.25);
        for (h, v, third) in [
            (0, 1, 2),
            (2, 0, 1),
            (1, 2, 0),
            (3, 3, 4),
            (5, 6, 5),
            (7, 0, 7),
        ] {
            let plane = PlaneAxes { h, v, third };
            for add in [None, Some(0.0), Some(4.0)] {
                let want = by_set_point(plane, &base, p, add);
                assert_eq!(with_plane_point(plane, &base, p, add), want, "{plane:?}");
            }
        }
        assert_eq!(base.len(), AXES);
    }
}
