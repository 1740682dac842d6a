//! Commands a host program sends besides object accesses: interpolation
//! profiles (`LIN`, `RAP`, `CIR`), direct commands (`JA`, `JS`), special
//! functions (`SSF`) and `rs()` (trace-format.md, "Requests").

use crate::plane::AXES;

/// Axis words of a command: `Some(v)` for each named machine axis.
pub type AxisWords = [Option<f64>; AXES];

/// Arc direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ArcDir {
    /// Clockwise (G2), σ = -1.
    Cw,
    /// Counter-clockwise (G3), σ = +1.
    Ccw,
}

impl ArcDir {
    /// σ: +1 CCW, -1 CW.
    pub const fn sigma(self) -> f64 {
        match self {
            ArcDir::Cw => -1.0,
            ArcDir::Ccw => 1.0,
        }
    }

    /// The trace keyword.
    pub const fn keyword(self) -> &'static str {
        match self {
            ArcDir::Cw => "CW",
            ArcDir::Ccw => "CCW",
        }
    }
}

/// One command to the motion side of the controller.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Motion {
    /// `LIN`/`RAP`: straight line to an absolute end point.
    Lin {
        /// End point words; unnamed axes keep their value.
        words: AxisWords,
        /// Modal feed `F` (units/min), if given.
        feed: Option<f64>,
        /// `RAP`: at the rapid feed, no wear.
        rapid: bool,
    },
    /// `CIR CW|CCW`: arc in the main plane.
    Cir {
        /// Direction.
        dir: ArcDir,
        /// End point words.
        words: AxisWords,
        /// Centre offsets `I J K` from the start along the axes allocated as X, Y, Z.
        centre: [Option<f64>; 3],
        /// Modal feed `F`, if given.
        feed: Option<f64>,
    },
    /// `JA`: direct absolute positioning of the named axes.
    Ja {
        /// Targets.
        words: AxisWords,
    },
    /// `JS`: direct stop of the listed axes.
    Js {
        /// Axes to stop.
        axes: [bool; AXES],
    },
    /// `SSF axis function`: special function to an axis.
    Ssf {
        /// Machine axis.
        axis: u8,
        /// Function number (2001: flush the correction buffer).
        function: i32,
    },
    /// `RS`: the legacy `rs()`, rotation back to 0.
    Rs,
}

/// The special function that spools the buffered profile and keeps running.
pub const SSF_FLUSH: i32 = 2001;
