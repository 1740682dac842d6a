//! `addipos run`: the seed NC programs run on the emulator, their
//! corrected paths (distance and side, the full circle), the dynamic
//! radius, the OTC checks (type, PLC offset, G40 before #OTC OFF, the
//! inclined disc), and the equivalent traces replayed.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::path::PathBuf;
use std::process::Command;

mod common;

use common::{replay_remote, session};
use nc::nc_run::NcRun;
use nc::run::{run_program, At, Controller, Report, RunError, RunErrorKind};
use tc_objects::OtcObject;
use tc_request::{Origin, Reply, Request, SpoolRecord};
use tool_store::{ToolKey, ToolValue};
use trace::{fresh_emulator, parse_trace, replay, Header};
use uoi::{Value, ValueType};

/// A run on the emulator a trace without header options replays on.
fn run_nc(text: &str) -> NcRun {
    let Ok(run) = nc::nc_run::run_nc(&mut fresh_emulator(&Header::new("nc")), text);
    run
}

/// [`run_nc`] with tool data written first.
fn run_nc_with_tools(text: &str, tools: &[(u8, ToolKey, ToolValue)]) -> NcRun {
    let mut emu = fresh_emulator(&Header::new("nc"));
    let Ok(run) = nc::nc_run::run_nc_with_tools(&mut emu, text, tools);
    run
}

/// Line and block number of a run error or fault.
fn line_and_block(e: &RunError) -> (usize, Option<u32>) {
    let at = e.location.expect("a place in the program");
    (at.line, at.block_number)
}

fn program_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/nc")
        .join(name)
}

fn program(name: &str) -> String {
    std::fs::read_to_string(program_path(name)).unwrap()
}

/// The program with a line of tool data inserted after its first line.
fn with_tool_data(name: &str, line: &str) -> String {
    let text = program(name);
    let (first, rest) = text.split_once('\n').unwrap();
    format!("{first}\n{line}\n{rest}")
}

const RUNNING: [&str; 9] = [
    "wzkg25.nc",
    "wzkg26.nc",
    "dynamic_radius.nc",
    "wr_quad_disc.nc",
    "otc_general.nc",
    "otc_length.nc",
    "otc_tool_dir.nc",
    "otc_surf_norm_dir.nc",
    "tool_data_change.nc",
];

fn spooled(run: &NcRun) -> Vec<SpoolRecord> {
    let all = run.exchanges.iter().flat_map(|x| x.spooled.iter().copied());
    all.collect()
}

fn corrected(run: &NcRun) -> Vec<SpoolRecord> {
    let all = spooled(run).into_iter();
    all.filter(|r| r.origin == Origin::Corrected).collect()
}

/// Signed distance of `p` from segment `a`→`b` (positive: left of it)
/// and the unsigned distance from the segment.
fn from_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> (f64, f64) {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0);
    let (cx, cy) = (a[0] + t * dx, a[1] + t * dy);
    let side = dx * (p[1] - a[1]) - dy * (p[0] - a[0]);
    let dist = (p[0] - cx).hypot(p[1] - cy);
    (side.signum() * dist, dist)
}

/// %WZKG25/26's contour, traversed from (20,20).
const CONTOUR: [[f64; 2]; 5] = [
    [20.0, 20.0],
    [30.0, 20.0],
    [35.0, 15.0],
    [35.0, 10.0],
    [30.0, 7.0],
];

fn check_left_at_10(name: &str) {
    let run = run_nc(&with_tool_data(name, "#set ToolParam(1; 4; 10)#"));
    assert!(
        !run.failed(),
        "{name}: {:?} {:?}",
        run.error,
        run.report.faults
    );
    let elements = corrected(&run);
    assert!(
        elements.len() >= 12,
        "{name}: {} corrected elements",
        elements.len()
    );
    for e in elements.iter().filter(|e| e.arc.is_none()) {
        for p in [e.start, e.end] {
            let (signed, _) = CONTOUR
                .windows(2)
                .map(|s| from_segment([p[0], p[1]], s[0], s[1]))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .unwrap();
            assert!((signed - 10.0).abs() < 1e-9, "{name}: {e:?}: {signed}");
        }
    }
}

