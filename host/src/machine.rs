//! [`Machine`]: one connection to a TC module, the Rust API of the
//! library. The C ABI (`crate::ffi`) is a thin layer over it.
//!
//! Every method takes `&self`: a machine holds its state behind one lock,
//! so one machine may be shared between threads (its calls are then
//! carried out one after the other), and different machines run in
//! parallel.

use std::collections::VecDeque;
use std::ffi::CString;
use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};
use std::time::{Duration, Instant};

use tc_module::{ArcDir, AxisPos, AxisWords, AXES};
use tc_request::{Motion, Reply, Request, SpoolRecord};
use uoi::{AccessError, Value};

use crate::error::{Error, ErrorCode, Result};
use crate::explain;
use crate::handles::{Handle, Handles};
use crate::link::{Embedded, Limits, Link};
use crate::objects::{find_object, Descriptor};
use crate::record::Recorder;
use crate::served::Served;
use crate::served_target::ServedTarget;
use crate::target::{EmbeddedOptions, Target};

/// How long a wait (`exec`) may last by default: the request timeout of
/// `addipos call`.
pub const DEFAULT_TIMEOUT: Duration = Duration::from_secs(30);

/// The environment variable naming the file a connection opened from a
/// target string records its session into.
pub const RECORD_ENV: &str = "ADDIPOS_RECORD";

/// Recordings `$ADDIPOS_RECORD` started in this process.
static RECORDINGS: AtomicU64 = AtomicU64::new(0);

/// Most spooled elements that wait for [`Machine::take_spooled`].
const SPOOL_LOG_LIMIT: usize = 1_000_000;

/// Connections opened so far in this process (for handle tags).
static OPENED: AtomicU64 = AtomicU64::new(0);

/// One connection to a TC module.
#[derive(Debug)]
pub struct Machine {
    session: Mutex<Session>,
    /// Set by [`Machine::close`]: a wait in progress ends.
    closing: AtomicBool,
    /// The target, as a target string names it.
    target: String,
    /// Whether the target is a server (not an emulator inside the
    /// process).
    served: bool,
}

/// The state behind the lock.
struct Session {
    link: Box<dyn Link>,
    handles: Handles,
    recorder: Option<Recorder>,
    /// The elements spooled and not yet taken, while the caller logs them.
    spool_log: Option<VecDeque<SpoolRecord>>,
    /// Why the recording stopped, if it did.
    record_failure: Option<String>,
    /// The last failure, in words, for C (`addipos_error_text`).
    failure: CString,
    /// Requests carried out so far.
    requests: u64,
    /// Whether the current call's outcome is in the recording already.
    recorded: bool,
    timeout: Duration,
}

impl std::fmt::Debug for Session {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Session")
            .field("target", &self.link.describe())
            .field("requests", &self.requests)
            .finish_non_exhaustive()
    }
}

impl Machine {
    /// Opens a target string (`""`: `$ADDIPOS_TARGET`, else `embedded`;
    /// see [`crate::target`]).
    ///
    /// With `$ADDIPOS_RECORD` set to a file name, the connection records
    /// its session into that file (the first connection of the process;
    /// later ones into `FILE.2`, `FILE.3`, ...). A file that cannot be
    /// created leaves the connection open but not recording: a line on
    /// standard error and [`record_failure`](Self::record_failure) say
    /// why.
    pub fn open(target: &str) -> Result<Self> {
        let m = Self::open_target(&Target::parse(target)?)?;
        m.record_from_env();
        Ok(m)
    }

    /// Starts the recording `$ADDIPOS_RECORD` asks for, if it does.
    fn record_from_env(&self) {
        let Some(file) = std::env::var_os(RECORD_ENV).filter(|f| !f.is_empty()) else {
            return;
        };
        let n = RECORDINGS.fetch_add(1, Ordering::Relaxed);
        let mut path = PathBuf::from(file);
        if n > 0 {
            let mut name = path.clone().into_os_string();
            name.push(format!(".{}", n + 1));
            path = PathBuf::from(name);
        }
        if let Err(e) = self.record(&path) {
            let why = format!(
                "{RECORD_ENV}: {}; this connection is not recorded",
                e.message()
            );
            eprintln!("libaddipos: {why}");
            self.lock().record_failure = Some(why);
        }
    }

