//! Property tests of the correction: for random open and
//! closed contours whose features are larger than the tool radius, every
//! corrected element keeps the distance |r| from the programmed contour on
//! the requested side, consecutive elements are continuous, and the
//! executor ends exactly on the last spooled end point.

// Test and bench helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::f64::consts::{FRAC_PI_3, TAU};

use proptest::prelude::*;
use tc_module::{ArcDir, Logged, Motion, NoExtension, Origin, Path, TcModule, AXES};
use tc_objects::TcObject;
use uoi::{ObjectAddress, ObjectBus, Value};

/// A programmed plane element, for measuring distances.
#[derive(Debug, Clone, Copy)]
enum Prog {
    Line([f64; 2], [f64; 2]),
    /// start, end, centre, ccw
    Arc([f64; 2], [f64; 2], [f64; 2], bool),
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}
fn norm(a: [f64; 2]) -> f64 {
    a[0].hypot(a[1])
}
fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    norm(sub(a, b))
}

/// Distance from p to the element, and whether the foot point is interior
/// (with the signed side: + left of the direction of travel).
fn distance(p: [f64; 2], e: &Prog) -> (f64, Option<f64>) {
    match *e {
        Prog::Line(a, b) => {
            let ab = sub(b, a);
            let l2 = ab[0] * ab[0] + ab[1] * ab[1];
            let u = ((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / l2;
            if u <= 1e-6 {
                (dist(p, a), None)
            } else if u >= 1.0 - 1e-6 {
                (dist(p, b), None)
            } else {
                let foot = [a[0] + ab[0] * u, a[1] + ab[1] * u];
                let side = ab[0] * (p[1] - a[1]) - ab[1] * (p[0] - a[0]);
                (dist(p, foot), Some(side.signum()))
            }
        }
        Prog::Arc(s, t, c, ccw) => {
            let ang = |q: [f64; 2]| (q[1] - c[1]).atan2(q[0] - c[0]);
            let sigma = if ccw { 1.0 } else { -1.0 };
            let mut sweep = (sigma * (ang(t) - ang(s))).rem_euclid(TAU);
            if sweep < 1e-12 {
                sweep = TAU;
            }
            let at = (sigma * (ang(p) - ang(s))).rem_euclid(TAU);
            let r = dist(s, c);
            if at > 1e-6 && at < sweep - 1e-6 {
                let rp = dist(p, c);
                // Left of a CCW arc is inside.
                let side = sigma * (r - rp).signum();
                ((rp - r).abs(), Some(side))
            } else {
                (dist(p, s).min(dist(p, t)), None)
            }
        }
    }
}

fn write(tc: &mut TcModule, a: ObjectAddress, v: Value) {
    tc.write_checked(a, v).expect("write accepted");
}

fn words(p: [f64; 2]) -> [Option<f64>; AXES] {
    let mut w = [None; AXES];
    w[0] = Some(p[0]);
    w[1] = Some(p[1]);
    w
}

/// Runs a contour through the correction and checks every property.
fn check(
    start: [f64; 2],
    prog: &[Prog],
    radius: f64,
    left: bool,
    linear: bool,
) -> Result<(), TestCaseError> {
    let mut pos = [0.0; AXES];
    pos[0] = start[0];
    pos[1] = start[1];
    let mut tc = TcModule::new(pos, tc_module::CycleTime::DEFAULT, NoExtension);
    tc.spooler_mut().set_logging(true);
    write(&mut tc, TcObject::WkzIndex.of(1), Value::I32(1));
    write(&mut tc, TcObject::Radius.of(1), Value::F64(radius));
    write(
        &mut tc,
        if left {
            TcObject::Left.of(1)
        } else {
            TcObject::Right.of(1)
        },
        Value::I32(0),
    );
    write(
        &mut tc,
        TcObject::TransitionMode.of(1),
        Value::I32(i32::from(linear)),
    );
    write(&mut tc, TcObject::Status.of(1), Value::I32(1));
    for e in prog {
        let m = match *e {
            Prog::Line(_, b) => Motion::Lin {
                words: words(b),
                feed: Some(60000.0),
            },
            Prog::Arc(s, t, c, ccw) => Motion::Cir {
                dir: if ccw { ArcDir::Ccw } else { ArcDir::Cw },
                words: words(t),
                centre: [Some(c[0] - s[0]), Some(c[1] - s[1]), None],
                feed: Some(60000.0),
            },
        };
        tc.command(&m)
            .map_err(|e| TestCaseError::fail(format!("{e}")))?;
    }
    write(&mut tc, TcObject::Status.of(1), Value::I32(0));
    let err = tc.group_at(1).map(|g| g.error.bits()).unwrap_or(-1);
    prop_assert_eq!(err, 0, "ERROR bits set for a contour that fits");
    let log: Vec<Logged> = tc.spooler_mut().take_log();
    prop_assert!(!log.is_empty());

    let want_side = if left { 1.0 } else { -1.0 };
    let mut prev_end = pos;
    for (
        i,
        Logged {
            start,
            end,
            element: e,
        },
    ) in log.iter().enumerate()
    {
        prop_assert!(
            start.iter().chain(end).all(|v| v.is_finite()),
            "non-finite element {i}"
        );
        prop_assert!(e.length().is_finite());
        for (a, b) in start.iter().zip(&prev_end) {
            prop_assert!(
                (a - b).abs() <= 1e-9,
                "element {i} does not start where {} ended",
                i.saturating_sub(1)
            );
        }
        prev_end = *end;
        if let Path::Arc(a) = e.path() {
            let c = [a.centre.x, a.centre.y];
            let (r0, r1) = (dist([start[0], start[1]], c), dist([end[0], end[1]], c));
            prop_assert!(
                (r0 - r1).abs() <= 1e-6,
                "arc element {i} changes radius {r0} -> {r1}"
            );
        }
        if !matches!(e.origin(), Origin::Corrected | Origin::Transition) {
            continue;
        }
        for j in 0..=16 {
            let q = e.point_at(start, end, e.length() * f64::from(j) / 16.0);
            let p = [q[0], q[1]];
            // The element spooled at STATUS=0 ends with its own offset end
            // (docs/trc.md "The one-profile buffer"): on a closed contour
            // that end lies next to the programmed start, so it is
            // measured against its own programmed element only.
            let against: &[Prog] = if i + 1 == log.len() {
                &prog[prog.len() - 1..]
            } else {
                prog
            };
            let mut best = (f64::INFINITY, None);
            for g in against {
                let d = distance(p, g);
                if d.0 < best.0 {
                    best = d;
                }
            }
            if linear {
                prop_assert!(
                    best.0 >= radius - 1e-6,
                    "element {i} at {p:?} is {} from the contour",
                    best.0
                );
            } else {
                prop_assert!(
                    (best.0 - radius).abs() <= 1e-6,
                    "element {i} ({:?}) at {p:?} is {} from the contour, radius {radius}",
                    e.path(),
                    best.0
                );
            }
            if let (Some(side), true) = (best.1, best.0 > 1e-9) {
                prop_assert_eq!(
                    side,
                    want_side,
                    "element {} at {:?} on the wrong side",
                    i,
                    p
                );
            }
        }
    }

    // The executor, stepped cycle by cycle, ends exactly on the last end point.
    tc.exec(Some(u64::MAX / 4));
    prop_assert_eq!(tc.queue_len(), 0);
    prop_assert_eq!(tc.position(), prev_end);
    Ok(())
}

/// An x-monotone open path of lines and arcs: headings stay within ±60°,
/// elements are at least 6 r long, arcs have radii of at least 3 r.
fn open_path(r: f64) -> impl Strategy<Value = Vec<Prog>> {
    prop::collection::vec(
        (
            0.0f64..1.0,
            0.0f64..1.0,
            0.0f64..1.0,
            0.0f64..1.0,
            any::<bool>(),
        ),
        2..10,
    )
    .prop_map(move |specs| {
        let mut p = [0.0, 0.0];
        let mut h = 0.0f64;
        let lim = FRAC_PI_3;
        let mut out = Vec::new();
        for (turn_u, kind_u, size_u, sweep_u, ccw) in specs {
            let mut turn = if turn_u < 0.3 {
                0.0
            } else {
                0.1 + 0.9 * (turn_u - 0.3) / 0.7
            };
            if ccw {
                turn = -turn;
            }
            if (h + turn).abs() > lim {
                turn = -turn;
            }
            if (h + turn).abs() > lim {
                turn = 0.0;
            }
            h += turn;
            let min_len = 6.0 * r;
            let mut as_line = kind_u < 0.5;
            if !as_line {
                let big = 3.0 * r + 17.0 * r * size_u;
                let sigma = if ccw { 1.0 } else { -1.0 };
                let allowed = if sigma > 0.0 { lim - h } else { h + lim };
                let min_sweep = min_len / big;
                if allowed > min_sweep {
                    let sweep = min_sweep + (allowed - min_sweep) * sweep_u;
                    let nl = [-h.sin(), h.cos()];
                    let c = [p[0] + sigma * big * nl[0], p[1] + sigma * big * nl[1]];
                    let rel = sub(p, c);
                    let a = sigma * sweep;
                    let t = [
                        c[0] + rel[0] * a.cos() - rel[1] * a.sin(),
                        c[1] + rel[0] * a.sin() + rel[1] * a.cos(),
                    ];
                    out.push(Prog::Arc(p, t, c, ccw));
                    p = t;
                    h += a;
                } else {
                    as_line = true;
                }
            }
            if as_line {
                let len = min_len + 30.0 * r * size_u;
                let t = [p[0] + len * h.cos(), p[1] + len * h.sin()];
                out.push(Prog::Line(p, t));
                p = t;
            }
        }
        out
    })
}

/// A closed convex polygon, traversed CCW from vertex 0 round to vertex 1
/// again so the closing corner is corrected too.
fn closed_polygon(r: f64) -> impl Strategy<Value = Vec<Prog>> {
    (
        prop::collection::vec(0.7f64..1.3, 4..9),
        20.0f64..60.0,
        0.0f64..TAU,
    )
        .prop_map(move |(gaps, rho, phase)| {
            let total: f64 = gaps.iter().sum();
            let mut ang = phase;
            let mut pts = Vec::new();
            for g in &gaps {
                pts.push([rho * r * ang.cos(), rho * r * ang.sin()]);
                ang += g / total * TAU;
            }
            let n = pts.len();
            (0..=n)
                .map(|i| Prog::Line(pts[i % n], pts[(i + 1) % n]))
                .collect()
        })
}

fn circle(r: f64) -> impl Strategy<Value = Vec<Prog>> {
    (3.0f64..30.0, any::<bool>()).prop_map(move |(k, ccw)| {
        let s = [0.0, 0.0];
        vec![Prog::Arc(s, s, [k * r, 0.0], ccw)]
    })
}

fn start_of(prog: &[Prog]) -> [f64; 2] {
    match prog[0] {
        Prog::Line(s, _) | Prog::Arc(s, _, _, _) => s,
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn open_contours_keep_the_radius((r, prog) in (0.5f64..3.0).prop_flat_map(|r| (Just(r), open_path(r))), left in any::<bool>(), linear in any::<bool>()) {
        check(start_of(&prog), &prog, r, left, linear)?;
    }

    #[test]
    fn closed_polygons_keep_the_radius((r, prog) in (0.5f64..3.0).prop_flat_map(|r| (Just(r), closed_polygon(r))), left in any::<bool>(), linear in any::<bool>()) {
        check(start_of(&prog), &prog, r, left, linear)?;
    }

    #[test]
    fn full_circles_keep_the_radius((r, prog) in (0.5f64..3.0).prop_flat_map(|r| (Just(r), circle(r))), left in any::<bool>()) {
        check(start_of(&prog), &prog, r, left, false)?;
    }

    #[test]
    fn negative_radius_equals_the_other_side((r, prog) in (0.5f64..3.0).prop_flat_map(|r| (Just(r), open_path(r)))) {
        // Left with -r must spool exactly what Right with r spools.
        let run = |radius: f64, side: ObjectAddress| {
            let mut tc = TcModule::default();
            tc.spooler_mut().set_logging(true);
            write(&mut tc, TcObject::Radius.of(1), Value::F64(radius));
            write(&mut tc, side, Value::I32(0));
            write(&mut tc, TcObject::Status.of(1), Value::I32(1));
            for e in &prog {
                let m = match *e {
                    Prog::Line(_, b) => Motion::Lin { words: words(b), feed: None },
                    Prog::Arc(s, t, c, ccw) => Motion::Cir {
                        dir: if ccw { ArcDir::Ccw } else { ArcDir::Cw },
                        words: words(t),
                        centre: [Some(c[0] - s[0]), Some(c[1] - s[1]), None],
                        feed: None,
                    },
                };
                let _ = tc.command(&m);
            }
            write(&mut tc, TcObject::Status.of(1), Value::I32(0));
            tc.spooler_mut().take_log()
        };
        let a = run(-r, TcObject::Left.of(1));
        let b = run(r, TcObject::Right.of(1));
        prop_assert_eq!(a, b);
    }
}

/// Coordinates that provoke degenerate geometry: coincident points, tiny
/// and huge values.
fn coord() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(0.0),
        Just(1e-12),
        Just(-1e-12),
        Just(1.0),
        Just(10.0),
        Just(1e6),
        Just(1e9),
        Just(-1e9),
        Just(1e12),
        -100.0f64..100.0,
    ]
}

#[derive(Debug, Clone)]
enum Cmd {
    Lin(f64, f64, f64),
    Cir(bool, f64, f64, f64, f64),
    Radius(f64),
    Status(i32),
    ClearError,
    Ssf,
    Ja(f64),
    Exec(u64),
}

fn cmd() -> impl Strategy<Value = Cmd> {
    prop_oneof![
        4 => (coord(), coord(), coord()).prop_map(|(x, y, z)| Cmd::Lin(x, y, z)),
        4 => (any::<bool>(), coord(), coord(), coord(), coord()).prop_map(|(c, x, y, i, j)| Cmd::Cir(c, x, y, i, j)),
        1 => prop_oneof![Just(0.0), Just(-2.0), Just(1e-12), Just(5.0), Just(1e9)].prop_map(Cmd::Radius),
        1 => (0..2i32).prop_map(Cmd::Status),
        1 => Just(Cmd::ClearError),
        1 => Just(Cmd::Ssf),
        1 => coord().prop_map(Cmd::Ja),
        1 => (0..50u64).prop_map(Cmd::Exec),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Whatever arrives, nothing panics and nothing non-finite is spooled
    /// or executed.
    #[test]
    fn degenerate_input_never_spools_nan(cmds in prop::collection::vec(cmd(), 1..40), left in any::<bool>(), linear in any::<bool>()) {
        let mut tc = TcModule::default();
        tc.spooler_mut().set_logging(true);
        write(&mut tc, TcObject::Radius.of(1), Value::F64(2.0));
        write(&mut tc, if left { TcObject::Left.of(1) } else { TcObject::Right.of(1) }, Value::I32(0));
        write(&mut tc, TcObject::TransitionMode.of(1), Value::I32(i32::from(linear)));
        write(&mut tc, TcObject::Status.of(1), Value::I32(1));
        for c in &cmds {
            let mut w = [None; AXES];
            match *c {
                Cmd::Lin(x, y, z) => {
                    w[0] = Some(x);
                    w[1] = Some(y);
                    w[2] = Some(z);
                    let _ = tc.command(&Motion::Lin { words: w, feed: None });
                }
                Cmd::Cir(ccw, x, y, i, j) => {
                    w[0] = Some(x);
                    w[1] = Some(y);
                    let dir = if ccw { ArcDir::Ccw } else { ArcDir::Cw };
                    let _ = tc.command(&Motion::Cir { dir, words: w, centre: [Some(i), Some(j), None], feed: None });
                }
                Cmd::Radius(r) => write(&mut tc, TcObject::Radius.of(1), Value::F64(r)),
                Cmd::Status(s) => write(&mut tc, TcObject::Status.of(1), Value::I32(s)),
                Cmd::ClearError => write(&mut tc, TcObject::Error.of(1), Value::I32(0)),
                Cmd::Ssf => {
                    let _ = tc.command(&Motion::Ssf { axis: 0, function: 2001 });
                }
                Cmd::Ja(x) => {
                    w[0] = Some(x);
                    let _ = tc.command(&Motion::Ja { words: w });
                }
                Cmd::Exec(n) => tc.exec(Some(n)),
            }
            for Logged { start, end, element: e } in tc.spooler_mut().take_log() {
                prop_assert!(start.iter().chain(&end).all(|v| v.is_finite()), "{:?}", e);
                prop_assert!(e.length().is_finite() && e.length() >= 0.0, "{:?}", e);
                prop_assert!(e.feed().is_finite() && e.feed() > 0.0);
                if let Path::Arc(a) = e.path() {
                    prop_assert!(a.centre.iter().all(|v| v.is_finite()));
                }
            }
            prop_assert!(tc.position().iter().all(|v| v.is_finite()));
        }
        tc.exec(None);
        prop_assert!(tc.position().iter().all(|v| v.is_finite()));
    }
}
