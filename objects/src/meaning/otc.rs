//! What each OTC object means to a user: the text of the object
//! reference (`docs/objects.md`).

use uoi::Meaning;

use crate::otc::OtcObject as O;

impl Meaning for O {
    fn meaning(&self) -> &'static str {
        switching_and_wear(*self).unwrap_or_else(|| tool_and_plc(*self))
    }
}

/// Both request registers.
const REQUEST: &str = "The command clamped to ± ToolMaxInfeed of the current entry of the group \
                       whose OTC is on (with none on: of group 1), enabled or not.";

/// Both state registers.
const STATE: &str = "The offset applied now, after the ramp, in 0.1 µm rounded to the nearest.";

/// The switching, mode and wear objects; `None` for the others.
fn switching_and_wear(o: O) -> Option<&'static str> {
    Some(match o {
        O::OtcOn => {
            "1 switches OTC on for the group (NC `#OTC ON`; needs a grinding tool, else \
                 OtcError ToolType; one group at a time, else OtcError Sequence), 0 switches \
                 it off and books the wear. Read: whether it is on."
        }
        O::ProcType => {
            "Where the wear acts: 0 RADIUS, 1 LENGTH (default), 2 TOOL_DIR, \
                 3 SURF_NORM_DIR. Changed only while OTC is off (else OtcError Sequence)."
        }
        O::Mode => {
            "Which wear counts: 0 DISC (PLC units only), 1 CONT (path only), 2 AUTO \
                 (both, default). Changed only while OTC is off."
        }
        O::WearConst => {
            "Wear per path length in 0.1 µm/m, modal (NC `WEAR_CONST=`). Read: the \
                 constant in force."
        }
        O::WearConstTool => {
            "Any value: use the tool entry's own constant again (NC `WEAR_CONST_TOOL`)."
        }
        O::AccWeight => {
            "How fast a PLC offset is ramped, in percent of 1e-3 units per cycle \
                 (default 100)."
        }
        O::OtcError => "Read: the OTC error bits (table below). Write (any value): clears them.",
        O::WearRadius => "Radius wear booked for the current tool at OTC switch-off, in units.",
        O::WearRadiusCont => "Its continuous (path) part, in units.",
        O::WearAxis => {
            "Wear booked on machine axis 0..7 (sub 20 + axis) for the length and \
                 direction types, in units."
        }
        _ => return None,
    })
}

/// The tool fields, position requests, PLC units and hand-off objects.
fn tool_and_plc(o: O) -> &'static str {
    match o {
        O::ToolType => {
            "Type of the entry at WKZINDEX: 0 milling, 1 turning, 2 grinding, 3 wire. \
             OTC needs 2."
        }
        O::ToolWearConst => "Wear constant of the entry at WKZINDEX, in 0.1 µm/m.",
        O::ToolMaxInfeed => {
            "Largest PLC offset the entry at WKZINDEX accepts, in 0.1 µm (0: none)."
        }
        O::ToolTiltAngle => "Tilt of the entry at WKZINDEX for the LENGTH type, in 0.0001 degree.",
        O::AllowPosReq => {
            "1 allows direct commands (JA, JS) and ReInit while OTC is on; with 0 they \
             are refused with State and OtcError PosRequest."
        }
        O::OriAxis => {
            "Machine axis whose position is the tool orientation angle B in degrees, \
             for TOOL_DIR and SURF_NORM_DIR (default 4)."
        }
        O::RadiusOffsetCommand => "PLC channel unit: the radius offset asked for, in 0.1 µm.",
        O::RadiusOffsetEnable => "PLC channel unit: 1 lets the command act.",
        O::RadiusOffsetRequest | O::AxisOffsetRequest => REQUEST,
        O::RadiusOffsetState | O::AxisOffsetState => STATE,
        O::HandoffCount => {
            "How many tools were handed back to external tool management: one per \
             WKZINDEX change, with the outgoing tool's booked wear."
        }
        O::HandoffToolIndex => "WKZINDEX of the tool handed back last.",
        O::HandoffWearRadius => "Its WearRadius at the hand-back.",
        O::HandoffWearRadiusCont => "Its WearRadiusCont at the hand-back.",
        O::AxisOffsetCommand => "PLC axis unit: the offset asked for on this axis, in 0.1 µm.",
        O::AxisOffsetEnable => "PLC axis unit: 1 lets the command act.",

        // Answered by `switching_and_wear`.
        _ => "",
    }
}
