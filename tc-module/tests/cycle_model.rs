//! The per-cycle seam: a test model that adds a constant offset
//! along the contour normal proves that the model is called once per
//! interpolation cycle, that its offset shows in the executed position and
//! never in the spool log, that `EXEC` and `EXEC n` agree, and that a cycle
//! crossing element boundaries reports its path per element.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use tc_module::NoKey;
use tc_module::{
    AxisPos, Cycle, CycleModel, CycleTime, Groups, NoExtension, Origin, TcExtension, TcModule, AXES,
};
use tc_request::text::parse_request;
use tc_request::Request;
use uoi::{ObjectBus, ObjectDesc};

/// Distance of the test offset along the contour normal.
const W: f64 = 0.25;

/// What the model saw.
#[derive(Debug, Default, Clone, PartialEq)]
struct Seen {
    calls: u64,
    /// Path travelled per origin code.
    per_origin: [f64; 5],
    /// Most parts one cycle reported.
    most_parts: usize,
    /// The parts of the cycle that reported most, as (origin, length).
    busiest: Vec<(Origin, f64)>,
    /// Origins of the current element at each cycle's end, deduplicated.
    currents: Vec<Origin>,
}

/// The test model: offset `W` along the contour normal, every cycle while
/// it is on (it is on from the start unless switched off).
#[derive(Debug)]
struct NormalOffset {
    seen: Seen,
    on: bool,
    /// The unit tangent at the end of the last cycle.
    tangent: Option<AxisPos>,
}

impl Default for NormalOffset {
    fn default() -> Self {
        Self {
            seen: Seen::default(),
            on: true,
            tangent: None,
        }
    }
}

impl TcExtension for NormalOffset {
    type Key = NoKey;
    type Group = ();
    type Tool = ();
    type Model<'a> = &'a mut Self;
    const GROUP_OBJECTS: &'static [ObjectDesc<NoKey>] = &[];
    const OBJECTS: &'static [ObjectDesc<NoKey>] = &[];

    fn cycle_model<'a>(&'a mut self, _: Groups<'a, Self>) -> &'a mut Self {
        self
    }
}

impl CycleModel for NormalOffset {
    fn active(&self) -> bool {
        self.on
    }

    fn cycle(&mut self, c: &Cycle<'_>) -> AxisPos {
        let s = &mut self.seen;
        s.calls += 1;
        for p in c.parts {
            s.per_origin[usize::from(p.origin.code())] += p.length;
        }
        if c.parts.len() > s.most_parts {
            s.most_parts = c.parts.len();
            s.busiest = c.parts.iter().map(|p| (p.origin, p.length)).collect();
        }
        self.tangent = c.tangent();
        if let Some(e) = c.current {
            if s.currents.last() != Some(&e.origin()) {
                s.currents.push(e.origin());
            }
        }
        c.normal().map_or([0.0; AXES], |n| n.map(|v| W * v))
    }
}

fn run<E: TcExtension>(tc: &mut TcModule<E>, program: &str) {
    for line in program.lines().map(str::trim).filter(|l| !l.is_empty()) {
        match parse_request(line).unwrap_or_else(|e| panic!("{line}: {e}")) {
            Request::Write(a, v) => tc
                .write_checked(a, v)
                .unwrap_or_else(|e| panic!("{line}: {e}")),
            Request::Motion(m) => tc.command(&m).unwrap_or_else(|e| panic!("{line}: {e}")),
            Request::Exec(n) => tc.exec(n),
            other => panic!("not in these programs: {other:?}"),
        }
    }
}

/// Tool radius 1 on the right of a square's lower and right edges (outside
/// corners: circular transitions), at 600 units/min (0.01 per 1 ms cycle),
/// ended with STATUS=0 and a departure.
const SQUARE: &str = "
    W 1300/1/1/6 d 1
    W 1300/1/1/10 i 1
    W 1300/1/1/3 i 1
    LIN X10 Y0 F600
    LIN X10 Y10
    LIN X0 Y10
    W 1300/1/1/3 i 0
    LIN X-5 Y15
";

