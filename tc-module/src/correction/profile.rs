//! What enters the correction: a programmed profile in machine axes, and
//! the transition mode its outside corners take.

use crate::geometry::Contour;
use crate::plane::AxisPos;

/// A programmed profile as it enters the correction (rotated, machine
/// axes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Profile {
    /// The element in the group's plane.
    pub contour: Contour,
    /// Programmed start, all axes.
    pub start: AxisPos,
    /// Programmed end, all axes.
    pub end: AxisPos,
    /// Feed, units/min.
    pub feed: f64,
    /// A rapid move.
    pub rapid: bool,
}

/// Transition inserted at outside corners (device 2 sub 1; NC G26/G25).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum TransitionMode {
    /// 0: one arc about the programmed corner (G26). Default.
    #[default]
    Circular,
    /// 1: straight lines (G25).
    Linear,
}

impl TransitionMode {
    /// The register value.
    pub const fn code(self) -> i32 {
        match self {
            TransitionMode::Circular => 0,
            TransitionMode::Linear => 1,
        }
    }

    /// The mode for a register value (the table allows 0 and 1).
    pub const fn from_code(code: i32) -> Self {
        if code == 1 {
            TransitionMode::Linear
        } else {
            TransitionMode::Circular
        }
    }
}
