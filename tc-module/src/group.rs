//! A compensation group: the registers of device 1 and 2 for one index,
//! its tool table and its correction state.

use crate::bits::ErrorBits;
use crate::correction::Buffer;
use crate::plane::{PlaneAxes, TcPlane};
use crate::tool_table::{ToolEntry, ToolTable, WkzIndex};

/// Correction side (device 1 sub 9 Left / sub 10 Right; NC G41/G42).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Side {
    /// Left of the contour, s = +1.
    Left,
    /// Right of the contour, s = -1.
    Right,
}

impl Side {
    /// s: +1 Left, -1 Right.
    pub const fn sign(self) -> f64 {
        match self {
            Side::Left => 1.0,
            Side::Right => -1.0,
        }
    }
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
}

/// One compensation group (device 1 index = group number).
#[derive(Debug, Clone)]
pub struct CorrGroup {
    /// ERROR register.
    pub error: ErrorBits,
    /// XAxis, YAxis, ZAxis (sub 4, 5, 11).
    pub axes: [u8; 3],
    /// WKZINDEX (sub 8).
    pub wkz: WkzIndex,
    /// Side selected since the last RESET.
    pub side: Option<Side>,
    /// TransitionMode (device 2 sub 1).
    pub transition: TransitionMode,
    /// The tool table.
    pub tools: ToolTable,
    /// The one-profile buffer.
    pub buffer: Buffer,
    /// Faulted by a motion error: interpolation refused until ERROR is written.
    pub faulted: bool,
}

impl Default for CorrGroup {
    fn default() -> Self {
        Self {
            error: ErrorBits::empty(),
            axes: [0, 1, 2],
            wkz: WkzIndex::default(),
            side: None,
            transition: TransitionMode::default(),
            tools: ToolTable::default(),
            buffer: Buffer::default(),
            faulted: false,
        }
    }
}

impl CorrGroup {
    /// The tool entry at WKZINDEX.
    pub fn tool(&self) -> &ToolEntry {
        self.tools.entry(self.wkz)
    }

    /// The tool entry at WKZINDEX, mutable.
    pub fn tool_mut(&mut self) -> &mut ToolEntry {
        self.tools.entry_mut(self.wkz)
    }

    /// The group's plane axes in `plane`.
    pub fn plane_axes(&self, plane: TcPlane) -> PlaneAxes {
        plane.pick(self.axes)
    }

    /// The group RESET (device 1 sub 2): side cleared, buffer, fault and
    /// error bits dropped, every table entry back to default; WKZINDEX, axes
    /// and TransitionMode stay. The caller clears Run.
    pub fn reset(&mut self) {
        self.side = None;
        self.buffer = Buffer::default();
        self.faulted = false;
        self.error = ErrorBits::empty();
        self.tools.clear();
    }
}