    /// Opens a target.
    pub fn open_target(target: &Target) -> Result<Self> {
        match target {
            Target::Embedded(opts) => Ok(Self::embedded(opts.clone())),
            Target::Served(addr) => Self::served(addr),
        }
    }

    /// A connection to a running `addipos serve` at `addr` (`HOST:PORT`,
    /// `localhost:PORT` or a bare `PORT`): `Connection` when none answers
    /// there within 5 s.
    pub fn served(addr: &str) -> Result<Self> {
        Self::served_within(addr, DEFAULT_TIMEOUT)
    }

    /// As [`served`](Self::served), every request (the first, `INFO`,
    /// included) waiting at most `timeout` for its answer.
    pub fn served_within(addr: &str, timeout: Duration) -> Result<Self> {
        let link = Served::connect(&ServedTarget::parse(addr)?, timeout)?;
        let mut m = Self::with_link(Box::new(link));
        m.served = true;
        m.lock().timeout = timeout;
        Ok(m)
    }

    /// A fresh emulator inside this process.
    pub fn embedded(opts: EmbeddedOptions) -> Self {
        Self::with_link(Box::new(Embedded::new(opts)))
    }

    fn with_link(link: Box<dyn Link>) -> Self {
        let serial = OPENED.fetch_add(1, Ordering::Relaxed);
        Self {
            target: link.describe(),
            session: Mutex::new(Session {
                link,
                handles: Handles::new(serial),
                recorder: None,
                spool_log: None,
                record_failure: None,
                failure: CString::default(),
                requests: 0,
                recorded: false,
                timeout: DEFAULT_TIMEOUT,
            }),
            closing: AtomicBool::new(false),
            served: false,
        }
    }

    /// The target, as a target string names it.
    pub fn target(&self) -> &str {
        &self.target
    }

    /// The real-time factor, if the machine runs in real time.
    pub fn realtime(&self) -> Option<f64> {
        self.lock().link.realtime()
    }

    /// Whether [`exec`](Self::exec) waits for something outside the
    /// calling thread (a clock, a server), rather than computing.
    pub fn exec_waits(&self) -> bool {
        self.served || self.realtime().is_some()
    }

    /// Locks the session (a call that panicked left it usable).
    fn lock(&self) -> MutexGuard<'_, Session> {
        self.session.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Runs `f` on the session; a failure is kept as the last failure and,
    /// when the recording does not hold it yet, written there as a
    /// comment.
    fn with<T>(&self, f: impl FnOnce(&mut Session) -> Result<T>) -> Result<T> {
        let mut s = self.lock();
        s.recorded = false;
        let out = f(&mut s);
        if let Err(e) = &out {
            if !s.recorded {
                s.note(&format!("{}: {}", e.code().name(), e.message()));
            }
            s.fail(e.message());
        }
        out
    }

    /// Refuses a call before it reaches the target (a wrapper's check of
    /// its arguments: the C ABI's NULL pointers, a Python value): `e` is
    /// kept as the last failure (and noted in the recording).
    pub fn refuse(&self, e: Error) -> Result<()> {
        self.with(|_| Err(e))
    }

    /// As [`refuse`](Self::refuse), giving the error back.
    pub fn refuse_with(&self, e: Error) -> Error {
        self.refuse(e.clone()).err().unwrap_or(e)
    }

    /// The last failure on this machine, in words (`""`: none yet).
    pub fn last_failure(&self) -> String {
        self.lock().failure.to_string_lossy().into_owned()
    }

    /// Calls `f` with the last failure as a C string, under the lock.
    pub fn with_failure<T>(&self, f: impl FnOnce(&CString) -> T) -> T {
        f(&self.lock().failure)
    }

