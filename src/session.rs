//! Conformance sessions: `SETUP` gives the connection that sends it an
//! emulator of its own, fresh at the given start and cycle. Every later
//! request of that connection goes to it, no other connection sees it, and
//! it ends with the connection. Only a session keeps a spool log, and the
//! log is bounded.

use std::collections::VecDeque;
use std::sync::atomic::{AtomicUsize, Ordering};

use tc_module::limits::check_point;
use tc_module::{AxisPos, CycleTime};
use tc_module::{DEFAULT_SPOOL_CAPACITY, MIN_SPOOL_CAPACITY};
use tc_request::wire::{TcOp, SPOOL_BATCH};
use tc_request::{Reply, Request, SpoolRecord};
use uoi::tcp::{Served, Session, Slice};
use uoi::wire::{Answer, Op, ProtocolError, Request as WireRequest};
use uoi::AccessError;

use crate::service::{serve_slice, Control};
use crate::Emulator;

/// Most conformance sessions open at once in one server process: each
/// may hold a spooler of up to [`MAX_SESSION_SPOOL`] elements, so this
/// bounds what sessions can take of memory (16 × 25 MB).
pub const MAX_SESSIONS: usize = 16;

/// Largest spooler a session may ask for (the server's default capacity).
pub const MAX_SESSION_SPOOL: usize = DEFAULT_SPOOL_CAPACITY;

/// Sessions open now, in this process.
static OPEN_SESSIONS: AtomicUsize = AtomicUsize::new(0);

/// One of the [`MAX_SESSIONS`] places; given back when dropped.
#[derive(Debug)]
struct SessionPlace;

impl SessionPlace {
    /// A place, or `None` when all are taken.
    fn take() -> Option<Self> {
        OPEN_SESSIONS
            .fetch_update(Ordering::AcqRel, Ordering::Acquire, |n| {
                (n < MAX_SESSIONS).then_some(n + 1)
            })
            .ok()
            .map(|_| SessionPlace)
    }
}

impl Drop for SessionPlace {
    fn drop(&mut self) {
        OPEN_SESSIONS.fetch_sub(1, Ordering::AcqRel);
    }
}

/// Most spooled elements a session's log holds before they are fetched
/// (ten `SPOOL_LOG` answers).
pub const LOG_CAPACITY: usize = 10 * SPOOL_BATCH;

/// A connection's conformance session, once it has sent `SETUP`.
#[derive(Debug, Default)]
pub struct ConformanceSession {
    own: Option<Box<Conformance>>,
}

impl Session for ConformanceSession {
    /// `SETUP` always; everything else once there is a session, one slice
    /// at a time (a long `EXEC` comes back as [`Served::More`], so the
    /// connection lets others run and stops it if it is closed).
    fn handle(&mut self, req: WireRequest) -> Served {
        if req.op() == Op::Ext(TcOp::Setup.code()) {
            return Served::Here(self.setup(&req));
        }
        match self.own.as_deref_mut() {
            Some(own) => own.handle_slice(req),
            None => Served::Shared(req),
        }
    }
}

impl ConformanceSession {
    /// `SETUP`: a fresh emulator for this connection, in place of any it
    /// had. Refused (`BadPayload`, `Range`, `Full` when [`MAX_SESSIONS`]
    /// are open), it changes nothing.
    fn setup(&mut self, req: &WireRequest) -> Answer {
        let (start, cycle_s, capacity) = match Request::from_wire(req) {
            Ok(Request::Setup {
                start,
                cycle_s,
                spool_capacity,
            }) => (start, cycle_s, spool_capacity),
            Ok(_) => return Answer::Protocol(ProtocolError::UnknownOp),
            Err(e) => return Answer::Protocol(e),
        };
        let (cycle, capacity) = match check_setup(&start, cycle_s, capacity) {
            Ok(v) => v,
            Err(e) => return Answer::Access(e),
        };
        let place = match self.own.take() {
            Some(own) => own.place,
            None => match SessionPlace::take() {
                Some(p) => p,
                None => return Answer::Access(AccessError::Full),
            },
        };
        self.own = Some(Box::new(Conformance {
            emu: Emulator::new(start, cycle).with_spool_capacity(capacity),
            log: SpoolLog::default(),
            place,
        }));
        Answer::Ok
    }
}

/// The checked cycle and spooler capacity of a `SETUP` (capacity 0: the
/// default one); `Range` for a start, cycle or capacity out of limits.
fn check_setup(
    start: &AxisPos,
    cycle_s: f64,
    capacity: u64,
) -> Result<(CycleTime, usize), AccessError> {
    check_point(start)?;
    let cycle = CycleTime::from_secs(cycle_s).map_err(|_| AccessError::Range)?;
    let capacity = match capacity {
        0 => DEFAULT_SPOOL_CAPACITY,
        n => usize::try_from(n)
            .ok()
            .filter(|n| (MIN_SPOOL_CAPACITY..=MAX_SESSION_SPOOL).contains(n))
            .ok_or(AccessError::Range)?,
    };
    Ok((cycle, capacity))
}

/// The private emulator of a session and its spool log.
#[derive(Debug)]
struct Conformance {
    emu: Emulator,
    log: SpoolLog,
    /// Its place among the [`MAX_SESSIONS`].
    place: SessionPlace,
}

impl Conformance {
    /// Serves one slice of a request on the private emulator.
    fn handle_slice(&mut self, req: WireRequest) -> Served {
        let served = match serve_slice(&mut self.emu, req) {
            Ok(Slice::Done(ans)) => Served::Here(ans),
            Ok(Slice::More(rest)) => Served::More(rest),
            // `serve_slice` never waits: only the shared service persists.
            Ok(Slice::Wait(_)) => Served::Here(Answer::Protocol(ProtocolError::Busy)),
            Err(Control::SpoolLog(logging)) => {
                Served::Here(self.log.fetch(&mut self.emu, logging).to_wire())
            }
            // The session takes SETUP before its emulator sees it.
            Err(Control::Setup) => Served::Here(Answer::Access(AccessError::State)),
        };
        self.log.collect(&mut self.emu);
        served
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
