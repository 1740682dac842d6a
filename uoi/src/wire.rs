//! The binary wire protocol (docs/protocol.md): length-prefixed frames with
//! a fixed little-endian header and one payload layout per operation. Every
//! layout is declared with `zerocopy`; nothing is shuffled by hand.

use zerocopy::byteorder::little_endian::{F64, I32, U16, U32, U64};
use zerocopy::{FromBytes, Immutable, IntoBytes, KnownLayout, Unaligned};

use crate::{AccessError, ObjectAddress, Value, ValueType};

/// `"UO"`: the first two bytes of every header.
pub const MAGIC: [u8; 2] = *b"UO";
/// The protocol version this crate speaks.
pub const VERSION: u8 = 1;
/// Largest frame (header + payload) accepted, in bytes.
pub const MAX_FRAME: usize = 64 * 1024;
/// Size of the length prefix.
pub const PREFIX_LEN: usize = 4;
/// Most spool elements in one `SPOOL_LOG` answer (fits [`MAX_FRAME`]).
pub const SPOOL_BATCH: usize = 400;

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
    /// Operation ([`Op`]); an answer repeats the request's.
    pub op: u8,
    /// Chosen by the client, echoed in the answer.
    pub request_id: U32,
    /// 0 in requests; in answers 0 = ok, else an error code.
    pub status: U32,
}

/// Size of [`Header`].
pub const HEADER_LEN: usize = std::mem::size_of::<Header>();

// A full SPOOL_LOG answer must fit one frame.
const _: () = assert!(
    HEADER_LEN
        + std::mem::size_of::<SpoolLogAns>()
        + SPOOL_BATCH * std::mem::size_of::<WireElement>()
        <= MAX_FRAME
);

/// An object address (8 bytes).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct WireAddr {
    /// BusNumber.
    pub bus: U16,
    /// DeviceNumber.
    pub device: U16,
    /// Index.
    pub index: U16,
    /// SubIndex.
    pub sub: U16,
}

/// `READ` request payload (12 bytes).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct ReadReq {
    /// The object.
    pub addr: WireAddr,
    /// Type asked for: `b'i'` or `b'd'`.
    pub ty: u8,
    /// Zero.
    pub pad: [u8; 3],
}

/// A value (12 bytes): type letter and 64 bits (an `i` value sign-extended,
/// a `d` value as IEEE bits).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct WireValue {
    /// `b'i'` or `b'd'`.
    pub ty: u8,
    /// Zero.
    pub pad: [u8; 3],
    /// The value's bits.
    pub bits: U64,
}

/// `WRITE` request payload (20 bytes).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct WriteReq {
    /// The object.
    pub addr: WireAddr,
    /// The value.
    pub value: WireValue,
}

/// `MOTION` request payload (108 bytes).
#[derive(
    Debug, Clone, Copy, PartialEq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct MotionReq {
    /// [`MotionKind`] code.
    pub kind: u8,
    /// 1 = CCW, 0 = CW (CIR only).
    pub ccw: u8,
    /// Axis of `SSF`.
    pub axis: u8,
    /// Zero.
    pub pad: u8,
    /// Bit k set: `words[k]` is given (0..7 axes X..V, 8..10 I J K, 11 F).
    /// For `JS`: the axes to stop.
    pub present: U16,
    /// Zero.
    pub pad2: [u8; 2],
    /// Function number of `SSF`.
    pub function: I32,
    /// Axis words, I J K, F.
    pub words: [F64; 12],
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
    pub pos: [F64; 8],
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

/// `SETUP` request payload: a fresh emulator at `start` with cycle `cycle_s`.
#[derive(
    Debug, Clone, Copy, PartialEq, FromBytes, IntoBytes, KnownLayout, Immutable, Unaligned,
)]
#[repr(C)]
pub struct SetupReq {
    /// Initial machine position.
    pub start: [F64; 8],
    /// Interpolation cycle in seconds.
    pub cycle_s: F64,
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

/// One spooled element (152 bytes).
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
    /// 0 plain, 1 approach, 2 corrected, 3 transition.
    pub origin: u8,
    /// Zero.
    pub pad: u8,
    /// Start position.
    pub start: [F64; 8],
    /// End position.
    pub end: [F64; 8],
    /// Arc centre in its plane.
    pub centre: [F64; 2],
    /// Feed, units/min.
    pub feed: F64,
}

