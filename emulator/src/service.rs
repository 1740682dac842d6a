//! The emulator behind the wire: the [`Handler`] the TCP server drives.
//! Requests are served as in [`crate::serving`]; a long `EXEC` is served
//! in slices, so the server can release the emulator in between, and a
//! write of tool data waits until it is on disk. The emulator-control ops
//! (`SETUP`, `SPOOL_LOG`) belong to a connection's conformance session
//! ([`crate::session`]), which the service opens for each connection and
//! counts: the emulator all connections share is never reset or logged by
//! a client.
//!
//! In real time ([`EmulatorService::set_realtime`]) the clock's cycles are
//! run before every request and at every [`tick`](EmulatorService::tick)
//! (the server calls it a few hundred times a second), and `EXEC` waits
//! for the clock ([`crate::exec_waits`]). With a [`RequestLog`] every request
//! carried out is recorded ([`crate::request_log`]). `INFO` ([`crate::info_op`])
//! is answered here, never journaled.

use std::collections::HashMap;
use std::fs::File;
use std::path::Path;
use std::time::Instant;

use otc_ext::OtcExtension;
use tc_module::{AxisPos, CycleTime, TcExtension};
use tc_request::{Reply, Request, SpoolRecord};
use uoi::tcp::{Handler, Slice};
use uoi::wire::ProtocolError;
use uoi::wire::{Answer, Request as WireRequest};
use uoi::AccessError;

use crate::clock::{RealTimeClock, RealTimeFactor};
use crate::config::{Config, ConfigError};
use crate::exec_waits::{ExecWaits, Until, EXEC_WAIT_BIT};
use crate::guarded_write::GuardedWrite;
use crate::info_op::{is_info, new_server_identity, EmulatorInfo};
use crate::request_log::{LogError, RequestLog};
use crate::serving::{proceed_slice, serve_slice, ExecRest};
use crate::session::{ConformanceSession, SessionPlaces};
use crate::tools::durable::ToolPersistence;
use crate::tools::open::{open_durable, OpenToolsError};
use crate::Emulator;

/// The emulator all connections share, as the TCP server's handler
/// (extension `E`: OTC; a test model in tests).
#[derive(Debug)]
pub struct EmulatorService<E: TcExtension = OtcExtension> {
    emu: Emulator<E>,
    /// Where tool data is kept durably; `None`: in memory only.
    tools: Option<Tools<E>>,
    /// The conformance sessions open on this service's connections.
    sessions: SessionPlaces,
    /// Start, cycle and spooler, for `INFO`.
    settings: Settings,
    /// Real time: the clock; `None`: stepped.
    clock: Option<RealTimeClock>,
    /// `EXEC` requests waiting for the clock.
    waits: ExecWaits,
    /// The server stops: an `EXEC` wait is answered `Stopped`.
    stopping: bool,
    /// The recording, while one goes on.
    journal: Option<Box<dyn RequestLog>>,
    /// Tool writes waiting for the disk, by token, to be journaled when
    /// answered.
    journal_pending: HashMap<u64, WireRequest>,
    /// This server's identity, drawn at its start (`INFO`, `WRITE_IF`).
    identity: u64,
    /// Spooled elements kept for a viewer while one watches
    /// ([`EmulatorService::watch_spool`]).
    watched: Option<Watched>,
}

/// Most spooled elements kept for a viewer between two of its looks;
/// beyond, the newest are counted as missed, not kept.
pub const MAX_WATCHED: usize = 100_000;

/// The spooled elements a viewer has not taken yet.
#[derive(Debug, Default)]
struct Watched {
    records: Vec<SpoolRecord>,
    missed: u64,
}

/// The spooled elements since a viewer's last look
/// ([`EmulatorService::take_watched_spool`]).
#[derive(Debug, Default, Clone, PartialEq)]
pub struct WatchedSpool {
    /// The elements, in the order they entered the spooler.
    pub records: Vec<SpoolRecord>,
    /// Elements spooled but not kept (more than [`MAX_WATCHED`] between
    /// two looks).
    pub missed: u64,
}

