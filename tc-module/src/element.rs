//! A spooled element: the end of every axis, the plane geometry of an arc
//! with what the executor needs derived once (start direction, sweep,
//! radii, path length), feed, origin tag and the contour normal a wear
//! model needs (docs/trc.md "Spooler and execution"; docs/otc.md rules 2
//! to 4).
//!
//! An element does not keep its start: the spooler is a chain, each
//! element starting where the one before it ended (or, the first, where
//! the executor stands). Whoever runs or reports an element hands its
//! start in. The axes outside the plane cost nothing where they do not
//! move: a line's length and an arc's helix add only what they move.

use std::f64::consts::TAU;

use crate::geometry::tolerance::ZERO_SWEEP;
use crate::geometry::V2;
use crate::plane::{AxisPos, PlaneAxes, AXES};
pub use tc_request::Origin;
use tc_request::{ArcRecord, SpoolRecord};

/// The arc of an element as it is reported: plane, centre, direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArcPath {
    /// The plane axes.
    pub plane: PlaneAxes,
    /// Centre `(h, v)`.
    pub centre: V2,
    /// Counter-clockwise?
    pub ccw: bool,
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
/// found along an element the correction spooled (docs/otc.md rule 3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NormalRule {
    /// One vector all along: the side normal of a corrected line, and the
    /// normal an approach leads onto or a departure leaves.
    Fixed(V2),
    /// Radial about the arc centre: outward when the tool runs outside the
    /// programmed arc, inward when inside.
    Radial {
        /// The arc centre.
        centre: V2,
        /// Whether the tool centre lies outside the programmed arc.
        outward: bool,
    },
    /// From the programmed corner K to the tool centre (a transition).
    FromCorner(V2),
}

/// The contour normal of an element, in its group's plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContourNormal {
    /// The group's plane axes.
    pub plane: PlaneAxes,
    /// How the normal is found.
    pub rule: NormalRule,
}

/// The kind of contour normal an element carries, its vector (or point)
/// kept beside it in the element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum NormalKind {
    None,
    Fixed,
    Outward,
    Inward,
    FromCorner,
}

/// One element of the spooler (see the module documentation: its start
/// is the end of the element before it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpoolElement {
    end: AxisPos,
    /// Path length (arc length, helical where other axes move).
    length: f64,
    /// Feed, units/min.
    feed: f64,
    /// Arc centre `(h, v)`; unused on a line.
    centre: V2,
    /// Arc: unit vector from the centre to the start point.
    start_dir: V2,
    /// Arc: signed sweep (positive CCW); a full circle sweeps ±2π.
    sweep: f64,
    /// Arc: radius at the start.
    r0: f64,
    /// Arc: radius at the end (equal to `r0` up to rounding).
    r1: f64,
    /// The normal's vector, corner or centre (see [`NormalKind`]).
    normal_at: V2,
    /// Arc: its plane.
    plane: PlaneAxes,
    /// The normal's plane.
    normal_plane: PlaneAxes,
    normal: NormalKind,
    is_arc: bool,
    rapid: bool,
    origin: Origin,
}

/// The plane fields of an element that has none.
const NO_PLANE: PlaneAxes = PlaneAxes {
    h: 0,
    v: 1,
    third: 2,
};

/// `Σ (end − start)²` over the axes outside `plane`: zero where none moves.
fn off_plane_squared(start: &AxisPos, end: &AxisPos, plane: PlaneAxes) -> f64 {
    let (h, v) = (usize::from(plane.h), usize::from(plane.v));
    (0..AXES)
        .filter(|&i| i != h && i != v)
        .map(|i| (end[i] - start[i]) * (end[i] - start[i]))
        .sum()
}

fn line_length(start: &AxisPos, end: &AxisPos) -> f64 {
    start
        .iter()
        .zip(end)
        .map(|(a, b)| (b - a) * (b - a))
        .sum::<f64>()
        .sqrt()
}

/// The signed sweep from `s` to `e` (vectors from the centre) in the
/// direction given; start = end is a whole turn.
fn sweep_of(s: V2, e: V2, ccw: bool) -> f64 {
    let sweep = (s.x * e.y - s.y * e.x).atan2(s.x * e.x + s.y * e.y); // (-π, π]
    if ccw {
        if sweep <= ZERO_SWEEP {
            return sweep + TAU;
        }
    } else if sweep >= -ZERO_SWEEP {
        return sweep - TAU;
    }
    sweep
}

