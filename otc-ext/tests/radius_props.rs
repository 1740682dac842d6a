//! Property tests of OTC RADIUS CONT on a running correction:
//! random open and closed contours of lines and arcs, left or right,
//! circular or linear transitions, random radius, feeds and wear constant.
//!
//! What is checked, with the wear `w` computed here from the spool log
//! (k · path travelled on Corrected and Transition elements, k =
//! WearConst · 1e-7; the path along the element under way is measured
//! from the nominal position):
//!
//! * at the end of every cycle that ends strictly inside a Corrected
//!   element, the nominal position lies at signed distance r from the
//!   programmed element it corrects (its line or circle, on the tool's
//!   side) and the executed position `POS` at exactly r − w;
//! * inside a Transition element, `POS` lies on the ray from the
//!   programmed corner K through the nominal position, w closer to K
//!   (circular transitions: the nominal at distance r, `POS` at r − w);
//! * `EXEC n` gives bit for bit the `POS`, cycle count and registers of
//!   n × `EXEC 1`, and `EXEC` until empty those of enough `EXEC 1`;
//! * at OtcOn=0, WearRadiusCont and WearRadius equal k · the whole
//!   corrected path, and the tool's radius is r − w.
//!
//! Cycles that end exactly on an element's start are not checked against
//! that element (docs/otc.md, "RADIUS in detail": the element that just ended is current
//! there). Corners are kept out of (0, 0.08] rad and near reversal, where
//! the correction lets an element start off its offset geometry
//! (docs/trc.md, corner case 1) and the distance to the element would
//! not be r.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;

use std::f64::consts::{PI, TAU};

use common::{otc_module, read_d, read_i, run};
use otc_ext::OtcExtension;
use proptest::prelude::*;
use tc_module::{Logged, Origin, Path, TcModule, AXES};
use tc_objects::{OtcObject, TcObject};

type P2 = [f64; 2];

