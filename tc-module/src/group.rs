//! A compensation group: the registers of devices 1 and 2 for one index,
//! its tool table, its correction state, and an extension's own state of
//! the group (`ext`).

use crate::bits::ErrorBits;
use crate::correction::{Buffer, TransitionMode};
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

/// Default axis allocation of a group: XAxis 0, YAxis 1, ZAxis 2
/// (docs/objects.md device 1 sub 4, 5, 11; decision 9).
pub const DEFAULT_AXES: [u8; 3] = [0, 1, 2];

/// One compensation group (device 1 index = group number). `G` is an
/// extension's state of the group, `T` its fields of each tool entry.
#[derive(Debug, Clone)]
pub struct CorrGroup<G = (), T = ()> {
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
    pub tools: ToolTable<T>,
    /// The one-profile buffer.
    pub buffer: Buffer,
    /// Faulted by a motion error: interpolation refused until ERROR is written.
    pub faulted: bool,
    /// The extension's state of this group.
    pub ext: G,
}

impl<G: Default, T: Copy + Default> Default for CorrGroup<G, T> {
    fn default() -> Self {
        Self {
            error: ErrorBits::empty(),
            axes: DEFAULT_AXES,
            wkz: WkzIndex::default(),
            side: None,
            transition: TransitionMode::default(),
            tools: ToolTable::default(),
            buffer: Buffer::default(),
            faulted: false,
            ext: G::default(),
        }
    }
}

impl<G, T: Copy + Default> CorrGroup<G, T> {
    /// The tool entry at WKZINDEX.
    pub fn tool(&self) -> &ToolEntry<T> {
        self.tools.entry(self.wkz)
    }

    /// The tool entry at WKZINDEX, mutable.
    pub fn tool_mut(&mut self) -> &mut ToolEntry<T> {
        self.tools.entry_mut(self.wkz)
    }

    /// The group's plane axes in `plane`.
    pub fn plane_axes(&self, plane: TcPlane) -> PlaneAxes {
        plane.pick(self.axes)
    }

    /// The offset `d = s × radius` of the current entry (side Left when
    /// none was selected).
    pub fn offset(&self) -> f64 {
        self.side.map_or(1.0, Side::sign) * self.tool().radius
    }

    /// The group RESET (device 1 sub 2): side cleared, buffer, fault and
    /// error bits dropped, every field of every table entry back to
    /// default; WKZINDEX, axes and TransitionMode stay. The caller clears
    /// Run.
    pub fn reset(&mut self) {
        self.side = None;
        self.buffer = Buffer::default();
        self.faulted = false;
        self.error = ErrorBits::empty();
        self.tools.clear();
    }

    /// A motion error while running (docs/objects.md "ERROR bits"; decision
    /// 5): the bit is set, the buffered profile is dropped and the group is
    /// faulted until ERROR is written. The caller clears Run.
    pub fn fault(&mut self, bits: ErrorBits) {
        self.error |= bits;
        self.faulted = true;
        self.buffer.clear();
    }

    /// Writing ERROR: every bit cleared, the fault state left.
    pub fn clear_error(&mut self) {
        self.error = ErrorBits::empty();
        self.faulted = false;
    }
}
