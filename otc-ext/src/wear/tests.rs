//! The wear model against hand-computed values, without the executor.

use tc_module::{
    AxisPos, ContourNormal, Cycle, NormalRule, Origin, PathPart, PlaneAxes, SpoolElement, AXES, V2,
};

use super::*;

const XY: PlaneAxes = PlaneAxes {
    h: 0,
    v: 1,
    third: 2,
};

fn settings(proc_type: ProcType, mode: OtcMode) -> WearSettings {
    WearSettings {
        proc_type,
        mode,
        wear_const: WearRate(100_000.0),
        acc_weight: 100,
        max_infeed: TenthMicrons(200_000.0),
        tilt: TiltAngle(0.0),
        axes: XY,
        xyz: [0, 1, 2],
        ori_axis: 4,
    }
}

fn part(origin: Origin, rapid: bool, length: f64) -> PathPart {
    PathPart {
        origin,
        rapid,
        length,
    }
}

fn pos(x: f64, y: f64, z: f64) -> AxisPos {
    let mut p = [0.0; AXES];
    (p[0], p[1], p[2]) = (x, y, z);
    p
}

/// Where [`corrected_line`] starts and ends.
const LINE_START: AxisPos = [0.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
const LINE_END: AxisPos = [1000.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];

/// A corrected line along X at Y = 3, the tool on its left: n = +Y.
fn corrected_line() -> SpoolElement {
    SpoolElement::line(&LINE_START, &LINE_END, XY, 600.0, false, Origin::Corrected).with_normal(
        Some(ContourNormal {
            plane: XY,
            rule: NormalRule::Fixed(V2::new(0.0, 1.0)),
        }),
    )
}

/// A cycle on `e` (which runs from `ends.0` to `ends.1`), `done` along it
/// at `at`.
fn on<'a>(
    e: &'a SpoolElement,
    ends: (&'a AxisPos, &'a AxisPos),
    parts: &'a [PathPart],
    done: f64,
    at: &'a AxisPos,
) -> Cycle<'a> {
    Cycle {
        parts,
        current: Some(e),
        start: ends.0,
        end: ends.1,
        done,
        previous: None,
        nominal: at,
    }
}

#[test]
fn a_metre_of_feed_path_at_100000_wears_ten_millimetres() {
    // k = 100000 × 1e-7 = 0.01 per unit of path; 1000 mm → 10 mm.
    let parts = [part(Origin::Uncorrected, false, 1000.0)];
    let w = continuous_wear(&parts, ProcType::Length, WearRate(100_000.0));
    assert!((w - 10.0).abs() < 1e-12, "{w}");
}

#[test]
fn rapids_wear_nothing_and_radius_wears_only_on_corrected_elements() {
    let rapid = [part(Origin::Corrected, true, 1000.0)];
    assert_eq!(
        continuous_wear(&rapid, ProcType::Length, WearRate(1e5)),
        0.0
    );
    assert_eq!(
        continuous_wear(&rapid, ProcType::Radius, WearRate(1e5)),
        0.0
    );
    let mixed = [
        part(Origin::Approach, false, 1.0),
        part(Origin::Corrected, false, 2.0),
        part(Origin::Transition, false, 4.0),
        part(Origin::Departure, false, 8.0),
        part(Origin::Uncorrected, false, 16.0),
    ];
    // RADIUS: 2 + 4 = 6 units; LENGTH: all 31. k = 1e-7 × 1e7 = 1.
    assert_eq!(
        continuous_wear(&mixed, ProcType::Radius, WearRate(1e7)),
        6.0
    );
    assert_eq!(
        continuous_wear(&mixed, ProcType::Length, WearRate(1e7)),
        31.0
    );
}

#[test]
fn radius_cont_moves_the_tool_toward_the_contour_by_the_wear() {
    let e = corrected_line();
    let at = pos(10.0, 3.0, 0.0);
    let parts = [part(Origin::Corrected, false, 10.0)];
    let mut state = WearState::default();
    let mut units = TakenMut::default();
    let set = settings(ProcType::Radius, OtcMode::Cont);
    let off = run_cycle(
        &mut state,
        &mut units,
        &set,
        &on(&e, (&LINE_START, &LINE_END), &parts, 10.0, &at),
    );
    // w = 0.01 × 10 = 0.1 against n = +Y.
    assert!((off[1] + 0.1).abs() < 1e-15 && off[0] == 0.0, "{off:?}");
    assert!((state.w_cont - 0.1).abs() < 1e-15);
}