/// What `INFO` reports of the settings.
#[derive(Debug, Clone, Copy)]
struct Settings {
    start: AxisPos,
    cycle: CycleTime,
    spool_capacity: usize,
}

impl Config {
    /// The emulator to serve (start, cycle, spooler capacity, real time),
    /// checked ([`Config::service_settings`]).
    pub fn service(&self) -> Result<EmulatorService, ConfigError> {
        let set = self.service_settings()?;
        let mut service =
            EmulatorService::new(set.start, set.cycle).with_spool_capacity(set.spool_capacity);
        if let Some(f) = set.realtime {
            service.set_realtime(f);
        }
        Ok(service)
    }
}

impl EmulatorService {
    /// Opens the tool data in `data_dir` (docs/tool-files.md): locks the
    /// folder, loads it into the emulator and makes every later tool write
    /// durable. Returns the lock, to hold while serving. The error names
    /// the file and the line of a bad tool file or journal record.
    pub fn open_tools(
        &mut self,
        data_dir: &Path,
        ignore_bad: bool,
    ) -> Result<File, OpenToolsError> {
        let opened = open_durable(&mut self.emu, data_dir, ignore_bad)?;
        self.set_tools(Box::new(opened.durable));
        Ok(opened.lock)
    }

    /// Serves a fresh emulator at `start` with cycle `cycle`.
    pub fn new(start: AxisPos, cycle: CycleTime) -> Self {
        let mut s = Self::with_emulator(Emulator::new(start, cycle));
        s.settings = Settings {
            start,
            cycle,
            spool_capacity: tc_module::DEFAULT_SPOOL_CAPACITY,
        };
        s
    }
}

impl<E: TcExtension + Default> EmulatorService<E> {
    /// Serves `emu`.
    pub fn with_emulator(emu: Emulator<E>) -> Self {
        let settings = Settings {
            start: emu.position(),
            cycle: CycleTime::DEFAULT,
            spool_capacity: tc_module::DEFAULT_SPOOL_CAPACITY,
        };
        Self {
            emu,
            tools: None,
            sessions: SessionPlaces::default(),
            settings,
            clock: None,
            waits: ExecWaits::default(),
            stopping: false,
            journal: None,
            journal_pending: HashMap::new(),
            identity: new_server_identity(),
            watched: None,
        }
    }

    /// Keeps the tool data through `tools` from now on.
    pub fn set_tools(&mut self, tools: Box<dyn ToolPersistence<E>>) {
        self.tools = Some(Tools(Some(tools)));
    }

    /// The emulator served, mutable (to load its tool data at start).
    pub fn emulator_mut(&mut self) -> &mut Emulator<E> {
        &mut self.emu
    }

    /// Writes every queued tool change and compacts the tool journal (at
    /// shutdown; the emulator keeps serving without persistence).
    pub fn close_tools(&mut self) {
        drop(self.tools.take());
    }

    /// The same service with a spooler of `capacity` elements (checked by
    /// `check_capacity` where it comes from outside).
    pub fn with_spool_capacity(self, capacity: usize) -> Self {
        let mut settings = self.settings;
        settings.spool_capacity = capacity;
        Self {
            emu: self.emu.with_spool_capacity(capacity),
            settings,
            ..self
        }
    }

    /// Runs the executor with the wall clock from now on, `factor` times
    /// faster (the cycle is the one the service was made with).
    pub fn set_realtime(&mut self, factor: RealTimeFactor) {
        self.clock = Some(RealTimeClock::new(factor, self.settings.cycle));
    }

    /// The real-time factor; `None`: stepped.
    pub fn realtime(&self) -> Option<f64> {
        self.clock.as_ref().map(RealTimeClock::factor)
    }

    /// Records every request carried out from now on into `log`.
    pub fn set_request_log(&mut self, log: Box<dyn RequestLog>) {
        self.emu.set_spool_log(true);
        // What a viewer has not taken yet is its, not the recording's.
        let before = self.emu.take_spool_log();
        self.keep_watched(&before);
        self.journal = Some(log);
    }

