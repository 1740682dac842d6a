//! A spooled element: its path (line, or arc helical where other axes
//! move), feed, origin tag and the contour normal a wear model needs
//! (trc-geometry.md "Spooler and execution"; otc.md rules 2-4).

use std::f64::consts::TAU;

use crate::geometry::tolerance::ZERO_SWEEP;
use crate::plane::{AxisPos, PlaneAxes, AXES};
pub use tc_request::Origin;
use tc_request::{ArcRecord, SpoolRecord};

/// Geometry of an arc element in its plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArcPath {
    /// The plane axes.
    pub plane: PlaneAxes,
    /// Centre `(h, v)`.
    pub centre: [f64; 2],
    /// Counter-clockwise?
    pub ccw: bool,
    /// Unit vector from the centre to the start point.
    start_dir: [f64; 2],
    /// Signed sweep (positive CCW); a full circle sweeps ±2π.
    sweep: f64,
    /// Radius at the start.
    r0: f64,
    /// Radius at the end (equal to `r0` up to rounding).
    r1: f64,
}

/// Path of an element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Path {
    /// Straight line from start to end in all axes.
    Line,
    /// Arc in a plane, helical where other axes move.
    Arc(ArcPath),
}

/// How the unit vector from the programmed contour to the tool centre is
/// found along an element the correction spooled (otc.md rule 3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NormalRule {
    /// One vector all along: the side normal of a corrected line, and the
    /// normal an approach leads onto or a departure leaves.
    Fixed([f64; 2]),
    /// Radial about the arc centre: outward when the tool runs outside the
    /// programmed arc, inward when inside.
    Radial {
        /// The arc centre.
        centre: [f64; 2],
        /// Whether the tool centre lies outside the programmed arc.
        outward: bool,
    },
    /// From the programmed corner K to the tool centre (a transition).
    FromCorner([f64; 2]),
}

/// The contour normal of an element, in its group's plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContourNormal {
    /// The group's plane axes.
    pub plane: PlaneAxes,
    /// How the normal is found.
    pub rule: NormalRule,
}

/// One element of the spooler.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpoolElement {
    /// Start position (all axes).
    pub start: AxisPos,
    /// End position (all axes).
    pub end: AxisPos,
    /// Line or arc.
    pub path: Path,
    /// Feed in units/min.
    pub feed: f64,
    /// A rapid move (`RAP`).
    pub rapid: bool,
    /// Who spooled it.
    pub origin: Origin,
    /// Path length (arc length, helical where other axes move).
    pub length: f64,
    /// The contour normal, for elements the correction spooled.
    pub normal: Option<ContourNormal>,
}

impl ArcPath {
    /// Unit vector from the centre at fraction `f` of the sweep: the start
    /// direction turned by `sweep · f`.
    fn dir_at(&self, f: f64) -> [f64; 2] {
        let (sin, cos) = (self.sweep * f).sin_cos();
        let [c0, s0] = self.start_dir;
        [c0 * cos - s0 * sin, s0 * cos + c0 * sin]
    }
}

fn line_length(start: &AxisPos, end: &AxisPos) -> f64 {
    start
        .iter()
        .zip(end)
        .map(|(a, b)| (b - a) * (b - a))
        .sum::<f64>()
        .sqrt()
}

impl SpoolElement {
    /// A straight element.
    pub fn line(start: AxisPos, end: AxisPos, feed: f64, rapid: bool, origin: Origin) -> Self {
        Self {
            start,
            end,
            path: Path::Line,
            feed,
            rapid,
            origin,
            length: line_length(&start, &end),
            normal: None,
        }
    }