#[test]
fn disc_ramps_the_channel_unit_one_micrometre_per_cycle() {
    let e = corrected_line();
    let at = pos(10.0, 3.0, 0.0);
    let mut channel = PlcUnit {
        command: 20_000,
        enable: true,
        applied: 0.0,
    };
    let mut state = WearState::default();
    let set = settings(ProcType::Radius, OtcMode::Disc);
    let parts = [part(Origin::Corrected, false, 10.0)];
    let mut off = [0.0; AXES];
    for _ in 0..3 {
        let mut units = TakenMut {
            channel: Some(&mut channel),
            axis: None,
        };
        off = run_cycle(
            &mut state,
            &mut units,
            &set,
            &on(&e, (&LINE_START, &LINE_END), &parts, 10.0, &at),
        );
    }
    // DISC: no continuous wear; 3 cycles × 1 µm = 0.003 mm.
    assert_eq!(state.w_cont, 0.0);
    assert_eq!(channel.state(), 30);
    assert!((off[1] + 0.003).abs() < 1e-15, "{off:?}");
}

#[test]
fn tool_dir_ramps_two_units_separately_and_adds_them() {
    let mut b = [0.0; AXES];
    b[4] = 90.0;
    let idle = Cycle {
        parts: &[],
        current: None,
        start: &b,
        end: &b,
        done: 0.0,
        previous: None,
        nominal: &b,
    };
    let unit = |command| PlcUnit {
        command,
        enable: true,
        applied: 0.0,
    };
    let (mut channel, mut axis) = (unit(15), unit(-40));
    let mut state = WearState::default();
    let set = settings(ProcType::ToolDir, OtcMode::Disc);
    let mut off = [0.0; AXES];
    for _ in 0..2 {
        let mut units = TakenMut {
            channel: Some(&mut channel),
            axis: Some(&mut axis),
        };
        off = run_cycle(&mut state, &mut units, &set, &idle);
    }
    // Channel 10 then 15 (on target); axis −10 then −20: w = −5 × 1e-4.
    assert_eq!((channel.state(), axis.state()), (15, -20));
    // t = (sin 90°, 0, cos 90°) = X: offset −w·t = +5e-4 on X.
    assert!(
        (off[0] - 5e-4).abs() < 1e-15 && off[2].abs() < 1e-15,
        "{off:?}"
    );
}

#[test]
fn surface_normal_starts_as_the_tool_direction_and_keeps_the_last() {
    let at = [0.0; AXES];
    let set = settings(ProcType::SurfNormDir, OtcMode::Cont);
    let mut state = WearState::default();
    let mut units = TakenMut::default();
    let idle = Cycle {
        parts: &[],
        current: None,
        start: &at,
        end: &at,
        done: 0.0,
        previous: None,
        nominal: &at,
    };
    run_cycle(&mut state, &mut units, &set, &idle);
    // Before any motion n = t = +Z (B = 0).
    assert_eq!(state.last_dir, Some(pos(0.0, 0.0, 1.0)));
    // Down a 45° slope: n = (1, 0, 1)/√2.
    let down = pos(1.0, 0.0, -1.0);
    let slope = SpoolElement::line(&at, &down, XY, 600.0, false, Origin::Uncorrected);
    let parts = [part(Origin::Uncorrected, false, 0.5)];
    let off = run_cycle(
        &mut state,
        &mut units,
        &set,
        &on(&slope, (&at, &down), &parts, 0.5, &at),
    );
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let w = 0.01 * 0.5;
    assert!((off[0] + w * h).abs() < 1e-15 && (off[2] + w * h).abs() < 1e-15);
    // A plunge along Z is degenerate: the slope's normal is kept.
    let bottom = pos(0.0, 0.0, -1.0);
    let plunge = SpoolElement::line(&at, &bottom, XY, 600.0, false, Origin::Uncorrected);
    run_cycle(
        &mut state,
        &mut units,
        &set,
        &on(&plunge, (&at, &bottom), &parts, 0.5, &at),
    );
    let n = state.last_dir.unwrap_or_default();
    assert!((n[0] - h).abs() < 1e-15 && (n[2] - h).abs() < 1e-15);
}

#[test]
fn length_with_a_tilted_disc_splits_the_wear_over_x_and_z() {
    let at = [0.0; AXES];
    let mut set = settings(ProcType::Length, OtcMode::Cont);
    set.tilt = TiltAngle(300_000.0); // 30°
    let far = pos(100.0, 0.0, 0.0);
    let e = SpoolElement::line(&at, &far, XY, 600.0, false, Origin::Uncorrected);
    let parts = [part(Origin::Uncorrected, false, 100.0)];
    let mut state = WearState::default();
    let off = run_cycle(
        &mut state,
        &mut TakenMut::default(),
        &set,
        &on(&e, (&at, &far), &parts, 100.0, &at),
    );
    // w = 0.01 × 100 = 1: −(sin 30°, 0, cos 30°).
    assert!((off[0] + 0.5).abs() < 1e-15 && (off[2] + 0.75f64.sqrt()).abs() < 1e-15);
}