    /// How long a wait ([`exec`](Self::exec)) may last, and, on a server
    /// target, any request (the TCP connection is made again with it at
    /// the next call).
    pub fn set_timeout(&self, timeout: Duration) {
        let mut s = self.lock();
        s.timeout = timeout;
        let _ = s.link.set_timeout(timeout);
    }

    /// Stops a wait in progress and makes every later wait end at once
    /// (the C ABI's `addipos_close` does this before it lets go).
    pub fn close(&self) {
        self.closing.store(true, Ordering::Relaxed);
        let mut s = self.lock();
        s.stop_recording();
    }
}

/// Handles.
impl Machine {
    /// A handle to the object `d` names; refused (`NoObject`,
    /// `NoSubindex`) when no such object exists.
    pub fn handle(&self, d: &Descriptor) -> Result<Handle> {
        self.with(|s| {
            let (addr, ty) =
                find_object(d).map_err(|e| Error::access(e, format!("uoi_init {d}")))?;
            let epoch = s.link.clean_epoch()?;
            let h = s
                .handles
                .issue(crate::handles::Target { addr, ty }, epoch)?;
            s.note(&format!("uoi_init {addr} -> handle {h}"));
            Ok(h)
        })
    }

    /// Releases a handle: it answers `StaleHandle` from now on, and its
    /// place may be given out again.
    pub fn release(&self, h: Handle) -> Result<()> {
        self.with(|s| s.handles.release(h))
    }

    /// Reads an i32 object.
    pub fn read_int(&self, h: Handle) -> Result<i32> {
        let v = self.read(h, uoi::ValueType::I32, "uoi_read_int")?;
        v.as_i32().ok_or_else(|| wrong_type(&v))
    }

    /// Reads an f64 object (an i32 object answers `TypeMismatch`).
    pub fn read_double(&self, h: Handle) -> Result<f64> {
        let v = self.read(h, uoi::ValueType::F64, "uoi_read_double")?;
        v.as_f64().ok_or_else(|| wrong_type(&v))
    }

    /// Writes an i32 object.
    pub fn write_int(&self, h: Handle, value: i32) -> Result<()> {
        self.write(h, Value::I32(value), "uoi_write_int")
    }

    /// Writes an f64 object.
    pub fn write_double(&self, h: Handle, value: f64) -> Result<()> {
        self.write(h, Value::F64(value), "uoi_write_double")
    }

    fn read(&self, h: Handle, ty: uoi::ValueType, call: &str) -> Result<Value> {
        self.with(|s| {
            s.tick();
            let (t, epoch) = s.handles.lookup(h, call)?;
            let req = Request::Read(t.addr, ty);
            let Some(reply) = s.link.call_in_epoch(&req, epoch)? else {
                return Err(Handles::voided(h, t, call));
            };
            match s.answered(&req, reply, || format!("{call} {}", t.addr))? {
                Reply::Value(v) => Ok(v),
                other => Err(unexpected(&other)),
            }
        })
    }

    fn write(&self, h: Handle, value: Value, call: &str) -> Result<()> {
        self.with(|s| {
            s.tick();
            let (t, epoch) = s.handles.lookup(h, call)?;
            let req = Request::Write(t.addr, value);
            let Some(reply) = s.link.call_in_epoch(&req, epoch)? else {
                return Err(Handles::voided(h, t, call));
            };
            s.answered(&req, reply, || format!("{call} {} = {value}", t.addr))
                .map(|_| ())
        })
    }
}

/// Motion and the executor.
impl Machine {
    /// `LIN`: a feed line to the absolute end point `words` (axes not
    /// named keep their value); `feed` in units/min sets the modal feed.
    pub fn lin(&self, words: AxisWords, feed: Option<f64>) -> Result<()> {
        self.motion(Motion::Lin { words, feed })
    }