    /// Ends the recording: what it holds goes to its file.
    pub fn finish_request_log(&mut self) {
        if let Some(mut j) = self.journal.take() {
            if let Err(e) = j.finish() {
                tracing::error!("recording: {e}");
            }
        }
        self.log_spool_if_needed();
    }

    /// Keeps every element spooled from now on for a viewer (`on`), to
    /// be taken with [`take_watched_spool`](Self::take_watched_spool);
    /// or stops keeping them. Costs nothing while nobody watches; the
    /// recording, when one goes on, gets every element as before.
    pub fn watch_spool(&mut self, on: bool) {
        if on == self.watched.is_some() {
            return;
        }
        self.watched = on.then(Watched::default);
        if !on && self.journal.is_none() {
            // Elements logged since the viewer's last look are nobody's.
            let _ = self.emu.take_spool_log();
        }
        self.log_spool_if_needed();
    }

    /// The elements spooled since the last call (while watching; else
    /// none).
    pub fn take_watched_spool(&mut self) -> WatchedSpool {
        if self.journal.is_none() {
            let spooled = self.emu.take_spool_log();
            self.keep_watched(&spooled);
        }
        let w = self
            .watched
            .as_mut()
            .map(std::mem::take)
            .unwrap_or_default();
        WatchedSpool {
            records: w.records,
            missed: w.missed,
        }
    }

    /// Sessions open: one per connection of the server.
    pub fn connections(&self) -> usize {
        self.sessions.open()
    }

    /// The spool log on while a recording or a viewer needs it.
    fn log_spool_if_needed(&mut self) {
        let on = self.journal.is_some() || self.watched.is_some();
        self.emu.set_spool_log(on);
    }

    /// Copies `spooled` for the viewer, while one watches.
    fn keep_watched(&mut self, spooled: &[SpoolRecord]) {
        let Some(w) = self.watched.as_mut() else {
            return;
        };
        let room = MAX_WATCHED.saturating_sub(w.records.len());
        let kept = spooled.len().min(room);
        w.records.extend_from_slice(&spooled[..kept]);
        w.missed += (spooled.len() - kept) as u64;
    }

    /// The server stops: every `EXEC` waiting for the clock is answered
    /// `Stopped` now, and so is every later one (rather than holding the
    /// stop for the server's grace).
    pub fn stop_waits(&mut self) {
        self.stopping = true;
        self.waits.end_all();
    }

    /// Whether a recording goes on.
    pub fn recording(&self) -> bool {
        self.journal.is_some()
    }

    /// What `INFO` answers.
    pub fn info(&self) -> EmulatorInfo {
        EmulatorInfo {
            cleans: self.emu.clean_epoch(),
            realtime: self.realtime(),
            cycles: self.emu.tc().executor().cycles(),
            cycle_s: self.settings.cycle.secs(),
            // A capacity is at most 1,000,000.
            spool_capacity: self.settings.spool_capacity as u64,
            start: self.settings.start,
            server: self.identity,
        }
    }

    /// Real time: runs the cycles the clock owes (at most one `EXEC`
    /// slice), journals them as `EXEC n`, and ends the `EXEC` waits that
    /// are over. Stepped: nothing. Returns the cycles run.
    pub fn tick(&mut self) -> u64 {
        let Some(clock) = self.clock.as_mut() else {
            return 0;
        };
        let ran = clock.catch_up(&mut self.emu, Instant::now());
        let passed = clock.passed();
        if ran > 0 {
            self.journal_idle(ran);
        }
        self.waits.fire(passed, self.emu.queue_len() == 0);
        ran
    }
}

/// Recording.
impl<E: TcExtension + Default> EmulatorService<E> {
    /// Hands the journal one request with its reply and what it spooled;
    /// a journal that fails is dropped (logged), never the server.
    fn journal_reply(&mut self, req: &Request, reply: &Reply) {
        if self.journal.is_none() {
            return;
        }
        let spooled = self.emu.take_spool_log();
        self.keep_watched(&spooled);
        let Some(j) = self.journal.as_mut() else {
            return;
        };
        let axis_nr = self.emu.tc().axis_nr();
        if let Err(e) = j.exchange(req, reply, &spooled, axis_nr) {
            self.journal_failed(&e);
        }
    }

