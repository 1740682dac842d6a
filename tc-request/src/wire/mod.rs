//! The TC requests on the UOI wire: READ and WRITE are the object layer's
//! own ops; every other request is an extension op whose payload is laid
//! out here (docs/protocol.md, "Operations").

mod element;
pub mod layout;
mod motion;

use bytes::{BufMut, Bytes, BytesMut};
use uoi::wire::{exact, Answer, Op, ProtocolError, Request as WireRequest};
use zerocopy::{FromBytes, IntoBytes};

pub use layout::SPOOL_BATCH;
use layout::{
    ExecReq, FeedAdaptReq, PosAns, QueueAns, SetupReq, SpoolLogAns, SpoolLogReq, WireElement,
};

use crate::request::{Reply, Request, MAX_EXEC_CYCLES};

uoi::code_list! {
    /// The extension ops of the TC side (codes in `uoi::wire::EXT_OPS`).
    pub enum TcOp: u8 {
        /// A motion command.
        Motion = 0x10,
        /// Run the executor.
        Exec = 0x20,
        /// Executed position.
        Pos = 0x21,
        /// Spooler length.
        Queue = 0x22,
        /// Feed adaptation of corrected arcs (NC G10/G11).
        FeedAdapt = 0x12,
        /// A fresh emulator (conformance replay).
        Setup = 0x30,
        /// Take logged spool elements (conformance replay).
        SpoolLog = 0x31,
    }
}

fn ext(op: TcOp, payload: &[u8]) -> WireRequest {
    WireRequest::Ext(op.code(), Bytes::copy_from_slice(payload))
}

impl Request {
    /// The wire form of this request.
    pub fn to_wire(&self) -> WireRequest {
        match self {
            Request::Read(a, ty) => WireRequest::Read(*a, *ty),
            Request::Write(a, v) => WireRequest::Write(*a, *v),
            Request::Motion(m) => ext(TcOp::Motion, motion::encode(m).as_bytes()),
            Request::Exec(n) => {
                // u64::MAX stands for "until empty": a count saturates below it.
                let cycles = n.map_or(u64::MAX, |n| n.min(MAX_EXEC_CYCLES));
                let e = ExecReq {
                    cycles: cycles.into(),
                };
                ext(TcOp::Exec, e.as_bytes())
            }
            Request::Pos => ext(TcOp::Pos, &[]),
            Request::Queue => ext(TcOp::Queue, &[]),
            Request::FeedAdaption { on, rmin } => {
                let a = FeedAdaptReq {
                    on: u8::from(*on),
                    pad: [0; 7],
                    rmin: (*rmin).into(),
                };
                ext(TcOp::FeedAdapt, a.as_bytes())
            }
            Request::Setup {
                start,
                cycle_s,
                spool_capacity,
            } => {
                let s = SetupReq {
                    start: start.map(Into::into),
                    cycle_s: (*cycle_s).into(),
                    spool_capacity: (*spool_capacity).into(),
                };
                ext(TcOp::Setup, s.as_bytes())
            }
            Request::SpoolLog { logging } => {
                let s = SpoolLogReq {
                    logging: u8::from(*logging),
                    pad: [0; 3],
                };
                ext(TcOp::SpoolLog, s.as_bytes())
            }
        }
    }

    /// The op this request travels under.
    pub fn wire_op(&self) -> Op {
        let tc = match self {
            Request::Read(..) => return Op::Read,
            Request::Write(..) => return Op::Write,
            Request::Motion(_) => TcOp::Motion,
            Request::Exec(_) => TcOp::Exec,
            Request::Pos => TcOp::Pos,
            Request::Queue => TcOp::Queue,
            Request::FeedAdaption { .. } => TcOp::FeedAdapt,
            Request::Setup { .. } => TcOp::Setup,
            Request::SpoolLog { .. } => TcOp::SpoolLog,
        };
        Op::Ext(tc.code())
    }

