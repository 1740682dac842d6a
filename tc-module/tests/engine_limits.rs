//! Engine hardening against a hostile client: no
//! step that vanishes, no NaN from what enters the spooler, a bounded
//! spooler that gives its memory back, plane-null profiles counted, and
//! `EXEC` bounded by elements (or sliced for an active model, with idle
//! cycles at rest counted).

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use tc_module::NoKey;
use tc_module::KEEP_WHEN_EMPTY;
use tc_module::{
    AxisPos, Cycle, CycleModel, CycleTime, ExecLeft, Groups, NoExtension, TcExtension, TcModule,
    AXES, EXEC_SLICE_CYCLES,
};
use tc_request::text::parse_request;
use tc_request::Request;
use uoi::{AccessError, ObjectBus, ObjectDesc};

/// Runs one request in trace syntax; the answer of a write or motion.
fn req<E: TcExtension>(tc: &mut TcModule<E>, line: &str) -> Result<(), AccessError> {
    match parse_request(line).unwrap_or_else(|e| panic!("{line}: {e}")) {
        Request::Write(a, v) => tc.write_checked(a, v),
        Request::Motion(m) => tc.command(&m),
        Request::Exec(n) => {
            tc.exec(n);
            Ok(())
        }
        other => panic!("not in these programs: {other:?}"),
    }
}

fn ok<E: TcExtension>(tc: &mut TcModule<E>, line: &str) {
    req(tc, line).unwrap_or_else(|e| panic!("{line}: {e}"));
}

fn small(capacity: usize) -> TcModule {
    TcModule::default().with_spool_capacity(capacity)
}

// ---- point 1: steps that vanish, work under the lock --------------------

#[test]
fn feeds_whose_step_vanishes_are_refused_and_change_nothing() {
    let mut tc = TcModule::default();
    ok(&mut tc, "LIN X1 F600");
    for bad in ["F5e-324", "F1e-300", "F0.5"] {
        assert_eq!(
            req(&mut tc, &format!("LIN X2 {bad}")),
            Err(AccessError::Range),
            "{bad}"
        );
    }
    // 0.61 units/min steps 1.02e-5 per 1 ms cycle: accepted.
    ok(&mut tc, "LIN X2 F0.61");
    assert_eq!(tc.queue_len(), 2);
    // At a 1 s cycle the same feed steps far more than the minimum.
    let mut slow = TcModule::new([0.0; AXES], CycleTime::from_secs(1.0).unwrap(), NoExtension);
    ok(&mut slow, "LIN X1 F0.001");
}

#[test]
fn huge_exec_on_an_idle_machine_costs_nothing() {
    let mut tc = TcModule::default();
    tc.exec(Some(4_000_000_000));
    tc.exec(Some(u64::MAX - 1));
    assert_eq!(tc.executor().cycles(), u64::MAX);
    ok(&mut tc, "LIN X1 F600");
    tc.exec(Some(u64::MAX - 1));
    assert_eq!(tc.position()[0], 1.0);
}

/// A test model that counts its cycles and is at rest once told so.
#[derive(Debug, Default)]
struct Counting {
    calls: u64,
    rests_after: Option<u64>,
}

impl TcExtension for Counting {
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

impl CycleModel for Counting {
    fn active(&self) -> bool {
        true
    }

    fn cycle(&mut self, _: &Cycle<'_>) -> AxisPos {
        self.calls += 1;
        [0.0; AXES]
    }

