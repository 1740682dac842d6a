//! Requests and answers of the object layer, and their frames. READ and
//! WRITE are decoded here; an extension op's payload is handed on as bytes
//! for the request layer above to decode (this layer does not know what
//! the bus behind it does with it).

use bytes::{BufMut, Bytes, BytesMut};
use zerocopy::{FromBytes, Immutable, IntoBytes, KnownLayout, Unaligned};

use super::frame::{Header, Op, ProtocolError, HEADER_LEN, MAGIC, PREFIX_LEN, VERSION};
use super::layout::{type_from_wire, ReadReq, WireValue, WriteReq};
use crate::{AccessError, ObjectAddress, Value, ValueType};

/// A decoded request.
#[derive(Debug, Clone, PartialEq)]
pub enum Request {
    /// Read an object asking for a type.
    Read(ObjectAddress, ValueType),
    /// Write an object.
    Write(ObjectAddress, Value),
    /// An extension op (a code in [`super::EXT_OPS`]) with its payload.
    Ext(u8, Bytes),
    /// HELLO: the access token, as the client presents it. The server's
    /// connection answers it; a handler never sees one.
    Hello(Bytes),
}

impl Request {
    /// The op of this request.
    pub fn op(&self) -> Op {
        match self {
            Request::Read(..) => Op::Read,
            Request::Write(..) => Op::Write,
            Request::Ext(code, _) => Op::Ext(*code),
            Request::Hello(_) => Op::Hello,
        }
    }
}

/// An answer.
#[derive(Debug, Clone, PartialEq)]
pub enum Answer {
    /// Done, nothing to report (empty payload).
    Ok,
    /// A value read.
    Value(Value),
    /// The payload of an extension op's answer (status 0).
    Ext(Bytes),
    /// A UOI access error.
    Access(AccessError),
    /// A protocol error.
    Protocol(ProtocolError),
}

impl Answer {
    /// The status code carried in the header.
    pub fn status(&self) -> u32 {
        match self {
            Answer::Access(e) => e.code(),
            Answer::Protocol(e) => e.code(),
            _ => 0,
        }
    }
}

/// A frame the server could not take as a request: what it answers, with
/// the request id and op echoed where the header was readable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rejected {
    /// The request id (0 when the header was unreadable).
    pub id: u32,
    /// The op byte (0 when the header was unreadable).
    pub op: u8,
    /// Why.
    pub error: ProtocolError,
}

/// Reads a payload of exactly `T`'s size.
pub fn exact<T: FromBytes + KnownLayout + Immutable + Unaligned>(
    payload: &[u8],
) -> Result<&T, ProtocolError> {
    T::ref_from_bytes(payload).map_err(|_| ProtocolError::BadPayload)
}

/// Decodes a frame body (header + payload, without the length prefix).
/// An extension op's payload is a slice of `body` (no copy).
pub fn decode_request(body: Bytes) -> Result<(u32, Request), Rejected> {
    decode_request_with(&body, |_| body.slice(HEADER_LEN..))
}

/// Decodes a borrowed frame body (header + payload, without the length
/// prefix); `ext` makes an extension op's payload into the request's
/// [`Bytes`] (it is called only for an extension op). READ and WRITE are
/// decoded in place.
pub fn decode_request_with(
    body: &[u8],
    ext: impl FnOnce(&[u8]) -> Bytes,
) -> Result<(u32, Request), Rejected> {
    let Ok((h, payload)) = Header::ref_from_prefix(body) else {
        return Err(Rejected {
            id: 0,
            op: 0,
            error: ProtocolError::FrameTooShort,
        });
    };
    let (id, code) = (h.request_id.get(), h.op);
    let reject = |error| Rejected {
        id,
        op: code,
        error,
    };
    if h.magic != MAGIC {
        return Err(reject(ProtocolError::BadMagic));
    }
    if h.version != VERSION {
        return Err(reject(ProtocolError::UnsupportedVersion));
    }
    let op = Op::from_code(code).ok_or(reject(ProtocolError::UnknownOp))?;
    // A request's status field is reserved: zero.
    if h.status.get() != 0 {
        return Err(reject(ProtocolError::BadPayload));
    }
    let req = match op {
        Op::Read => {
            let r: &ReadReq = exact(payload).map_err(reject)?;
            let ty = type_from_wire(r.ty)
                .filter(|_| r.pad == [0; 3])
                .ok_or(reject(ProtocolError::BadPayload))?;
            Request::Read((&r.addr).into(), ty)
        }
        Op::Write => {
            let w: &WriteReq = exact(payload).map_err(reject)?;
            let v = w.value.value().ok_or(reject(ProtocolError::BadPayload))?;
            Request::Write((&w.addr).into(), v)
        }
        Op::Ext(c) => Request::Ext(c, ext(payload)),
        Op::Hello => Request::Hello(Bytes::copy_from_slice(payload)),
    };
    Ok((id, req))
}