/// Operation codes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum Op {
    /// Read an object.
    Read = 0x01,
    /// Write an object.
    Write = 0x02,
    /// A motion command (`LIN`, `RAP`, `CIR`, `JA`, `JS`, `SSF`, `RS`).
    Motion = 0x10,
    /// Run the executor.
    Exec = 0x20,
    /// Executed position.
    Pos = 0x21,
    /// Spooler length.
    Queue = 0x22,
    /// Replace the emulator by a fresh one (conformance replay).
    Setup = 0x30,
    /// Take logged spool elements (conformance replay).
    SpoolLog = 0x31,
}

impl Op {
    /// The op for a code.
    pub fn from_code(c: u8) -> Option<Self> {
        Some(match c {
            0x01 => Op::Read,
            0x02 => Op::Write,
            0x10 => Op::Motion,
            0x20 => Op::Exec,
            0x21 => Op::Pos,
            0x22 => Op::Queue,
            0x30 => Op::Setup,
            0x31 => Op::SpoolLog,
            _ => return None,
        })
    }
}

/// Errors of the protocol itself (answer status codes outside CiA 301).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
pub enum ProtocolError {
    /// The header's version is not [`VERSION`].
    #[error("unsupported protocol version")]
    UnsupportedVersion,
    /// The op code is unknown.
    #[error("unknown operation")]
    UnknownOp,
    /// The payload does not fit the op (length or content).
    #[error("malformed payload")]
    BadPayload,
    /// The header does not start with [`MAGIC`].
    #[error("bad magic")]
    BadMagic,
    /// The length prefix exceeds [`MAX_FRAME`]; the connection is closed.
    #[error("frame too large")]
    FrameTooLarge,
    /// The length prefix is smaller than a header.
    #[error("frame too short")]
    FrameTooShort,
    /// The server has no room for another connection; it is closed.
    #[error("server busy")]
    Busy,
}

impl ProtocolError {
    /// Every protocol error.
    pub const ALL: [ProtocolError; 7] = [
        ProtocolError::UnsupportedVersion,
        ProtocolError::UnknownOp,
        ProtocolError::BadPayload,
        ProtocolError::BadMagic,
        ProtocolError::FrameTooLarge,
        ProtocolError::FrameTooShort,
        ProtocolError::Busy,
    ];

    /// The status code.
    pub const fn code(self) -> u32 {
        match self {
            ProtocolError::UnsupportedVersion => 0xE000_0001,
            ProtocolError::UnknownOp => 0xE000_0002,
            ProtocolError::BadPayload => 0xE000_0003,
            ProtocolError::BadMagic => 0xE000_0004,
            ProtocolError::FrameTooLarge => 0xE000_0005,
            ProtocolError::FrameTooShort => 0xE000_0006,
            ProtocolError::Busy => 0xE000_0007,
        }
    }

    /// The error with this code.
    pub fn from_code(code: u32) -> Option<Self> {
        Self::ALL.into_iter().find(|e| e.code() == code)
    }
}

/// What a motion request asks, mirrored from `tc-module`'s commands
/// without depending on them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum MotionKind {
    /// `LIN`.
    Lin = 1,
    /// `RAP`.
    Rap = 2,
    /// `CIR`.
    Cir = 3,
    /// `JA`.
    Ja = 4,
    /// `JS`.
    Js = 5,
    /// `SSF`.
    Ssf = 6,
    /// `RS`.
    Rs = 7,
}

impl MotionKind {
    fn from_code(c: u8) -> Option<Self> {
        Some(match c {
            1 => MotionKind::Lin,
            2 => MotionKind::Rap,
            3 => MotionKind::Cir,
            4 => MotionKind::Ja,
            5 => MotionKind::Js,
            6 => MotionKind::Ssf,
            7 => MotionKind::Rs,
            _ => return None,
        })
    }
}