fn with_model() -> TcModule<NormalOffset> {
    TcModule::new([0.0; AXES], CycleTime::DEFAULT, NormalOffset::default())
}

#[test]
fn called_once_per_cycle_idle_or_moving() {
    let mut tc = with_model();
    tc.exec(Some(500));
    assert_eq!(tc.extension().seen.calls, 500);
    assert_eq!(tc.executor().cycles(), 500);
    run(&mut tc, SQUARE);
    run(&mut tc, "EXEC 123");
    assert_eq!(tc.extension().seen.calls, 623);
    tc.exec(None);
    assert_eq!(tc.queue_len(), 0);
    assert_eq!(tc.extension().seen.calls, tc.executor().cycles());
}

#[test]
fn offset_shows_in_pos_and_not_in_the_spool_log() {
    let mut tc = with_model();
    let mut plain = TcModule::new([0.0; AXES], CycleTime::DEFAULT, NoExtension);
    tc.spooler_mut().set_logging(true);
    plain.spooler_mut().set_logging(true);
    run(&mut tc, SQUARE);
    run(&mut plain, SQUARE);
    let log: Vec<_> = tc
        .spooler_mut()
        .take_log()
        .iter()
        .map(|e| e.record())
        .collect();
    let reference: Vec<_> = plain
        .spooler_mut()
        .take_log()
        .iter()
        .map(|e| e.record())
        .collect();
    assert_eq!(log, reference, "the model must not change what is spooled");
    // The corrected right edge runs at X = 11 (right of an upward line);
    // 0.7 units up it the contour normal points +X, so the tool stands W
    // further in +X than the path. Cycles: the approach from (0,0) to
    // (10,-1) is √101 long, the transition a quarter circle of radius 1.
    let cycles_to = |d: f64| (d / 0.01).round() as u64;
    let n = cycles_to(101f64.sqrt()) + cycles_to(std::f64::consts::FRAC_PI_2) + cycles_to(0.7);
    tc.exec(Some(n));
    plain.exec(Some(n));
    let (p, q) = (tc.position(), plain.position());
    assert!(
        (q[0] - 11.0).abs() < 1e-9 && (q[1] - 0.7).abs() < 0.02,
        "path at {q:?}"
    );
    assert!((p[0] - (q[0] + W)).abs() < 1e-9, "{p:?} vs {q:?}");
    assert!((p[1] - q[1]).abs() < 1e-9);
    let nominal = tc.executor().nominal();
    assert!((0..AXES).all(|i| (nominal[i] - q[i]).abs() < 1e-9));
}

#[test]
fn exec_and_exec_n_agree() {
    let mut a = with_model();
    run(&mut a, SQUARE);
    a.exec(None);
    let n = a.executor().cycles();
    let mut b = with_model();
    run(&mut b, SQUARE);
    b.exec(Some(n));
    assert_eq!(b.queue_len(), 0);
    assert_eq!(a.position(), b.position());
    assert_eq!(a.extension().seen, b.extension().seen);
    // In pieces, too.
    let mut c = with_model();
    run(&mut c, SQUARE);
    let mut left = n;
    for chunk in [1, 7, 250, 3].iter().cycle() {
        let k = (*chunk).min(left);
        c.exec(Some(k));
        left -= k;
        if left == 0 {
            break;
        }
    }
    assert_eq!(a.position(), c.position());
    assert_eq!(a.extension().seen, c.extension().seen);
}

#[test]
fn every_tag_is_seen_and_the_path_adds_up() {
    let mut tc = with_model();
    tc.spooler_mut().set_logging(true);
    run(&mut tc, SQUARE);
    let spooled = tc.spooler_mut().take_log();
    tc.exec(None);
    let seen = &tc.extension().seen;
    let mut want = [0.0; 5];
    for e in spooled.iter().map(|l| l.element) {
        want[usize::from(e.origin().code())] += e.length();
    }
    for (o, (got, want)) in seen.per_origin.iter().zip(want).enumerate() {
        assert!((got - want).abs() < 1e-9, "origin {o}: {got} vs {want}");
    }
    use Origin::*;
    // The first line is the approach (one element to its corrected end),
    // each outside corner a transition, STATUS=0 spools the last edge.
    assert_eq!(
        seen.currents,
        vec![Approach, Transition, Corrected, Transition, Corrected, Departure]
    );
    assert!(spooled.iter().any(|l| l.element.origin() == Departure));
}