    /// `RAP`: a rapid line (`feed` only sets the modal feed).
    pub fn rap(&self, words: AxisWords, feed: Option<f64>) -> Result<()> {
        self.motion(Motion::Rap { words, feed })
    }

    /// `CIR`: an arc in the main plane to `words`, with the centre offsets
    /// `I J K` from the start along the axes allocated as X, Y, Z.
    pub fn cir(
        &self,
        dir: ArcDir,
        words: AxisWords,
        centre: [Option<f64>; 3],
        feed: Option<f64>,
    ) -> Result<()> {
        self.motion(Motion::Cir {
            dir,
            words,
            centre,
            feed,
        })
    }

    /// `JA`: direct positioning of the named axes (drops what waits in
    /// the spooler and the correction buffer).
    pub fn ja(&self, words: AxisWords) -> Result<()> {
        self.motion(Motion::Ja { words })
    }

    /// `JS`: direct stop of the axes set in `axes`.
    pub fn js(&self, axes: [bool; AXES]) -> Result<()> {
        self.motion(Motion::Js { axes })
    }

    /// `SSF`: special function `function` to machine axis `axis` (0..7;
    /// 2001 spools the held profile).
    pub fn ssf(&self, axis: usize, function: i32) -> Result<()> {
        let axis = u8::try_from(axis)
            .ok()
            .filter(|&a| usize::from(a) < AXES)
            .ok_or_else(|| Error::argument(format!("tc_ssf: axis {axis} is not 0..7")))?;
        self.motion(Motion::Ssf { axis, function })
    }

    /// `RS`: the legacy `rs()`, the coordinate rotation back to 0.
    pub fn rs(&self) -> Result<()> {
        self.motion(Motion::Rs)
    }

    fn motion(&self, m: Motion) -> Result<()> {
        self.with(|s| {
            s.tick();
            s.request(&Request::Motion(m), || format!("{m}"))
                .map(|_| ())
        })
    }

    /// `EXEC`: `Some(n)` runs `n` cycles, `None` until the spooler is
    /// empty. Stepped, the executor runs them now; in real time the call
    /// waits until the clock has run them (or the spooler is empty),
    /// never ahead of the clock. Either way it returns at the latest
    /// after the timeout ([`set_timeout`](Self::set_timeout)) with
    /// `Timeout`; what ran stays run.
    pub fn exec(&self, cycles: Option<u64>) -> Result<()> {
        self.exec_until(cycles, &AtomicBool::new(false))
    }

    /// As [`exec`](Self::exec), given up as soon as `interrupt` is set
    /// (by another thread: a Python program's Ctrl-C): the wait ends at
    /// once with `Timeout`; what ran stays run (a server target's
    /// connection is dropped, the next call connects again).
    pub fn exec_until(&self, cycles: Option<u64>, interrupt: &AtomicBool) -> Result<()> {
        let closing = &self.closing;
        self.with(|s| {
            s.tick();
            let limits = Limits {
                deadline: Instant::now() + s.timeout,
                closing,
                interrupt,
            };
            let mut ran: Vec<Request> = Vec::new();
            let out = s.link.exec(cycles, limits, &mut |r| ran.push(r.clone()));
            if s.link.realtime().is_some() || out.is_err() {
                s.note(&format!("tc_exec {}", Request::Exec(cycles)));
            }
            s.requests += 1;
            for r in &ran {
                s.record(|rec| rec.ran(r));
            }
            s.flush_recording();
            out
        })
    }

    /// The executed position.
    pub fn position(&self) -> Result<AxisPos> {
        self.with(|s| {
            s.tick();
            match s.request(&Request::Pos, || "tc_pos".to_string())? {
                Reply::Pos(p) => Ok(p),
                other => Err(unexpected(&other)),
            }
        })
    }

    /// Motion waiting: elements in the spooler and plane-null profiles
    /// waiting with the held profile.
    pub fn queue(&self) -> Result<u64> {
        self.with(|s| {
            s.tick();
            match s.request(&Request::Queue, || "tc_queue".to_string())? {
                Reply::Queue(n) => Ok(n),
                other => Err(unexpected(&other)),
            }
        })
    }
}

