//! Commands to the motion side of the controller: interpolation profiles
//! (`LIN`, `RAP`, `CIR`), direct commands (`JA`, `JS`), special functions
//! (`SSF`) and the legacy `rs()` (docs/trace-format.md, "Requests").

use crate::axes::{AxisWords, AXES};

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

    /// The trace keyword, `CW` or `CCW`.
    pub const fn keyword(self) -> &'static str {
        match self {
            ArcDir::Cw => "CW",
            ArcDir::Ccw => "CCW",
        }
    }
}

/// One motion command: the only list of motion kinds in the project.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Motion {
    /// `LIN`: feed line to an absolute end point.
    Lin {
        /// End point words; unnamed axes keep their value.
        words: AxisWords,
        /// Modal feed `F` (units/min), if given.
        feed: Option<f64>,
    },
    /// `RAP`: rapid line at the rapid feed (no wear).
    Rap {
        /// End point words.
        words: AxisWords,
        /// An `F` word sets the modal feed of later commands; the rapid
        /// itself runs at the rapid feed.
        feed: Option<f64>,
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
        /// Function number ([`SSF_FLUSH`]: flush the correction buffer).
        function: i32,
    },
    /// `RS`: the legacy `rs()`, rotation back to 0.
    Rs,
}

/// The special function that spools the buffered profile and keeps the
/// correction running (docs/trc.md, "The one-profile buffer").
pub const SSF_FLUSH: i32 = 2001;
