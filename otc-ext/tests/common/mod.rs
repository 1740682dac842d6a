//! Helpers shared by the OTC tests and the `wear_cycle` bench: programs in
//! trace request syntax run against a module, register reads and writes,
//! and the OTC set-ups of the four processing types.

// Not every test binary uses every helper.
#![allow(dead_code)]

use otc_ext::OtcExtension;
use tc_module::{CycleTime, TcExtension, TcModule, AXES};
use tc_objects::{BusObject, OtcObject};
use tc_request::text::parse_request;
use tc_request::Request;
use uoi::{ObjectAddress, ObjectBus, Value, ValueType};

/// A module with the OTC extension, standing at the origin, 1 ms cycle.
pub fn otc_module() -> TcModule<OtcExtension> {
    TcModule::new([0.0; AXES], CycleTime::DEFAULT, OtcExtension::default())
}

/// Runs a program in trace request syntax (`W`, motion, `EXEC`); every
/// write and motion must succeed.
pub fn run<E: TcExtension>(tc: &mut TcModule<E>, program: &str) {
    let lines = program.lines().map(str::trim);
    for line in lines.filter(|l| !l.is_empty() && !l.starts_with('#')) {
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

/// Reads an `i` register.
pub fn read_i<E: TcExtension>(tc: &mut TcModule<E>, addr: ObjectAddress) -> i32 {
    match tc.read_checked(addr, ValueType::I32) {
        Ok(Value::I32(v)) => v,
        other => panic!("{addr}: {other:?}"),
    }
}

/// Reads a `d` register.
pub fn read_d<E: TcExtension>(tc: &mut TcModule<E>, addr: ObjectAddress) -> f64 {
    match tc.read_checked(addr, ValueType::F64) {
        Ok(Value::F64(v)) => v,
        other => panic!("{addr}: {other:?}"),
    }
}

/// The four processing types, as ProcType codes with their names.
pub const TYPES: [(i32, &str); 4] = [
    (0, "RADIUS"),
    (1, "LENGTH"),
    (2, "TOOL_DIR"),
    (3, "SURF_NORM_DIR"),
];

/// Group 1 corrects on the right with tool 1 of radius 1 and starts
/// (STATUS=1): every type runs on the same corrected elements.
pub const CORRECTION_ON: &str = "
    W 1300/1/1/8 i 1
    W 1300/1/1/6 d 1
    W 1300/1/1/10 i 1
    W 1300/1/1/3 i 1
";

/// The PLC units a type takes in AUTO (docs/otc.md, "Processing types and their directions"): the
/// channel unit (3/1/50..) for RADIUS and TOOL_DIR, the axis unit of the
/// third main axis (Z = axis 2 by default) for LENGTH, the axis unit of
/// axis 2 for TOOL_DIR and SURF_NORM_DIR. Returns the command addresses.
pub fn units_of(proc_type: i32) -> &'static [ObjectAddress] {
    match proc_type {
        0 => &[CHANNEL_UNIT],
        2 => &[CHANNEL_UNIT, Z_AXIS_UNIT],
        _ => &[Z_AXIS_UNIT],
    }
}

/// The command of group 1's channel unit.
const CHANNEL_UNIT: ObjectAddress = OtcObject::RadiusOffsetCommand.of(1);
/// The command of axis 2's unit.
const Z_AXIS_UNIT: ObjectAddress = OtcObject::AxisOffsetCommand.of(2);

/// The enable address that goes with a unit's command address.
fn enable_of(command: ObjectAddress) -> ObjectAddress {
    match BusObject::at(command) {
        Some(BusObject::Otc(OtcObject::RadiusOffsetCommand)) => {
            OtcObject::RadiusOffsetEnable.of(command.index)
        }
        _ => OtcObject::AxisOffsetEnable.of(command.index),
    }
}

/// Switches OTC on for group 1 in AUTO with `proc_type`: a grinding tool
/// (ToolType 2) of wear constant 1000 (0.1 µm/m: 1e-4 per unit of path),
/// ToolMaxInfeed 1e6 (0.1 µm), AccWeight 1 (the slowest ramp, so a unit
/// ramps for a long time), the units of the type enabled with command
/// `command` (0.1 µm).
pub fn otc_auto_on<E: TcExtension>(tc: &mut TcModule<E>, proc_type: i32, command: i32) {
    run(
        tc,
        &format!(
            "W 1300/3/1/30 i 2
             W 1300/3/1/31 d 1000
             W 1300/3/1/32 d 1000000
             W 1300/3/1/6 i 1
             W 1300/3/1/2 i {proc_type}
             W 1300/3/1/3 i 2"
        ),
    );
    set_units(tc, proc_type, command);
    for cmd in units_of(proc_type) {
        run(tc, &format!("W {} i 1", enable_of(*cmd)));
    }
    run(tc, "W 1300/3/1/1 i 1");
    assert_eq!(read_i(tc, OtcObject::OtcOn.of(1)), 1, "OTC on");
    assert_eq!(read_i(tc, OtcObject::OtcError.of(1)), 0, "OtcError");
}

/// Writes `command` (0.1 µm) to every unit of `proc_type`.
pub fn set_units<E: TcExtension>(tc: &mut TcModule<E>, proc_type: i32, command: i32) {
    for cmd in units_of(proc_type) {
        run(tc, &format!("W {cmd} i {command}"));
    }
}

/// An endless contour along +X at 6000 units/min (0.1 per cycle): a line
/// (B moving by 5°), a half circle CW above, a line, a half circle CCW
/// below, and again; with the tool on the right the corrected path has
/// outside corners (circular transitions) and inside corners, lines and
/// arcs, about 130 cycles per profile.
#[derive(Debug, Default)]
pub struct Contour {
    x: f64,
    k: u64,
}

impl Contour {
    /// The next `n` profiles.
    pub fn next_profiles(&mut self, n: usize) -> Vec<tc_module::Motion> {
        (0..n).map(|_| self.next_profile()).collect()
    }

    fn next_profile(&mut self) -> tc_module::Motion {
        use tc_module::{ArcDir, Motion};
        let mut w = [None; AXES];
        self.x += 10.0;
        w[0] = Some(self.x);
        w[1] = Some(0.0);
        let k = self.k;
        self.k += 1;
        match k % 4 {
            0 | 2 => {
                w[4] = Some(if k.is_multiple_of(8) { 5.0 } else { 0.0 });
                Motion::Lin {
                    words: w,
                    feed: Some(6000.0),
                }
            }
            q => Motion::Cir {
                dir: if q == 1 { ArcDir::Cw } else { ArcDir::Ccw },
                words: w,
                centre: [Some(5.0), Some(0.0), None],
                feed: None,
            },
        }
    }
}

/// Commands `profiles` (all must be taken).
pub fn command_all<E: TcExtension>(tc: &mut TcModule<E>, profiles: &[tc_module::Motion]) {
    for m in profiles {
        tc.command(m).unwrap_or_else(|e| panic!("{m:?}: {e}"));
    }
}