impl SpoolElement {
    /// An element to `end` of `length` without plane geometry or normal.
    #[inline]
    fn bare(end: AxisPos, length: f64, feed: f64, rapid: bool, origin: Origin) -> Self {
        Self {
            end,
            length,
            feed,
            centre: V2::zeros(),
            start_dir: V2::zeros(),
            sweep: 0.0,
            r0: 0.0,
            r1: 0.0,
            normal_at: V2::zeros(),
            plane: NO_PLANE,
            normal_plane: NO_PLANE,
            normal: NormalKind::None,
            is_arc: false,
            rapid,
            origin,
        }
    }

    /// A straight element from `start` to `end`.
    #[inline]
    pub fn line(start: &AxisPos, end: AxisPos, feed: f64, rapid: bool, origin: Origin) -> Self {
        Self::bare(end, line_length(start, &end), feed, rapid, origin)
    }

    /// An arc element from `start` to `end` about `centre` in `plane`;
    /// start = end in the plane is a full circle.
    #[inline]
    pub fn arc(
        start: &AxisPos,
        end: AxisPos,
        plane: PlaneAxes,
        centre: V2,
        ccw: bool,
        feed: f64,
        origin: Origin,
    ) -> Self {
        let s = plane.point(start) - centre;
        let e = plane.point(&end) - centre;
        let sweep = sweep_of(s, e, ccw);
        let (r0, r1) = (s.x.hypot(s.y), e.x.hypot(e.y));
        // On the centre, the start direction is that of angle 0.
        let start_dir = if r0 > 0.0 { s / r0 } else { V2::x() };
        let plane_len = sweep.abs() * 0.5 * (r0 + r1);
        let other = off_plane_squared(start, &end, plane);
        let length = (plane_len * plane_len + other).sqrt();
        Self {
            centre,
            start_dir,
            sweep,
            r0,
            r1,
            plane,
            is_arc: true,
            ..Self::bare(end, length, feed, false, origin)
        }
    }

    /// The same element with its contour normal.
    #[inline]
    pub fn with_normal(mut self, normal: Option<ContourNormal>) -> Self {
        let Some(n) = normal else {
            self.normal = NormalKind::None;
            return self;
        };
        self.normal_plane = n.plane;
        (self.normal, self.normal_at) = match n.rule {
            NormalRule::Fixed(v) => (NormalKind::Fixed, v),
            NormalRule::Radial { centre, outward } if outward => (NormalKind::Outward, centre),
            NormalRule::Radial { centre, .. } => (NormalKind::Inward, centre),
            NormalRule::FromCorner(k) => (NormalKind::FromCorner, k),
        };
        self
    }

    /// The end position, all axes.
    #[inline]
    pub fn end(&self) -> &AxisPos {
        &self.end
    }

    /// Path length (arc length, helical where other axes move).
    #[inline]
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Feed in units/min.
    #[inline]
    pub fn feed(&self) -> f64 {
        self.feed
    }

    /// A rapid move (`RAP`).
    #[inline]
    pub fn rapid(&self) -> bool {
        self.rapid
    }

    /// Who spooled it.
    #[inline]
    pub fn origin(&self) -> Origin {
        self.origin
    }

    /// The same element with another origin tag (the departure).
    pub fn with_origin(self, origin: Origin) -> Self {
        Self { origin, ..self }
    }

    /// Line or arc.
    pub fn path(&self) -> Path {
        if !self.is_arc {
            return Path::Line;
        }
        Path::Arc(ArcPath {
            plane: self.plane,
            centre: self.centre,
            ccw: self.sweep > 0.0,
        })
    }

    /// The contour normal, for elements the correction spooled.
    pub fn normal(&self) -> Option<ContourNormal> {
        let v = self.normal_at;
        let rule = match self.normal {
            NormalKind::None => return None,
            NormalKind::Fixed => NormalRule::Fixed(v),
            NormalKind::Outward => NormalRule::Radial {
                centre: v,
                outward: true,
            },
            NormalKind::Inward => NormalRule::Radial {
                centre: v,
                outward: false,
            },
            NormalKind::FromCorner => NormalRule::FromCorner(v),
        };
        Some(ContourNormal {
            plane: self.normal_plane,
            rule,
        })
    }

    /// The element from `start` as it is reported (spool log, wire).
    pub fn record(&self, start: &AxisPos) -> SpoolRecord {
        SpoolRecord {
            arc: self.is_arc.then(|| ArcRecord {
                plane: [self.plane.h, self.plane.v, self.plane.third],
                centre: [self.centre.x, self.centre.y],
                ccw: self.sweep > 0.0,
            }),
            start: *start,
            end: self.end,
            feed: self.feed,
            rapid: self.rapid,
            origin: self.origin,
        }
    }