/// A motion request.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WireMotion {
    /// What.
    pub kind: MotionKind,
    /// Arc direction (CIR).
    pub ccw: bool,
    /// Axis words X..V; for JS `Some(_)` marks an axis to stop.
    pub words: [Option<f64>; 8],
    /// I J K (CIR).
    pub centre: [Option<f64>; 3],
    /// F.
    pub feed: Option<f64>,
    /// SSF axis.
    pub axis: u8,
    /// SSF function.
    pub function: i32,
}

/// A spooled element as carried on the wire.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Element {
    /// `None` for a line; for an arc its plane `(h, v, third)`, centre and
    /// direction.
    pub arc: Option<([u8; 3], [f64; 2], bool)>,
    /// Start position.
    pub start: [f64; 8],
    /// End position.
    pub end: [f64; 8],
    /// Feed.
    pub feed: f64,
    /// Rapid?
    pub rapid: bool,
    /// 0 plain, 1 approach, 2 corrected, 3 transition.
    pub origin: u8,
}

/// A decoded request.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Request {
    /// Read an object asking for a type.
    Read(ObjectAddress, ValueType),
    /// Write an object.
    Write(ObjectAddress, Value),
    /// A motion command.
    Motion(WireMotion),
    /// Run `Some(n)` cycles or until empty.
    Exec(Option<u64>),
    /// Executed position.
    Pos,
    /// Spooler length.
    Queue,
    /// Fresh emulator.
    Setup {
        /// Start position.
        start: [f64; 8],
        /// Cycle in seconds.
        cycle_s: f64,
    },
    /// Take logged spool elements; set logging on or off.
    SpoolLog {
        /// Logging from now on.
        logging: bool,
    },
}

impl Request {
    /// The op of this request.
    pub fn op(&self) -> Op {
        match self {
            Request::Read(..) => Op::Read,
            Request::Write(..) => Op::Write,
            Request::Motion(_) => Op::Motion,
            Request::Exec(_) => Op::Exec,
            Request::Pos => Op::Pos,
            Request::Queue => Op::Queue,
            Request::Setup { .. } => Op::Setup,
            Request::SpoolLog { .. } => Op::SpoolLog,
        }
    }
}