#[test]
fn wzkg25_and_wzkg26_keep_10_left_of_the_contour() {
    check_left_at_10("wzkg25.nc");
    check_left_at_10("wzkg26.nc");
}

#[test]
fn grinding_cycle_radius_shrinks_by_0_010_for_11_passes() {
    // The data set before N00 selects it.
    let text = format!("#set ToolParam(6; 4; 5)#\n{}", program("dynamic_radius.nc"));
    let run = run_nc(&text);
    assert!(!run.failed(), "{:?}", run.error);
    // The top edge Y250 to X300, run in +X with G41: it ends at 250 + r
    // (from the second pass on, it starts on the last pass's offset).
    let tops: Vec<f64> = spooled(&run)
        .iter()
        .filter(|e| e.arc.is_none() && e.end[0] == 300.0 && e.end[1] > 250.0)
        .map(|e| e.end[1] - 250.0)
        .collect();
    assert_eq!(tops.len(), 11, "{tops:?}");
    for (k, r) in tops.iter().enumerate() {
        assert!(
            (r - (5.0 - 0.01 * k as f64)).abs() < 1e-9,
            "pass {k}: {tops:?}"
        );
    }
}

#[test]
fn otc_on_with_a_milling_tool_is_p_err_21391() {
    let run = run_nc(&program("otc_general.nc"));
    assert!(run.error.is_none(), "{:?}", run.error);
    assert_eq!(run.report.faults.len(), 1, "{:?}", run.report.faults);
    let f = &run.report.faults[0];
    assert!(matches!(f.kind, RunErrorKind::Otc { bit: 1, .. }), "{f:?}");
    assert!(f.to_string().contains("P-ERR-21391"), "{f}");
    assert_eq!(line_and_block(f), (5, Some(50)));
    assert!(run.failed());
}

#[test]
fn every_seed_program_runs_and_its_trace_replays() {
    for name in RUNNING {
        let run = run_nc(&program(name));
        assert!(run.parse_errors.is_empty(), "{name}");
        assert!(run.position.is_some(), "{name}");
        assert_eq!(run.wear.len(), 10, "{name}");
        assert!(!run.spool_lines().is_empty(), "{name}");
        let trace = parse_trace(name, &run.trace(name)).unwrap();
        assert!(trace.steps.len() > 5, "{name}");
        let mismatches = replay(&trace);
        assert!(mismatches.is_empty(), "{name}: {mismatches:?}");
    }
}

/// The printed tool-data example's second circle does not close (start
/// 15 from its centre, end 11.2): the engine flags CenterError and the run
/// stops naming the circle's block, N140, whose profile raised it.
#[test]
fn tool_data_change_stops_at_the_circle_that_does_not_close() {
    let run = run_nc(&program("tool_data_change.nc"));
    let e = run.error.expect("an error");
    assert_eq!(line_and_block(&e).1, Some(140));
    let RunErrorKind::CorrectionFault { bits } = &e.kind else {
        panic!("{e:?}")
    };
    assert_eq!(bits, &["CenterError".to_string()], "{e}");
}