    fn at_rest(&mut self) -> bool {
        self.rests_after.is_some_and(|n| self.calls >= n)
    }
}

fn counting(rests_after: Option<u64>) -> TcModule<Counting> {
    let ext = Counting {
        calls: 0,
        rests_after,
    };
    TcModule::new([0.0; AXES], CycleTime::DEFAULT, ext)
}

#[test]
fn an_active_model_runs_a_huge_exec_slice_by_slice() {
    let mut tc = counting(None);
    let n = 1_000_000_000_000;
    assert_eq!(
        tc.exec_slice(Some(n)),
        ExecLeft::Rest(Some(n - EXEC_SLICE_CYCLES))
    );
    assert_eq!(tc.extension().calls, EXEC_SLICE_CYCLES);
    // Until the spooler is empty: one slice each, then done.
    ok(&mut tc, "LIN X200 F600");
    assert_eq!(tc.exec_slice(None), ExecLeft::Rest(None));
    assert_eq!(tc.extension().calls, 2 * EXEC_SLICE_CYCLES);
    tc.exec(None);
    assert_eq!(tc.position()[0], 200.0);
    // Slices add up to the whole request.
    let mut whole = counting(None);
    let mut sliced = counting(None);
    for t in [&mut whole, &mut sliced] {
        ok(t, "LIN X300 Y2 F600");
    }
    whole.exec(Some(25_001));
    let mut left = ExecLeft::Rest(Some(25_001));
    while let ExecLeft::Rest(rest) = left {
        left = sliced.exec_slice(rest);
    }
    assert_eq!(whole.position(), sliced.position());
    assert_eq!(whole.extension().calls, sliced.extension().calls);
}

#[test]
fn idle_cycles_of_a_model_at_rest_are_counted_not_stepped() {
    let mut tc = counting(Some(3));
    tc.exec(Some(u64::MAX - 1));
    assert_eq!(tc.extension().calls, 3);
    assert_eq!(tc.executor().cycles(), u64::MAX - 1);
    // Moving, every cycle is stepped even at rest; standing still after
    // the last one, the rest are counted.
    let mut tc = counting(Some(0));
    ok(&mut tc, "LIN X1 F600");
    tc.exec(Some(1_000_000_000));
    assert_eq!(tc.position()[0], 1.0);
    assert_eq!(tc.extension().calls, 100);
}

// ---- point 2: what enters the spooler stays finite and in range ---------

#[test]
fn rotation_cannot_carry_a_point_beyond_the_limit() {
    let mut tc = TcModule::default();
    assert_eq!(
        req(&mut tc, "W 1300/0/21/0 d 1e308"),
        Err(AccessError::Range)
    );
    assert_eq!(
        req(&mut tc, "W 1300/0/22/0 d 1e308"),
        Err(AccessError::Range)
    );
    ok(&mut tc, "W 1300/0/21/0 d 1e9");
    ok(&mut tc, "W 1300/0/22/0 d 1e9");
    ok(&mut tc, "W 1300/0/20/0 d 180");
    // (1e9, 1e9) is the centre: it stays; (-1e9, 1e9) turns to (3e9, 1e9).
    ok(&mut tc, "LIN X1e9 Y1e9 F600");
    assert_eq!(
        req(&mut tc, "LIN X-1e9 Y1e9 F6000"),
        Err(AccessError::Range)
    );
    assert_eq!(
        req(&mut tc, "CIR CW X1e9 Y1e9 I-1e9 J-1e9"),
        Err(AccessError::Range),
        "a centre turned beyond the limit"
    );
    assert_eq!(tc.queue_len(), 1);
    tc.exec(None);
    assert!(tc.position().iter().all(|v| v.is_finite()));
    assert_eq!(tc.position()[0], 1e9);
}

#[test]
fn tool_length_cannot_carry_a_corrected_point_beyond_the_limit() {
    let mut tc = TcModule::default();
    assert_eq!(
        req(&mut tc, "W 1300/1/1/12 d 1.7e308"),
        Err(AccessError::Range)
    );
    assert_eq!(
        req(&mut tc, "W 1300/1/1/6 d -1e300"),
        Err(AccessError::Range)
    );
    for line in [
        "W 1300/1/1/12 d 1e9",
        "W 1300/1/1/6 d 1",
        "W 1300/1/1/10 i 1",
    ] {
        ok(&mut tc, line);
    }
    ok(&mut tc, "W 1300/1/1/3 i 1");
    ok(&mut tc, "LIN X10 Y0 Z0 F600");
    // Z 1 plus the length 1e9 is beyond the limit, as the held end point
    // and as a plane-null move.
    assert_eq!(req(&mut tc, "LIN X10 Y-10 Z1"), Err(AccessError::Range));
    assert_eq!(req(&mut tc, "LIN Z1"), Err(AccessError::Range));
    assert_eq!(tc.queue_len(), 0);
    ok(&mut tc, "LIN X10 Y-10 Z0");
    ok(&mut tc, "W 1300/1/1/3 i 0");
    tc.exec(None);
    let p = tc.position();
    assert_eq!([p[0], p[1], p[2]], [9.0, -10.0, 1e9]);
}

// ---- points 3 and 4: bounded spooler, memory back, plane-null moves -----

#[test]
fn a_full_spooler_refuses_with_full_and_changes_nothing() {
    let mut tc = small(8);
    for k in 1..=8 {
        ok(&mut tc, &format!("LIN X{k} F600"));
    }
    assert_eq!(req(&mut tc, "LIN X9 F6000"), Err(AccessError::Full));
    assert_eq!(tc.queue_len(), 8);
    tc.exec(Some(150));
    assert_eq!(tc.queue_len(), 7);
    ok(&mut tc, "LIN X9");
    tc.exec(None);
    // The refused F6000 did not become modal: 50 cycles at 600/min.
    ok(&mut tc, "LIN X10");
    tc.exec(Some(50));
    assert!((tc.position()[0] - 9.5).abs() < 1e-9);
}

#[test]
fn spooler_memory_comes_back_after_exec() {
    let mut tc = TcModule::default();
    let mut refused = 0;
    for k in 0..100_010 {
        if req(&mut tc, &format!("LIN X{}", k % 2)) == Err(AccessError::Full) {
            refused += 1;
        }
    }
    assert_eq!(refused, 10);
    assert_eq!(tc.queue_len(), 100_000);
    assert!(tc.spooler().allocated() >= 100_000);
    tc.exec(None);
    assert!(tc.spooler().allocated() <= KEEP_WHEN_EMPTY);
}

/// A running group holding a profile, with capacity `capacity`.
fn holding(capacity: usize) -> TcModule {
    let mut tc = small(capacity);
    for line in ["W 1300/1/1/6 d 1", "W 1300/1/1/10 i 1", "W 1300/1/1/3 i 1"] {
        ok(&mut tc, line);
    }
    ok(&mut tc, "LIN X10 Y0 F600");
    tc
}

#[test]
fn plane_null_profiles_count_toward_the_capacity() {
    let mut tc = holding(100_000);
    let mut accepted = 0;
    for k in 0..200_000 {
        match req(
            &mut tc,
            &format!("LIN Z{}", if k % 2 == 0 { 1 } else { -1 }),
        ) {
            Ok(()) => accepted += 1,
            Err(e) => assert_eq!(e, AccessError::Full),
        }
    }
    // One place for the held profile, five for the corner after it.
    assert_eq!(accepted, 100_000 - 1 - 5);
    assert_eq!(tc.queue_len(), accepted);
    // STATUS=0 spools them all: within the capacity.
    ok(&mut tc, "W 1300/1/1/3 i 0");
    assert_eq!(tc.queue_len(), accepted + 1);
    assert!(tc.spooler().len() <= tc.spooler().capacity());
}

#[test]
fn the_next_profile_in_the_plane_still_fits_after_plane_null_ones() {
    let mut tc = holding(8);
    ok(&mut tc, "LIN Z1");
    ok(&mut tc, "LIN Z2");
    assert_eq!(req(&mut tc, "LIN Z3"), Err(AccessError::Full));
    assert_eq!(tc.queue_len(), 2);
    // The corner spools the held profile and both waiting moves.
    ok(&mut tc, "LIN X10 Y-10");
    assert_eq!(tc.queue_len(), 3);
    // With the spooler full of plane elements, the next profile waits
    // for EXEC, then fits.
    let mut tc = holding(8);
    let mut k = 0;
    let refused = loop {
        k += 1;
        let y = if k % 2 == 0 { 0 } else { -10 };
        if let Err(e) = req(&mut tc, &format!("LIN X{} Y{y}", 10 + k)) {
            break e;
        }
    };
    assert_eq!(refused, AccessError::Full);
    let before = tc.queue_len();
    tc.exec(None);
    assert!(before > 0 && tc.queue_len() == 0);
    let y = if k % 2 == 0 { 0 } else { -10 };
    ok(&mut tc, &format!("LIN X{} Y{y}", 10 + k));
}