    /// Cycles the clock ran between requests.
    fn journal_idle(&mut self, cycles: u64) {
        if let Some(j) = self.journal.as_mut() {
            if let Err(e) = j.idle(cycles) {
                self.journal_failed(&e);
            }
        }
    }

    /// A comment in the journal.
    fn journal_note(&mut self, text: &str) {
        if let Some(j) = self.journal.as_mut() {
            if let Err(e) = j.note(text) {
                self.journal_failed(&e);
            }
        }
    }

    fn journal_failed(&mut self, why: &LogError) {
        tracing::error!("recording stopped ({why}); the server goes on serving");
        self.journal = None;
        self.log_spool_if_needed();
    }

    /// Journals one slice of `req` served with `slice`; `before`: the
    /// executor's cycles before it.
    fn journal_slice(&mut self, req: &WireRequest, slice: &Slice<ExecRest>, before: u64) {
        if self.journal.is_none() {
            return;
        }
        let tc = match Request::from_wire(req) {
            Ok(r) => r,
            Err(e) => return self.journal_note(&format!("a request refused: {e}")),
        };
        match (slice, &tc) {
            (Slice::Done(_), Request::Setup { .. } | Request::SpoolLog { .. }) => {
                self.journal_note(&format!("{tc}: refused on the shared emulator (State)"));
            }
            (Slice::Done(a), _) => match Reply::from_wire(req.op(), a) {
                Some(reply) => self.journal_reply(&tc, &reply),
                None => self.journal_note(&format!("{tc}: answered {a:?}")),
            },
            (Slice::More(left), Request::Exec(cycles)) => self.journal_exec(*cycles, *left, before),
            (Slice::More(_), _) | (Slice::Wait(_), _) => {}
        }
    }

    /// Journals one slice of an `EXEC` of `cycles` that left `left` (an
    /// `EXEC` cut into slices is written as the cycles each slice ran, so
    /// that requests of other connections served in between keep their
    /// place); `before`: the executor's cycles before it.
    fn journal_exec(&mut self, cycles: Option<u64>, left: ExecRest, before: u64) {
        let ran = match cycles {
            Some(n) => n.saturating_sub(left.0.unwrap_or(0)),
            None => self.emu.tc().executor().cycles().saturating_sub(before),
        };
        self.journal_reply(&Request::Exec(Some(ran)), &Reply::Ok);
    }

    /// Journals the slice of an `EXEC`'s rest `rest` served with `slice`;
    /// the last one as the `EXEC` of what was left.
    fn journal_rest(&mut self, rest: ExecRest, slice: &Slice<ExecRest>, before: u64) {
        match slice {
            Slice::Done(_) => self.journal_reply(&Request::Exec(rest.0), &Reply::Ok),
            Slice::More(left) => self.journal_exec(rest.0, *left, before),
            Slice::Wait(_) => {}
        }
    }
}

/// Real time.
impl<E: TcExtension + Default> EmulatorService<E> {
    /// `EXEC` in real time: a wait for the clock (`None`: not an `EXEC`).
    fn exec_wait(&mut self, req: &WireRequest) -> Option<Slice<ExecRest>> {
        let clock = self.clock.as_ref()?;
        let Ok(Request::Exec(cycles)) = Request::from_wire(req) else {
            return None;
        };
        if self.stopping {
            return Some(Slice::Done(Answer::Protocol(ProtocolError::Stopped)));
        }
        let until = match cycles {
            Some(n) => Until::Cycle(clock.passed().saturating_add(n)),
            None => Until::Empty,
        };
        let over = match until {
            Until::Cycle(c) => clock.passed() >= c,
            Until::Empty => self.emu.queue_len() == 0,
        };
        self.journal_note(&format!(
            "{} (real time: waited for the clock)",
            Request::Exec(cycles)
        ));
        if over {
            return Some(Slice::Done(Answer::Ok));
        }
        Some(match self.waits.add(until) {
            Some(w) => Slice::Wait(w),
            None => Slice::Done(Answer::Protocol(ProtocolError::Busy)),
        })
    }
}

