//! [`frame_sequence`](super::frame_sequence): a byte stream of frames
//! served the way a connection serves it, every answer checked.

use bytes::BytesMut;
use tc_module::{CycleTime, AXES};
use tc_request::wire::SPOOL_BATCH;
use tc_request::{Reply, Request, SpoolRecord};
use tokio_util::codec::{Decoder, Encoder};
use uoi::tcp::{Handler, Session};
use uoi::wire::{Answer, ClientCodec, Op, Rejected, Request as WireRequest, ServerCodec};

use emulator::ConformanceSession;
use emulator::EmulatorService;
use trace::Trace;

use super::frames::check_answer_round_trip;
use crate::limits::{EXEC_BUDGET, MAX_FRAMES, MAX_INPUT, POS_LIMIT, SPOOLED_PER_FRAME};

/// One connection as the server serves it, without the socket: its
/// session sees each request first, else the shared emulator answers.
#[derive(Debug)]
pub struct Connection {
    shared: EmulatorService,
    session: ConformanceSession,
    /// Cycles `EXEC` may still run ([`EXEC_BUDGET`]).
    cycles_left: u64,
    /// Frames served.
    frames: u64,
}

impl Default for Connection {
    fn default() -> Self {
        let mut shared = EmulatorService::new([0.0; AXES], CycleTime::DEFAULT);
        Self {
            session: shared.open_session(),
            shared,
            cycles_left: EXEC_BUDGET,
            frames: 0,
        }
    }
}

impl Connection {
    /// The answer to one decoded frame, checked; HELLO is taken (the
    /// server asks no token of a loopback peer).
    pub fn serve(&mut self, item: Result<(u32, WireRequest), Rejected>) -> Answer {
        self.frames += 1;
        let (id, op, ans) = match item {
            Ok((id, WireRequest::Hello(_))) => (id, Op::Hello.code(), Answer::Ok),
            Ok((id, req)) => {
                let op = req.op().code();
                (id, op, self.answer(req))
            }
            Err(r) => (r.id, r.op, Answer::Protocol(r.error)),
        };
        self.check(id, op, &ans);
        ans
    }

    /// The answer of the session, else of the shared emulator, to `req`
    /// within the harness's bounds.
    fn answer(&mut self, req: WireRequest) -> Answer {
        let req = self.bounded(req);
        if self.session.takes(&req) {
            let session = &mut self.session;
            session.serve(req).finish(|rest| session.proceed(rest))
        } else {
            let shared = &mut self.shared;
            shared.serve(req).finish(|rest| shared.proceed(rest))
        }
    }

    /// `req`, an `EXEC` cut to the cycles left of [`EXEC_BUDGET`].
    fn bounded(&mut self, req: WireRequest) -> WireRequest {
        match Request::from_wire(&req) {
            Ok(Request::Exec(n)) => {
                let n = n.unwrap_or(u64::MAX).min(self.cycles_left);
                self.cycles_left -= n;
                Request::Exec(Some(n)).to_wire()
            }
            _ => req,
        }
    }

    /// An answer is well formed: it encodes, and the client decodes it to
    /// the same answer with the request's id. A TC answer stands for a
    /// reply, whose positions are finite and within [`POS_LIMIT`], and a
    /// queue length stays within what the frames served can have spooled.
    fn check(&self, id: u32, op: u8, ans: &Answer) {
        let mut out = BytesMut::new();
        let reply = uoi::wire::Reply {
            id,
            op,
            answer: ans.clone(),
        };
        if let Err(e) = ServerCodec.encode(reply, &mut out) {
            panic!("answer {ans:?} to op {op:#x} does not encode: {e}");
        }
        let Some(op) = Op::from_code(op) else {
            return;
        };
        check_answer_round_trip(id, op, ans);
        let Op::Ext(code) = op else {
            return;
        };
        if code == emulator::INFO_OP || code == emulator::WRITE_IF_OP {
            // The emulator's own ops, not TC requests: an INFO answer (to
            // INFO, or to a write it did not carry out) reads back.
            if let Answer::Ext(p) = ans {
                let info = emulator::EmulatorInfo::from_wire(ans);
                assert!(
                    p.is_empty() || info.is_some(),
                    "answer {ans:?} to op {code:#x}"
                );
            }
            return;
        }
        let Some(reply) = Reply::from_wire(op, ans) else {
            panic!("answer {ans:?} to op {code:#x} is no TC reply");
        };
        self.check_reply(&reply);
    }

