//! The state the view shows, taken from the served emulator in one look:
//! axes, spooler, each group in use with its STATUS and ERROR (the values
//! the bus reads, bits named), its tool entries, its OTC state; and the
//! clock. Serialised as the JSON of `/state` (docs/web.md).

use emulator::EmulatorService;
use otc_ext::{running_wear, OtcExtension, OtcGroup, GRINDING};
use serde::Serialize;
use tc_module::{Group, ToolEntry, WkzIndex, AXIS_NAMES, TOOL_ENTRIES};
use tc_objects::GROUPS;
use tc_objects::{ErrorBits, OtcObject, StatusBits, TcObject};
use uoi::{Value, ValueType};

/// 0.1 µm (the PLC units' state registers) in mm.
const PLC_UNIT_MM: f64 = 1e-4;

/// Everything the page shows but the path.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Snapshot {
    /// The emulator's clock.
    pub clock: Clock,
    /// The executed position of every axis, `X` to `V`.
    pub axes: Vec<Axis>,
    /// The spooler.
    pub queue: Queue,
    /// The machine axes of the main plane, as drawn (`h` across, `v` up).
    pub plane: Plane,
    /// The groups in use (written or read on the bus since the start).
    pub groups: Vec<GroupView>,
    /// Who is connected.
    pub clients: Clients,
}

/// Stepped or real time.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Clock {
    /// `"stepped"` or `"realtime"`.
    pub mode: &'static str,
    /// The real-time factor (`null` when stepped).
    pub factor: Option<f64>,
}

/// One axis and where it stands.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Axis {
    /// `X` .. `V`.
    pub name: String,
    /// Executed position, mm.
    pub pos: f64,
}

/// The spooler's fill.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Queue {
    /// Motion waiting, as `QUEUE` answers.
    pub waiting: usize,
    /// Elements the spooler holds at most.
    pub capacity: usize,
}

/// The main plane's two machine axes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Plane {
    /// The machine axis drawn across (0 = X).
    pub h: u8,
    /// The machine axis drawn up.
    pub v: u8,
}

/// One compensation group.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GroupView {
    /// 1..=32.
    pub index: u16,
    /// STATUS as the bus reads it.
    pub status: i32,
    /// Its bits by name.
    pub status_bits: Vec<&'static str>,
    /// ERROR as the bus reads it.
    pub error: i32,
    /// Its bits by name.
    pub error_bits: Vec<&'static str>,
    /// WKZINDEX: the entry in use.
    pub wkz: usize,
    /// The entries that hold data, and the one in use.
    pub tools: Vec<ToolView>,
    /// OTC, where it is configured.
    pub otc: Option<OtcView>,
}

/// One tool entry.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ToolView {
    /// WKZINDEX of the entry.
    pub index: usize,
    /// RADIUS, mm.
    pub radius: f64,
    /// WkzLen, mm.
    pub length: f64,
    /// The booked wear radius (the entry in use only), mm.
    pub wear: f64,
    /// The wear of the running OTC period (the entry in use, OTC on), mm.
    pub otc_wear: Option<f64>,
}

/// The OTC state of a group.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OtcView {
    /// `#OTC ON`.
    pub on: bool,
    /// ProcType.
    pub proc_type: String,
    /// Mode.
    pub mode: String,
    /// The wear of the running period, mm (0 when off).
    pub running_wear: f64,
    /// OtcError.
    pub error: i32,
}

/// The connected clients.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Clients {
    /// UOI connections.
    pub uoi: usize,
    /// OPC UA client connections open (the OPC UA face's door counts
    /// them); `null` without the OPC UA face.
    pub opcua: Option<usize>,
    /// Open pages of this view.
    pub web: usize,
}

