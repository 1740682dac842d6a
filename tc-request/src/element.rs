//! A spooled element as it is reported (spool log, wire): its geometry,
//! feed and who spooled it.

use crate::axes::AxisPos;

uoi::code_list! {
    /// Who put an element into the spooler. OTC's continuous wear only
    /// counts on elements the running correction spooled, and its RADIUS
    /// weight rises along the approach and falls along the departure
    /// (docs/otc.md).
    pub enum Origin: u8 {
        /// No correction running (also a move after a fault or a RESET).
        Uncorrected = 0,
        /// The approach element of a correction.
        Approach = 1,
        /// A corrected profile element (plane-null profiles included).
        Corrected = 2,
        /// A transition inserted at an outside corner.
        Transition = 3,
        /// The departure: the first element after STATUS=0.
        Departure = 4,
    }
}

/// The arc part of a reported element: plane, centre, direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArcRecord {
    /// Machine axes `(h, v, third)` of the arc's plane.
    pub plane: [u8; 3],
    /// Centre `(h, v)`.
    pub centre: [f64; 2],
    /// Counter-clockwise?
    pub ccw: bool,
}

/// A spooled element as reported.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpoolRecord {
    /// `None` for a line.
    pub arc: Option<ArcRecord>,
    /// Start position.
    pub start: AxisPos,
    /// End position.
    pub end: AxisPos,
    /// Feed, units/min.
    pub feed: f64,
    /// A rapid move.
    pub rapid: bool,
    /// Who spooled it.
    pub origin: Origin,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn origin_codes_round_trip() {
        for &o in Origin::ALL {
            assert_eq!(Origin::from_code(o.code()), Some(o));
        }
        assert_eq!(Origin::from_code(5), None);
    }
}
