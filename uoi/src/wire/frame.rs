//! The frame: a 4-byte little-endian length prefix, a fixed 12-byte header
//! and the payload of one operation (docs/protocol.md, "Frame").

use std::ops::RangeInclusive;

use zerocopy::byteorder::little_endian::U32;
use zerocopy::{FromBytes, Immutable, IntoBytes, KnownLayout, Unaligned};

/// `"UO"`: the first two bytes of every header.
pub const MAGIC: [u8; 2] = *b"UO";
/// The protocol version this crate speaks.
pub const VERSION: u8 = 1;
/// Largest frame (header + payload, without the prefix) accepted, in bytes.
pub const MAX_FRAME: usize = 64 * 1024;
/// Size of the length prefix.
pub const PREFIX_LEN: usize = 4;

/// The fixed frame header (12 bytes) after the 4-byte length prefix.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct Header {
    /// [`MAGIC`].
    pub magic: [u8; 2],
    /// [`VERSION`].
    pub version: u8,
    /// Operation code ([`Op`]); an answer repeats the request's.
    pub op: u8,
    /// Chosen by the client, echoed in the answer.
    pub request_id: U32,
    /// 0 in requests; in answers 0 = ok, else an error code.
    pub status: U32,
}

/// Size of [`Header`].
pub const HEADER_LEN: usize = std::mem::size_of::<Header>();

impl Header {
    /// A header of this version for `op`, request `id`, with `status`.
    pub fn new(op: u8, id: u32, status: u32) -> Self {
        Self {
            magic: MAGIC,
            version: VERSION,
            op,
            request_id: id.into(),
            status: status.into(),
        }
    }
}

/// Operation codes a bus's request layer may define for itself: their
/// payload travels opaque through this layer.
pub const EXT_OPS: RangeInclusive<u8> = 0x10..=0x7F;

/// An operation of the object layer, or one of a bus's own.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Op {
    /// `0x01`: read an object.
    Read,
    /// `0x02`: write an object.
    Write,
    /// `0x03`: present the access token (docs/protocol.md, "HELLO"); taken
    /// by the connection itself, never handed to the bus.
    Hello,
    /// A code in [`EXT_OPS`], defined by the request layer above.
    Ext(u8),
}

impl Op {
    /// The op for a code: `None` outside READ, WRITE and [`EXT_OPS`].
    pub fn from_code(code: u8) -> Option<Self> {
        match code {
            0x01 => Some(Op::Read),
            0x02 => Some(Op::Write),
            0x03 => Some(Op::Hello),
            c if EXT_OPS.contains(&c) => Some(Op::Ext(c)),
            _ => None,
        }
    }

    /// The code carried in the header.
    pub const fn code(self) -> u8 {
        match self {
            Op::Read => 0x01,
            Op::Write => 0x02,
            Op::Hello => 0x03,
            Op::Ext(c) => c,
        }
    }
}

crate::code_enum! {
    /// Errors of the protocol itself: answer status codes outside CiA 301
    /// (docs/protocol.md, "Status codes").
    pub enum ProtocolError {
        /// The header's version is not [`VERSION`].
        UnsupportedVersion = 0xE000_0001 => "unsupported protocol version",
        /// The op code is unknown.
        UnknownOp = 0xE000_0002 => "unknown operation",
        /// The payload does not fit the op (length or content), or a
        /// reserved field (a request's status, padding) is not zero.
        BadPayload = 0xE000_0003 => "malformed payload",
        /// The header does not start with [`MAGIC`].
        BadMagic = 0xE000_0004 => "bad magic",
        /// The length prefix exceeds [`MAX_FRAME`]; the connection is closed.
        FrameTooLarge = 0xE000_0005 => "frame too large",
        /// The length prefix is smaller than a header.
        FrameTooShort = 0xE000_0006 => "frame too short",
        /// The server has no room for another connection (or its address
        /// opens new ones too fast); it is closed. Id 0, op 0.
        Busy = 0xE000_0007 => "server busy",
        /// The connection must present the access token in a HELLO
        /// frame first, or the token it presented is wrong; it is closed.
        Unauthorized = 0xE000_0008 => "access token missing or wrong",
        /// The request was stopped before its end: the server is
        /// shutting down (or closed the connection). What the request did
        /// up to there stays done; answered with the request's op and id,
        /// then the connection is closed.
        Stopped = 0xE000_0009 => "request stopped: the server is shutting down",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_is_twelve_bytes() {
        assert_eq!(HEADER_LEN, 12);
    }

    #[test]
    fn ops_round_trip_and_unknown_codes_are_refused() {
        for c in 0..=u8::MAX {
            match Op::from_code(c) {
                Some(op) => assert_eq!(op.code(), c),
                None => assert!(c == 0 || (0x04..0x10).contains(&c) || c >= 0x80),
            }
        }
    }

    #[test]
    fn protocol_codes_round_trip() {
        for &e in ProtocolError::ALL {
            assert_eq!(ProtocolError::from_code(e.code()), Some(e));
        }
        assert_eq!(ProtocolError::Busy.code(), 0xE000_0007);
    }
}
