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
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_1_SQRT_2, FRAC_PI_2};

    fn pos(x: f64, y: f64) -> AxisPos {
        let mut p = [0.0; AXES];
        p[0] = x;
        p[1] = y;
        p
    }

    const XY: PlaneAxes = PlaneAxes {
        h: 0,
        v: 1,
        third: 2,
    };

    fn quarter(ccw: bool) -> SpoolElement {
        let (s, e) = (pos(1.0, 0.0), pos(0.0, 1.0));
        SpoolElement::arc(s, e, XY, [0.0, 0.0], ccw, 1000.0, Origin::Uncorrected)
    }

    #[test]
    fn quarter_arc_length_midpoint_and_tangent() {
        let e = quarter(true);
        assert!((e.length - FRAC_PI_2).abs() < 1e-12);
        let m = e.point_at(e.length / 2.0);
        assert!((m[0] - FRAC_1_SQRT_2).abs() < 1e-12 && (m[1] - FRAC_1_SQRT_2).abs() < 1e-12);
        let t = e.tangent_at(0.0);
        assert!((t[0]).abs() < 1e-12 && (t[1] - 1.0).abs() < 1e-12);
        let cw = quarter(false);
        assert!((cw.length - 3.0 * FRAC_PI_2).abs() < 1e-12);
        let t = cw.tangent_at(0.0);
        assert!((t[1] + 1.0).abs() < 1e-12);
    }

    #[test]
    fn arc_starting_on_its_centre_runs_from_angle_zero() {
        // Start on the centre: no sweep can be measured, so a whole CCW
        // turn from angle 0 (as atan2(0, 0) gave) while the radius grows
        // from 0 to 1.
        let e = SpoolElement::arc(
            pos(0.0, 0.0),
            pos(0.0, 1.0),
            XY,
            [0.0, 0.0],
            true,
            1000.0,
            Origin::Uncorrected,
        );
        let q = e.point_at(e.length / 2.0);
        let (r, ang) = (0.5, std::f64::consts::PI);
        assert!((q[0] - r * ang.cos()).abs() < 1e-12 && (q[1] - r * ang.sin()).abs() < 1e-12);
    }

    #[test]
    fn the_tangent_through_a_point_is_the_tangent_at_its_distance() {
        let arcs = [
            quarter(true),
            quarter(false),
            SpoolElement::arc(
                pos(2.0, 0.0),
                pos(-1.0, 0.0),
                XY,
                [0.0, 0.0],
                true,
                1000.0,
                Origin::Uncorrected,
            ),
        ];
        let line = SpoolElement::line(pos(0.0, 0.0), pos(3.0, 4.0), 1.0, false, Origin::Corrected);
        for e in arcs.iter().chain([&line]) {
            for k in 0..=10 {
                let s = e.length * f64::from(k) / 10.0;
                let (a, b) = (e.tangent_at(s), e.tangent_through(s, &e.point_at(s)));
                assert!(
                    a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12),
                    "{a:?} {b:?}"
                );
                let d = e.direction_through(s, &e.point_at(s));
                let scaled = a.map(|x| x * e.length);
                assert!(
                    d.iter().zip(scaled).all(|(x, y)| (x - y).abs() < 1e-11),
                    "{d:?}"
                );
            }
        }
    }

    #[test]
    fn full_circle() {
        let s = pos(1.0, 0.0);
        let e = SpoolElement::arc(s, s, XY, [0.0, 0.0], false, 1000.0, Origin::Uncorrected);
        assert!((e.length - TAU).abs() < 1e-12);
        let q = e.point_at(e.length / 4.0);
        assert!((q[0]).abs() < 1e-12 && (q[1] + 1.0).abs() < 1e-12);
    }

    #[test]
    fn line_tangent_and_normals() {
        let l = SpoolElement::line(pos(0.0, 0.0), pos(3.0, 4.0), 1.0, false, Origin::Corrected);
        assert_eq!(l.tangent_at(1.0)[..2], [0.6, 0.8]);
        assert_eq!(l.normal_at(&pos(1.0, 1.0)), None);
        let fixed = l.with_normal(Some(ContourNormal {
            plane: XY,
            rule: NormalRule::Fixed([-0.8, 0.6]),
        }));
        assert_eq!(
            fixed.normal_at(&pos(1.0, 1.0)).map(|n| [n[0], n[1]]),
            Some([-0.8, 0.6])
        );
        let radial = quarter(true).with_normal(Some(ContourNormal {
            plane: XY,
            rule: NormalRule::Radial {
                centre: [0.0, 0.0],
                outward: false,
            },
        }));
        assert_eq!(
            radial.normal_at(&pos(0.0, 2.0)).map(|n| [n[0], n[1]]),
            Some([0.0, -1.0])
        );
        let corner = l.with_normal(Some(ContourNormal {
            plane: XY,
            rule: NormalRule::FromCorner([1.0, 1.0]),
        }));
        assert_eq!(
            corner.normal_at(&pos(1.0, 3.0)).map(|n| [n[0], n[1]]),
            Some([0.0, 1.0])
        );
        assert_eq!(corner.normal_at(&pos(1.0, 1.0)), None);
    }
}
