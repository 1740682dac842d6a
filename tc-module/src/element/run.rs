//! Where an element puts the tool: the position, path tangent and
//! contour normal at a distance along it, for the executor and the
//! per-cycle models. The element is run from the start to the end the
//! caller hands in (see the parent module).

use super::{NormalKind, SpoolElement};
use crate::plane::{AxisPos, AXES};

impl SpoolElement {
    /// The fraction of the element run at path distance `s`.
    #[inline]
    pub fn fraction(&self, s: f64) -> f64 {
        if self.length > 0.0 {
            (s / self.length).clamp(0.0, 1.0)
        } else {
            1.0
        }
    }

    /// The position at path distance `s` (0 ≤ s ≤ length) of the element
    /// run from `start` to `end`.
    pub fn point_at(&self, start: &AxisPos, end: &AxisPos, s: f64) -> AxisPos {
        let f = self.fraction(s);
        let mut p = *start;
        for (i, q) in p.iter_mut().enumerate() {
            *q += (end[i] - start[i]) * f;
        }
        if let Some(a) = &self.arc {
            let r = a.r0 + (a.r1 - a.r0) * f;
            self.plane.set_point(&mut p, a.centre + a.dir_at(f) * r);
        }
        p
    }

    /// The chord direction per unit of path, all axes (a line's tangent).
    fn chord(&self, start: &AxisPos, end: &AxisPos) -> AxisPos {
        std::array::from_fn(|i| (end[i] - start[i]) / self.length)
    }

    /// The unit path tangent at distance `s` of the element run from
    /// `start` to `end`, on all axes (zero for an element without length).
    pub fn tangent_at(&self, start: &AxisPos, end: &AxisPos, s: f64) -> AxisPos {
        if self.length <= 0.0 {
            return [0.0; AXES];
        }
        let mut t = self.chord(start, end);
        if let Some(a) = &self.arc {
            let f = self.fraction(s);
            let d = a.dir_at(f);
            let r = a.r0 + (a.r1 - a.r0) * f;
            self.plane
                .set_point(&mut t, a.tangent(d.x, d.y, r, self.length));
        }
        t
    }

    /// The unit path tangent at distance `s`, where the element passes
    /// through `p` (its [`SpoolElement::point_at`] of `s`): as
    /// [`SpoolElement::tangent_at`], but an arc takes its direction from
    /// `p` and the centre instead of turning the start direction again (no
    /// trigonometry; the per-cycle models ask this every cycle).
    pub fn tangent_through(&self, start: &AxisPos, end: &AxisPos, s: f64, p: &AxisPos) -> AxisPos {
        let Some(a) = &self.arc else {
            return self.tangent_at(start, end, s);
        };
        let c = self.plane.point(p) - a.centre;
        // Within ±1e9: no overflow; a square root is several times
        // cheaper than `hypot`.
        let r = (c.x * c.x + c.y * c.y).sqrt();
        if r.is_nan() || r <= 0.0 || self.length <= 0.0 {
            return self.tangent_at(start, end, s);
        }
        let mut t = self.chord(start, end);
        self.plane
            .set_point(&mut t, a.tangent(c.x / r, c.y / r, r, self.length));
        t
    }

    /// The path direction at distance `s` through `p`, not normalised:
    /// [`SpoolElement::tangent_through`] times the element's length (a
    /// line: end − start), without a division for the axes outside an
    /// arc's plane; zero for an element without length.
    #[inline]
    pub fn direction_through(
        &self,
        start: &AxisPos,
        end: &AxisPos,
        s: f64,
        p: &AxisPos,
    ) -> AxisPos {
        if self.length <= 0.0 {
            return [0.0; AXES];
        }
        let d: AxisPos = std::array::from_fn(|i| end[i] - start[i]);
        let Some(a) = &self.arc else {
            return d;
        };
        let c = self.plane.point(p) - a.centre;
        // Within ±1e9: no overflow.
        let r = (c.x * c.x + c.y * c.y).sqrt();
        if r.is_nan() || r <= 0.0 {
            return self.tangent_at(start, end, s).map(|x| x * self.length);
        }
        // Along the circle (sweep · r per unit of fraction) plus the
        // radius' own drift (r1 − r0), in the direction of the point.
        let drift = (a.r1 - a.r0) / r;
        let (ph, pv) = (-a.sweep * c.y + drift * c.x, a.sweep * c.x + drift * c.y);
        // Chosen per axis rather than stored at the plane's indexes: the
        // array then stays in registers (a per-cycle path).
        let (h, v) = (usize::from(self.plane.h), usize::from(self.plane.v));
        std::array::from_fn(|i| match i {
            _ if i == h => ph,
            _ if i == v => pv,
            _ => d[i],
        })
    }

    /// The unit vector from the programmed contour to the tool centre at
    /// position `p` of this element, on all axes; `None` for elements the
    /// correction did not spool, or where it is undefined (on the centre
    /// or the corner itself).
    #[inline]
    pub fn normal_at(&self, p: &AxisPos) -> Option<AxisPos> {
        let q = self.normal_plane.point(p);
        let a = self.normal_at;
        let v = match self.normal {
            NormalKind::None => return None,
            NormalKind::Fixed => a,
            NormalKind::Outward => q - a,
            NormalKind::Inward => -(q - a),
            NormalKind::FromCorner => q - a,
        };
        // Within ±1e9 (see `tangent_through`): no overflow.
        let len = (v.x * v.x + v.y * v.y).sqrt();
        if !(len > 0.0 && len.is_finite()) {
            return None;
        }
        let inv = 1.0 / len;
        let (h, v2) = (
            usize::from(self.normal_plane.h),
            usize::from(self.normal_plane.v),
        );
        // Chosen per axis, not stored at the plane's indexes (see
        // `direction_through`).
        Some(std::array::from_fn(|i| match i {
            _ if i == h => v.x * inv,
            _ if i == v2 => v.y * inv,
            _ => 0.0,
        }))
    }
}