/// Appends a whole frame (prefix, header, payload) to `out`. The codecs
/// refuse a payload that would make the body exceed `MAX_FRAME`; a frame
/// encoded here directly must keep within it too.
pub fn encode_frame(out: &mut BytesMut, header: Header, payload: &[u8]) {
    let len = HEADER_LEN + payload.len();
    // Prefix and header in one piece: one copy into `out`, not two.
    let mut head = [0u8; PREFIX_LEN + HEADER_LEN];
    // Saturating: a body over u32::MAX is over MAX_FRAME anyway, and the
    // peer refuses it.
    head[..PREFIX_LEN].copy_from_slice(&u32::try_from(len).unwrap_or(u32::MAX).to_le_bytes());
    head[PREFIX_LEN..].copy_from_slice(header.as_bytes());
    out.reserve(PREFIX_LEN + len);
    out.put_slice(&head);
    out.put_slice(payload);
}

/// Appends a whole request frame to `out`.
pub fn encode_request(id: u32, req: &Request, out: &mut BytesMut) {
    let header = Header::new(req.op().code(), id, 0);
    match req {
        Request::Read(a, ty) => {
            let r = ReadReq {
                addr: (*a).into(),
                ty: ty.letter() as u8,
                pad: [0; 3],
            };
            encode_frame(out, header, r.as_bytes());
        }
        Request::Write(a, v) => {
            let w = WriteReq {
                addr: (*a).into(),
                value: (*v).into(),
            };
            encode_frame(out, header, w.as_bytes());
        }
        Request::Ext(_, payload) | Request::Hello(payload) => encode_frame(out, header, payload),
    }
}

/// Appends a whole answer frame for request `id` of op code `op` to `out`.
/// An answer with a non-zero status has an empty payload.
pub fn encode_answer(id: u32, op: u8, ans: &Answer, out: &mut BytesMut) {
    let header = Header::new(op, id, ans.status());
    match ans {
        Answer::Value(v) => encode_frame(out, header, WireValue::from(*v).as_bytes()),
        Answer::Ext(payload) => encode_frame(out, header, payload),
        Answer::Ok | Answer::Access(_) | Answer::Protocol(_) => encode_frame(out, header, &[]),
    }
}

