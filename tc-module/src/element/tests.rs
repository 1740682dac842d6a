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

const START: AxisPos = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
const QUARTER_END: AxisPos = [0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];

/// A quarter circle about the origin from [`START`] to [`QUARTER_END`].
fn quarter(ccw: bool) -> SpoolElement {
    let (centre, o) = (V2::zeros(), Origin::Uncorrected);
    SpoolElement::arc(&START, &QUARTER_END, XY, centre, ccw, 1000.0, o)
}

#[test]
fn quarter_arc_length_midpoint_and_tangent() {
    let (s, e) = (&START, &QUARTER_END);
    let ccw = quarter(true);
    assert!((ccw.length() - FRAC_PI_2).abs() < 1e-12);
    let m = ccw.point_at(s, e, ccw.length() / 2.0);
    assert!((m[0] - FRAC_1_SQRT_2).abs() < 1e-12 && (m[1] - FRAC_1_SQRT_2).abs() < 1e-12);
    let t = ccw.tangent_at(s, e, 0.0);
    assert!((t[0]).abs() < 1e-12 && (t[1] - 1.0).abs() < 1e-12);
    let cw = quarter(false);
    assert!((cw.length() - 3.0 * FRAC_PI_2).abs() < 1e-12);
    let t = cw.tangent_at(s, e, 0.0);
    assert!((t[1] + 1.0).abs() < 1e-12);
    let r = cw.record(s, e);
    assert_eq!((r.start, r.end), (START, QUARTER_END));
    assert_eq!(r.arc.map(|a| (a.centre, a.ccw)), Some(([0.0, 0.0], false)));
    assert_eq!(cw.to(), V2::new(0.0, 1.0));
}

#[test]
fn arc_starting_on_its_centre_runs_from_angle_zero() {
    // Start on the centre: no sweep can be measured, so a whole CCW
    // turn from angle 0 (as atan2(0, 0) gave) while the radius grows
    // from 0 to 1.
    let (start, o) = (pos(0.0, 0.0), Origin::Uncorrected);
    let e = SpoolElement::arc(&start, &QUARTER_END, XY, V2::zeros(), true, 1000.0, o);
    let q = e.point_at(&start, &QUARTER_END, e.length() / 2.0);
    let (r, ang) = (0.5, std::f64::consts::PI);
    assert!((q[0] - r * ang.cos()).abs() < 1e-12 && (q[1] - r * ang.sin()).abs() < 1e-12);
}

#[test]
fn the_tangent_through_a_point_is_the_tangent_at_its_distance() {
    let (two, zero, o) = (pos(2.0, 0.0), pos(0.0, 0.0), Origin::Uncorrected);
    let mut helix_end = pos(-1.0, 0.0);
    helix_end[2] = 3.0;
    let spiral = SpoolElement::arc(&two, &helix_end, XY, V2::zeros(), true, 1.0, o);
    let slope = pos(3.0, 4.0);
    let line = SpoolElement::line(&zero, &slope, XY, 1.0, false, Origin::Corrected);
    let elements = [
        (START, QUARTER_END, quarter(true)),
        (START, QUARTER_END, quarter(false)),
        (two, helix_end, spiral),
        (zero, slope, line),
    ];
    for (start, end, e) in &elements {
        for k in 0..=10 {
            let s = e.length() * f64::from(k) / 10.0;
            let p = e.point_at(start, end, s);
            let a = e.tangent_at(start, end, s);
            let b = e.tangent_through(start, end, s, &p);
            assert!(
                a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12),
                "{a:?} {b:?}"
            );
            let d = e.direction_through(start, end, s, &p);
            let scaled = a.map(|x| x * e.length());
            assert!(
                d.iter().zip(scaled).all(|(x, y)| (x - y).abs() < 1e-11),
                "{d:?}"
            );
        }
    }
}

#[test]
fn full_circle() {
    let o = Origin::Uncorrected;
    let e = SpoolElement::arc(&START, &START, XY, V2::zeros(), false, 1000.0, o);
    assert!((e.length() - TAU).abs() < 1e-12);
    let q = e.point_at(&START, &START, e.length() / 4.0);
    assert!((q[0]).abs() < 1e-12 && (q[1] + 1.0).abs() < 1e-12);
}

#[test]
fn line_tangent_and_normals() {
    let (zero, end) = (pos(0.0, 0.0), pos(3.0, 4.0));
    let l = SpoolElement::line(&zero, &end, XY, 1.0, false, Origin::Corrected);
    assert_eq!(l.tangent_at(&zero, &end, 1.0)[..2], [0.6, 0.8]);
    assert_eq!(l.normal_at(&pos(1.0, 1.0)), None);
    assert_eq!(l.normal(), None);
    let fixed = l.with_normal(Some(ContourNormal {
        plane: XY,
        rule: NormalRule::Fixed(V2::new(-0.8, 0.6)),
    }));
    assert_eq!(
        fixed.normal_at(&pos(1.0, 1.0)).map(|n| [n[0], n[1]]),
        Some([-0.8, 0.6])
    );
    let inward = NormalRule::Radial {
        centre: V2::zeros(),
        outward: false,
    };
    let radial = quarter(true).with_normal(Some(ContourNormal {
        plane: XY,
        rule: inward,
    }));
    assert_eq!(radial.normal().map(|n| n.rule), Some(inward));
    assert_eq!(
        radial.normal_at(&pos(0.0, 2.0)).map(|n| [n[0], n[1]]),
        Some([0.0, -1.0])
    );
    let corner = l.with_normal(Some(ContourNormal {
        plane: XY,
        rule: NormalRule::FromCorner(V2::new(1.0, 1.0)),
    }));
    assert_eq!(
        corner.normal_at(&pos(1.0, 3.0)).map(|n| [n[0], n[1]]),
        Some([0.0, 1.0])
    );
    assert_eq!(corner.normal_at(&pos(1.0, 1.0)), None);
}

#[test]
fn only_the_axes_that_move_add_to_the_length() {
    // A plane arc: the third axis stays; a helix adds its rise.
    let flat = quarter(true);
    let mut up = QUARTER_END;
    up[2] = 2.0;
    let helix = SpoolElement::arc(&START, &up, XY, V2::zeros(), true, 1.0, Origin::Corrected);
    assert!(!flat.moves_off_plane() && helix.moves_off_plane());
    assert_eq!(flat.length(), FRAC_PI_2);
    assert_eq!(helix.length(), (FRAC_PI_2 * FRAC_PI_2 + 4.0).sqrt());
    let mid = helix.point_at(&START, &up, helix.length() / 2.0);
    assert!((mid[2] - 1.0).abs() < 1e-15);
    let end = flat.point_at(&START, &QUARTER_END, flat.length());
    assert_eq!(end[2], 0.0);
    // A zero that turns into −0 is kept as a move: the end is kept whole.
    let mut minus = QUARTER_END;
    minus[3] = -0.0;
    let signed = SpoolElement::arc(
        &START,
        &minus,
        XY,
        V2::zeros(),
        true,
        1.0,
        Origin::Corrected,
    );
    assert!(signed.moves_off_plane());
}