    /// The TC request a wire request stands for: `UnknownOp` for an
    /// extension op the TC side does not have, `BadPayload` for a payload
    /// that does not fit its op.
    pub fn from_wire(req: &WireRequest) -> Result<Request, ProtocolError> {
        let (code, payload) = match req {
            WireRequest::Read(a, ty) => return Ok(Request::Read(*a, *ty)),
            WireRequest::Write(a, v) => return Ok(Request::Write(*a, *v)),
            WireRequest::Ext(code, payload) => (*code, payload),
            // The server's connection answers HELLO; it is no TC request.
            WireRequest::Hello(_) => return Err(ProtocolError::UnknownOp),
        };
        let op = TcOp::from_code(code).ok_or(ProtocolError::UnknownOp)?;
        let bad = ProtocolError::BadPayload;
        Ok(match op {
            TcOp::Motion => Request::Motion(motion::decode(exact(payload)?).ok_or(bad)?),
            TcOp::Exec => {
                let n = exact::<ExecReq>(payload)?.cycles.get();
                Request::Exec((n != u64::MAX).then_some(n))
            }
            TcOp::Pos | TcOp::Queue if !payload.is_empty() => return Err(bad),
            TcOp::Pos => Request::Pos,
            TcOp::Queue => Request::Queue,
            TcOp::FeedAdapt => {
                let a: &FeedAdaptReq = exact(payload)?;
                if a.on > 1 || a.pad != [0; 7] {
                    return Err(bad);
                }
                Request::FeedAdaption {
                    on: a.on == 1,
                    rmin: a.rmin.get(),
                }
            }
            TcOp::Setup => {
                let s: &SetupReq = exact(payload)?;
                Request::Setup {
                    start: s.start.map(|v| v.get()),
                    cycle_s: s.cycle_s.get(),
                    spool_capacity: s.spool_capacity.get(),
                }
            }
            TcOp::SpoolLog => {
                let s: &SpoolLogReq = exact(payload)?;
                if s.logging > 1 || s.pad != [0; 3] {
                    return Err(bad);
                }
                Request::SpoolLog {
                    logging: s.logging == 1,
                }
            }
        })
    }
}

fn spool_payload(els: &[crate::element::SpoolRecord], more: bool) -> Bytes {
    let n = els.len().min(SPOOL_BATCH);
    let mut out = BytesMut::with_capacity(4 + n * std::mem::size_of::<WireElement>());
    let head = SpoolLogAns {
        // n <= SPOOL_BATCH (400) fits u16.
        count: (n as u16).into(),
        more: u8::from(more || els.len() > n),
        pad: 0,
    };
    out.put_slice(head.as_bytes());
    for e in &els[..n] {
        out.put_slice(element::encode(e).as_bytes());
    }
    out.freeze()
}

fn spool_from(payload: &[u8]) -> Option<Reply> {
    let (head, rest) = SpoolLogAns::ref_from_prefix(payload).ok()?;
    let els = <[WireElement]>::ref_from_bytes(rest).ok()?;
    if els.len() != usize::from(head.count.get()) {
        return None;
    }
    let list = els
        .iter()
        .map(element::decode)
        .collect::<Option<Vec<_>>>()?;
    Some(Reply::Spool(list, head.more == 1))
}

impl Reply {
    /// The wire answer of this reply (a `Spool` reply carries at most
    /// [`SPOOL_BATCH`] elements; `more` is set when it had more).
    pub fn to_wire(&self) -> Answer {
        match self {
            Reply::Ok => Answer::Ok,
            Reply::Value(v) => Answer::Value(*v),
            Reply::Pos(p) => {
                let a = PosAns {
                    pos: p.map(Into::into),
                };
                Answer::Ext(Bytes::copy_from_slice(a.as_bytes()))
            }
            Reply::Queue(n) => {
                let q = QueueAns { count: (*n).into() };
                Answer::Ext(Bytes::copy_from_slice(q.as_bytes()))
            }
            Reply::Spool(els, more) => Answer::Ext(spool_payload(els, *more)),
            Reply::Access(e) => Answer::Access(*e),
            Reply::Protocol(e) => Answer::Protocol(*e),
        }
    }

