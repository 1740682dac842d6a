//! Property tests of programmed full circles (decisions 48, 76, 77 and
//! 330: a programmed full circle
//! keeps its whole turn): a full circle entered at a tangent, or nearly
//! so, is corrected as a whole turn, on either side and in either
//! direction, whether it is left by a flush, at a tangent, at an outside
//! or at an inside corner; one whose corrected start lies before its
//! offset start runs a whole turn and on to its own end. The expected
//! sweeps and end point are computed here from the exact geometry of the
//! program, independently of the correction code.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::f64::consts::{PI, TAU};

use proptest::prelude::*;
use tc_module::{ArcDir, ErrorBits, Logged, Motion, NoExtension, Origin, Path, TcModule, AXES};
use tc_objects::TcObject;
use uoi::{ObjectAddress, ObjectBus, Value};

type P2 = [f64; 2];

fn add(a: P2, b: P2) -> P2 {
    [a[0] + b[0], a[1] + b[1]]
}
fn sub(a: P2, b: P2) -> P2 {
    [a[0] - b[0], a[1] - b[1]]
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
fn unit(angle: f64) -> P2 {
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

/// How the circle is entered.
#[derive(Debug, Clone, Copy)]
enum Entry {
    /// A line of this length along the circle's tangent.
    Line(f64),
    /// An arc of radius `rho` and sweep `sweep`, tangent to the circle,
    /// its centre on the circle's side (`same_side`) or the other.
    Arc {
        rho: f64,
        sweep: f64,
        same_side: bool,
    },
}

/// How the circle is left.
#[derive(Debug, Clone, Copy)]
enum Exit {
    /// STATUS=0 right after it: the circle ends on its offset end.
    Flush,
    /// A line along the circle's end tangent.
    Tangent,
    /// A line turning by θ (0.1 .. π - 0.1) to the tool's side: an inside
    /// corner.
    Inside(f64),
    /// A line turning by θ (0.1 .. π - 0.1) away from the tool's side: an
    /// outside corner.
    Outside(f64),
}

/// One random program: lead-in, entry, full circle, exit.
#[derive(Debug, Clone, Copy)]
struct Case {
    /// Circle centre, radius, CCW.
    centre: P2,
    radius: f64,
    ccw: bool,
    /// Angle of the circle's start about its centre.
    alpha: f64,
    entry: Entry,
    /// The entry's end point (the circle's programmed start) moved by
    /// `eps` in direction `eps_dir` off the exact tangent point.
    eps: f64,
    eps_dir: f64,
    /// The entry's end tangent turned off the circle's tangent by this
    /// (radians; 0 for an exact tangent).
    tilt: f64,
    exit: Exit,
    /// Tool radius and side.
    tool: f64,
    tool_left: bool,
}

impl Case {
    fn sigma(&self) -> f64 {
        if self.ccw {
            1.0
        } else {
            -1.0
        }
    }
    /// The offset `d` (positive: left).
    fn d(&self) -> f64 {
        if self.tool_left {
            self.tool
        } else {
            -self.tool
        }
    }
    /// The circle's programmed start (and end): the exact tangent point
    /// moved by eps.
    fn start(&self) -> P2 {
        let exact = add(self.centre, mul(unit(self.alpha), self.radius));
        add(exact, mul(unit(self.eps_dir), self.eps))
    }
    /// The circle's tangent at the exact tangent point.
    fn tangent(&self) -> P2 {
        mul(left(unit(self.alpha)), self.sigma())
    }
}

fn entry() -> impl Strategy<Value = Entry> {
    prop_oneof![
        (5.0f64..40.0).prop_map(Entry::Line),
        (3.0f64..30.0, 0.2f64..1.5, any::<bool>()).prop_map(|(rho, sweep, same_side)| {
            Entry::Arc {
                rho,
                sweep,
                same_side,
            }
        }),
    ]
}

fn exit() -> impl Strategy<Value = Exit> {
    prop_oneof![
        Just(Exit::Flush),
        Just(Exit::Tangent),
        (0.1f64..PI - 0.1).prop_map(Exit::Inside),
        (0.1f64..PI - 0.1).prop_map(Exit::Outside),
    ]
}

/// A tilt of 1e-9 .. 0.04 rad either way (under the 0.05 rad of corner
/// case 1: the join stays smooth), or none.
fn tilt(tilted: bool) -> impl Strategy<Value = f64> {
    (-9.0f64..0.04f64.log10(), any::<bool>()).prop_map(move |(e, neg)| match (tilted, neg) {
        (false, _) => 0.0,
        (true, false) => 10f64.powf(e),
        (true, true) => -(10f64.powf(e)),
    })
}

prop_compose! {
    fn case(tilted: bool)(
        cx in -50.0f64..50.0, cy in -50.0f64..50.0, radius in 3.0f64..30.0,
        ccw in any::<bool>(), alpha in -PI..PI, entry in entry(),
        eps_exp in -12.0f64..-6.0, eps_dir in -PI..PI, tilt in tilt(tilted), exit in exit(),
        tool in 0.5f64..2.5, tool_left in any::<bool>(),
    ) -> Case {
        Case {
            centre: [cx, cy], radius, ccw, alpha, entry,
            eps: 10f64.powf(eps_exp), eps_dir, tilt, exit, tool, tool_left,
        }
    }
}

/// A programmed element: line to, or arc to with centre and direction.
#[derive(Debug, Clone, Copy)]
enum Prog {
    Line(P2),
    Arc(P2, P2, bool),
}

/// The program: lead-in line, entry, the full circle, the exit; and the
/// point it starts from.
fn program(c: &Case) -> (P2, Vec<Prog>) {
    let p = c.start();
    let t = c.tangent();
    let te = turn(t, [0.0, 0.0], c.tilt);
    let mut out = Vec::new();
    // The entry, ending on p along te, with its start and start tangent.
    let (entry_start, entry_tangent) = match c.entry {
        Entry::Line(len) => {
            let s = sub(p, mul(te, len));
            out.push(Prog::Line(p));
            (s, te)
        }
        Entry::Arc {
            rho,
            sweep,
            same_side,
        } => {
            let centre = entry_arc_centre(c, rho, same_side);
            // CCW arcs run with the centre on their left.
            let ccw = cross(te, sub(centre, p)) > 0.0;
            let s_arc = if ccw { 1.0 } else { -1.0 };
            let s = turn(p, centre, -s_arc * sweep);
            out.push(Prog::Arc(p, centre, ccw));
            let u = sub(s, centre);
            (s, mul(left(mul(u, 1.0 / norm(u))), s_arc))
        }
    };
    let lead_start = sub(entry_start, mul(entry_tangent, 5.0));
    out.insert(0, Prog::Line(entry_start));
    out.push(Prog::Arc(p, c.centre, c.ccw));
    match c.exit {
        Exit::Flush => {}
        Exit::Tangent => out.push(Prog::Line(add(p, mul(t, 20.0)))),
        Exit::Inside(theta) => {
            let to_side = if c.tool_left { theta } else { -theta };
            let tb = turn(t, [0.0, 0.0], to_side);
            out.push(Prog::Line(add(p, mul(tb, 80.0))));
        }
        Exit::Outside(theta) => {
            let away = if c.tool_left { -theta } else { theta };
            let tb = turn(t, [0.0, 0.0], away);
            out.push(Prog::Line(add(p, mul(tb, 20.0))));
        }
    }
    (lead_start, out)
}

/// The centre of an entry arc of radius rho ending on the circle's start
/// along the (tilted) tangent: on the normal there, on the circle's centre
/// side or the other.
fn entry_arc_centre(c: &Case, rho: f64, same_side: bool) -> P2 {
    let inward = turn(unit(c.alpha + PI), [0.0, 0.0], c.tilt);
    let nrm = if same_side { inward } else { mul(inward, -1.0) };
    add(c.start(), mul(nrm, rho))
}

fn words(p: P2) -> [Option<f64>; AXES] {
    let mut w = [None; AXES];
    w[0] = Some(p[0]);
    w[1] = Some(p[1]);
    w
}

fn write(tc: &mut TcModule, a: ObjectAddress, v: Value) {
    tc.write_checked(a, v).expect("write accepted");
}

/// Runs the program corrected; the ERROR bits and the spool log.
fn run(c: &Case) -> (i32, Vec<Logged>) {
    let (from, prog) = program(c);
    let mut pos = [0.0; AXES];
    pos[..2].copy_from_slice(&from);
    let mut tc = TcModule::new(pos, tc_module::CycleTime::DEFAULT, NoExtension);
    tc.spooler_mut().set_logging(true);
    write(&mut tc, TcObject::WkzIndex.of(1), Value::I32(1));
    write(&mut tc, TcObject::Radius.of(1), Value::F64(c.tool));
    let side = if c.tool_left {
        TcObject::Left.of(1)
    } else {
        TcObject::Right.of(1)
    };
    write(&mut tc, side, Value::I32(0));
    write(&mut tc, TcObject::Status.of(1), Value::I32(1));
    let mut at = from;
    for e in &prog {
        let m = match *e {
            Prog::Line(to) => {
                at = to;
                Motion::Lin {
                    words: words(to),
                    feed: None,
                }
            }
            Prog::Arc(to, centre, ccw) => {
                let m = Motion::Cir {
                    dir: if ccw { ArcDir::Ccw } else { ArcDir::Cw },
                    words: words(to),
                    centre: [Some(centre[0] - at[0]), Some(centre[1] - at[1]), None],
                    feed: None,
                };
                at = to;
                m
            }
        };
        tc.command(&m).expect("command accepted");
    }
    write(&mut tc, TcObject::Status.of(1), Value::I32(0));
    let err = tc.group_at(1).map(|g| g.error.bits()).unwrap_or(-1);
    (err, tc.spooler_mut().take_log())
}

/// The sweep of an arc element as the executor runs it: its plane length
/// over its mean radius.
fn sweep_of(l: &Logged, centre: P2) -> f64 {
    let (start, end) = (l.start, l.end);
    let r0 = norm(sub([start[0], start[1]], centre));
    let r1 = norm(sub([end[0], end[1]], centre));
    l.element.length() / (0.5 * (r0 + r1))
}

/// The corrected elements about the circle's centre (the full circle):
/// their sweeps, and where the last one ends.
fn circle_sweeps(c: &Case, log: &[Logged]) -> (Vec<f64>, Option<P2>) {
    let centre = c.centre;
    let on_circle: Vec<&Logged> = log
        .iter()
        .filter(|l| l.element.origin() == Origin::Corrected)
        .filter(|l| match l.element.path() {
            Path::Arc(a) => norm(sub([a.centre.x, a.centre.y], centre)) <= 1e-9,
            Path::Line => false,
        })
        .collect();
    let sweeps = on_circle.iter().map(|l| sweep_of(l, centre)).collect();
    let end = on_circle.last().map(|l| [l.end[0], l.end[1]]);
    (sweeps, end)
}

/// The angle from `a` to `b` about `centre`, positive in direction
/// `sigma`, in (-π, π].
fn angle_about(centre: P2, a: P2, b: P2, sigma: f64) -> f64 {
    let (a, b) = (sub(a, centre), sub(b, centre));
    sigma * cross(a, b).atan2(dot(a, b))
}

/// The circle's offset: (offset start = offset end, offset radius).
fn circle_offset(c: &Case) -> (P2, f64) {
    let u = sub(c.start(), c.centre);
    let radius = norm(u);
    let r_off = radius - c.sigma() * c.d();
    (add(c.centre, mul(u, r_off / radius)), r_off)
}

/// Where an inside corner after the circle cuts it: the exit line's
/// offset, k + d nL(tb) + s tb for s in [0, 80], meets the offset circle
/// (s² + 2 s (f·tb) + |f|² - r_off² = 0) at the point nearest the corner
/// k, if `on_circle` accepts it.
///
/// `tb` is the exit line's direction exactly as [`program`] writes it:
/// turned from the tangent at the exact tangent point, not from the
/// circle's tangent at k (up to eps / radius, 3.3e-7 rad, apart). Where
/// the exit's offset line all but touches the offset circle, the cut
/// turns about the centre |x - k| / √disc times as far as the line turns
/// (52 times in `grazing_inside_cut_after_a_tangent_entry`, unbounded
/// near a touch), so a model of a slightly different line is off by more
/// than any fixed tolerance.
fn inside_cut(c: &Case, theta: f64, on_circle: impl Fn(P2) -> bool) -> Option<P2> {
    let (k, d) = (c.start(), c.d());
    let (_, r_off) = circle_offset(c);
    let tb = turn(
        c.tangent(),
        [0.0, 0.0],
        if c.tool_left { theta } else { -theta },
    );
    let pb = add(k, mul(left(tb), d));
    let f = sub(pb, c.centre);
    let b = dot(f, tb);
    let disc = b * b - (dot(f, f) - r_off * r_off);
    if disc < 0.0 {
        return None;
    }
    [-b - disc.sqrt(), -b + disc.sqrt()]
        .into_iter()
        .filter(|s| (-1e-9..=80.0).contains(s))
        .map(|s| add(pb, mul(tb, s)))
        .filter(|x| on_circle(*x))
        .min_by(|p, q| norm(sub(*p, k)).total_cmp(&norm(sub(*q, k))))
}

/// Where the entry's corrected element ends: where the circle's corrected
/// element starts (corner case 1, b continues from a's end).
fn entry_offset_end(c: &Case) -> P2 {
    let (p, d) = (c.start(), c.d());
    let te = turn(c.tangent(), [0.0, 0.0], c.tilt);
    match c.entry {
        Entry::Line(_) => add(p, mul(left(te), d)),
        Entry::Arc { rho, same_side, .. } => {
            let centre = entry_arc_centre(c, rho, same_side);
            let s_arc = if cross(te, sub(centre, p)) > 0.0 {
                1.0
            } else {
                -1.0
            };
            let u = sub(p, centre);
            add(centre, mul(u, (rho - s_arc * d) / norm(u)))
        }
    }
}

/// What the corrected circle spools: the sweep of each element about its
/// centre, and where the last one ends.
#[derive(Debug, Clone, PartialEq)]
struct Expected {
    sweeps: Vec<f64>,
    end: P2,
}

/// The angle by which the circle's corrected start `from` (the entry's
/// offset end) lies after its offset start: negative before it.
fn start_shift(c: &Case) -> f64 {
    let (off_start, _) = circle_offset(c);
    angle_about(c.centre, off_start, entry_offset_end(c), c.sigma())
}

/// The corrected circle: from where its corrected element starts (the
/// entry's offset end) to where it ends. That start lies off the offset
/// start when the entry is tilted (up to 0.04 rad), and, by up to d·eps /
/// (radius·r_off) (1.7e-6 rad at the extremes of [`case`]), when the
/// entry's end point is eps off the tangent point. It keeps its whole
/// turn when it starts within 1e-7 rad of its offset start or before it;
/// otherwise its part ends at its offset end. Its end is the offset end
/// (flush, tangent or outside exit) or the inside cut nearest the
/// corner. A whole turn whose end lies at most 1e-7 rad past its start is
/// one exact turn; one past it by at most the overlap (how far the start
/// lies before the offset start) plus 1e-7 rad is a whole turn ending on
/// the start and then the arc on to the end (decision 330).
fn expected(c: &Case) -> Option<Expected> {
    let (sigma, centre) = (c.sigma(), c.centre);
    let (off_start, _) = circle_offset(c);
    let from = entry_offset_end(c);
    let shift = start_shift(c);
    let whole = shift.abs() <= 1e-7 || shift < 0.0;
    let x = match c.exit {
        Exit::Inside(theta) => inside_cut(c, theta, |x| {
            let on = |p: P2| angle_about(centre, from, p, sigma).rem_euclid(TAU);
            whole || on(x) <= on(off_start) + 1e-9
        })?,
        _ => off_start,
    };
    let past = angle_about(centre, from, x, sigma);
    let one = |sweep: f64, end: P2| Expected {
        sweeps: vec![sweep],
        end,
    };
    if whole && (0.0..=1e-7).contains(&past) {
        return Some(one(TAU, from));
    }
    if whole && past > 1e-7 && past <= (-shift).max(0.0) + 1e-7 {
        return Some(Expected {
            sweeps: vec![TAU, past],
            end: x,
        });
    }
    let sweep = past.rem_euclid(TAU);
    Some(one(if sweep <= 1e-12 { TAU } else { sweep }, x))
}

/// Runs the case and compares the spooled circle with `want`: its
/// elements' sweeps (within 1e-6 rad) and where it ends (within 1e-9).
fn check(c: &Case, want: Option<Expected>) -> Result<(), TestCaseError> {
    let (err, log) = run(c);
    let Some(want) = want else {
        // The exact geometry does not fit: KorrError.
        let korr = ErrorBits::KORR_ERROR.bits();
        prop_assert_eq!(err & korr, korr, "KorrError expected");
        return Ok(());
    };
    prop_assert_eq!(err, 0, "ERROR bits for a program that fits: {:?}", log);
    let (sweeps, end) = circle_sweeps(c, &log);
    prop_assert_eq!(
        sweeps.len(),
        want.sweeps.len(),
        "circle elements {:?}, expected {:?}: {:?}",
        sweeps,
        want.sweeps,
        log
    );
    for (got, exp) in sweeps.iter().zip(&want.sweeps) {
        prop_assert!(
            (got - exp).abs() <= 1e-6,
            "circle sweeps {:?} instead of {:?}",
            sweeps,
            want.sweeps
        );
    }
    let end = end.unwrap_or([f64::NAN; 2]);
    prop_assert!(
        norm(sub(end, want.end)) <= 1e-9,
        "circle ends at {:?} instead of {:?}",
        end,
        want.end
    );
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(384))]

    /// Tangent entries into full circles (lines and arcs, both sides, both
    /// directions, the tangent point off by 1e-12 .. 1e-6): the circle is
    /// spooled as one element covering a whole turn (within 1e-6 rad),
    /// less what an inside corner after it cuts, and no error is raised
    /// where the tool fits. (A start more than 1e-7 rad ahead of the
    /// offset start, possible only with eps near 1e-6 on a small circle
    /// with a large tool inside, runs to the offset end: a turn less that.)
    #[test]
    fn tangent_entry_keeps_the_whole_turn(c in case(false)) {
        check(&c, expected(&c))?;
    }

    /// Entries tilted by 1e-9 .. 0.04 rad off the tangent (still a smooth
    /// join): never a sliver, and the sweep the geometry gives.
    #[test]
    fn nearly_tangent_entry_never_leaves_a_sliver(c in case(true)) {
        check(&c, expected(&c))?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 256,
        // About half the tilted cases start before the offset start.
        max_global_rejects: 4096,
        ..ProptestConfig::default()
    })]

    /// Tilted entries whose corrected start lies more than 1e-7 rad before
    /// the circle's offset start: a whole turn ending
    /// on that start, then on to the circle's own end (its offset end
    /// after a flush, a tangent or an outside corner; the cut at an inside
    /// corner), so that the next element starts on its own offset geometry.
    #[test]
    fn start_before_the_offset_start_runs_a_turn_and_on(c in case(true)) {
        prop_assume!(start_shift(&c) < -1e-7);
        let want = expected(&c);
        if let Some(w) = &want {
            if matches!(c.exit, Exit::Flush | Exit::Tangent | Exit::Outside(_)) {
                prop_assert_eq!(w.sweeps.len(), 2, "a turn and on: {:?}", w);
            }
        }
        check(&c, want)?;
    }
}