    /// An arc element about `centre` in `plane`; start = end in the plane
    /// is a full circle.
    pub fn arc(
        start: AxisPos,
        end: AxisPos,
        plane: PlaneAxes,
        centre: [f64; 2],
        ccw: bool,
        feed: f64,
        origin: Origin,
    ) -> Self {
        let s = plane.point(&start);
        let e = plane.point(&end);
        let (sh, sv) = (s[0] - centre[0], s[1] - centre[1]);
        let (eh, ev) = (e[0] - centre[0], e[1] - centre[1]);
        let mut sweep = (sh * ev - sv * eh).atan2(sh * eh + sv * ev); // (-π, π]
        if ccw {
            if sweep <= ZERO_SWEEP {
                sweep += TAU;
            }
        } else if sweep >= -ZERO_SWEEP {
            sweep -= TAU;
        }
        let r0 = sh.hypot(sv);
        let r1 = eh.hypot(ev);
        // On the centre, the start direction is that of angle 0.
        let start_dir = if r0 > 0.0 {
            [sh / r0, sv / r0]
        } else {
            [1.0, 0.0]
        };
        let plane_len = sweep.abs() * 0.5 * (r0 + r1);
        let other: f64 = (0..AXES)
            .filter(|&i| i != plane.h as usize && i != plane.v as usize)
            .map(|i| (end[i] - start[i]) * (end[i] - start[i]))
            .sum();
        Self {
            start,
            end,
            path: Path::Arc(ArcPath {
                plane,
                centre,
                ccw,
                start_dir,
                sweep,
                r0,
                r1,
            }),
            feed,
            rapid: false,
            origin,
            length: (plane_len * plane_len + other).sqrt(),
            normal: None,
        }
    }

    /// The element as it is reported (spool log, wire).
    pub fn record(&self) -> SpoolRecord {
        SpoolRecord {
            arc: match &self.path {
                Path::Line => None,
                Path::Arc(a) => Some(ArcRecord {
                    plane: [a.plane.h, a.plane.v, a.plane.third],
                    centre: a.centre,
                    ccw: a.ccw,
                }),
            },
            start: self.start,
            end: self.end,
            feed: self.feed,
            rapid: self.rapid,
            origin: self.origin,
        }
    }

    /// The same element with its contour normal.
    pub fn with_normal(mut self, normal: Option<ContourNormal>) -> Self {
        self.normal = normal;
        self
    }

    fn fraction(&self, s: f64) -> f64 {
        if self.length > 0.0 {
            (s / self.length).clamp(0.0, 1.0)
        } else {
            1.0
        }
    }

    /// The position at path distance `s` (0 ≤ s ≤ length).
    pub fn point_at(&self, s: f64) -> AxisPos {
        let f = self.fraction(s);
        let mut p = self.start;
        for (i, q) in p.iter_mut().enumerate() {
            *q += (self.end[i] - self.start[i]) * f;
        }
        if let Path::Arc(a) = &self.path {
            let [cos, sin] = a.dir_at(f);
            let r = a.r0 + (a.r1 - a.r0) * f;
            a.plane
                .set_point(&mut p, [a.centre[0] + r * cos, a.centre[1] + r * sin]);
        }
        p
    }

    /// The unit path tangent at distance `s`, on all axes (zero for an
    /// element without length).
    pub fn tangent_at(&self, s: f64) -> AxisPos {
        let mut t = [0.0; AXES];
        if self.length <= 0.0 {
            return t;
        }
        for (i, q) in t.iter_mut().enumerate() {
            *q = (self.end[i] - self.start[i]) / self.length;
        }
        if let Path::Arc(a) = &self.path {
            let f = self.fraction(s);
            let [cos, sin] = a.dir_at(f);
            // Along the circle (r dθ/ds) plus the radius' own drift (dr/ds).
            let k = a.sweep * (a.r0 + (a.r1 - a.r0) * f) / self.length;
            let dr = (a.r1 - a.r0) / self.length;
            a.plane
                .set_point(&mut t, [-k * sin + dr * cos, k * cos + dr * sin]);
        }
        t
    }

