//! Unit tests of `element`.

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