/// Guarded writes.
impl<E: TcExtension + Default> EmulatorService<E> {
    /// `req` itself, or the plain WRITE a `WRITE_IF` carries when this
    /// server and its Clean count are the ones it expects (checked and
    /// carried out in one step: no request comes between); else the
    /// answer: the current `INFO` (nothing carried out), or `BadPayload`.
    fn unguard(&self, req: WireRequest) -> Result<WireRequest, Answer> {
        match GuardedWrite::from_wire(&req) {
            None => Ok(req),
            Some(Err(e)) => Err(Answer::Protocol(e)),
            Some(Ok(w)) => {
                let now = self.info();
                if w.expected(&now) {
                    Ok(w.write())
                } else {
                    Err(now.to_wire())
                }
            }
        }
    }
}

/// The tool persistence of a service; when it goes (the server stopped),
/// every queued tool change is written and the journal compacted into
/// the tool files.
#[derive(Debug)]
struct Tools<E: TcExtension>(Option<Box<dyn ToolPersistence<E>>>);

impl<E: TcExtension> Drop for Tools<E> {
    fn drop(&mut self) {
        if let Some(t) = self.0.take() {
            t.close();
        }
    }
}

impl<E: TcExtension + Default> Handler for EmulatorService<E> {
    /// `SETUP` gives a connection an emulator of its own.
    type Session = ConformanceSession;

    /// The rest of a long `EXEC`, continued by `proceed`.
    type Rest = ExecRest;

    /// A connection's session, without an emulator until it sends
    /// `SETUP`; at most [`MAX_SESSIONS`](crate::session::MAX_SESSIONS)
    /// of this service's sessions have one at once.
    fn open_session(&mut self) -> ConformanceSession {
        ConformanceSession::new(self.sessions.clone())
    }

    /// Serves the shared emulator, a long `EXEC` in slices; a write that
    /// changes tool data waits until it is on disk. `SPOOL_LOG` (and a
    /// `SETUP`, which a connection's session always takes first) is
    /// refused with `State`: only a conformance session has a spool log.
    fn serve(&mut self, req: WireRequest) -> Slice<ExecRest> {
        self.tick();
        if is_info(&req) {
            return Slice::Done(match &req {
                WireRequest::Ext(_, p) if p.is_empty() => self.info().to_wire(),
                _ => Answer::Protocol(ProtocolError::BadPayload),
            });
        }
        let req = match self.unguard(req) {
            Ok(req) => req,
            Err(answer) => return Slice::Done(answer),
        };
        if let Some(wait) = self.exec_wait(&req) {
            return wait;
        }
        let tools = self.tools.as_mut().and_then(|t| t.0.as_mut());
        if let (Some(t), WireRequest::Write(a, v)) = (tools, &req) {
            if let Some(slice) = t.serve(&mut self.emu, *a, *v) {
                match &slice {
                    Slice::Wait(w) if self.journal.is_some() => {
                        self.journal_pending.insert(w.token, req.clone());
                    }
                    _ => self.journal_slice(&req, &slice, 0),
                }
                return slice;
            }
        }
        let before = self.emu.tc().executor().cycles();
        // The request is kept only for a recording (the hot path moves it).
        let kept = self.journal.is_some().then(|| req.clone());
        let slice = serve_slice(&mut self.emu, req)
            .unwrap_or(Slice::Done(Answer::Access(AccessError::State)));
        if let Some(req) = kept {
            self.journal_slice(&req, &slice, before);
        }
        slice
    }

    /// The next slice of a long `EXEC`, from its rest as it is (run in
    /// real time, an `EXEC` waits for the clock and leaves no rest).
    fn proceed(&mut self, rest: ExecRest) -> Slice<ExecRest> {
        self.tick();
        let before = self.emu.tc().executor().cycles();
        let slice = proceed_slice(&mut self.emu, rest);
        if self.journal.is_some() {
            self.journal_rest(rest, &slice, before);
        }
        slice
    }