/// Recording.
impl Machine {
    /// Records the session into the file `path` (created, or emptied).
    /// Only before the first request: a trace replays from a fresh
    /// emulator.
    pub fn record(&self, path: &Path) -> Result<()> {
        self.with(|s| {
            s.may_record()?;
            let file = File::create(path).map_err(|e| {
                Error::new(
                    ErrorCode::Record,
                    format!("addipos_record {}: cannot create: {e}", path.display()),
                )
            })?;
            s.start_recording(Box::new(file))
        })
    }

    /// Records the session into `out`.
    pub fn record_to(&self, out: Box<dyn Write + Send>) -> Result<()> {
        self.with(|s| s.start_recording(out))
    }

    /// Ends the recording: everything written is handed to the file.
    pub fn stop_recording(&self) {
        self.lock().stop_recording();
    }

    /// Whether a recording is going on.
    pub fn recording(&self) -> bool {
        self.lock().recorder.is_some()
    }

    /// Keeps the elements every request spools from now on, for
    /// [`take_spooled`](Self::take_spooled) (at most the last
    /// 1,000,000 wait), or stops keeping them.
    pub fn set_spool_log(&self, on: bool) {
        let mut s = self.lock();
        s.spool_log = on.then(|| s.spool_log.take().unwrap_or_default());
        s.sync_spool_log();
    }

    /// The elements spooled since the last call, while the spool log is
    /// on.
    pub fn take_spooled(&self) -> Vec<SpoolRecord> {
        self.lock()
            .spool_log
            .as_mut()
            .map(|l| l.drain(..).collect())
            .unwrap_or_default()
    }

    /// Why the recording stopped, if a write failed.
    pub fn record_failure(&self) -> Option<String> {
        self.lock().record_failure.clone()
    }
}

/// A value of the other type than the one asked for (a target never
/// answers one: it is refused where the answer is read).
fn wrong_type(v: &Value) -> Error {
    Error::new(
        ErrorCode::Protocol,
        format!("a value of the other type was answered ({v}): not taken"),
    )
}

fn unexpected(reply: &Reply) -> Error {
    Error::new(ErrorCode::Internal, format!("unexpected answer {reply:?}"))
}

impl Session {
    /// Keeps `message` as the last failure.
    fn fail(&mut self, message: &str) {
        let text = message.replace('\0', " ");
        self.failure = CString::new(text).unwrap_or_default();
    }

    /// Runs the cycles the clock owes; the recording gets them as
    /// `EXEC n`.
    fn tick(&mut self) {
        let n = self.link.tick();
        if n > 0 {
            self.record(|r| r.ran(&Request::Exec(Some(n))));
        }
    }

    /// One request to the target, recorded with its answer and what it
    /// spooled; an access error explained with `what`.
    fn request(&mut self, req: &Request, what: impl FnOnce() -> String) -> Result<Reply> {
        let reply = self.link.run(req)?;
        self.answered(req, reply, what)
    }

    /// What [`request`](Self::request) does once the reply is in.
    fn answered(
        &mut self,
        req: &Request,
        reply: Reply,
        what: impl FnOnce() -> String,
    ) -> Result<Reply> {
        self.requests += 1;
        let beside = self.link.take_beside();
        if beside > 0 {
            self.record(|r| r.ran(&Request::Exec(Some(beside))));
        }
        if let (Request::Read(addr, ty), Some(_)) = (req, &self.recorder) {
            self.record(|r| r.read(*addr, *ty, &reply));
            self.recorded = true;
        } else if self.recorder.is_some() || self.spool_log.is_some() {
            let spooled = self.link.take_spooled()?;
            if self.recorder.is_some() {
                let axis_nr = self.link.axis_nr()?;
                self.record(|r| r.exchange(req, &reply, &spooled, axis_nr));
                self.recorded = true;
            }
            if let Some(log) = &mut self.spool_log {
                log.extend(spooled);
                let over = log.len().saturating_sub(SPOOL_LOG_LIMIT);
                log.drain(..over);
            }
        }
        if let Some(w) = self.link.take_warning() {
            self.note(&w);
        }
        match reply {
            Reply::Access(e) => Err(self.explained(req, e, what())),
            Reply::Protocol(uoi::wire::ProtocolError::Stopped) => Err(Error::new(
                ErrorCode::Stopped,
                format!(
                    "{}: the server stopped the request before its end (it is shutting down)",
                    what()
                ),
            )),
            Reply::Protocol(p) => Err(Error::new(ErrorCode::Protocol, format!("{}: {p}", what()))),
            other => Ok(other),
        }
    }