    /// The unit path tangent at distance `s`, where the element passes
    /// through `p` (its [`SpoolElement::point_at`] of `s`): as
    /// [`SpoolElement::tangent_at`], but an arc takes its direction from
    /// `p` and the centre instead of turning the start direction again (no
    /// trigonometry; the per-cycle models ask this every cycle).
    pub fn tangent_through(&self, s: f64, p: &AxisPos) -> AxisPos {
        let Path::Arc(a) = &self.path else {
            return self.tangent_at(s);
        };
        let q = a.plane.point(p);
        let (ch, cv) = (q[0] - a.centre[0], q[1] - a.centre[1]);
        // Coordinates stay within ±1e9: the squares cannot overflow, and
        // a square root is several times cheaper than `hypot`.
        let r = (ch * ch + cv * cv).sqrt();
        if r.is_nan() || r <= 0.0 || self.length <= 0.0 {
            return self.tangent_at(s);
        }
        let (cos, sin) = (ch / r, cv / r);
        let mut t = [0.0; AXES];
        for (i, x) in t.iter_mut().enumerate() {
            *x = (self.end[i] - self.start[i]) / self.length;
        }
        let k = a.sweep * r / self.length;
        let dr = (a.r1 - a.r0) / self.length;
        a.plane
            .set_point(&mut t, [-k * sin + dr * cos, k * cos + dr * sin]);
        t
    }

    /// The path direction at distance `s` through `p`, not normalised:
    /// [`SpoolElement::tangent_through`] times the element's length (a
    /// line: end − start), without a division for the axes outside an
    /// arc's plane; zero for an element without length.
    #[inline]
    pub fn direction_through(&self, s: f64, p: &AxisPos) -> AxisPos {
        let mut d = [0.0; AXES];
        if self.length <= 0.0 {
            return d;
        }
        for (i, x) in d.iter_mut().enumerate() {
            *x = self.end[i] - self.start[i];
        }
        let Path::Arc(a) = &self.path else {
            return d;
        };
        let q = a.plane.point(p);
        let (ch, cv) = (q[0] - a.centre[0], q[1] - a.centre[1]);
        // Within ±1e9: no overflow.
        let r = (ch * ch + cv * cv).sqrt();
        if r.is_nan() || r <= 0.0 {
            return self.tangent_at(s).map(|x| x * self.length);
        }
        // Along the circle (sweep · r per unit of fraction) plus the
        // radius' own drift (r1 − r0), in the direction of the point.
        let drift = (a.r1 - a.r0) / r;
        let (ph, pv) = (-a.sweep * cv + drift * ch, a.sweep * ch + drift * cv);
        // Chosen per axis rather than stored at the plane's indexes: the
        // array then stays in registers (a per-cycle path).
        let (h, v) = (usize::from(a.plane.h), usize::from(a.plane.v));
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
        let n = self.normal?;
        let q = n.plane.point(p);
        let v = match n.rule {
            NormalRule::Fixed(v) => v,
            NormalRule::Radial { centre, outward } => {
                let sign = if outward { 1.0 } else { -1.0 };
                [sign * (q[0] - centre[0]), sign * (q[1] - centre[1])]
            }
            NormalRule::FromCorner(k) => [q[0] - k[0], q[1] - k[1]],
        };
        // Within ±1e9 (see `tangent_through`): no overflow.
        let len = (v[0] * v[0] + v[1] * v[1]).sqrt();
        if !(len > 0.0 && len.is_finite()) {
            return None;
        }
        let inv = 1.0 / len;
        let (h, v2) = (usize::from(n.plane.h), usize::from(n.plane.v));
        // Chosen per axis, not stored at the plane's indexes (see
        // `direction_through`).
        Some(std::array::from_fn(|i| match i {
            _ if i == h => v[0] * inv,
            _ if i == v2 => v[1] * inv,
            _ => 0.0,
        }))
    }
}

#[cfg(test)]
mod tests;