/// An answer.
#[derive(Debug, Clone, PartialEq)]
pub enum Answer {
    /// Done, nothing to report.
    Ok,
    /// A value read.
    Value(Value),
    /// The executed position.
    Pos([f64; 8]),
    /// The spooler length.
    Queue(u64),
    /// Logged spool elements (at most [`SPOOL_BATCH`]) and whether more wait.
    Spool(Vec<Element>, bool),
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

fn addr_to_wire(a: ObjectAddress) -> WireAddr {
    WireAddr {
        bus: a.bus.into(),
        device: a.device.into(),
        index: a.index.into(),
        sub: a.sub.into(),
    }
}

fn addr_from_wire(a: &WireAddr) -> ObjectAddress {
    ObjectAddress::new(a.bus.get(), a.device.get(), a.index.get(), a.sub.get())
}

fn value_to_wire(v: Value) -> WireValue {
    let (ty, bits) = match v {
        Value::I32(i) => (b'i', i64::from(i) as u64),
        Value::F64(d) => (b'd', d.to_bits()),
    };
    WireValue {
        ty,
        pad: [0; 3],
        bits: bits.into(),
    }
}

fn type_from_wire(t: u8) -> Option<ValueType> {
    match t {
        b'i' => Some(ValueType::I32),
        b'd' => Some(ValueType::F64),
        _ => None,
    }
}

fn value_from_wire(v: &WireValue) -> Option<Value> {
    let bits = v.bits.get();
    match type_from_wire(v.ty)? {
        ValueType::I32 => i32::try_from(bits as i64).ok().map(Value::I32),
        ValueType::F64 => Some(Value::F64(f64::from_bits(bits))),
    }
}

/// Reads a payload of exactly `T`'s size.
fn exact<T: FromBytes + KnownLayout + Immutable + Unaligned>(
    payload: &[u8],
) -> Result<&T, ProtocolError> {
    T::ref_from_bytes(payload).map_err(|_| ProtocolError::BadPayload)
}

/// Decodes the frame body (header + payload, without the length prefix).
/// On error, the header's request id and op (when readable) are returned
/// so the answer can echo them.
pub fn decode_request(frame: &[u8]) -> Result<(u32, Request), (u32, u8, ProtocolError)> {
    let Ok((h, payload)) = Header::ref_from_prefix(frame) else {
        return Err((0, 0, ProtocolError::FrameTooShort));
    };
    let id = h.request_id.get();
    let fail = |e| Err((id, h.op, e));
    if h.magic != MAGIC {
        return fail(ProtocolError::BadMagic);
    }
    if h.version != VERSION {
        return fail(ProtocolError::UnsupportedVersion);
    }
    let Some(op) = Op::from_code(h.op) else {
        return fail(ProtocolError::UnknownOp);
    };
    let req = match decode_payload(op, payload) {
        Ok(r) => r,
        Err(e) => return fail(e),
    };
    Ok((id, req))
}

fn decode_payload(op: Op, payload: &[u8]) -> Result<Request, ProtocolError> {
    let bad = ProtocolError::BadPayload;
    Ok(match op {
        Op::Read => {
            let r: &ReadReq = exact(payload)?;
            Request::Read(addr_from_wire(&r.addr), type_from_wire(r.ty).ok_or(bad)?)
        }
        Op::Write => {
            let w: &WriteReq = exact(payload)?;
            Request::Write(
                addr_from_wire(&w.addr),
                value_from_wire(&w.value).ok_or(bad)?,
            )
        }
        Op::Motion => {
            let m: &MotionReq = exact(payload)?;
            let kind = MotionKind::from_code(m.kind).ok_or(bad)?;
            let present = m.present.get();
            let word = |k: usize| (present & (1 << k) != 0).then(|| m.words[k].get());
            Request::Motion(WireMotion {
                kind,
                ccw: m.ccw == 1,
                words: std::array::from_fn(word),
                centre: [word(8), word(9), word(10)],
                feed: word(11),
                axis: m.axis,
                function: m.function.get(),
            })
        }
        Op::Exec => {
            let e: &ExecReq = exact(payload)?;
            let n = e.cycles.get();
            Request::Exec((n != u64::MAX).then_some(n))
        }
        Op::Pos if payload.is_empty() => Request::Pos,
        Op::Queue if payload.is_empty() => Request::Queue,
        Op::Pos | Op::Queue => return Err(bad),
        Op::Setup => {
            let s: &SetupReq = exact(payload)?;
            Request::Setup {
                start: s.start.map(|v| v.get()),
                cycle_s: s.cycle_s.get(),
            }
        }
        Op::SpoolLog => {
            let s: &SpoolLogReq = exact(payload)?;
            Request::SpoolLog {
                logging: s.logging == 1,
            }
        }
    })
}

/// Appends a whole request frame (prefix, header, payload) to `out`.
pub fn encode_request(id: u32, req: &Request, out: &mut Vec<u8>) {
    let start = begin_frame(out, req.op() as u8, id, 0);
    match *req {
        Request::Read(a, ty) => out.extend_from_slice(
            ReadReq {
                addr: addr_to_wire(a),
                ty: ty.letter() as u8,
                pad: [0; 3],
            }
            .as_bytes(),
        ),
        Request::Write(a, v) => out.extend_from_slice(
            WriteReq {
                addr: addr_to_wire(a),
                value: value_to_wire(v),
            }
            .as_bytes(),
        ),
        Request::Motion(m) => {
            let mut words = [F64::new(0.0); 12];
            let mut present = 0u16;
            let all = m
                .words
                .iter()
                .chain(&m.centre)
                .chain(std::iter::once(&m.feed));
            for (k, w) in all.enumerate() {
                if let Some(v) = *w {
                    present |= 1 << k;
                    words[k] = F64::new(v);
                }
            }
            out.extend_from_slice(
                MotionReq {
                    kind: m.kind as u8,
                    ccw: u8::from(m.ccw),
                    axis: m.axis,
                    pad: 0,
                    present: present.into(),
                    pad2: [0; 2],
                    function: m.function.into(),
                    words,
                }
                .as_bytes(),
            );
        }
        Request::Exec(n) => out.extend_from_slice(
            ExecReq {
                cycles: n.unwrap_or(u64::MAX).into(),
            }
            .as_bytes(),
        ),
        Request::Pos | Request::Queue => {}
        Request::Setup { start: s, cycle_s } => out.extend_from_slice(
            SetupReq {
                start: s.map(F64::new),
                cycle_s: cycle_s.into(),
            }
            .as_bytes(),
        ),
        Request::SpoolLog { logging } => out.extend_from_slice(
            SpoolLogReq {
                logging: u8::from(logging),
                pad: [0; 3],
            }
            .as_bytes(),
        ),
    }
    end_frame(out, start);
}

fn begin_frame(out: &mut Vec<u8>, op: u8, id: u32, status: u32) -> usize {
    let start = out.len();
    out.extend_from_slice(&[0; PREFIX_LEN]);
    out.extend_from_slice(
        Header {
            magic: MAGIC,
            version: VERSION,
            op,
            request_id: id.into(),
            status: status.into(),
        }
        .as_bytes(),
    );
    start
}

fn end_frame(out: &mut [u8], start: usize) {
    let len = (out.len() - start - PREFIX_LEN) as u32;
    out[start..start + PREFIX_LEN].copy_from_slice(&len.to_le_bytes());
}

/// Appends a whole answer frame for request `id` of op `op` to `out`.
pub fn encode_answer(id: u32, op: u8, ans: &Answer, out: &mut Vec<u8>) {
    let start = begin_frame(out, op, id, ans.status());
    match ans {
        Answer::Value(v) => out.extend_from_slice(value_to_wire(*v).as_bytes()),
        Answer::Pos(p) => out.extend_from_slice(
            PosAns {
                pos: p.map(F64::new),
            }
            .as_bytes(),
        ),
        Answer::Queue(n) => out.extend_from_slice(QueueAns { count: (*n).into() }.as_bytes()),
        Answer::Spool(els, more) => {
            let n = els.len().min(SPOOL_BATCH);
            out.extend_from_slice(
                SpoolLogAns {
                    count: (n as u16).into(),
                    more: u8::from(*more || els.len() > n),
                    pad: 0,
                }
                .as_bytes(),
            );
            for e in &els[..n] {
                let (plane, centre, ccw) = e.arc.unwrap_or(([0; 3], [0.0; 2], false));
                out.extend_from_slice(
                    WireElement {
                        kind: if e.arc.is_some() { 2 } else { 1 },
                        ccw: u8::from(ccw),
                        plane_h: plane[0],
                        plane_v: plane[1],
                        plane_third: plane[2],
                        rapid: u8::from(e.rapid),
                        origin: e.origin,
                        pad: 0,
                        start: e.start.map(F64::new),
                        end: e.end.map(F64::new),
                        centre: centre.map(F64::new),
                        feed: e.feed.into(),
                    }
                    .as_bytes(),
                );
            }
        }
        Answer::Ok | Answer::Access(_) | Answer::Protocol(_) => {}
    }
    end_frame(out, start);
}

/// Decodes an answer frame body (header + payload) for a request of op
/// `op`. Returns the request id and the answer; `None` when the frame
/// cannot be an answer to that op.
pub fn decode_answer(frame: &[u8], op: Op) -> Option<(u32, Answer)> {
    let (h, payload) = Header::ref_from_prefix(frame).ok()?;
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
        Op::Read => Answer::Value(value_from_wire(WireValue::ref_from_bytes(payload).ok()?)?),
        Op::Pos => Answer::Pos(PosAns::ref_from_bytes(payload).ok()?.pos.map(|v| v.get())),
        Op::Queue => Answer::Queue(QueueAns::ref_from_bytes(payload).ok()?.count.get()),
        Op::SpoolLog => {
            let (head, rest) = SpoolLogAns::ref_from_prefix(payload).ok()?;
            let els = <[WireElement]>::ref_from_bytes(rest).ok()?;
            if els.len() != usize::from(head.count.get()) {
                return None;
            }
            let list = els
                .iter()
                .map(|e| Element {
                    arc: (e.kind == 2).then(|| {
                        (
                            [e.plane_h, e.plane_v, e.plane_third],
                            e.centre.map(|v| v.get()),
                            e.ccw == 1,
                        )
                    }),
                    start: e.start.map(|v| v.get()),
                    end: e.end.map(|v| v.get()),
                    feed: e.feed.get(),
                    rapid: e.rapid == 1,
                    origin: e.origin,
                })
                .collect();
            Answer::Spool(list, head.more == 1)
        }
        Op::Write | Op::Motion | Op::Exec | Op::Setup if payload.is_empty() => Answer::Ok,
        _ => return None,
    };
    Some((id, ans))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip(req: Request) {
        let mut buf = Vec::new();
        encode_request(7, &req, &mut buf);
        let len = u32::from_le_bytes([buf[0], buf[1], buf[2], buf[3]]) as usize;
        assert_eq!(len, buf.len() - PREFIX_LEN);
        assert_eq!(decode_request(&buf[PREFIX_LEN..]), Ok((7, req)));
    }