    /// The fraction of the element run at path distance `s`.
    #[inline]
    pub fn fraction(&self, s: f64) -> f64 {
        if self.length > 0.0 {
            (s / self.length).clamp(0.0, 1.0)
        } else {
            1.0
        }
    }

    /// Arc: the unit vector from the centre at fraction `f` of the sweep,
    /// the start direction turned by `sweep · f`.
    fn dir_at(&self, f: f64) -> V2 {
        let (sin, cos) = (self.sweep * f).sin_cos();
        let [c0, s0] = [self.start_dir.x, self.start_dir.y];
        V2::new(c0 * cos - s0 * sin, s0 * cos + c0 * sin)
    }

    /// The position at path distance `s` (0 ≤ s ≤ length) of the element
    /// run from `start`.
    pub fn point_at(&self, start: &AxisPos, s: f64) -> AxisPos {
        let f = self.fraction(s);
        let mut p = *start;
        for (i, q) in p.iter_mut().enumerate() {
            *q += (self.end[i] - start[i]) * f;
        }
        if self.is_arc {
            let r = self.r0 + (self.r1 - self.r0) * f;
            self.plane
                .set_point(&mut p, self.centre + self.dir_at(f) * r);
        }
        p
    }

    /// The chord direction per unit of path, all axes (a line's tangent).
    fn chord(&self, start: &AxisPos) -> AxisPos {
        std::array::from_fn(|i| (self.end[i] - start[i]) / self.length)
    }

    /// Arc: the tangent in its plane where the direction from the centre
    /// is `(cos, sin)` at radius `r`: along the circle (r dθ/ds) plus the
    /// radius' own drift (dr/ds).
    fn arc_tangent(&self, cos: f64, sin: f64, r: f64) -> V2 {
        let k = self.sweep * r / self.length;
        let dr = (self.r1 - self.r0) / self.length;
        V2::new(-k * sin + dr * cos, k * cos + dr * sin)
    }

    /// The unit path tangent at distance `s` of the element run from
    /// `start`, on all axes (zero for an element without length).
    pub fn tangent_at(&self, start: &AxisPos, s: f64) -> AxisPos {
        if self.length <= 0.0 {
            return [0.0; AXES];
        }
        let mut t = self.chord(start);
        if self.is_arc {
            let f = self.fraction(s);
            let d = self.dir_at(f);
            let r = self.r0 + (self.r1 - self.r0) * f;
            self.plane.set_point(&mut t, self.arc_tangent(d.x, d.y, r));
        }
        t
    }

    /// The unit path tangent at distance `s`, where the element passes
    /// through `p` (its [`SpoolElement::point_at`] of `s`): as
    /// [`SpoolElement::tangent_at`], but an arc takes its direction from
    /// `p` and the centre instead of turning the start direction again (no
    /// trigonometry; the per-cycle models ask this every cycle).
    pub fn tangent_through(&self, start: &AxisPos, s: f64, p: &AxisPos) -> AxisPos {
        if !self.is_arc {
            return self.tangent_at(start, s);
        }
        let c = self.plane.point(p) - self.centre;
        // Within ±1e9: no overflow; a square root is several times
        // cheaper than `hypot`.
        let r = (c.x * c.x + c.y * c.y).sqrt();
        if r.is_nan() || r <= 0.0 || self.length <= 0.0 {
            return self.tangent_at(start, s);
        }
        let mut t = self.chord(start);
        self.plane
            .set_point(&mut t, self.arc_tangent(c.x / r, c.y / r, r));
        t
    }

    /// The path direction at distance `s` through `p`, not normalised:
    /// [`SpoolElement::tangent_through`] times the element's length (a
    /// line: end − start), without a division for the axes outside an
    /// arc's plane; zero for an element without length.
    #[inline]
    pub fn direction_through(&self, start: &AxisPos, s: f64, p: &AxisPos) -> AxisPos {
        if self.length <= 0.0 {
            return [0.0; AXES];
        }
        let d: AxisPos = std::array::from_fn(|i| self.end[i] - start[i]);
        if !self.is_arc {
            return d;
        }
        let c = self.plane.point(p) - self.centre;
        // Within ±1e9: no overflow.
        let r = (c.x * c.x + c.y * c.y).sqrt();
        if r.is_nan() || r <= 0.0 {
            return self.tangent_at(start, s).map(|x| x * self.length);
        }
        // Along the circle (sweep · r per unit of fraction) plus the
        // radius' own drift (r1 − r0), in the direction of the point.
        let drift = (self.r1 - self.r0) / r;
        let (ph, pv) = (
            -self.sweep * c.y + drift * c.x,
            self.sweep * c.x + drift * c.y,
        );
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

#[cfg(test)]
mod tests;