/// A corrected run of `count` collinear lines `step` long at 6000
/// units/min (0.1 per cycle), after a 1-long approach.
fn short_lines(step: f64, count: u32) -> TcModule<NormalOffset> {
    let mut tc = with_model();
    let mut program =
        String::from("W 1300/1/1/6 d 0.5\nW 1300/1/1/10 i 1\nW 1300/1/1/3 i 1\nLIN X1 Y0 F6000\n");
    for k in 1..=count {
        program.push_str(&format!("LIN X{} Y0\n", 1.0 + step * f64::from(k)));
    }
    program.push_str("W 1300/1/1/3 i 0\n");
    run(&mut tc, &program);
    tc.exec(None);
    tc
}

#[test]
fn a_cycle_over_several_elements_reports_each_part() {
    // 0.02-long elements: a cycle crosses five or six of them.
    let tc = short_lines(0.02, 100);
    let seen = &tc.extension().seen;
    assert!(seen.most_parts >= 5, "parts per cycle: {}", seen.most_parts);
    let travelled: f64 = seen.busiest.iter().map(|p| p.1).sum();
    assert!((travelled - 0.1).abs() < 1e-9, "{travelled}");
    // One part per element: none longer than an element.
    assert!(
        seen.busiest.iter().all(|p| p.1 <= 0.02 + 1e-9),
        "{:?}",
        seen.busiest
    );
    assert!(seen
        .busiest
        .iter()
        .all(|p| p.0 == Origin::Corrected || p.0 == Origin::Approach));
}

#[test]
fn many_tiny_elements_merge_by_tag_and_keep_the_distance() {
    // 0.004-long elements: 25 a cycle, more than MAX_PARTS.
    let tc = short_lines(0.004, 200);
    let seen = &tc.extension().seen;
    assert!(seen.most_parts <= tc_module::MAX_PARTS);
    let travelled: f64 = seen.busiest.iter().map(|p| p.1).sum();
    assert!((travelled - 0.1).abs() < 1e-9, "{travelled}");
    let corrected: f64 = 200.0 * 0.004;
    assert!((seen.per_origin[usize::from(Origin::Corrected.code())] - corrected).abs() < 1e-9);
}

#[test]
fn approach_and_departure_carry_the_normals_they_lead_onto_and_leave() {
    let mut tc = with_model();
    let mut plain = TcModule::new([0.0; AXES], CycleTime::DEFAULT, NoExtension);
    run(&mut tc, SQUARE);
    run(&mut plain, SQUARE);
    let offset = |tc: &TcModule<NormalOffset>, plain: &TcModule<NoExtension>| {
        let (p, q) = (tc.position(), plain.position());
        [p[0] - q[0], p[1] - q[1]]
    };
    // Halfway along the approach: the side normal of the first line
    // (right of +X: -Y).
    tc.exec(Some(500));
    plain.exec(Some(500));
    let o = offset(&tc, &plain);
    assert!(o[0].abs() < 1e-9 && (o[1] + W).abs() < 1e-9, "{o:?}");
    // On the departure: the normal the top edge ended with (right of -X:
    // +Y), while the path leaves towards (-5, 15).
    let total = {
        let mut probe = with_model();
        run(&mut probe, SQUARE);
        probe.exec(None);
        probe.executor().cycles()
    };
    tc.exec(Some(total - 500 - 100));
    plain.exec(Some(total - 500 - 100));
    let q = plain.position();
    assert!(q[0] < 0.0 && q[1] > 11.0, "not on the departure yet: {q:?}");
    let o = offset(&tc, &plain);
    assert!(o[0].abs() < 1e-9 && (o[1] - W).abs() < 1e-9, "{o:?}");
}