    #[test]
    fn layouts_have_documented_sizes() {
        assert_eq!(HEADER_LEN, 12);
        assert_eq!(std::mem::size_of::<ReadReq>(), 12);
        assert_eq!(std::mem::size_of::<WriteReq>(), 20);
        assert_eq!(std::mem::size_of::<MotionReq>(), 108);
        assert_eq!(std::mem::size_of::<SetupReq>(), 72);
        assert_eq!(std::mem::size_of::<WireElement>(), 160);
    }

    #[test]
    fn requests_round_trip() {
        let a = ObjectAddress::new(1300, 1, 2, 8);
        round_trip(Request::Read(a, ValueType::I32));
        round_trip(Request::Write(a, Value::I32(-5)));
        round_trip(Request::Write(a, Value::F64(2.5)));
        let mut words = [None; 8];
        words[0] = Some(10.0);
        words[7] = Some(-1.0);
        round_trip(Request::Motion(WireMotion {
            kind: MotionKind::Cir,
            ccw: true,
            words,
            centre: [Some(1.0), None, Some(3.0)],
            feed: Some(600.0),
            axis: 0,
            function: 0,
        }));
        round_trip(Request::Exec(Some(25)));
        round_trip(Request::Exec(None));
        round_trip(Request::Pos);
        round_trip(Request::Queue);
        round_trip(Request::Setup {
            start: [1.0; 8],
            cycle_s: 1e-3,
        });
        round_trip(Request::SpoolLog { logging: true });
    }

