//! `WRITE_IF` (extension op `0x24`): a write carried out only while the
//! server is still the one, and in the Clean epoch, the writer expects
//! (docs/protocol.md, "WRITE_IF"). The host library sends every write
//! through a handle this way, so that the check and the write are one
//! step on the server: a write through a handle issued before a Clean is
//! carried out before the Clean or not at all, never after it; and a
//! handle issued by a server that has since restarted stays void.
//!
//! The request is the server identity and Clean count the writer expects
//! (from `INFO`), then an ordinary WRITE's payload. The answer of a write
//! carried out is the WRITE's (empty, or its access error); a write not
//! carried out because the server or its Clean count differ is answered
//! with the current `INFO` answer (so the writer learns both at once).

use bytes::{Bytes, BytesMut};
use uoi::wire::{
    decode_request, encode_request, Answer, Header, Op, ProtocolError, Request as WireRequest,
    HEADER_LEN, PREFIX_LEN,
};
use uoi::{ObjectAddress, Value};

use crate::info_op::EmulatorInfo;

/// The op code of `WRITE_IF` (in `uoi::wire::EXT_OPS`, beside `INFO`).
pub const WRITE_IF_OP: u8 = 0x24;

/// Bytes of a WRITE's payload (address and value).
const WRITE_LEN: usize = 20;

/// Bytes of a `WRITE_IF` payload: identity, Clean count, the write.
pub const WRITE_IF_LEN: usize = 16 + WRITE_LEN;

/// A write that expects a server and a Clean epoch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GuardedWrite {
    /// The identity of the server the handle was issued by
    /// ([`EmulatorInfo::server`]).
    pub server: u64,
    /// The Clean count the handle was issued in.
    pub cleans: u64,
    /// The object.
    pub addr: ObjectAddress,
    /// The value.
    pub value: Value,
}

/// What the server made of a `WRITE_IF`, as the writer reads its answer.
#[derive(Debug, Clone, PartialEq)]
pub enum GuardedOutcome {
    /// Carried out: the WRITE's answer (`Ok` or an access error).
    Written(Answer),
    /// Not carried out: the server or its Clean count is not the one
    /// expected; what `INFO` answers now.
    Voided(EmulatorInfo),
}

impl GuardedWrite {
    /// The wire request.
    pub fn to_wire(&self) -> WireRequest {
        let mut frame = BytesMut::new();
        encode_request(0, &WireRequest::Write(self.addr, self.value), &mut frame);
        let write = &frame[PREFIX_LEN + HEADER_LEN..];
        let mut out = Vec::with_capacity(WRITE_IF_LEN);
        out.extend_from_slice(&self.server.to_le_bytes());
        out.extend_from_slice(&self.cleans.to_le_bytes());
        out.extend_from_slice(write);
        WireRequest::Ext(WRITE_IF_OP, Bytes::from(out))
    }

    /// The guarded write `req` carries: `None` when it is not a
    /// `WRITE_IF`, `BadPayload` when its payload is not one.
    pub fn from_wire(req: &WireRequest) -> Option<Result<Self, ProtocolError>> {
        let WireRequest::Ext(WRITE_IF_OP, p) = req else {
            return None;
        };
        Some(Self::decode(p).ok_or(ProtocolError::BadPayload))
    }

    fn decode(p: &[u8]) -> Option<Self> {
        if p.len() != WRITE_IF_LEN {
            return None;
        }
        let word = |k: usize| -> Option<u64> {
            let w: [u8; 8] = p.get(8 * k..8 * k + 8)?.try_into().ok()?;
            Some(u64::from_le_bytes(w))
        };
        let mut body = Vec::with_capacity(HEADER_LEN + WRITE_LEN);
        body.extend_from_slice(zerocopy_header(Op::Write.code()).as_slice());
        body.extend_from_slice(&p[16..]);
        let (_, inner) = decode_request(Bytes::from(body)).ok()?;
        let WireRequest::Write(addr, value) = inner else {
            return None;
        };
        Some(Self {
            server: word(0)?,
            cleans: word(1)?,
            addr,
            value,
        })
    }

    /// The plain WRITE it carries out.
    pub fn write(&self) -> WireRequest {
        WireRequest::Write(self.addr, self.value)
    }

    /// Whether it may be carried out on the server `now` describes.
    pub fn expected(&self, now: &EmulatorInfo) -> bool {
        self.server == now.server && self.cleans == now.cleans
    }
}

/// The 12 header bytes of a request of op `op` (id 0, status 0).
fn zerocopy_header(op: u8) -> Vec<u8> {
    let mut frame = BytesMut::new();
    uoi::wire::encode_frame(&mut frame, Header::new(op, 0, 0), &[]);
    frame[PREFIX_LEN..].to_vec()
}

impl GuardedOutcome {
    /// The writer's reading of the answer to a `WRITE_IF`; `None`: not an
    /// answer of its shape.
    pub fn from_wire(ans: &Answer) -> Option<Self> {
        match ans {
            Answer::Ext(p) if p.is_empty() => Some(Self::Written(Answer::Ok)),
            Answer::Ok => Some(Self::Written(Answer::Ok)),
            Answer::Access(_) | Answer::Protocol(_) => Some(Self::Written(ans.clone())),
            Answer::Ext(_) => EmulatorInfo::from_wire(ans).map(Self::Voided),
            Answer::Value(_) => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_guarded_write_reads_back_and_a_bad_payload_is_refused() {
        let w = GuardedWrite {
            server: 0xDEAD_BEEF_0000_0001,
            cleans: 7,
            addr: tc_objects::TcObject::WkzIndex.of(1),
            value: Value::F64(2.5),
        };
        let req = w.to_wire();
        assert_eq!(GuardedWrite::from_wire(&req), Some(Ok(w)));
        assert_eq!(w.write(), WireRequest::Write(w.addr, w.value));
        let short = WireRequest::Ext(WRITE_IF_OP, Bytes::from_static(&[0; 35]));
        assert_eq!(
            GuardedWrite::from_wire(&short),
            Some(Err(ProtocolError::BadPayload))
        );
        let mut bad_type = match &req {
            WireRequest::Ext(_, p) => p.to_vec(),
            _ => unreachable!(),
        };
        bad_type[16 + 8] = b'x';
        let bad = WireRequest::Ext(WRITE_IF_OP, Bytes::from(bad_type));
        assert_eq!(
            GuardedWrite::from_wire(&bad),
            Some(Err(ProtocolError::BadPayload))
        );
        assert_eq!(
            GuardedWrite::from_wire(&WireRequest::Write(w.addr, w.value)),
            None
        );
        assert!(uoi::wire::EXT_OPS.contains(&WRITE_IF_OP));
        assert!(tc_request::wire::TcOp::from_code(WRITE_IF_OP).is_none());
    }
}