/// The state of `service` now; `web`: pages open.
pub fn take(service: &mut EmulatorService, web: usize) -> Snapshot {
    let realtime = service.realtime();
    let uoi = service.connections();
    let emu = service.emulator_mut();
    let pos = emu.position();
    let axes = AXIS_NAMES
        .iter()
        .zip(pos)
        .map(|(n, p)| Axis {
            name: n.to_string(),
            pos: p,
        })
        .collect();
    let queue = Queue {
        waiting: emu.queue_len(),
        capacity: emu.tc().spooler().capacity(),
    };
    let main = emu.tc().main_axes().plane;
    let in_use: Vec<u16> = GROUPS.filter(|g| emu.tc().group_at(*g).is_some()).collect();
    let groups = in_use.into_iter().filter_map(|g| group(emu, g)).collect();
    Snapshot {
        clock: Clock {
            mode: if realtime.is_some() {
                "realtime"
            } else {
                "stepped"
            },
            factor: realtime,
        },
        axes,
        queue,
        plane: Plane {
            h: main.h,
            v: main.v,
        },
        groups,
        clients: Clients {
            uoi,
            opcua: None,
            web,
        },
    }
}

/// Group `g` (in use) as the page shows it.
fn group(emu: &mut emulator::Emulator, g: u16) -> Option<GroupView> {
    let status = read_i32(emu, TcObject::Status.of(g));
    let error = read_i32(emu, TcObject::Error.of(g));
    let axis_unit = axis_unit_mm(emu);
    let tc = emu.tc();
    let grp = tc.group_at(g)?;
    let running = grp.ext.on.then(|| running_wear(tc, grp).0 + axis_unit);
    Some(GroupView {
        index: g,
        status,
        status_bits: StatusBits::from_bits_retain(status)
            .iter_names()
            .map(|(n, _)| n)
            .collect(),
        error,
        error_bits: ErrorBits::from_bits_retain(error)
            .iter_names()
            .map(|(n, _)| n)
            .collect(),
        wkz: grp.wkz.get(),
        tools: tools(grp, running),
        otc: otc(grp, running),
    })
}

/// The entries of `grp` that hold data, and the one in use.
fn tools(grp: &Group<OtcExtension>, running: Option<f64>) -> Vec<ToolView> {
    let mut out = Vec::new();
    for i in 0..TOOL_ENTRIES {
        let Some(w) = i32::try_from(i).ok().and_then(WkzIndex::new) else {
            continue;
        };
        let e = grp.tools.entry(w);
        let current = grp.wkz == w;
        if !current && *e == ToolEntry::default() {
            continue;
        }
        out.push(ToolView {
            index: w.get(),
            radius: e.radius,
            length: e.length,
            wear: if current { grp.ext.wear_radius } else { 0.0 },
            otc_wear: running.filter(|_| current),
        });
    }
    out
}

/// OTC of `grp`, where it is configured: on, wear booked, or a grinding
/// tool in use.
fn otc(grp: &Group<OtcExtension>, running: Option<f64>) -> Option<OtcView> {
    let s: &OtcGroup = &grp.ext;
    let grinding = grp.tools.entry(grp.wkz).ext.tool_type == GRINDING;
    let configured = s.on || s.wear_radius != 0.0 || s.wear_radius_cont != 0.0 || grinding;
    configured.then(|| OtcView {
        on: s.on,
        proc_type: format!("{:?}", s.proc_type),
        mode: format!("{:?}", s.mode),
        running_wear: running.unwrap_or(0.0),
        error: s.error.bits(),
    })
}

/// The offset applied by the PLC unit of the tool axis, mm (0 when none
/// is taken).
fn axis_unit_mm(emu: &mut emulator::Emulator) -> f64 {
    let tc = emu.tc();
    let running = GROUPS
        .filter_map(|g| tc.group_at(g))
        .find(|g| g.ext.on)
        .map(|g| running_wear(tc, g).1);
    let Some(Some(axis)) = running else {
        return 0.0;
    };
    let Ok(index) = u16::try_from(axis) else {
        return 0.0;
    };
    f64::from(read_i32(emu, OtcObject::AxisOffsetState.of(index))) * PLC_UNIT_MM
}

/// An I32 object as the bus reads it (0 when refused).
fn read_i32(emu: &mut emulator::Emulator, addr: uoi::ObjectAddress) -> i32 {
    match emu.read(addr, ValueType::I32) {
        Ok(Value::I32(v)) => v,
        _ => 0,
    }
}
