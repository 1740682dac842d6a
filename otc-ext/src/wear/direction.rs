//! The direction wear acts in, per processing type (docs/otc.md,
//! "Processing types and their directions" and "RADIUS in detail"): the
//! RADIUS weight and contour normal, the tilted LENGTH direction, the tool direction from
//! the orientation axis, and the surface normal.

use tc_module::{AxisPos, Cycle, Origin, PlaneAxes, SpoolElement, AXES};

/// Below this length `t − (t·v)·v` has no direction: the surface normal
/// is kept from before (SURF_NORM_DIR).
pub const DEGENERATE_NORMAL: f64 = 1e-9;

/// The RADIUS weight at the end of an element, by its tag: 1 after the
/// elements the correction spooled and the approach, 0 after the others
/// (the departure ends at 0), and 0 with no element before (a direct
/// command).
fn end_weight(e: Option<&SpoolElement>) -> f64 {
    match e.map(SpoolElement::origin) {
        Some(Origin::Corrected | Origin::Transition | Origin::Approach) => 1.0,
        _ => 0.0,
    }
}

/// The RADIUS weight at the cycle's end (docs/otc.md, "RADIUS in detail"): 1 on corrected and
/// transition elements; rising linearly in path length from its value at
/// the start to 1 along an approach; falling from it to 0 along the
/// departure; 0 elsewhere and before any element.
pub fn radius_weight(c: &Cycle<'_>) -> f64 {
    let Some(e) = c.current else { return 0.0 };
    let start = end_weight(c.previous);
    let f = e.fraction(c.done);
    match e.origin() {
        Origin::Corrected | Origin::Transition => 1.0,
        Origin::Approach => start + (1.0 - start) * f,
        Origin::Departure => start * (1.0 - f),
        _ => 0.0,
    }
}

fn axis(a: u8) -> usize {
    usize::from(a).min(AXES - 1)
}

/// LENGTH: `sin α · e1 + cos α · e3` on the first and third main axes,
/// `α` the disc tilt in degrees.
pub fn length_dir(tilt_deg: f64, axes: PlaneAxes) -> AxisPos {
    let (sin, cos) = tilt_deg.to_radians().sin_cos();
    let mut u = [0.0; AXES];
    u[axis(axes.h)] += sin;
    u[axis(axes.third)] += cos;
    u
}

/// The tool direction `(sin B, 0, cos B)` on the machine's X, Y, Z, `B` the
/// orientation axis in degrees (TOOL_DIR; SURF_NORM_DIR's `t`).
pub fn tool_dir(b_deg: f64, xyz: [u8; 3]) -> AxisPos {
    let (sin, cos) = b_deg.to_radians().sin_cos();
    let mut t = [0.0; AXES];
    t[axis(xyz[0])] += sin;
    t[axis(xyz[2])] += cos;
    t
}

/// 1 on the machine axes allocated as X, Y, Z, 0 on the others: the
/// surface normal lives on those axes only.
pub fn xyz_mask(xyz: [u8; 3]) -> AxisPos {
    let mut m = [0.0; AXES];
    for a in xyz {
        m[axis(a)] = 1.0;
    }
    m
}

fn dot(a: &AxisPos, b: &AxisPos) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// SURF_NORM_DIR: `normalize(t − (t·v)·v)` on X, Y, Z (`mask`, see
/// [`xyz_mask`]; `t` lies on them), `v` the unit path tangent there; or
/// `None` where it degenerates (no element, a path that moves none of X,
/// Y, Z, or `t` along it: `|t − (t·v)·v| < DEGENERATE_NORMAL`). Computed
/// from the unscaled path direction `p` as the same vector scaled by
/// `p·p`, `(p·p)·t − (t·p)·p`: one square root and one division a cycle.
pub fn surface_normal(c: &Cycle<'_>, t: &AxisPos, mask: &AxisPos) -> Option<AxisPos> {
    let d = c.direction()?;
    let p: AxisPos = std::array::from_fn(|i| d[i] * mask[i]);
    let pp = dot(&p, &p);
    if pp.is_nan() || pp <= 0.0 {
        return None;
    }
    let tp = dot(t, &p);
    let n: AxisPos = std::array::from_fn(|i| pp * t[i] - tp * p[i]);
    let len = dot(&n, &n).sqrt();
    if len.is_nan() || len < DEGENERATE_NORMAL * pp {
        return None;
    }
    let inv = 1.0 / len;
    Some(n.map(|x| x * inv))
}

#[cfg(test)]
mod tests {
    use super::*;

    const XYZ: AxisPos = [1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0];

    const XY: PlaneAxes = PlaneAxes {
        h: 0,
        v: 1,
        third: 2,
    };

