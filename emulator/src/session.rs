//! Conformance sessions: `SETUP` gives the connection that sends it an
//! emulator of its own, fresh at the given start and cycle. Every later
//! request of that connection goes to it, no other connection sees it, and
//! it ends with the connection. Only a session keeps a spool log, and the
//! log is bounded. The service that opens the sessions counts them
//! ([`SessionPlaces`]).

use std::collections::VecDeque;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use tc_module::limits::check_point;
use tc_module::{AxisPos, CycleTime};
use tc_module::{DEFAULT_SPOOL_CAPACITY, MIN_SPOOL_CAPACITY};
use tc_request::wire::{TcOp, SPOOL_BATCH};
use tc_request::{Reply, Request, SpoolRecord};
use uoi::tcp::{Session, Slice};
use uoi::wire::{Answer, Op, ProtocolError, Request as WireRequest};
use uoi::AccessError;

use crate::serving::{proceed_slice, serve_slice, Control, ExecRest};
use crate::Emulator;

/// Most conformance sessions open at once in one server: each may hold a
/// spooler of up to [`MAX_SESSION_SPOOL`] elements, so this bounds what
/// sessions can take of memory (16 × 25 MB).
pub const MAX_SESSIONS: usize = 16;

/// Largest spooler a session may ask for (the server's default capacity).
pub const MAX_SESSION_SPOOL: usize = DEFAULT_SPOOL_CAPACITY;

/// The places of the sessions of one service: at most [`MAX_SESSIONS`]
/// have an emulator at once (cloned into each session it opens); and the
/// count of the sessions open, one per connection, with an emulator or
/// not (what a dashboard shows as the connected UOI clients).
#[derive(Debug, Clone, Default)]
pub struct SessionPlaces {
    /// Sessions with an emulator of their own (after `SETUP`).
    setups: Arc<AtomicUsize>,
    /// Sessions open: the service's connections.
    open: Arc<AtomicUsize>,
}

impl SessionPlaces {
    /// A place, or `None` when all are taken.
    fn take(&self) -> Option<SessionPlace> {
        self.setups
            .fetch_update(Ordering::AcqRel, Ordering::Acquire, |n| {
                (n < MAX_SESSIONS).then_some(n + 1)
            })
            .ok()
            .map(|_| SessionPlace(Arc::clone(&self.setups)))
    }

    /// Sessions open now: one per connection of the service.
    pub fn open(&self) -> usize {
        self.open.load(Ordering::Acquire)
    }

    /// Counts one more session open, until the seat is dropped.
    fn seat(&self) -> SessionPlace {
        self.open.fetch_add(1, Ordering::AcqRel);
        SessionPlace(Arc::clone(&self.open))
    }
}

/// One of the [`MAX_SESSIONS`] places, or one open session; given back
/// when dropped.
#[derive(Debug)]
struct SessionPlace(Arc<AtomicUsize>);

impl Drop for SessionPlace {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::AcqRel);
    }
}

/// Most spooled elements a session's log holds before they are fetched
/// (ten `SPOOL_LOG` answers).
pub const LOG_CAPACITY: usize = 10 * SPOOL_BATCH;

/// A connection's session: a conformance session once it has sent
/// `SETUP`, until then nothing of its own.
#[derive(Debug)]
pub struct ConformanceSession {
    own: Option<Box<Conformance>>,
    /// Where its place comes from when it sends `SETUP`.
    places: SessionPlaces,
    /// It counts among the sessions open while it lives.
    _open: SessionPlace,
}

/// Whether `req` is a `SETUP`.
fn is_setup(req: &WireRequest) -> bool {
    req.op() == Op::Ext(TcOp::Setup.code())
}

impl Session<ExecRest> for ConformanceSession {
    /// `SETUP` always; everything else once there is a session.
    fn takes(&self, req: &WireRequest) -> bool {
        self.own.is_some() || is_setup(req)
    }

    /// One slice at a time (a long `EXEC` comes back as [`Slice::More`],
    /// so the connection lets others run and stops it if it is closed).
    fn serve(&mut self, req: WireRequest) -> Slice<ExecRest> {
        if is_setup(&req) {
            return Slice::Done(self.setup(&req));
        }
        match self.own.as_deref_mut() {
            Some(own) => own.serve(req),
            // Not taken: `takes` says no without an emulator.
            None => Slice::Done(Answer::Access(AccessError::State)),
        }
    }

    /// The next slice of a long `EXEC` on the session's emulator.
    fn proceed(&mut self, rest: ExecRest) -> Slice<ExecRest> {
        match self.own.as_deref_mut() {
            Some(own) => {
                let slice = proceed_slice(&mut own.emu, rest);
                own.log.collect(&mut own.emu);
                slice
            }
            // A rest comes only from a slice of its emulator.
            None => Slice::Done(Answer::Access(AccessError::State)),
        }
    }
}

impl ConformanceSession {
    /// A session with nothing of its own yet, taking its place from
    /// `places` on `SETUP`.
    pub fn new(places: SessionPlaces) -> Self {
        let open = places.seat();
        Self {
            own: None,
            places,
            _open: open,
        }
    }

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
            None => match self.places.take() {
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
    fn serve(&mut self, req: WireRequest) -> Slice<ExecRest> {
        let slice = match serve_slice(&mut self.emu, req) {
            Ok(slice) => slice,
            Err(Control::SpoolLog(logging)) => {
                Slice::Done(self.log.fetch(&mut self.emu, logging).to_wire())
            }
            // The session takes SETUP before its emulator sees it.
            Err(Control::Setup) => Slice::Done(Answer::Access(AccessError::State)),
        };
        self.log.collect(&mut self.emu);
        slice
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

#[cfg(test)]
mod tests {
    use super::*;
    use tc_module::CycleTime;

    fn setup() -> WireRequest {
        Request::Setup {
            start: [0.0; 8],
            cycle_s: CycleTime::DEFAULT.secs(),
            spool_capacity: 0,
        }
        .to_wire()
    }

    /// `SETUP` on a fresh session of `places`: its answer, and the session.
    fn open(places: &SessionPlaces) -> (Answer, ConformanceSession) {
        let mut s = ConformanceSession::new(places.clone());
        assert!(s.takes(&setup()));
        let answer = s.serve(setup()).finish(|_| unreachable!("one slice"));
        (answer, s)
    }

    #[test]
    fn each_service_counts_its_own_sessions() {
        let mine = SessionPlaces::default();
        let held: Vec<_> = (0..MAX_SESSIONS).map(|_| open(&mine)).collect();
        assert!(held.iter().all(|(a, _)| *a == Answer::Ok));
        assert_eq!(open(&mine).0, Answer::Access(AccessError::Full));
        // Another service's sessions are not counted against these.
        assert_eq!(open(&SessionPlaces::default()).0, Answer::Ok);
        // A session that ends gives its place back; one without an
        // emulator never took one.
        let read = WireRequest::Read(tc_objects::TcObject::TcPlane.address(), uoi::ValueType::I32);
        let without = ConformanceSession::new(mine.clone());
        assert!(!without.takes(&read));
        drop(held);
        assert_eq!(open(&mine).0, Answer::Ok);
    }

    #[test]
    fn every_session_counts_as_open_until_it_ends() {
        let places = SessionPlaces::default();
        assert_eq!(places.open(), 0);
        let plain = ConformanceSession::new(places.clone());
        let (_, with_emulator) = open(&places);
        assert_eq!(places.open(), 2);
        drop(plain);
        assert_eq!(places.open(), 1);
        drop(with_emulator);
        assert_eq!(places.open(), 0);
    }
}