/// Each of `a` and `b` within `tol` of the other, axis by axis.
fn near(a: AxisPos, b: AxisPos, tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

#[test]
fn switched_on_mid_run_the_model_sees_the_element_that_ended() {
    let mut tc = with_model();
    tc.extension_mut().on = false;
    run(&mut tc, SQUARE);
    tc.exec(None);
    assert_eq!(tc.extension().seen.calls, 0);
    tc.extension_mut().on = true;
    tc.exec(Some(3));
    let seen = &tc.extension().seen;
    assert_eq!(seen.calls, 3);
    // Idle at the end of the departure (from the tool at (0, 11) to
    // (-5, 15)): that element is current, with the normal it leaves; its
    // tangent points along it.
    assert_eq!(seen.currents, vec![Origin::Departure]);
    let t = tc.extension().tangent.expect("a current element");
    let k = 1.0 / 41f64.sqrt();
    assert!(
        near(t, [-5.0 * k, 4.0 * k, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], 1e-12),
        "{t:?}"
    );
    assert!((tc.position()[1] - (15.0 + W)).abs() < 1e-12);
}

#[test]
fn a_direct_command_leaves_no_current_element_and_no_offset() {
    let mut tc = with_model();
    run(&mut tc, SQUARE);
    run(&mut tc, "EXEC 500");
    assert_ne!(tc.position(), *tc.executor().nominal());
    run(&mut tc, "JA X50 Y50");
    run(&mut tc, "EXEC 2");
    assert_eq!(tc.position(), *tc.executor().nominal());
    assert_eq!(tc.position()[..2], [50.0, 50.0]);
}

#[test]
fn the_offset_goes_when_the_model_stops() {
    let mut tc = with_model();
    run(&mut tc, SQUARE);
    run(&mut tc, "EXEC 500");
    assert_ne!(tc.position(), *tc.executor().nominal());
    tc.extension_mut().on = false;
    // Any write asks the extension whether it still acts.
    run(&mut tc, "W 1300/0/20/0 d 0");
    assert_eq!(tc.position(), *tc.executor().nominal());
    // So does every cycle.
    tc.extension_mut().on = true;
    run(&mut tc, "EXEC 1");
    assert_ne!(tc.position(), *tc.executor().nominal());
    tc.extension_mut().on = false;
    run(&mut tc, "EXEC 1");
    assert_eq!(tc.position(), *tc.executor().nominal());
}

#[test]
fn an_exact_end_point_is_stepped_alike_with_and_without_a_model() {
    // 0.01 per cycle: the first line ends exactly on a cycle; a zero-length
    // line follows it.
    let program = "LIN X0.01 F600\nLIN X0.01\nLIN X1";
    let mut with = with_model();
    let mut without = TcModule::new([0.0; AXES], CycleTime::DEFAULT, NoExtension);
    run(&mut with, program);
    run(&mut without, program);
    with.exec(Some(1));
    without.exec(Some(1));
    assert_eq!(with.queue_len(), without.queue_len());
    assert_eq!(*with.executor().nominal(), *without.executor().nominal());
    // Standing exactly on the end of the first line: it is current.
    assert_eq!(with.extension().seen.currents, vec![Origin::Uncorrected]);
}

#[test]
fn without_a_model_the_fast_paths_match_stepping() {
    let mut fast = TcModule::new([0.0; AXES], CycleTime::DEFAULT, NoExtension);
    let mut stepped = TcModule::new([0.0; AXES], CycleTime::DEFAULT, NoExtension);
    run(&mut fast, SQUARE);
    run(&mut stepped, SQUARE);
    // EXEC n jumps whole cycles inside an element: the same position as
    // n single cycles up to the rounding of repeated addition.
    fast.exec(Some(1234));
    for _ in 0..1234 {
        stepped.exec(Some(1));
    }
    assert!(near(fast.position(), stepped.position(), 1e-9));
    // EXEC without a count jumps whole elements: exactly the end point
    // that stepping reaches.
    fast.exec(None);
    while stepped.queue_len() > 0 {
        stepped.exec(Some(1));
    }
    assert_eq!(fast.position(), stepped.position());
}
