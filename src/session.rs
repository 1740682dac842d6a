//! Conformance sessions: `SETUP` gives the connection that sends it an
//! emulator of its own, fresh at the given start and cycle. Every later
//! request of that connection goes to it, no other connection sees it, and
//! it ends with the connection. Only a session keeps a spool log, and the
//! log is bounded.

use std::collections::VecDeque;

use tc_module::{AxisPos, MAX_COORD};
use tc_request::wire::{TcOp, SPOOL_BATCH};
use tc_request::{Reply, Request, SpoolRecord};
use uoi::tcp::{Served, Session};
use uoi::wire::{Answer, Op, ProtocolError, Request as WireRequest};
use uoi::AccessError;

use crate::service::{serve, Control};
use crate::Emulator;

/// Longest interpolation cycle a `SETUP` may ask for, in seconds.
pub const MAX_CYCLE_S: f64 = 1.0;

/// Most spooled elements a session's log holds before they are fetched
/// (ten `SPOOL_LOG` answers).
pub const LOG_CAPACITY: usize = 10 * SPOOL_BATCH;

/// A connection's conformance session, once it has sent `SETUP`.
#[derive(Debug, Default)]
pub struct ConformanceSession {
    own: Option<Box<Conformance>>,
}

impl Session for ConformanceSession {
    /// `SETUP` always; everything else once there is a session.
    fn handle(&mut self, req: WireRequest) -> Served {
        if req.op() == Op::Ext(TcOp::Setup.code()) {
            return Served::Here(self.setup(&req));
        }
        match self.own.as_deref_mut() {
            Some(own) => Served::Here(own.handle(req)),
            None => Served::Shared(req),
        }
    }
}

impl ConformanceSession {
    /// `SETUP`: a fresh emulator for this connection, in place of any it
    /// had. Refused (`BadPayload`, `Range`), it changes nothing.
    fn setup(&mut self, req: &WireRequest) -> Answer {
        let (start, cycle_s) = match Request::from_wire(req) {
            Ok(Request::Setup { start, cycle_s }) => (start, cycle_s),
            Ok(_) => return Answer::Protocol(ProtocolError::UnknownOp),
            Err(e) => return Answer::Protocol(e),
        };
        if let Err(e) = check_setup(&start, cycle_s) {
            return Answer::Access(e);
        }
        self.own = Some(Box::new(Conformance {
            emu: Emulator::new(start, cycle_s),
            log: SpoolLog::default(),
        }));
        Answer::Ok
    }
}

/// `Range` for a start or cycle out of limits.
fn check_setup(start: &AxisPos, cycle_s: f64) -> Result<(), AccessError> {
    let ok = start.iter().all(|v| v.is_finite() && v.abs() <= MAX_COORD)
        && cycle_s.is_finite()
        && cycle_s > 0.0
        && cycle_s <= MAX_CYCLE_S;
    if ok {
        Ok(())
    } else {
        Err(AccessError::Range)
    }
}

/// The private emulator of a session and its spool log.
#[derive(Debug)]
struct Conformance {
    emu: Emulator,
    log: SpoolLog,
}

impl Conformance {
    /// Serves one request on the private emulator.
    fn handle(&mut self, req: WireRequest) -> Answer {
        let ans = match serve(&mut self.emu, req) {
            Ok(ans) => ans,
            Err(Control::SpoolLog(logging)) => self.log.fetch(&mut self.emu, logging).to_wire(),
            // The session takes SETUP before its emulator sees it.
            Err(Control::Setup) => Answer::Access(AccessError::State),
        };
        self.log.collect(&mut self.emu);
        ans
    }
}

/// The elements spooled while logging and not yet fetched.
#[derive(Debug, Default)]
struct SpoolLog {
    pending: VecDeque<SpoolRecord>,
    /// Logging is on.
    on: bool,
    /// More than [`LOG_CAPACITY`] elements were waiting: the log was
    /// dropped. Until the next `SETUP`, `SPOOL_LOG` answers `State`.
    overflowed: bool,
}

impl SpoolLog {
    /// Takes what the emulator logged. Past [`LOG_CAPACITY`] the log is
    /// dropped and logging stops: a log with a gap is worth nothing to a
    /// comparison, and memory stays bounded.
    fn collect(&mut self, emu: &mut Emulator) {
        if !self.on {
            return;
        }
        self.pending.extend(emu.take_spool_log());
        if self.pending.len() > LOG_CAPACITY {
            self.pending = VecDeque::new();
            self.on = false;
            self.overflowed = true;
            emu.set_spool_log(false);
        }
    }

    /// `SPOOL_LOG`: one batch of the logged elements; logging on or off.
    /// `State`, changing nothing, once the log has overflowed.
    fn fetch(&mut self, emu: &mut Emulator, logging: bool) -> Reply {
        self.collect(emu);
        if self.overflowed {
            return Reply::Access(AccessError::State);
        }
        self.on = logging;
        emu.set_spool_log(logging);
        let n = self.pending.len().min(SPOOL_BATCH);
        let batch: Vec<SpoolRecord> = self.pending.drain(..n).collect();
        Reply::Spool(batch, !self.pending.is_empty())
    }
}
