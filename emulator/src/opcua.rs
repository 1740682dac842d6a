//! What the OPC UA face (`opcua-face`, docs/opcua.md) shows of the TC
//! module: the whole object table of bus 1300 with the meaning of each
//! object, devices as in `docs/objects.md`, groups and axes as folders of
//! their own, and a dashboard: the executed position of each axis, the
//! spooler queue, and each group's STATUS and ERROR (read-only). And the
//! machine of the OPC UA for Machine Tools model: its tools are the
//! entries of the tool tables that hold data, read from the tables
//! directly (no WKZINDEX switched), its channel's state from the spooler
//! and the groups' faults.

use std::any::Any;
use std::sync::Arc;

use opcua_face::{
    answer_value, ChannelState, Device, Identity, IndexKind, MachineSource, MachineTool,
    MachineView, Reading, Row, Table, ToolRecord,
};
use otc_ext::{running_wear, OtcExtension, OtcTool};
use tc_module::object_map::object_table;
use tc_module::{Group, ToolEntry, WkzIndex, AXIS_NAMES};
use tc_objects::TcObject;
use tc_objects::{GROUPS, TC_BUS};
use tc_request::{Reply, Request};
use tool_store::TOOL_ENTRIES;
use uoi::wire::Answer;
use uoi::{AccessError, Value, ValueType};

use tc_objects::DEVICES;

use crate::service::EmulatorService;
use crate::Emulator;

/// The table the face serves.
pub fn table() -> Table {
    Table {
        bus: TC_BUS,
        devices: DEVICES
            .iter()
            .map(|d| Device {
                number: d.number,
                title: format!("{}. {}", d.title, d.index),
                index: index_kind(d.number),
            })
            .collect(),
        rows: object_table::<OtcExtension>()
            .iter()
            .map(Row::from_desc)
            .collect(),
        readings: readings(),
        machine: None,
    }
}

/// Device 0 holds objects; devices 1..3 a folder per group, 4 per axis.
fn index_kind(device: u16) -> IndexKind {
    match device {
        0 => IndexKind::Object,
        4 => IndexKind::Instance {
            name: "Axis".into(),
            note: "Machine axis {}: its OTC control unit".into(),
        },
        _ => IndexKind::Instance {
            name: "Group".into(),
            note: "Compensation group {}. Every group exists: one never written holds the \
                   defaults (the module makes its storage on first access)"
                .into(),
        },
    }
}

/// The dashboard's readings.
fn readings() -> Vec<Reading> {
    let mut out = Vec::new();
    for (axis, name) in AXIS_NAMES.iter().enumerate() {
        out.push(Reading {
            id: format!("dashboard/position/{name}"),
            path: vec!["ExecutedPosition".into()],
            name: name.to_string(),
            doc: format!("Executed position of machine axis {axis} ({name}), as POS reports it"),
            ty: ValueType::F64,
            request: Request::Pos.to_wire(),
            pick: Arc::new(move |a| axis_position(a, axis)),
        });
    }
    out.push(Reading {
        id: "dashboard/queue".into(),
        path: Vec::new(),
        name: "QueueLength".into(),
        doc: "Motion waiting: elements in the spooler and plane-null profiles held with the \
              buffered one, as QUEUE reports it"
            .into(),
        ty: ValueType::I32,
        request: Request::Queue.to_wire(),
        pick: Arc::new(queue_length),
    });
    for g in GROUPS {
        for (object, name, what) in [
            (TcObject::Status, "STATUS", "status bits"),
            (TcObject::Error, "ERROR", "error bits"),
        ] {
            let addr = object.of(g);
            out.push(Reading {
                id: format!("dashboard/group/{g}/{name}"),
                path: vec!["Groups".into(), format!("Group{g}")],
                name: name.into(),
                doc: format!("The {what} of group {g} ({addr}), read-only"),
                ty: ValueType::I32,
                request: Request::Read(addr, ValueType::I32).to_wire(),
                pick: Arc::new(answer_value),
            });
        }
    }
    out
}

/// Axis `axis` of a POS answer.
fn axis_position(answer: &Answer, axis: usize) -> Result<Value, AccessError> {
    match Reply::from_wire(Request::Pos.wire_op(), answer) {
        Some(Reply::Pos(pos)) => pos
            .get(axis)
            .map(|&v| Value::F64(v))
            .ok_or(AccessError::NoObject),
        Some(Reply::Access(e)) => Err(e),
        _ => Err(AccessError::State),
    }
}

/// The count of a QUEUE answer (beyond i32: the largest i32).
fn queue_length(answer: &Answer) -> Result<Value, AccessError> {
    match Reply::from_wire(Request::Queue.wire_op(), answer) {
        Some(Reply::Queue(n)) => Ok(Value::I32(i32::try_from(n).unwrap_or(i32::MAX))),
        Some(Reply::Access(e)) => Err(e),
        _ => Err(AccessError::State),
    }
}

/// The tool kinds of ToolType (1300/3/g/30), by value.
const TOOL_KINDS: [&str; 4] = ["milling", "turning", "grinding", "wire"];

/// 0.1 µm (the PLC units' state registers) in mm.
const PLC_UNIT_MM: f64 = 1e-4;

/// The machine the face shows in the Machine Tools model: this build,
/// with the serial number of the settings.
pub fn machine(serial: &str) -> MachineTool {
    MachineTool {
        name: "addipos-tc".into(),
        identity: Identity {
            manufacturer: "addipos-tc".into(),
            model: "TC module emulator (bus 1300) with OTC".into(),
            software_revision: env!("CARGO_PKG_VERSION").into(),
            serial_number: serial.into(),
            product_instance_uri: format!("urn:addipos-tc:machine:{serial}"),
        },
        tool_kinds: TOOL_KINDS.iter().map(|k| k.to_string()).collect(),
        source: Arc::new(TcMachine),
    }
}