fn sub(a: P2, b: P2) -> P2 {
    [a[0] - b[0], a[1] - b[1]]
}
fn add(a: P2, b: P2) -> P2 {
    [a[0] + b[0], a[1] + b[1]]
}
fn mul(a: P2, k: f64) -> P2 {
    [a[0] * k, a[1] * k]
}
fn dot(a: P2, b: P2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
fn cross(a: P2, b: P2) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
fn norm(a: P2) -> f64 {
    a[0].hypot(a[1])
}
fn unit(a: P2) -> P2 {
    mul(a, 1.0 / norm(a))
}
fn dir(angle: f64) -> P2 {
    [angle.cos(), angle.sin()]
}
/// Left normal `(-y, x)`.
fn left(a: P2) -> P2 {
    [-a[1], a[0]]
}
/// `p` turned about `c` by `angle`.
fn turn(p: P2, c: P2, angle: f64) -> P2 {
    let (s, k) = angle.sin_cos();
    let r = sub(p, c);
    add(c, [r[0] * k - r[1] * s, r[0] * s + r[1] * k])
}
fn xy(p: &[f64; AXES]) -> P2 {
    [p[0], p[1]]
}

/// A programmed profile (absolute end, absolute centre).
#[derive(Debug, Clone, Copy)]
enum Seg {
    Line {
        start: P2,
        end: P2,
    },
    Arc {
        start: P2,
        end: P2,
        centre: P2,
        ccw: bool,
    },
}

impl Seg {
    fn start(&self) -> P2 {
        match *self {
            Seg::Line { start, .. } | Seg::Arc { start, .. } => start,
        }
    }
    fn end(&self) -> P2 {
        match *self {
            Seg::Line { end, .. } | Seg::Arc { end, .. } => end,
        }
    }
    /// Unit tangent at point `p` of the element.
    fn tangent_at(&self, p: P2) -> P2 {
        match *self {
            Seg::Line { start, end } => unit(sub(end, start)),
            Seg::Arc { centre, ccw, .. } => {
                let t = unit(left(sub(p, centre)));
                if ccw {
                    t
                } else {
                    mul(t, -1.0)
                }
            }
        }
    }
    /// Signed distance of `p` from the element's line or circle, positive
    /// on the tool's side (`s` = +1 left, -1 right).
    fn side_distance(&self, p: P2, s: f64) -> f64 {
        match *self {
            Seg::Line { start, end } => s * dot(sub(p, start), left(unit(sub(end, start)))),
            Seg::Arc {
                start, centre, ccw, ..
            } => {
                let sigma = if ccw { 1.0 } else { -1.0 };
                sigma * s * (norm(sub(start, centre)) - norm(sub(p, centre)))
            }
        }
    }
    /// The request line, at feed `f`.
    fn request(&self, f: f64) -> String {
        match *self {
            Seg::Line { end, .. } => format!("LIN X{} Y{} F{f}", end[0], end[1]),
            Seg::Arc {
                start,
                end,
                centre,
                ccw,
            } => {
                let ij = sub(centre, start);
                let d = if ccw { "CCW" } else { "CW" };
                format!("CIR {d} X{} Y{} I{} J{} F{f}", end[0], end[1], ij[0], ij[1])
            }
        }
    }
}

/// Raw random parameters of one element.
type Raw = (u8, f64, f64, f64, f64);

/// One random case.
#[derive(Debug, Clone)]
struct Case {
    /// Profile 0 is the lead-in line (the approach); the others are
    /// corrected.
    profiles: Vec<Seg>,
    feeds: Vec<f64>,
    left: bool,
    r: f64,
    transition_mode: i32,
    wear_const: f64,
    /// Where `EXEC n` stops to compare with n × `EXEC 1`, as a fraction
    /// of the run.
    cut: f64,
}

/// An open contour: a lead-in line, then lines and arcs, each joined at
/// a corner of 0 (tangent) or 0.1..2 rad either way.
fn open_contour(h0: f64, lead: f64, raw: &[Raw]) -> Vec<Seg> {
    let v0 = mul(dir(h0), lead);
    let mut segs = vec![Seg::Line {
        start: [0.0, 0.0],
        end: v0,
    }];
    let (mut p, mut h) = (v0, h0);
    for &(kind, a, b, c, _) in raw {
        h += if c < 0.25 {
            0.0
        } else if c < 0.625 {
            -(0.1 + 1.9 * (c - 0.25) / 0.375)
        } else {
            0.1 + 1.9 * (c - 0.625) / 0.375
        };
        let len = 3.0 + 9.0 * a;
        if kind < 2 {
            let end = add(p, mul(dir(h), len));
            segs.push(Seg::Line { start: p, end });
            p = end;
        } else {
            let ccw = kind == 2;
            let sigma = if ccw { 1.0 } else { -1.0 };
            let rad = 2.5 + 9.5 * b;
            let sweep = (len / rad).min(2.5);
            let centre = add(p, mul(left(dir(h)), sigma * rad));
            let end = turn(p, centre, sigma * sweep);
            segs.push(Seg::Arc {
                start: p,
                end,
                centre,
                ccw,
            });
            p = end;
            h += sigma * sweep;
        }
    }
    segs
}

/// A closed contour around the origin: a lead-in from the origin to the
/// first vertex, the edges (lines, or short arcs bulging either way) all
/// round, and the first edge again so the closing corner is corrected.
fn closed_contour(reverse: bool, raw: &[Raw]) -> Vec<Seg> {
    let n = raw.len() as f64;
    let gap = TAU / n;
    let vertices: Vec<P2> = raw
        .iter()
        .enumerate()
        .map(|(i, &(_, a, b, _, _))| {
            let phi = gap * (i as f64 + 0.4 * (a - 0.5));
            mul(dir(if reverse { -phi } else { phi }), 8.0 + 7.0 * b)
        })
        .collect();
    let mut segs = vec![Seg::Line {
        start: [0.0, 0.0],
        end: vertices[0],
    }];
    for i in 0..=raw.len() {
        let (kind, _, _, c, _) = raw[i % raw.len()];
        let (start, end) = (vertices[i % raw.len()], vertices[(i + 1) % raw.len()]);
        if kind < 2 {
            segs.push(Seg::Line { start, end });
        } else {
            let chord = sub(end, start);
            let h = (0.5 + 2.5 * c) * norm(chord) * if kind == 2 { 1.0 } else { -1.0 };
            let centre = add(mul(add(start, end), 0.5), mul(left(unit(chord)), h));
            segs.push(Seg::Arc {
                start,
                end,
                centre,
                ccw: h > 0.0,
            });
        }
    }
    segs
}

/// Turn angle (0..π) at every corner between consecutive profiles.
fn corner_angles(segs: &[Seg]) -> Vec<f64> {
    segs.windows(2)
        .map(|w| {
            let k = w[0].end();
            let (ta, tb) = (w[0].tangent_at(k), w[1].tangent_at(w[1].start()));
            cross(ta, tb).abs().atan2(dot(ta, tb))
        })
        .collect()
}

fn cases() -> impl Strategy<Value = Case> {
    let raw = (0u8..4, 0.0..1.0, 0.0..1.0, 0.0..1.0, 1200.0..6000.0);
    (
        (any::<bool>(), any::<bool>(), 0.0..TAU, 3.0..10.0),
        prop::collection::vec(raw, 3..7),
        (
            any::<bool>(),
            0.3..1.5,
            0..2i32,
            1000.0..20000.0f64,
            0.0..1.0f64,
        ),
    )
        .prop_map(
            |((closed, reverse, h0, lead), raw, (left, r, mode, wear_const, cut))| {
                let profiles = if closed {
                    closed_contour(reverse, &raw)
                } else {
                    open_contour(h0, lead, &raw)
                };
                let mut feeds: Vec<f64> = raw.iter().map(|x| x.4.round()).collect();
                feeds.insert(0, 3000.0);
                feeds.resize(profiles.len(), 2000.0);
                Case {
                    profiles,
                    feeds,
                    left,
                    r,
                    transition_mode: mode,
                    wear_const: wear_const.round(),
                    cut,
                }
            },
        )
        .prop_filter("corners off the tangency tolerance and reversal", |c| {
            corner_angles(&c.profiles)
                .iter()
                .all(|&t| t < 1e-9 || (0.08..PI - 0.1).contains(&t))
        })
}

/// The module with the case spooled (OTC RADIUS CONT on, correction run
/// from the lead-in to STATUS=0, then a departure to the origin) and the
/// spool log; `None` when the correction refused the contour.
fn spooled(case: &Case) -> Option<(TcModule<OtcExtension>, Vec<Logged>)> {
    let mut tc = otc_module();
    tc.spooler_mut().set_logging(true);
    let side = if case.left { 9 } else { 10 };
    run(
        &mut tc,
        &format!(
            "W 1300/1/1/8 i 1
             W 1300/1/1/6 d {}
             W 1300/1/1/{side} i 1
             W 1300/2/1/1 i {}
             W 1300/3/1/30 i 2
             W 1300/3/1/2 i 0
             W 1300/3/1/3 i 1
             W 1300/3/1/4 d {}
             W 1300/3/1/1 i 1
             W 1300/1/1/3 i 1",
            case.r, case.transition_mode, case.wear_const
        ),
    );
    for (p, f) in case.profiles.iter().zip(&case.feeds) {
        let line = p.request(*f);
        let m = match tc_request::text::parse_request(&line) {
            Ok(tc_request::Request::Motion(m)) => m,
            other => panic!("{line}: {other:?}"),
        };
        if tc.command(&m).is_err() {
            return None;
        }
    }
    if read_i(&mut tc, TcObject::Error.of(1)) != 0 {
        return None;
    }
    run(&mut tc, "W 1300/1/1/3 i 0\nLIN X0 Y0");
    let log = tc.spooler_mut().take_log();
    Some((tc, log))
}

/// Path run on the logged element `l` from its start to `p` (on it).
fn along(l: &Logged, p: &[f64; AXES]) -> f64 {
    let (start, e) = (&l.start, &l.element);
    match e.path() {
        Path::Line => (0..AXES)
            .map(|i| (p[i] - start[i]).powi(2))
            .sum::<f64>()
            .sqrt(),
        Path::Arc(a) => {
            let (h, v) = (usize::from(a.plane.h), usize::from(a.plane.v));
            let c = [a.centre.x, a.centre.y];
            let s = [start[h] - c[0], start[v] - c[1]];
            let q = [p[h] - c[0], p[v] - c[1]];
            let mut angle = cross(s, q).atan2(dot(s, q));
            if !a.ccw {
                angle = -angle;
            }
            let angle = angle.rem_euclid(TAU);
            let run = norm(s) * angle;
            // Just short of the start, numerically: the start itself.
            if run > e.length() + 1e-6 {
                0.0
            } else {
                run
            }
        }
    }
}

fn wears(o: Origin) -> bool {
    matches!(o, Origin::Corrected | Origin::Transition)
}

/// What one run ends with: position, cycles, and the registers read
/// after OtcOn=0.
#[derive(Debug, PartialEq)]
struct End {
    pos: [u64; AXES],
    cycles: u64,
    wear_radius: u64,
    wear_radius_cont: u64,
    radius: u64,
    otc_error: i32,
}

fn bits(p: [f64; AXES]) -> [u64; AXES] {
    p.map(f64::to_bits)
}

fn finish(tc: &mut TcModule<OtcExtension>) -> End {
    let (pos, cycles) = (bits(tc.position()), tc.executor().cycles());
    run(tc, "W 1300/3/1/1 i 0");
    End {
        pos,
        cycles,
        wear_radius: read_d(tc, OtcObject::WearRadius.of(1)).to_bits(),
        wear_radius_cont: read_d(tc, OtcObject::WearRadiusCont.of(1)).to_bits(),
        radius: read_d(tc, TcObject::Radius.of(1)).to_bits(),
        otc_error: read_i(tc, OtcObject::OtcError.of(1)),
    }
}

/// Tolerance of the distance checks.
const TOL: f64 = 1e-9;

/// Checks the cycle that just ended against the geometry (see the module
/// doc).
fn check_cycle(
    tc: &TcModule<OtcExtension>,
    case: &Case,
    log: &[Logged],
    before: &[f64],
) -> Result<(), TestCaseError> {
    let Some(front) = tc.spooler().front() else {
        return Ok(());
    };
    let idx = log.len() - tc.spooler().len();
    prop_assert_eq!(front, &log[idx].element);
    let nominal = *tc.executor().nominal();
    let done = along(&log[idx], &nominal);
    if done <= 1e-9 {
        return Ok(());
    }
    let k = case.wear_const * 1e-7;
    let w = k * (before[idx] + if wears(front.origin()) { done } else { 0.0 });
    let (nom, pos) = (xy(&nominal), xy(&tc.position()));
    let s = if case.left { 1.0 } else { -1.0 };
    // The profile of the element: Approach is profile 0, the n-th
    // Corrected element profile n.
    let profile = log[..=idx]
        .iter()
        .filter(|e| matches!(e.element.origin(), Origin::Approach | Origin::Corrected))
        .count()
        - 1;
    match front.origin() {
        Origin::Corrected => {
            let seg = case.profiles[profile];
            let dn = seg.side_distance(nom, s);
            let dp = seg.side_distance(pos, s);
            prop_assert!((dn - case.r).abs() < TOL, "nominal at {dn}, r {}", case.r);
            prop_assert!(
                (dp - (case.r - w)).abs() < TOL,
                "POS at {dp}, want r - w = {} - {w}; element {idx}: {:?}",
                case.r,
                log[idx]
            );
        }
        Origin::Transition => {
            let corner = case.profiles[profile].end();
            let (dn, dp) = (norm(sub(nom, corner)), norm(sub(pos, corner)));
            if case.transition_mode == 0 {
                prop_assert!((dn - case.r).abs() < TOL, "nominal {dn} from K");
            }
            prop_assert!(
                (dp - (dn - w)).abs() < TOL,
                "POS {dp} from K, nominal {dn}, w {w}"
            );
            prop_assert!(cross(sub(nom, corner), sub(pos, corner)).abs() < TOL);
        }
        _ => {}
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 64,
        max_global_rejects: 4000,
        ..ProptestConfig::default()
    })]

    #[test]
    fn radius_cont_pos_lies_at_r_minus_w(case in cases()) {
        let Some((mut a, log)) = spooled(&case) else {
            return Err(TestCaseError::reject("the correction refused the contour"));
        };
        // One Approach, then one Corrected element per profile.
        let count = |o| log.iter().filter(|e| e.element.origin() == o).count();
        prop_assert_eq!(count(Origin::Approach), 1);
        prop_assert_eq!(count(Origin::Corrected), case.profiles.len() - 1);
        // Wearing path before each element.
        let mut before = vec![0.0];
        for e in log.iter().map(|l| l.element) {
            let last = *before.last().unwrap();
            before.push(last + if wears(e.origin()) { e.length() } else { 0.0 });
        }
        let total = *before.last().unwrap();

        // n × EXEC 1, checked every cycle.
        let mut at_cut = None;
        let budget = 200_000u64;
        while a.queue_len() > 0 {
            prop_assert!(a.executor().cycles() < budget, "does not end");
            a.exec(Some(1));
            check_cycle(&a, &case, &log, &before)?;
            if at_cut.is_none() && a.executor().cycles() as f64 >= 1.0 + case.cut * 4000.0 {
                at_cut = Some((a.executor().cycles(), bits(a.position())));
            }
        }
        let n = a.executor().cycles();
        let (cut, pos_at_cut) = at_cut.unwrap_or((n, bits(a.position())));
        let end_a = finish(&mut a);
        prop_assert_eq!(end_a.otc_error, 0);
        let w = case.wear_const * 1e-7 * total;
        let wear_cont = f64::from_bits(end_a.wear_radius_cont);
        prop_assert!((wear_cont - w).abs() < TOL, "WearRadiusCont {wear_cont}, want {w}");
        prop_assert_eq!(end_a.wear_radius, end_a.wear_radius_cont);
        prop_assert!((f64::from_bits(end_a.radius) - (case.r - wear_cont)).abs() < 1e-12);

        // EXEC cut, then EXEC until empty.
        let (mut b, _) = spooled(&case).unwrap();
        b.exec(Some(cut));
        prop_assert_eq!(bits(b.position()), pos_at_cut);
        b.exec(None);
        prop_assert_eq!(&finish(&mut b), &end_a);
        // EXEC n at once.
        let (mut c, _) = spooled(&case).unwrap();
        c.exec(Some(n));
        prop_assert_eq!(c.queue_len(), 0);
        prop_assert_eq!(&finish(&mut c), &end_a);
        // EXEC until empty from the start.
        let (mut d, _) = spooled(&case).unwrap();
        d.exec(None);
        prop_assert_eq!(&finish(&mut d), &end_a);
    }
}