    fn pos(x: f64, y: f64, z: f64) -> AxisPos {
        let mut p = [0.0; AXES];
        (p[0], p[1], p[2]) = (x, y, z);
        p
    }

    /// Where the test elements start.
    const ZERO: AxisPos = [0.0; AXES];

    fn line(origin: Origin, to: AxisPos) -> SpoolElement {
        SpoolElement::line(&ZERO, &to, XY, 1000.0, false, origin)
    }

    /// A cycle `done` along `current` (from [`ZERO`] to `end`).
    fn cycle<'a>(
        current: Option<&'a SpoolElement>,
        end: &'a AxisPos,
        previous: Option<&'a SpoolElement>,
        done: f64,
        nominal: &'a AxisPos,
    ) -> Cycle<'a> {
        Cycle {
            parts: &[],
            current,
            start: &ZERO,
            end,
            done,
            previous,
            nominal,
        }
    }

    #[test]
    fn weight_rises_along_the_approach_and_falls_along_the_departure() {
        let (p, ten) = ([0.0; AXES], pos(10.0, 0.0, 0.0));
        let approach = line(Origin::Approach, ten);
        let corrected = line(Origin::Corrected, ten);
        let departure = line(Origin::Departure, ten);
        let plain = line(Origin::Uncorrected, ten);
        let w = |c, prev, d| radius_weight(&cycle(Some(c), &ten, prev, d, &p));
        assert_eq!(w(&approach, None, 2.5), 0.25);
        assert_eq!(w(&approach, Some(&plain), 10.0), 1.0);
        assert_eq!(w(&approach, Some(&corrected), 2.5), 1.0);
        assert_eq!(w(&corrected, None, 2.5), 1.0);
        assert_eq!(w(&departure, Some(&corrected), 2.5), 0.75);
        assert_eq!(w(&departure, Some(&plain), 2.5), 0.0);
        assert_eq!(w(&departure, None, 10.0), 0.0);
        assert_eq!(w(&plain, Some(&corrected), 2.5), 0.0);
        assert_eq!(radius_weight(&cycle(None, &p, None, 0.0, &p)), 0.0);
    }

    #[test]
    fn length_direction_follows_the_tilt() {
        let u = length_dir(0.0, XY);
        assert_eq!((u[0], u[2]), (0.0, 1.0));
        let u = length_dir(30.0, XY);
        assert!((u[0] - 0.5).abs() < 1e-15 && (u[2] - 0.75f64.sqrt()).abs() < 1e-15);
        let zx = PlaneAxes {
            h: 2,
            v: 0,
            third: 1,
        };
        let u = length_dir(-30.0, zx);
        assert!((u[2] + 0.5).abs() < 1e-15 && (u[1] - 0.75f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn tool_direction_at_45_and_90_degrees() {
        let t = tool_dir(45.0, [0, 1, 2]);
        let h = std::f64::consts::FRAC_1_SQRT_2;
        assert!((t[0] - h).abs() < 1e-15 && (t[2] - h).abs() < 1e-15 && t[1] == 0.0);
        let t = tool_dir(90.0, [0, 1, 2]);
        assert!((t[0] - 1.0).abs() < 1e-15 && t[2].abs() < 1e-15);
    }

    #[test]
    fn surface_normal_is_t_without_its_tangent_part() {
        let p = [0.0; AXES];
        let t = tool_dir(0.0, [0, 1, 2]);
        // Down a 45° slope in X-Z: v = (1, 0, -1)/√2, n = (1, 0, 1)/√2.
        let down = pos(1.0, 0.0, -1.0);
        let slope = line(Origin::Uncorrected, down);
        let n = surface_normal(&cycle(Some(&slope), &down, None, 0.5, &p), &t, &XYZ);
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let n = n.map(|n| [n[0], n[1], n[2]]);
        assert!(n.is_some_and(|n| (n[0] - h).abs() < 1e-15 && (n[2] - h).abs() < 1e-15));
        // Along Z, t is the tangent: no normal.
        let bottom = pos(0.0, 0.0, -1.0);
        let plunge = line(Origin::Uncorrected, bottom);
        assert_eq!(
            surface_normal(&cycle(Some(&plunge), &bottom, None, 0.5, &p), &t, &XYZ),
            None
        );
        // A pure B move has no X/Y/Z tangent; nothing moved: none either.
        let mut b = [0.0; AXES];
        b[4] = 10.0;
        let turn = line(Origin::Uncorrected, b);
        assert_eq!(
            surface_normal(&cycle(Some(&turn), &b, None, 1.0, &p), &t, &XYZ),
            None
        );
        assert_eq!(
            surface_normal(&cycle(None, &p, None, 0.0, &p), &t, &XYZ),
            None
        );
    }
}