/// Decodes an answer frame body (header + payload) to a request of op
/// `op`. Returns the request id and the answer; `None` when the frame
/// cannot be an answer to that op.
pub fn decode_answer(body: Bytes, op: Op) -> Option<(u32, Answer)> {
    let (h, payload) = Header::ref_from_prefix(&body).ok()?;
    if h.magic != MAGIC || h.version != VERSION {
        return None;
    }
    let id = h.request_id.get();
    let status = h.status.get();
    if status != 0 {
        let ans = AccessError::from_code(status)
            .map(Answer::Access)
            .or_else(|| ProtocolError::from_code(status).map(Answer::Protocol))?;
        return Some((id, ans));
    }
    let ans = match op {
        Op::Read => Answer::Value(WireValue::ref_from_bytes(payload).ok()?.value()?),
        Op::Write | Op::Hello if payload.is_empty() => Answer::Ok,
        Op::Write | Op::Hello => return None,
        Op::Ext(_) => Answer::Ext(body.slice(HEADER_LEN..)),
    };
    Some((id, ans))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bus of the example: the wire carries any bus number (bus 1300's
    /// objects are named in tc-objects, which this layer does not know;
    /// docs/decisions.md, decision 521).
    const EXAMPLE_BUS: u16 = 7;

    fn body(frame: &BytesMut) -> Bytes {
        let len = u32::from_le_bytes([frame[0], frame[1], frame[2], frame[3]]) as usize;
        assert_eq!(len, frame.len() - PREFIX_LEN);
        Bytes::copy_from_slice(&frame[PREFIX_LEN..])
    }

    #[test]
    fn requests_round_trip() {
        let a = ObjectAddress::new(EXAMPLE_BUS, 1, 2, 8);
        for req in [
            Request::Read(a, ValueType::I32),
            Request::Write(a, Value::I32(-5)),
            Request::Write(a, Value::F64(2.5)),
            Request::Ext(0x10, Bytes::from_static(&[1, 2, 3])),
            Request::Ext(0x21, Bytes::new()),
            Request::Hello(Bytes::from_static(b"0123456789abcdef")),
        ] {
            let mut out = BytesMut::new();
            encode_request(7, &req, &mut out);
            assert_eq!(decode_request(body(&out)), Ok((7, req)));
        }
    }

    #[test]
    fn answers_round_trip() {
        for (op, ans) in [
            (Op::Read, Answer::Value(Value::I32(-7))),
            (Op::Read, Answer::Value(Value::F64(1.5))),
            (Op::Write, Answer::Ok),
            (Op::Write, Answer::Access(AccessError::Range)),
            (Op::Hello, Answer::Ok),
            (Op::Hello, Answer::Protocol(ProtocolError::Unauthorized)),
            (Op::Ext(0x10), Answer::Protocol(ProtocolError::BadPayload)),
            (Op::Ext(0x21), Answer::Ext(Bytes::from_static(&[9; 64]))),
        ] {
            let mut out = BytesMut::new();
            encode_answer(9, op.code(), &ans, &mut out);
            assert_eq!(decode_answer(body(&out), op), Some((9, ans)));
        }
    }

    /// The body of request `req` as id 3, with byte `at` (counted from the
    /// start of the header) set to `v`, and what the server makes of it.
    fn with_byte(req: &Request, at: usize, v: u8) -> Result<(u32, Request), Rejected> {
        let mut out = BytesMut::new();
        encode_request(3, req, &mut out);
        let mut b = BytesMut::from(&out[PREFIX_LEN..]);
        b[at] = v;
        decode_request(b.freeze())
    }

    fn bad_payload(op: Op) -> Result<(u32, Request), Rejected> {
        Err(Rejected {
            id: 3,
            op: op.code(),
            error: ProtocolError::BadPayload,
        })
    }

    #[test]
    fn a_request_with_a_non_zero_status_is_refused() {
        let read = Request::Read(ObjectAddress::new(EXAMPLE_BUS, 0, 3, 0), ValueType::I32);
        for at in 8..12 {
            assert_eq!(with_byte(&read, at, 1), bad_payload(Op::Read), "byte {at}");
        }
        let ext = Request::Ext(0x21, Bytes::new());
        assert_eq!(with_byte(&ext, 11, 0x80), bad_payload(Op::Ext(0x21)));
    }

    #[test]
    fn read_padding_must_be_zero() {
        let read = Request::Read(ObjectAddress::new(EXAMPLE_BUS, 0, 3, 0), ValueType::I32);
        // ReadReq: address 8 bytes, type, then 3 bytes of padding.
        for at in HEADER_LEN + 9..HEADER_LEN + 12 {
            assert_eq!(with_byte(&read, at, 1), bad_payload(Op::Read), "byte {at}");
        }
    }

    #[test]
    fn value_padding_must_be_zero() {
        let write = Request::Write(ObjectAddress::new(EXAMPLE_BUS, 1, 1, 6), Value::F64(2.5));
        // WriteReq: address 8 bytes, type, then 3 bytes of padding.
        for at in HEADER_LEN + 9..HEADER_LEN + 12 {
            assert_eq!(
                with_byte(&write, at, 0xff),
                bad_payload(Op::Write),
                "byte {at}"
            );
        }
    }

    #[test]
    fn protocol_errors_keep_id_and_op() {
        let mut out = BytesMut::new();
        encode_request(42, &Request::Ext(0x21, Bytes::new()), &mut out);
        let mut b = BytesMut::from(&out[PREFIX_LEN..]);
        let reject = |b: &BytesMut| decode_request(Bytes::copy_from_slice(b));
        b[2] = 9; // version
        assert_eq!(
            reject(&b),
            Err(Rejected {
                id: 42,
                op: 0x21,
                error: ProtocolError::UnsupportedVersion
            })
        );
        b[2] = VERSION;
        b[3] = 0x04;
        assert_eq!(
            reject(&b).map_err(|r| r.error),
            Err(ProtocolError::UnknownOp)
        );
        b[3] = 0x01;
        assert_eq!(
            reject(&b).map_err(|r| r.error),
            Err(ProtocolError::BadPayload)
        );
        b[0] = b'X';
        assert_eq!(
            reject(&b).map_err(|r| r.error),
            Err(ProtocolError::BadMagic)
        );
        assert_eq!(
            decode_request(Bytes::from_static(&[1, 2, 3])).map_err(|r| r.error),
            Err(ProtocolError::FrameTooShort)
        );
    }
}