/// Found by `tangent_entry_keeps_the_whole_turn`: the exit's offset line
/// all but touches the offset circle (the tool just fits the inside
/// corner), so the cut turns 52 times as far as the exit line does. The model must turn the exit line exactly as the
/// program does, from the tangent the entry runs along, not from the
/// circle's tangent at its start 1e-6 off the tangent point (1.3e-7 rad
/// apart, 6.8e-6 rad in the cut).
#[test]
fn grazing_inside_cut_after_a_tangent_entry() {
    let c = Case {
        centre: [0.0, 0.0],
        radius: 7.507807531474972,
        ccw: true,
        alpha: 0.0,
        entry: Entry::Line(5.0),
        eps: 1e-6,
        eps_dir: -1.415793133465441,
        tilt: 0.0,
        exit: Exit::Inside(2.60402937117801),
        tool: 0.5292636962517333,
        tool_left: true,
    };
    check(&c, expected(&c)).unwrap();
}

/// A tangent entry ending 1e-6 off the tangent point of a small circle
/// with a large tool inside it: the circle's corrected start lies 1.6e-6
/// rad ahead of its offset start, beyond the 1e-7 rad of the whole-turn
/// rule, so the circle runs from there to its offset end (a turn less
/// 1.6e-6 rad), not a whole turn.
#[test]
fn tangent_entry_starting_ahead_of_the_offset_start() {
    let c = Case {
        centre: [0.0, 0.0],
        radius: 3.0,
        ccw: true,
        alpha: 0.3,
        entry: Entry::Line(5.0),
        eps: 1e-6,
        eps_dir: 1.8653206380689396,
        tilt: 0.0,
        exit: Exit::Flush,
        tool: 2.49,
        tool_left: true,
    };
    check(&c, expected(&c)).unwrap();
}
