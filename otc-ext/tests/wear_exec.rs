//! The wear model through the TC module and its executor, against values
//! computed by hand: a square ground at radius 3 with circular
//! transitions, the weight after a direct command, one group with OTC on
//! at a time, the request registers' bound, NotAllowed, and `EXEC n`
//! against cycle-by-cycle stepping.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;

use std::f64::consts::TAU;

use common::{otc_module as tc, read_d as read_f64, read_i as read_i32, run};
use tc_objects::{OtcObject, TcObject};

/// A grinding tool in entry 1 of group 1 with radius 3, wear constant
/// 100000 (0.01 per unit of path), max infeed 2 mm.
const GRINDING_TOOL: &str = "
    W 1300/1/1/8 i 1
    W 1300/1/1/6 d 3.0
    W 1300/3/1/30 i 2
    W 1300/3/1/31 d 100000
    W 1300/3/1/32 d 20000
";

#[test]
fn a_square_at_radius_3_wears_along_its_sides_and_transitions_only() {
    let mut tc = tc();
    run(&mut tc, GRINDING_TOOL);
    // CW square of side 40 from (0,0), tool on the left: outside, with
    // circular transitions at its four corners; approached along its first
    // side from (0,-10), left again up the first side by 1, departed.
    run(
        &mut tc,
        "W 1300/3/1/2 i 0
         W 1300/3/1/3 i 1
         W 1300/3/1/1 i 1
         RAP X0 Y-10
         W 1300/1/1/9 i 0
         W 1300/1/1/3 i 1
         LIN X0 Y0 F3000
         LIN X0 Y40
         LIN X40 Y40
         LIN X40 Y0
         LIN X0 Y0
         LIN X0 Y1
         W 1300/1/1/3 i 0
         LIN X-20 Y1
         EXEC
         W 1300/3/1/1 i 0",
    );
    // Corrected path: 4 sides of 40, 4 quarter circles of radius 3 (one
    // whole circle), and the 1 unit up the first side again.
    let path = 4.0 * 40.0 + TAU * 3.0 + 1.0;
    let w = 0.01 * path;
    assert!((read_f64(&mut tc, OtcObject::WearRadiusCont.of(1)) - w).abs() < 1e-9);
    assert!((read_f64(&mut tc, OtcObject::WearRadius.of(1)) - w).abs() < 1e-9);
    assert!((read_f64(&mut tc, TcObject::Radius.of(1)) - (3.0 - w)).abs() < 1e-9);
    // The departure ends with weight 0: the executed position is nominal.
    assert_eq!(tc.position()[..2], [-20.0, 1.0]);
}

#[test]
fn a_direct_command_takes_the_radius_offset_away_at_once() {
    let mut tc = tc();
    run(&mut tc, GRINDING_TOOL);
    run(
        &mut tc,
        "W 1300/3/1/2 i 0
         W 1300/3/1/40 i 1
         W 1300/3/1/1 i 1
         W 1300/1/1/9 i 0
         W 1300/1/1/3 i 1
         LIN X10 Y0 F600
         LIN X1000 Y0
         LIN X1000 Y500
         EXEC 5000",
    );
    // 5000 cycles of 0.01: 50 units, of which the approach to (10, 3)
    // took √109; the rest wore the tool on the corrected line.
    let worn = 50.0 - 109f64.sqrt();
    let y = tc.position()[1];
    assert!((y - (3.0 - 0.01 * worn)).abs() < 1e-9, "{y}");
    run(&mut tc, "JA X0");
    // The weight is 0 now: the executed position is the nominal one.
    assert_eq!(tc.position(), *tc.executor().nominal());
}

#[test]
fn only_one_group_has_otc_on() {
    let mut tc = tc();
    run(
        &mut tc,
        "W 1300/3/1/30 i 2
         W 1300/3/2/30 i 2
         W 1300/3/1/1 i 1
         W 1300/3/2/1 i 1",
    );
    assert_eq!(read_i32(&mut tc, OtcObject::OtcOn.of(2)), 0);
    assert_eq!(read_i32(&mut tc, OtcObject::OtcError.of(2)), 2);
    assert_eq!(read_i32(&mut tc, OtcObject::OtcError.of(1)), 0);
}

#[test]
fn requests_clamp_against_group_1_or_the_group_whose_otc_is_on() {
    let mut tc = tc();
    run(
        &mut tc,
        "W 1300/3/1/32 d 100
         W 1300/3/2/30 i 2
         W 1300/3/2/32 d 50
         W 1300/3/2/50 i 500
         W 1300/4/3/1 i -500",
    );
    // No OTC on: group 1's entry bounds both, even group 2's channel unit.
    assert_eq!(read_i32(&mut tc, OtcObject::RadiusOffsetRequest.of(2)), 100);
    assert_eq!(read_i32(&mut tc, OtcObject::AxisOffsetRequest.of(3)), -100);
    run(&mut tc, "W 1300/3/2/1 i 1");
    assert_eq!(read_i32(&mut tc, OtcObject::RadiusOffsetRequest.of(2)), 50);
    assert_eq!(read_i32(&mut tc, OtcObject::AxisOffsetRequest.of(3)), -50);
}

#[test]
fn not_allowed_when_an_enabled_unit_is_ignored() {
    let mut tc = tc();
    // LENGTH (default) takes the axis unit of Z only.
    run(
        &mut tc,
        "W 1300/3/1/30 i 2\nW 1300/3/1/51 i 1\nW 1300/3/1/1 i 1",
    );
    assert_eq!(read_i32(&mut tc, OtcObject::OtcError.of(1)), 8);
    // Any Enable=1 looks at every unit: the channel unit is still on.
    run(&mut tc, "W 1300/3/1/7 i 0\nW 1300/4/2/2 i 1");
    assert_eq!(read_i32(&mut tc, OtcObject::OtcError.of(1)), 8);
    run(
        &mut tc,
        "W 1300/3/1/51 i 0\nW 1300/3/1/7 i 0\nW 1300/4/2/2 i 1",
    );
    assert_eq!(read_i32(&mut tc, OtcObject::OtcError.of(1)), 0);
    run(&mut tc, "W 1300/4/5/2 i 1");
    assert_eq!(read_i32(&mut tc, OtcObject::OtcError.of(1)), 8);
    assert_eq!(read_i32(&mut tc, OtcObject::OtcOn.of(1)), 1);
}

#[test]
fn exec_n_is_the_same_as_stepping_each_cycle() {
    let program = "W 1300/3/1/32 d 20000
         W 1300/3/1/30 i 2
         W 1300/3/1/31 d 3000
         W 1300/3/1/6 i 37
         W 1300/4/2/1 i 12345
         W 1300/4/2/2 i 1
         W 1300/3/1/1 i 1
         LIN X3 Y4 F2000
         CIR CCW X-2 Y9 I-5 J0
         RAP X0 Y0
         LIN Z-1";
    let (mut whole, mut stepped) = (tc(), tc());
    run(&mut whole, program);
    run(&mut stepped, program);
    whole.exec(Some(4000));
    for _ in 0..4000 {
        stepped.exec(Some(1));
    }
    assert_eq!(whole.position(), stepped.position());
    assert_eq!(
        read_i32(&mut whole, OtcObject::AxisOffsetState.of(2)),
        read_i32(&mut stepped, OtcObject::AxisOffsetState.of(2))
    );
    // 4000 cycles at 37 %: 0.37 µm a cycle reaches the 1.2345 mm command.
    assert_eq!(
        read_i32(&mut whole, OtcObject::AxisOffsetState.of(2)),
        12345
    );
}