fn addipos(args: &[&std::ffi::OsStr]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_addipos"))
        .args(args)
        .output()
        .expect("run addipos");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn run_command_prints_spool_position_wear_and_writes_a_replayable_trace() {
    let dir = std::env::temp_dir().join(format!("addipos-nc-run-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("wzkg25.trace");
    let prog = program_path("wzkg25.nc");
    let (code, stdout, stderr) = addipos(&[
        "run".as_ref(),
        prog.as_os_str(),
        "--trace".as_ref(),
        out.as_os_str(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.lines().next().unwrap().starts_with("< LIN"),
        "{stdout}"
    );
    assert!(stdout.contains("\nPOS X"), "{stdout}");
    assert!(stdout.contains("V.G.WZ_AKT.WEAR_RADIUS = "), "{stdout}");
    assert!(stderr.contains("warning:"), "{stderr}");
    let (code, stdout, _) = addipos(&["replay".as_ref(), out.as_os_str()]);
    assert_eq!(code, 0, "{stdout}");
    assert!(stdout.contains("1 passed, 0 failed"), "{stdout}");
}

#[test]
fn run_command_fails_on_the_tool_param_samples_bare_y() {
    for name in ["toolparam_set.nc", "toolparam_get.nc"] {
        let prog = program_path(name);
        let (code, stdout, stderr) = addipos(&["run".as_ref(), prog.as_os_str()]);
        assert_eq!(code, 1, "{name}: {stderr}");
        assert!(stdout.is_empty(), "{name}: {stdout}");
        assert!(
            stderr.contains("line 6, block N60, column 14"),
            "{name}: {stderr}"
        );
    }
    let (code, _, stderr) = addipos(&["run".as_ref(), "/no/such/prog.nc".as_ref()]);
    assert_eq!(code, 2, "{stderr}");
}

#[test]
fn run_command_reports_the_otc_type_error() {
    let prog = program_path("otc_general.nc");
    let (code, _, stderr) = addipos(&["run".as_ref(), prog.as_os_str()]);
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("error:") && stderr.contains("P-ERR-21391"),
        "{stderr}"
    );
}

#[test]
fn every_seed_trace_replays_over_tcp() {
    let server = common::TestServer::local();
    let mut target = session(&server.addr.to_string());
    for name in RUNNING {
        let run = run_nc(&program(name));
        let trace = parse_trace(name, &run.trace(name)).unwrap();
        let mismatches = replay_remote(&trace, &mut target);
        assert!(mismatches.is_empty(), "{name}: {mismatches:?}");
    }
}

/// The OTC manual's grinding disc (its tool data example: type 2, radius
/// 30 mm, wear constant 100000, max infeed 20 mm) for entry 1 of group 1.
fn grinding_disc() -> Vec<(u8, ToolKey, ToolValue)> {
    use tool_store::{ToolField as F, ToolKey, ToolValue as V};
    let key = |f| ToolKey::new(1, f).unwrap();
    vec![
        (1, key(F::ToolType), V::I32(2)),
        (1, key(F::Radius), V::F64(30.0)),
        (1, key(F::Length), V::F64(50.0)),
        (1, key(F::WearConst), V::F64(100_000.0)),
        (1, key(F::MaxInfeed), V::F64(200_000.0)),
    ]
}

/// The general RADIUS example with the manual's disc: OTC on, the wear of
/// the corrected line from X50 to X1000 (950 × 0.01 = 9.5 mm, none on the
/// approach and the departure) booked at `#OTC OFF`, and the run's trace
/// replays.
#[test]
fn the_general_otc_example_wears_the_disc_along_the_corrected_line() {
    let run = run_nc_with_tools(&program("otc_general.nc"), &grinding_disc());
    assert!(!run.failed(), "{:?} {:?}", run.error, run.report.faults);
    let wear = |n: &str| run.wear.iter().find(|(k, _)| k == n).map(|w| w.1);
    let w = wear("V.G.WZ_AKT.WEAR_RADIUS").unwrap();
    assert!((w - 9.5).abs() < 1e-9, "{w}");
    assert_eq!(wear("V.G.WZ_AKT.WEAR_RADIUS_CONT"), Some(w));
    let trace = parse_trace("otc_general", &run.trace("otc_general")).unwrap();
    assert!(replay(&trace).is_empty());
}

/// The printed tool-data example with a 5 mm tool in D100: the full
/// circle N90 (CW, centre (-5, 10), radius 15) is corrected left of it as
/// one arc of radius 20 that starts at its offset start (15, 10) and keeps
/// its whole turn up to the inside corner with the next compensating
/// motion N130, where the two offset paths meet: not the sliver past the
/// start point. With no radius it is a whole circle back to its start.
#[test]
fn tool_data_change_corrects_the_full_circle_as_a_whole_turn() {
    use tool_store::{ToolField as F, ToolKey, ToolValue as V};
    let centre = [-5.0, 10.0];
    let circle = |run: &NcRun| -> Vec<SpoolRecord> {
        let arcs = corrected(run).into_iter().filter(|e| e.arc.is_some());
        arcs.filter(|e| e.arc.unwrap().centre == centre).collect()
    };
    // No radius: the whole programmed circle, start = end.
    let bare = run_nc(&program("tool_data_change.nc"));
    let arcs = circle(&bare);
    assert_eq!(arcs.len(), 1, "{arcs:?}");
    assert!(!arcs[0].arc.unwrap().ccw);
    assert_eq!(
        (&arcs[0].start[..2], &arcs[0].end[..2]),
        (&[10.0, 10.0][..], &[10.0, 10.0][..])
    );
    // Radius 5 left of a CW circle: radius 20, cut where N130's offset
    // line (10,10)→(20,20) shifted 5 to its left meets it.
    let tools = [(1, ToolKey::new(100, F::Radius).unwrap(), V::F64(5.0))];
    let run = run_nc_with_tools(&program("tool_data_change.nc"), &tools);
    let arcs = circle(&run);
    assert_eq!(arcs.len(), 1, "{arcs:?}");
    let arc = arcs[0];
    assert!((arc.start[0] - 15.0).abs() < 1e-9 && (arc.start[1] - 10.0).abs() < 1e-9);
    let s = 5.0 / 2f64.sqrt();
    let (px, py) = (10.0 - s - centre[0], 10.0 + s - centre[1]);
    // (px + t)² + (py + t)² = 20², t > 0: the meeting point ahead on N130.
    let (b, c) = (px + py, px * px + py * py - 400.0);
    let t = (-b + (b * b - 2.0 * c).sqrt()) / 2.0;
    let meet = [centre[0] + px + t, centre[1] + py + t];
    assert!(
        (arc.end[0] - meet[0]).abs() < 1e-6 && (arc.end[1] - meet[1]).abs() < 1e-6,
        "{arc:?} ends not at {meet:?}"
    );
    // Swept clockwise from the start: more than 300° (a sliver: 28.7°).
    let angle = |p: [f64; 8]| (p[1] - centre[1]).atan2(p[0] - centre[0]);
    let sweep = (angle(arc.start) - angle(arc.end)).rem_euclid(std::f64::consts::TAU);
    assert!(sweep.to_degrees() > 300.0, "{}°", sweep.to_degrees());
}

/// The emulator with the PLC of the OTC manual's discrete example: the
/// channel unit `otc_radius_offset` (device 3, 50..53 of group 1) enabled
/// with a command of 2 mm (20000 × 0.1 µm) before the program starts; its
/// `state_r` is read where `#OTC OFF` switches OTC off.
struct PlcOffset {
    emu: emulator::Emulator,
    state_at_off: Option<Reply>,
}

impl Controller for PlcOffset {
    fn call(&mut self, req: &Request, _at: At) -> Reply {
        if *req == Request::Write(OtcObject::OtcOn.of(1), Value::I32(0)) {
            let state = Request::Read(OtcObject::RadiusOffsetState.of(1), ValueType::I32);
            self.state_at_off = Some(self.emu.run(&state));
        }
        self.emu.run(req)
    }
}

/// `wr_quad_disc` with the manual's grinding disc and a PLC offset of
/// 2 mm: the offset has ramped to the full 2 mm (state 20000) when
/// `#OTC OFF` comes, is booked as radius wear there (DISC: no continuous
/// part) and the state is back at 0 after it.
#[test]
fn wr_quad_disc_with_a_plc_offset_of_2_mm_ends_at_state_20000() {
    let (blocks, errors) = nc::parse_program(&program("wr_quad_disc.nc"));
    assert!(errors.is_empty(), "{errors:?}");
    let mut plc = PlcOffset {
        emu: emulator::Emulator::default(),
        state_at_off: None,
    };
    emulator::tools::entries::load(plc.emu.tc_mut(), grinding_disc().into_iter());
    for (unit, v) in [
        (OtcObject::RadiusOffsetCommand, 20_000),
        (OtcObject::RadiusOffsetEnable, 1),
    ] {
        assert_eq!(
            plc.emu.run(&Request::Write(unit.of(1), Value::I32(v))),
            Reply::Ok
        );
    }
    let mut report = Report::default();
    run_program(&blocks, &mut plc, &mut report).unwrap();
    assert!(report.faults.is_empty(), "{:?}", report.faults);
    assert_eq!(plc.state_at_off, Some(Reply::Value(Value::I32(20_000))));
    let read = |plc: &mut PlcOffset, key: OtcObject, ty| plc.emu.run(&Request::Read(key.of(1), ty));
    assert_eq!(
        read(&mut plc, OtcObject::RadiusOffsetState, ValueType::I32),
        Reply::Value(Value::I32(0))
    );
    assert_eq!(
        read(&mut plc, OtcObject::WearRadius, ValueType::F64),
        Reply::Value(Value::F64(2.0))
    );
    assert_eq!(
        read(&mut plc, OtcObject::WearRadiusCont, ValueType::F64),
        Reply::Value(Value::F64(0.0))
    );
}

/// `#OTC OFF` before `G40` (the two blocks of `wr_quad_disc` swapped): the
/// correction still runs, so OTC stays on with error 90050 at `#OTC OFF`;
/// the program as printed has no fault.
#[test]
fn otc_off_before_g40_in_wr_quad_disc_is_90050() {
    let printed = program("wr_quad_disc.nc");
    let run = run_nc_with_tools(&printed, &grinding_disc());
    assert!(!run.failed(), "{:?} {:?}", run.error, run.report.faults);
    let swapped = printed
        .replace("N100 G40 G1 X0", "N100 #OTC OFF")
        .replace("N110 #OTC OFF", "N110 G40 G1 X0");
    assert_ne!(swapped, printed);
    let run = run_nc_with_tools(&swapped, &grinding_disc());
    assert_eq!(run.report.faults.len(), 1, "{:?}", run.report.faults);
    let f = &run.report.faults[0];
    assert!(matches!(f.kind, RunErrorKind::Otc { bit: 2, .. }), "{f:?}");
    assert!(f.to_string().contains("90050"), "{f}");
    assert_eq!(line_and_block(f), (15, Some(100)));
}

/// The inclined grinding disc (the manual gives no program for it, only
/// the tool parameter): the tool-length example with the disc tilted by
/// 30° (300000 × 0.0001°) books its 10 mm of wear (1000 mm × 0.01) on X
/// and Z in the proportion of the tilt; upright, all on Z.
#[test]
fn the_length_example_with_an_inclined_disc_wears_x_and_z() {
    use tool_store::{ToolField as F, ToolKey, ToolValue as V};
    let tilt = (1, ToolKey::new(1, F::TiltAngle).unwrap());
    for (angle, x, z) in [(0.0, 0.0, 10.0), (300_000.0, 5.0, 10.0 * 0.75f64.sqrt())] {
        let mut tools = grinding_disc();
        tools.push((tilt.0, tilt.1, V::F64(angle)));
        let run = run_nc_with_tools(&program("otc_length.nc"), &tools);
        assert!(!run.failed(), "{:?} {:?}", run.error, run.report.faults);
        let wear = |n: &str| run.wear.iter().find(|(k, _)| k == n).unwrap().1;
        let (wx, wz) = (wear("V.G.WZ_AKT.WEAR[0]"), wear("V.G.WZ_AKT.WEAR[2]"));
        assert!(
            (wx - x).abs() < 1e-9 && (wz - z).abs() < 1e-9,
            "{angle}: {wx} {wz}"
        );
    }
}