    /// The reply a wire answer to a request of `op` stands for; `None`
    /// when the answer cannot belong to that op.
    pub fn from_wire(op: Op, ans: &Answer) -> Option<Reply> {
        let payload = match ans {
            Answer::Ok => return Some(Reply::Ok),
            Answer::Value(v) => return Some(Reply::Value(*v)),
            Answer::Access(e) => return Some(Reply::Access(*e)),
            Answer::Protocol(e) => return Some(Reply::Protocol(*e)),
            Answer::Ext(p) => p,
        };
        let Op::Ext(code) = op else { return None };
        match TcOp::from_code(code)? {
            TcOp::Motion | TcOp::Exec | TcOp::Setup | TcOp::FeedAdapt if payload.is_empty() => {
                Some(Reply::Ok)
            }
            TcOp::Pos => Some(Reply::Pos(
                PosAns::ref_from_bytes(payload).ok()?.pos.map(|v| v.get()),
            )),
            TcOp::Queue => Some(Reply::Queue(
                QueueAns::ref_from_bytes(payload).ok()?.count.get(),
            )),
            TcOp::SpoolLog => spool_from(payload),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::layout::MotionReq;
    use super::*;
    use crate::motion::{ArcDir, Motion};

    /// What the server makes of a TC op's payload with one byte changed.
    fn with_byte(req: &Request, at: usize, v: u8) -> Result<Request, ProtocolError> {
        let WireRequest::Ext(code, payload) = req.to_wire() else {
            panic!("not an extension op: {req:?}");
        };
        let mut p = payload.to_vec();
        p[at] = v;
        Request::from_wire(&WireRequest::Ext(code, Bytes::from(p)))
    }

    fn lin() -> Request {
        let mut words = [None; crate::axes::AXES];
        words[0] = Some(20.0);
        Request::Motion(Motion::Lin {
            words,
            feed: Some(600.0),
        })
    }

    fn cir() -> Request {
        Request::Motion(Motion::Cir {
            dir: ArcDir::Cw,
            words: [Some(1.0); crate::axes::AXES],
            centre: [Some(1.0), None, None],
            feed: None,
        })
    }

    const BAD: Result<Request, ProtocolError> = Err(ProtocolError::BadPayload);
    const CCW: usize = std::mem::offset_of!(MotionReq, ccw);
    const PRESENT: usize = std::mem::offset_of!(MotionReq, present);

    #[test]
    fn canonical_payloads_decode() {
        for r in [lin(), cir(), Request::SpoolLog { logging: true }] {
            let wire = r.to_wire();
            assert_eq!(Request::from_wire(&wire), Ok(r));
        }
    }

    #[test]
    fn motion_padding_must_be_zero() {
        for at in [
            std::mem::offset_of!(MotionReq, pad),
            std::mem::offset_of!(MotionReq, pad2),
            std::mem::offset_of!(MotionReq, pad2) + 1,
        ] {
            assert_eq!(with_byte(&lin(), at, 1), BAD, "byte {at}");
            assert_eq!(with_byte(&cir(), at, 0x80), BAD, "byte {at}");
        }
    }

    #[test]
    fn ccw_is_0_or_1_on_cir_and_0_elsewhere() {
        assert!(matches!(
            with_byte(&cir(), CCW, 1),
            Ok(Request::Motion(Motion::Cir {
                dir: ArcDir::Ccw,
                ..
            }))
        ));
        for v in [2, 0xff] {
            assert_eq!(with_byte(&cir(), CCW, v), BAD, "ccw {v}");
        }
        assert_eq!(with_byte(&lin(), CCW, 1), BAD);
    }

    /// What the server makes of a TC op's payload with `bits` set in byte `at`.
    fn with_bits(req: &Request, at: usize, bits: u8) -> Result<Request, ProtocolError> {
        let WireRequest::Ext(_, payload) = req.to_wire() else {
            panic!("not an extension op: {req:?}");
        };
        with_byte(req, at, payload[at] | bits)
    }

    #[test]
    fn centre_bits_are_refused_on_lin_and_rap() {
        let rap = Request::Motion(Motion::Rap {
            words: [Some(0.0); crate::axes::AXES],
            feed: None,
        });
        // I J K are bits 8, 9, 10: bits 0, 1, 2 of the mask's second byte.
        for bit in 0..3 {
            assert_eq!(with_bits(&lin(), PRESENT + 1, 1 << bit), BAD, "{bit}");
            assert_eq!(with_bits(&rap, PRESENT + 1, 1 << bit), BAD, "{bit}");
        }
    }

    #[test]
    fn present_bits_beyond_the_words_are_refused() {
        for bit in 4..8 {
            assert_eq!(with_bits(&cir(), PRESENT + 1, 1 << bit), BAD, "{bit}");
        }
    }

    #[test]
    fn words_a_kind_does_not_take_are_refused() {
        let ja = Request::Motion(Motion::Ja {
            words: [Some(1.0); crate::axes::AXES],
        });
        let js = Request::Motion(Motion::Js {
            axes: [true; crate::axes::AXES],
        });
        let rs = Request::Motion(Motion::Rs);
        let ssf = Request::Motion(Motion::Ssf {
            axis: 2,
            function: 2001,
        });
        // F on a direct command, any word on RS or SSF.
        assert_eq!(with_bits(&ja, PRESENT + 1, 1 << 3), BAD);
        assert_eq!(with_bits(&js, PRESENT + 1, 1 << 3), BAD);
        assert_eq!(with_bits(&rs, PRESENT, 1), BAD);
        assert_eq!(with_bits(&ssf, PRESENT, 1), BAD);
    }

    #[test]
    fn ssf_fields_are_zero_on_other_kinds() {
        assert_eq!(
            with_byte(&lin(), std::mem::offset_of!(MotionReq, axis), 1),
            BAD
        );
        let function = std::mem::offset_of!(MotionReq, function);
        assert_eq!(with_byte(&cir(), function, 1), BAD);
        assert_eq!(
            with_byte(&Request::Motion(Motion::Rs), function + 3, 1),
            BAD
        );
    }

    #[test]
    fn spool_log_byte_is_0_or_1() {
        let on = Request::SpoolLog { logging: true };
        assert_eq!(
            with_byte(&on, 0, 0),
            Ok(Request::SpoolLog { logging: false })
        );
        for v in [2, 0xff] {
            assert_eq!(with_byte(&on, 0, v), BAD, "logging byte {v}");
        }
    }

    #[test]
    fn spool_log_padding_must_be_zero() {
        let on = Request::SpoolLog { logging: true };
        for at in 1..4 {
            assert_eq!(with_byte(&on, at, 1), BAD, "byte {at}");
        }
    }
}