    /// The error of `req` refused with `e`, with why when the library can
    /// tell (the range of the object, the smallest feed, the faulted
    /// group: `crate::explain`).
    fn explained(&mut self, req: &Request, e: AccessError, what: String) -> Error {
        let why = match (req, e) {
            (Request::Write(addr, v), AccessError::Range) => explain::write_range(*addr, *v),
            (Request::Motion(m), AccessError::Range) => {
                explain::motion_range(m, self.link.cycle_s())
            }
            (Request::Motion(_), AccessError::State) => self.faulted_groups(req, e),
            _ => None,
        };
        let base = Error::access(e, what);
        match why {
            Some(why) => Error::new(base.code(), format!("{}: {why}", base.message())),
            None => base,
        }
    }

    /// The faulted groups, read from their ERROR registers (reads change
    /// nothing; they are not part of the recording).
    fn faulted_groups(&mut self, req: &Request, e: AccessError) -> Option<String> {
        let errors: Vec<(u16, Option<i32>)> = explain::error_registers(req, e)
            .into_iter()
            .map(|(g, addr)| {
                let read = self.link.run(&Request::Read(addr, uoi::ValueType::I32));
                let bits = match read {
                    Ok(Reply::Value(v)) => v.as_i32(),
                    _ => None,
                };
                (g, bits)
            })
            .collect();
        explain::faulted_groups(&errors)
    }

    /// Writes to the recording, if one goes on; a write error stops it
    /// and says why in the last failure.
    fn record(&mut self, write: impl FnOnce(&mut Recorder) -> std::io::Result<()>) {
        let Some(r) = self.recorder.as_mut() else {
            return;
        };
        if let Err(e) = write(r) {
            self.recorder = None;
            self.sync_spool_log();
            let why = format!("the recording stopped: cannot write: {e}");
            self.fail(&why);
            self.record_failure = Some(why);
        }
    }

    /// A comment in the recording.
    fn note(&mut self, text: &str) {
        self.record(|r| r.comment(text));
    }

    fn flush_recording(&mut self) {
        self.record(Recorder::flush);
    }

    /// Whether a recording may start: before the first request, once.
    fn may_record(&self) -> Result<()> {
        if self.requests > 0 || self.recorder.is_some() {
            return Err(Error::new(
                ErrorCode::Record,
                "addipos_record: a recording starts before the first request of a connection, \
                 once (a trace replays from a fresh emulator)",
            ));
        }
        Ok(())
    }

    fn start_recording(&mut self, out: Box<dyn Write + Send>) -> Result<()> {
        self.may_record()?;
        let header = self.link.record_header();
        let rec = Recorder::start(out, &header).map_err(|e| {
            Error::new(
                ErrorCode::Record,
                format!("addipos_record: cannot write: {e}"),
            )
        })?;
        self.recorder = Some(rec);
        self.sync_spool_log();
        self.record_failure = None;
        Ok(())
    }

    fn stop_recording(&mut self) {
        self.flush_recording();
        self.recorder = None;
        self.sync_spool_log();
    }

    /// The target logs spooled elements while someone takes them.
    fn sync_spool_log(&mut self) {
        let on = self.recorder.is_some() || self.spool_log.is_some();
        self.link.set_spool_log(on);
    }
}