    /// A tool write is on disk (or refused): applied and answered. An
    /// `EXEC` wait is over: answered.
    fn resume(&mut self, token: u64, ok: bool) -> Slice<ExecRest> {
        if token & EXEC_WAIT_BIT != 0 {
            self.tick();
            return Slice::Done(match (ok, self.stopping) {
                (true, _) => Answer::Ok,
                (false, true) => Answer::Protocol(ProtocolError::Stopped),
                (false, false) => Answer::Protocol(ProtocolError::Busy),
            });
        }
        let slice = match self.tools.as_mut().and_then(|t| t.0.as_mut()) {
            Some(t) => t.resume(&mut self.emu, token, ok),
            None => Slice::Done(Answer::Protocol(ProtocolError::Busy)),
        };
        // Only what a recording kept is looked up.
        if self.journal_pending.is_empty() {
            return slice;
        }
        if let Some(req) = self.journal_pending.remove(&token) {
            self.journal_slice(&req, &slice, 0);
        }
        slice
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tc_request::text::parse_request;

    /// The answer of the shared service to `req`, served to its end.
    fn answer(s: &mut EmulatorService, req: WireRequest) -> Answer {
        s.serve(req).finish(|rest| s.proceed(rest))
    }

    /// A journal that keeps its lines.
    #[derive(Debug, Default, Clone)]
    struct Lines(std::sync::Arc<std::sync::Mutex<Vec<String>>>);

    impl RequestLog for Lines {
        fn exchange(
            &mut self,
            req: &Request,
            reply: &Reply,
            spooled: &[tc_request::SpoolRecord],
            _axis_nr: [u8; 3],
        ) -> Result<(), LogError> {
            let mut l = self.0.lock().unwrap();
            l.push(format!("{req} => {reply:?}"));
            l.extend(spooled.iter().map(|_| "<".to_string()));
            Ok(())
        }
        fn note(&mut self, text: &str) -> Result<(), LogError> {
            self.0.lock().unwrap().push(format!("# {text}"));
            Ok(())
        }
        fn finish(&mut self) -> Result<(), LogError> {
            Err("disk gone".into())
        }
    }

    #[test]
    fn info_reports_cleans_settings_and_cycles() {
        let mut s = EmulatorService::new([1.0; 8], CycleTime::DEFAULT).with_spool_capacity(64);
        let info = |s: &mut EmulatorService| {
            EmulatorInfo::from_wire(&answer(s, crate::info_op::info_request())).unwrap()
        };
        let first = info(&mut s);
        assert_eq!((first.cleans, first.realtime, first.cycles), (0, None, 0));
        assert_eq!((first.spool_capacity, first.start), (64, [1.0; 8]));
        let clean = parse_request("W 1300/0/1/0 i 1").unwrap().to_wire();
        assert_eq!(answer(&mut s, clean), Answer::Ok);
        let lin = parse_request("LIN X11 F6000").unwrap().to_wire();
        assert_eq!(answer(&mut s, lin), Answer::Ok);
        let exec = Request::Exec(None).to_wire();
        assert_eq!(answer(&mut s, exec), Answer::Ok);
        let after = info(&mut s);
        assert_eq!(after.cleans, 1);
        assert_eq!(after.cycles, 100, "10 mm at 100 mm/s in 1 ms cycles");
        let junk = WireRequest::Ext(crate::INFO_OP, bytes::Bytes::from_static(&[1]));
        assert_eq!(
            answer(&mut s, junk),
            Answer::Protocol(ProtocolError::BadPayload)
        );
    }

    #[test]
    fn the_journal_gets_every_request_with_its_answer_and_spooled_elements() {
        let mut s = EmulatorService::new([0.0; 8], CycleTime::DEFAULT);
        let lines = Lines::default();
        s.set_request_log(Box::new(lines.clone()));
        for text in [
            "LIN X1 F600",
            "R 1300/0/3/0 i",
            "EXEC 7",
            "W 1300/0/1/0 i 2",
        ] {
            answer(&mut s, parse_request(text).unwrap().to_wire());
        }
        answer(&mut s, crate::info_op::info_request());
        let got = lines.0.lock().unwrap().clone();
        assert_eq!(
            got,
            [
                "LIN X1 F600 => Ok",
                "<",
                "R 1300/0/3/0 i => Value(I32(17))",
                "EXEC 7 => Ok",
                "W 1300/0/1/0 i 2 => Access(Range)",
            ]
        );
        s.finish_request_log();
        assert!(!s.recording());
    }

    #[test]
    fn exec_in_real_time_waits_for_the_clock() {
        let mut s = EmulatorService::new([0.0; 8], CycleTime::DEFAULT);
        s.set_realtime(RealTimeFactor::new(10_000.0).unwrap());
        let lin = parse_request("LIN X1000 F60000").unwrap().to_wire();
        assert_eq!(answer(&mut s, lin), Answer::Ok);
        let Slice::Wait(mut w) = s.serve(Request::Exec(None).to_wire()) else {
            panic!("EXEC waits in real time");
        };
        // 1000 mm at 1000 mm/s: 1 s of machine time, 0.1 ms of wall time.
        let mut ticks = 0;
        while w.done.try_recv().is_err() {
            std::thread::sleep(std::time::Duration::from_millis(1));
            s.tick();
            ticks += 1;
            assert!(ticks < 10_000, "the wait never ended");
        }
        assert!(matches!(s.resume(w.token, true), Slice::Done(Answer::Ok)));
        assert_eq!(s.emu.position()[0], 1000.0);
        assert!(s.info().cycles >= 1000);
    }

    #[test]
    fn the_shared_emulator_never_logs() {
        let mut s = EmulatorService::new([0.0; 8], CycleTime::DEFAULT);
        let on = Request::SpoolLog { logging: true }.to_wire();
        assert_eq!(answer(&mut s, on), Answer::Access(AccessError::State));
        let lin = parse_request("LIN X1").expect("LIN").to_wire();
        assert_eq!(answer(&mut s, lin), Answer::Ok);
        assert!(s.emu.take_spool_log().is_empty());
        assert_eq!(s.emu.queue_len(), 1);
    }

    #[test]
    fn a_viewer_gets_every_spooled_element_and_the_recording_too() {
        let mut s = EmulatorService::new([0.0; 8], CycleTime::DEFAULT);
        let lin = |s: &mut EmulatorService, x: u32| {
            let req = parse_request(&format!("LIN X{x} F600")).unwrap().to_wire();
            assert_eq!(answer(s, req), Answer::Ok);
        };
        lin(&mut s, 1);
        assert!(s.take_watched_spool().records.is_empty(), "nobody watched");
        s.watch_spool(true);
        lin(&mut s, 2);
        let lines = Lines::default();
        s.set_request_log(Box::new(lines.clone()));
        lin(&mut s, 3);
        let seen = s.take_watched_spool();
        let ends: Vec<f64> = seen.records.iter().map(|r| r.end[0]).collect();
        assert_eq!((ends, seen.missed), (vec![2.0, 3.0], 0));
        assert!(lines.0.lock().unwrap().contains(&"<".to_string()));
        s.watch_spool(false);
        lin(&mut s, 4);
        assert!(s.take_watched_spool().records.is_empty());
        assert_eq!(lines.0.lock().unwrap().len(), 4, "the recording goes on");
        // Without a recording: what the viewer left untaken is not kept
        // for the next one.
        s.finish_request_log();
        s.watch_spool(true);
        lin(&mut s, 5);
        s.watch_spool(false);
        s.watch_spool(true);
        lin(&mut s, 6);
        let ends: Vec<f64> = s
            .take_watched_spool()
            .records
            .iter()
            .map(|r| r.end[0])
            .collect();
        assert_eq!(ends, [6.0]);
    }
}