    #[test]
    fn answers_round_trip() {
        let cases = [
            (Op::Read, Answer::Value(Value::I32(-7))),
            (Op::Read, Answer::Value(Value::F64(1.5))),
            (Op::Write, Answer::Ok),
            (Op::Write, Answer::Access(AccessError::Range)),
            (Op::Motion, Answer::Protocol(ProtocolError::BadPayload)),
            (
                Op::Pos,
                Answer::Pos([1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]),
            ),
            (Op::Queue, Answer::Queue(3)),
            (
                Op::SpoolLog,
                Answer::Spool(
                    vec![Element {
                        arc: Some(([0, 1, 2], [1.0, 2.0], true)),
                        start: [0.0; 8],
                        end: [1.0; 8],
                        feed: 1000.0,
                        rapid: false,
                        origin: 2,
                    }],
                    false,
                ),
            ),
        ];
        for (op, ans) in cases {
            let mut buf = Vec::new();
            encode_answer(9, op as u8, &ans, &mut buf);
            assert_eq!(decode_answer(&buf[PREFIX_LEN..], op), Some((9, ans)));
        }
    }

    #[test]
    fn protocol_errors_keep_id_and_op() {
        let mut buf = Vec::new();
        encode_request(42, &Request::Pos, &mut buf);
        let body = &mut buf[PREFIX_LEN..];
        body[2] = 9; // version
        assert_eq!(
            decode_request(body),
            Err((42, Op::Pos as u8, ProtocolError::UnsupportedVersion))
        );
        body[2] = VERSION;
        body[3] = 0x7f;
        assert_eq!(
            decode_request(body),
            Err((42, 0x7f, ProtocolError::UnknownOp))
        );
        body[0] = b'X';
        assert_eq!(
            decode_request(body).map_err(|e| e.2),
            Err(ProtocolError::BadMagic)
        );
        assert_eq!(
            decode_request(&[1, 2, 3]).map_err(|e| e.2),
            Err(ProtocolError::FrameTooShort)
        );
    }
}
