//! What each object of the TC module means to a user: the text of the
//! object reference (`docs/objects.md`).

use uoi::Meaning;

use crate::tc::TcObject;

impl Meaning for TcObject {
    fn meaning(&self) -> &'static str {
        device0(*self).unwrap_or_else(|| group(*self))
    }
}

/// The meaning of an object of device 0 (the whole module); `None` for a
/// group object.
fn device0(obj: TcObject) -> Option<&'static str> {
    Some(match obj {
        TcObject::Clean => {
            "Writing 1 puts every TC object back to its default: all groups, their tool \
                 tables and the rotation."
        }
        TcObject::AxisNr => {
            "Which machine axis plays X (sub 0), Y (sub 1) and Z (sub 2). \
                 Defaults 0, 1, 2."
        }
        TcObject::TcPlane => {
            "The main plane for arcs and the correction: 17 X-Y (default), 18 Z-X, 19 Y-Z."
        }
        TcObject::ReInit => {
            "Any value: every group drops its buffered profile and starts again with an \
                 approach. Tools, sides and status are kept."
        }
        TcObject::Reset => "Any value: the group RESET (1/g/2) on every group at once.",
        TcObject::RotAngle => {
            "Coordinate rotation in degrees, counter-clockwise in the main plane, applied \
                 to each interpolation command as it arrives. Default 0."
        }
        TcObject::RotCenterX => {
            "Centre of the rotation on the first axis of the main plane. Default 0."
        }
        TcObject::RotCenterY => {
            "Centre of the rotation on the second axis of the main plane. Default 0."
        }
        _ => return None,
    })
}

/// The meaning of an object of a compensation group (device 1).
fn group(obj: TcObject) -> &'static str {
    match obj {
        TcObject::Error => {
            "Read: the group's error bits (table below). Write (any value): clears them \
                 and ends the fault state."
        }
        TcObject::GroupReset => {
            "Any value: ends the correction, clears the side, the status, the buffer and \
                 the fault, and returns every tool entry to 0. WKZINDEX, the axes and the \
                 TransitionMode are kept."
        }
        TcObject::Status => {
            "Write 1: start the correction (InitError when no side is chosen, the plane \
                 axes coincide or another group runs). Write 0: end it; the held profile is \
                 spooled. Read: the status bits (table below)."
        }
        TcObject::XAxis => {
            "Machine axis the group uses as X (default 0). Written while running: \
                 InitError, the value stays."
        }
        TcObject::YAxis => "Machine axis the group uses as Y (default 1). Same rule as XAxis.",
        TcObject::Radius => {
            "Tool radius of the entry at WKZINDEX (default 0). May change while running; \
                 it applies from the next profile. A negative radius corrects on the other side."
        }
        TcObject::WkzIndex => {
            "The current tool entry, 0..1023. Written while running: InitError, the value \
                 stays."
        }
        TcObject::Left => "Any value: correct on the left of the contour. InitError while running.",
        TcObject::Right => {
            "Any value: correct on the right of the contour. InitError while running."
        }
        TcObject::ZAxis => {
            "Machine axis that takes the tool length (default 2). Same rule as XAxis."
        }
        TcObject::WkzLen => "Tool length of the entry at WKZINDEX (default 0).",
        TcObject::TransitionMode => {
            "What is inserted at an outside corner: 0 an arc around the corner (default, \
                 NC G26), 1 straight lines (NC G25)."
        }
        _ => device0(obj).unwrap_or_default(),
    }
}
