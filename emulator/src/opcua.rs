//! What the OPC UA face (`opcua-face`, docs/opcua.md) shows of the TC
//! module: the whole object table of bus 1300 with the meaning of each
//! object, devices as in `docs/objects.md`, groups and axes as folders of
//! their own, and a dashboard: the executed position of each axis, the
//! spooler queue, and each group's STATUS and ERROR (read-only).

use std::sync::Arc;

use opcua_face::{answer_value, Device, IndexKind, Reading, Row, Table};
use otc_ext::OtcExtension;
use tc_module::object_map::object_table;
use tc_module::{AXIS_NAMES, GROUPS, TC_BUS};
use tc_objects::TcObject;
use tc_request::{Reply, Request};
use uoi::wire::Answer;
use uoi::{AccessError, Value, ValueType};

use tc_objects::DEVICES;

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
    fn readings_pick_their_value() {
        let pos = Reply::Pos([1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 0.0, 8.5]).to_wire();
        assert_eq!(axis_position(&pos, 7), Ok(Value::F64(8.5)));
        let q = Reply::Queue(u64::MAX).to_wire();
        assert_eq!(queue_length(&q), Ok(Value::I32(i32::MAX)));
        let refused = Answer::Access(AccessError::State);
        assert_eq!(queue_length(&refused), Err(AccessError::State));
    }
}