/// The TC module as a machine: looked at through the served emulator.
struct TcMachine;

impl MachineSource for TcMachine {
    fn look(&self, handler: &mut dyn Any) -> Option<MachineView> {
        let service = handler.downcast_mut::<EmulatorService>()?;
        Some(view(service.emulator_mut()))
    }
}

/// The emulator's channel and tools now.
fn view(emu: &mut Emulator) -> MachineView {
    let tc = emu.tc();
    let groups = || GROUPS.filter_map(|g| tc.group_at(g).map(|grp| (g, grp)));
    let state = if tc.queue_len() > 0 {
        ChannelState::Running
    } else if groups().any(|(_, g)| g.faulted || !g.error.is_empty()) {
        ChannelState::Interrupted
    } else {
        ChannelState::Idle
    };
    let mut tools = Vec::new();
    let mut axis_unit = None;
    for (index, g) in groups() {
        let running = g.ext.on.then(|| running_wear(tc, g));
        if let Some((_, Some(axis))) = running {
            axis_unit = Some(axis);
        }
        for i in 0..TOOL_ENTRIES {
            let Some(w) = WkzIndex::new(i32::from(i)) else {
                continue;
            };
            let current = g.wkz == w;
            let r = record(index, w, g.tools.entry(w), current.then_some(g));
            let r = ToolRecord {
                running_wear: running.filter(|_| current).map(|(w, _)| w),
                ..r
            };
            if holds_data(&r, g.tools.entry(w)) {
                tools.push(r);
            }
        }
    }
    if let Some(axis) = axis_unit {
        add_axis_unit(emu, axis, &mut tools);
    }
    MachineView { state, tools }
}

/// The record of entry `w` of group `index` (`current`: the group, when
/// it is the group's current entry: its booked wear).
fn record(
    index: u16,
    w: WkzIndex,
    e: &ToolEntry<OtcTool>,
    current: Option<&Group<OtcExtension>>,
) -> ToolRecord {
    ToolRecord {
        group: u32::from(index),
        // Below 1024.
        number: w.get() as u32,
        radius: e.radius,
        length: e.length,
        kind: u32::try_from(e.ext.tool_type).unwrap_or(0),
        wear: current.map_or(0.0, |g| g.ext.wear_radius),
        running_wear: None,
    }
}

/// Whether an entry is a tool: any field off its default, or wear.
fn holds_data(r: &ToolRecord, e: &ToolEntry<OtcTool>) -> bool {
    *e != ToolEntry::default() || r.wear != 0.0 || r.running_wear.is_some()
}

/// Adds the applied value of axis `axis`'s PLC unit (its OffsetState
/// 4/a/4, to 0.1 µm) to the running wear.
fn add_axis_unit(emu: &mut Emulator, axis: usize, tools: &mut [ToolRecord]) {
    let Ok(index) = u16::try_from(axis) else {
        return;
    };
    let addr = tc_objects::OtcObject::AxisOffsetState.of(index);
    let Ok(Value::I32(state)) = emu.read(addr, ValueType::I32) else {
        return;
    };
    for r in tools.iter_mut() {
        if let Some(w) = &mut r.running_wear {
            *w += f64::from(state) * PLC_UNIT_MM;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_device_of_the_reference_and_every_row() {
        let t = table();
        assert_eq!(t.devices.len(), 5);
        assert_eq!(t.rows.len(), object_table::<OtcExtension>().len());
        // 8 axes, the queue, STATUS and ERROR of 32 groups.
        assert_eq!(t.readings.len(), 8 + 1 + 2 * 32);
    }

    #[test]
    fn the_machine_sees_the_tool_tables_and_the_channel() {
        use tc_module::CycleTime;
        let mut emu = Emulator::new([0.0; 8], CycleTime::DEFAULT);
        let fresh = view(&mut emu);
        assert!(fresh.tools.is_empty());
        assert_eq!(fresh.state, ChannelState::Idle);
        emu.write(TcObject::WkzIndex.of(2), Value::I32(5)).unwrap();
        // Selecting an entry makes no tool of it; a radius does.
        assert!(view(&mut emu).tools.is_empty());
        emu.write(TcObject::Radius.of(2), Value::F64(2.5)).unwrap();
        let tools = view(&mut emu).tools;
        assert_eq!(tools.len(), 1);
        assert_eq!(
            (tools[0].group, tools[0].number, tools[0].radius),
            (2, 5, 2.5)
        );
        assert_eq!((tools[0].wear, tools[0].running_wear), (0.0, None));
        let lin = tc_request::text::parse_request("LIN X10").unwrap();
        emu.run(&lin);
        assert_eq!(view(&mut emu).state, ChannelState::Running);
        // Another group's entry written through its own WKZINDEX.
        emu.write(TcObject::WkzLen.of(7), Value::F64(40.0)).unwrap();
        let tools = view(&mut emu).tools;
        assert_eq!(
            tools
                .iter()
                .map(|t| (t.group, t.number))
                .collect::<Vec<_>>(),
            [(2, 5), (7, 0)]
        );
    }

    #[test]
    fn readings_pick_their_value() {
        let pos = Reply::Pos([1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 0.0, 8.5]).to_wire();
        assert_eq!(axis_position(&pos, 7), Ok(Value::F64(8.5)));
        let q = Reply::Queue(u64::MAX).to_wire();
        assert_eq!(queue_length(&q), Ok(Value::I32(i32::MAX)));
        let refused = Answer::Access(AccessError::State);
        assert_eq!(queue_length(&refused), Err(AccessError::State));
    }
}