    /// The values of a TC reply are within limits.
    fn check_reply(&self, reply: &Reply) {
        match reply {
            Reply::Pos(p) => check_position(p, "POS"),
            Reply::Queue(n) => {
                let most = self.frames * SPOOLED_PER_FRAME;
                assert!(*n <= most, "QUEUE {n} after {} frames", self.frames);
            }
            Reply::Spool(els, _) => {
                assert!(els.len() <= SPOOL_BATCH);
                els.iter().for_each(check_record);
            }
            _ => {}
        }
    }
}

/// Every coordinate finite and within [`POS_LIMIT`].
fn check_position(p: &[f64], what: &str) {
    let ok = p.iter().all(|v| v.is_finite() && v.abs() <= POS_LIMIT);
    assert!(ok, "{what} out of limits: {p:?}");
}

/// A logged element's ends, centre and feed are within limits.
fn check_record(e: &SpoolRecord) {
    check_position(&e.start, "spooled start");
    check_position(&e.end, "spooled end");
    if let Some(a) = &e.arc {
        check_position(&a.centre, "spooled arc centre");
    }
    assert!(
        e.feed.is_finite() && e.feed > 0.0,
        "spooled feed {}",
        e.feed
    );
}

/// Frames against the emulator: `data` is the byte stream a client sends
/// (at most [`MAX_FRAMES`] frames of it are served). Each frame is decoded
/// by the server's codec and served as a connection serves it
/// ([`Connection`]), with `EXEC` bounded by [`EXEC_BUDGET`]. Checks that
/// nothing panics; every answer encodes and decodes back to itself; a TC
/// op's answer is a TC reply; `POS` and logged spool elements are finite
/// and within [`POS_LIMIT`]; `QUEUE` stays within what the frames served
/// can have spooled.
pub fn frame_sequence(data: &[u8]) {
    serve_stream(data, &mut Connection::default());
}

/// Serves the frames of `data` on `conn`, as [`frame_sequence`] does.
pub fn serve_stream(data: &[u8], conn: &mut Connection) {
    let data = &data[..data.len().min(MAX_INPUT)];
    let mut buf = BytesMut::from(data);
    for _ in 0..MAX_FRAMES {
        // A prefix over the limit closes the connection (after its answer).
        let Ok(Some(item)) = ServerCodec.decode(&mut buf) else {
            return;
        };
        conn.serve(item);
    }
}

/// The frames of `requests` as a client sends them, numbered from 1: a
/// seed for [`frame_sequence`].
pub fn request_stream(requests: &[Request]) -> Vec<u8> {
    let mut out = BytesMut::new();
    for (id, req) in (1u32..).zip(requests) {
        // A TC request always fits a frame.
        let _ = ClientCodec.encode((id, &req.to_wire()), &mut out);
    }
    out.to_vec()
}

/// The requests of a trace as a conformance client sends them: `SETUP`
/// at its start and cycle, spool log on, then its steps.
pub fn trace_requests(trace: &Trace) -> Vec<Request> {
    let h = &trace.header;
    let mut out = vec![
        Request::Setup {
            start: h.start,
            cycle_s: h.cycle.secs(),
            // A capacity is at most 1,000,000: it fits u64.
            spool_capacity: h.spool_capacity as u64,
        },
        Request::SpoolLog { logging: true },
    ];
    out.extend(trace.steps.iter().map(|s| s.request.clone()));
    out.push(Request::SpoolLog { logging: false });
    out
}
