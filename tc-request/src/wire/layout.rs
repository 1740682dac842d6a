//! Payload layouts of the TC ops (docs/protocol.md), declared with
//! `zerocopy`.

use zerocopy::byteorder::little_endian::{F64, I32, U16, U64};
use zerocopy::{FromBytes, Immutable, IntoBytes, KnownLayout, Unaligned};

use crate::axes::AXES;

/// Most spool elements in one `SPOOL_LOG` answer (fits `MAX_FRAME`).
pub const SPOOL_BATCH: usize = 400;

// A full SPOOL_LOG answer must fit one frame.
const _: () = assert!(
    uoi::wire::HEADER_LEN
        + std::mem::size_of::<SpoolLogAns>()
        + SPOOL_BATCH * std::mem::size_of::<WireElement>()
        <= uoi::wire::MAX_FRAME
);

/// Word slots of [`MotionReq::words`]: 0..7 axes, then `I J K`, then `F`.
pub const WORD_SLOTS: usize = AXES + 4;
/// Slot of `I` in [`MotionReq::words`].
pub const SLOT_I: usize = AXES;
/// Slot of `F` in [`MotionReq::words`].
pub const SLOT_F: usize = AXES + 3;

/// `MOTION` request payload (108 bytes).
#[derive(
    Debug, Clone, Copy, PartialEq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct MotionReq {
    /// Motion kind: 1 LIN, 2 RAP, 3 CIR, 4 JA, 5 JS, 6 SSF, 7 RS.
    pub kind: u8,
    /// 1 = CCW, 0 = CW (CIR only).
    pub ccw: u8,
    /// Axis of `SSF`.
    pub axis: u8,
    /// Zero.
    pub pad: u8,
    /// Bit k set: `words[k]` is given. For `JS`: the axes to stop.
    pub present: U16,
    /// Zero.
    pub pad2: [u8; 2],
    /// Function number of `SSF`.
    pub function: I32,
    /// Axis words, I J K, F.
    pub words: [F64; WORD_SLOTS],
}

/// `EXEC` request payload: cycles, `u64::MAX` = until the spooler is empty.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct ExecReq {
    /// Cycles.
    pub cycles: U64,
}

/// `POS` answer payload: executed position of the 8 axes.
#[derive(
    Debug, Clone, Copy, PartialEq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct PosAns {
    /// X Y Z A B C U V.
    pub pos: [F64; AXES],
}

/// `QUEUE` answer payload.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct QueueAns {
    /// Elements waiting in the spooler.
    pub count: U64,
}

/// `SETUP` request payload (80 bytes): a fresh emulator at `start` with
/// cycle `cycle_s` and a spooler of `spool_capacity` elements.
#[derive(
    Debug, Clone, Copy, PartialEq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct SetupReq {
    /// Initial machine position.
    pub start: [F64; AXES],
    /// Interpolation cycle in seconds.
    pub cycle_s: F64,
    /// Spooler capacity in elements; 0: the server's configured one.
    pub spool_capacity: U64,
}

/// `FEED_ADAPT` request payload (16 bytes).
#[derive(
    Debug, Clone, Copy, PartialEq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct FeedAdaptReq {
    /// 1: adapt (G11); 0: do not (G10).
    pub on: u8,
    /// Zero.
    pub pad: [u8; 7],
    /// The smallest programmed radius adapted.
    pub rmin: F64,
}

/// `SPOOL_LOG` request payload.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct SpoolLogReq {
    /// 1: keep logging spooled elements from now on; 0: stop.
    pub logging: u8,
    /// Zero.
    pub pad: [u8; 3],
}

/// `SPOOL_LOG` answer head; `count` [`WireElement`]s follow.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct SpoolLogAns {
    /// Elements that follow.
    pub count: U16,
    /// 1 when more logged elements wait: ask again.
    pub more: u8,
    /// Zero.
    pub pad: u8,
}

/// One spooled element (160 bytes).
#[derive(
    Debug, Clone, Copy, PartialEq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct WireElement {
    /// 1 line, 2 arc.
    pub kind: u8,
    /// Arc direction: 1 CCW.
    pub ccw: u8,
    /// Arc plane: first axis.
    pub plane_h: u8,
    /// Arc plane: second axis.
    pub plane_v: u8,
    /// Arc plane: third axis.
    pub plane_third: u8,
    /// 1 for a rapid move.
    pub rapid: u8,
    /// Origin code (`Origin`).
    pub origin: u8,
    /// Zero.
    pub pad: u8,
    /// Start position.
    pub start: [F64; AXES],
    /// End position.
    pub end: [F64; AXES],
    /// Arc centre in its plane.
    pub centre: [F64; 2],
    /// Feed, units/min.
    pub feed: F64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layouts_have_documented_sizes() {
        assert_eq!(std::mem::size_of::<MotionReq>(), 108);
        assert_eq!(std::mem::size_of::<ExecReq>(), 8);
        assert_eq!(std::mem::size_of::<PosAns>(), 64);
        assert_eq!(std::mem::size_of::<QueueAns>(), 8);
        assert_eq!(std::mem::size_of::<SetupReq>(), 80);
        assert_eq!(std::mem::size_of::<SpoolLogReq>(), 4);
        assert_eq!(std::mem::size_of::<FeedAdaptReq>(), 16);
        assert_eq!(std::mem::size_of::<SpoolLogAns>(), 4);
        assert_eq!(std::mem::size_of::<WireElement>(), 160);
    }
}
