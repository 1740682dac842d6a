//! A connection to a running `addipos serve`: the second [`Link`], over
//! the UOI wire (docs/protocol.md) with the one wire client
//! ([`WireClient`], `crate::wire_client`).
//!
//! * Every call is bounded in time: connecting by [`CONNECT_TIMEOUT`],
//!   each request by the connection's timeout (30 s,
//!   `addipos_set_timeout`). A server that does not answer in time gives
//!   `Timeout`, one that went away (or refused) `Connection`, each with
//!   the address and what to do; the TCP connection is dropped then and
//!   the next call connects again (the shared emulator keeps its state).
//! * Handles and Clean: `INFO` (op `0x23`) reports the emulator's Clean
//!   count. A read goes out in one write together with an `INFO` before
//!   it (one round trip); a write, a handle and a motion ask `INFO` first.
//!   A Clean by any connection or face voids the handles issued before
//!   it.
//! * Time: the server's. `EXEC` on a stepped server runs the cycles
//!   there; on a server in real time it waits for the server's clock.
//! * Recording: the wire shows requests and answers, not what the shared
//!   emulator spooled. While a recording goes on, the library runs a
//!   shadow emulator of its own with the server's settings (from `INFO`)
//!   on the same requests and writes the elements *it* spools as `<`
//!   lines; the cycles the server ran beside this connection's requests
//!   (its clock, other clients) as `EXEC n`, counted from `INFO` before
//!   each call; in real time a read is sent between two `INFO`s until
//!   both name the same cycle, so it lands after exactly the cycles it
//!   followed (a motion or write, which cannot be sent twice, after an
//!   `INFO` in the same write: a tick of the server's clock may fall
//!   between them). An answer of the server that
//!   the shadow does not give is written as a warning comment: the trace
//!   then does not replay (the server had other clients, or did not start
//!   fresh).

use std::time::Duration;

use emulator::info_op::info_request;
use emulator::{Emulator, EmulatorInfo, GuardedOutcome, GuardedWrite};
use tc_module::CycleTime;
use tc_request::{Reply, Request, Runner, SpoolRecord};
use uoi::tcp::{ClientError, ClientOptions, Waited};
use uoi::wire::{Answer, ProtocolError, Request as WireRequest};

use crate::error::{Error, ErrorCode, Result};
use crate::handles::Epoch;
use crate::link::{Limits, Link};
use crate::record::RecordHeader;
use crate::served_target::ServedTarget;
use crate::wire_client::{WireClient, WireError};

/// Longest wait for a server to accept a connection.
pub const CONNECT_TIMEOUT: Duration = Duration::from_secs(5);

/// A running `addipos serve`.
pub struct Served {
    /// The address as the target string gave it.
    name: String,
    /// The connection, with the access token and the timeouts (a child
    /// after `fork` does not use its parent's socket).
    wire: WireClient,
    /// What `INFO` answered last.
    info: EmulatorInfo,
    /// While recording: the shadow emulator whose spool log gives the
    /// `<` lines.
    shadow: Option<Emulator>,
    /// A warning for the recording (the shadow and the server differ).
    warning: Option<String>,
    /// Whether the recording has been warned already.
    warned: bool,
    /// The server's executor cycles the recording has accounted for
    /// (as this connection's `EXEC` or as `EXEC n` beside it).
    accounted: u64,
    /// Cycles beside this connection's requests run on the shadow and not
    /// yet handed to the recording.
    beside: u64,
}

/// Most times a read in a real-time recording is sent again to pin it to
/// one cycle of the server's clock.
const PIN_TRIES: usize = 8;

impl std::fmt::Debug for Served {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Served({})", self.name)
    }
}

impl Served {
    /// Connects to the server `target` names and asks it `INFO`; every
    /// request waits at most `timeout`.
    pub fn connect(target: &ServedTarget, timeout: Duration) -> Result<Self> {
        let name = target.address.as_str();
        let opts = ClientOptions {
            connect_timeout: CONNECT_TIMEOUT,
            request_timeout: timeout,
            token: target.token.clone(),
        };
        let wire = WireClient::new(name, opts)
            .map_err(|e| Error::new(ErrorCode::Connection, format!("target `{name}`: {e}")))?;
        let mut s = Self {
            name: name.to_string(),
            wire,
            info: EmulatorInfo {
                cleans: 0,
                realtime: None,
                cycles: 0,
                cycle_s: CycleTime::DEFAULT.secs(),
                spool_capacity: tc_module::DEFAULT_SPOOL_CAPACITY as u64,
                start: [0.0; tc_module::AXES],
                server: 0,
            },
            shadow: None,
            warning: None,
            warned: false,
            accounted: 0,
            beside: 0,
        };
        s.refresh().map_err(|e| opening(e, name))?;
        Ok(s)
    }

    /// The library error of a failed exchange of the wire client.
    fn wire_failure(&mut self, e: WireError, what: &str) -> Error {
        match e {
            WireError::Connect(e) => self.failure(e, "connect"),
            WireError::Exchange(e) => self.failure(e, what),
            WireError::Unexpected(ans) => self.unreadable(what, &ans),
            WireError::Address(m) => Error::new(
                ErrorCode::Connection,
                format!("target `{}`: {m}", self.name),
            ),
            WireError::Forked { pid } => Error::new(
                ErrorCode::Connection,
                format!(
                    "this connection to the server at {} was opened by process {pid} before a \
                     fork: a child process cannot use it (the two would read each other's \
                     answers); open a connection of its own in the child with addipos_open",
                    self.name
                ),
            ),
        }
    }

    /// The library error of a failed exchange; a lost or timed-out
    /// connection is dropped, so that the next call connects again.
    fn failure(&mut self, e: ClientError, what: &str) -> Error {
        let at = &self.name;
        let (code, text) = match &e {
            ClientError::TimedOut {
                waited: Waited::Answer,
                after,
                ..
            } => (
                ErrorCode::Timeout,
                format!(
                    "{what}: the server at {at} did not answer within {} s (the connection's \
                     timeout, addipos_set_timeout); the request may still be carried out there. \
                     The next call connects again",
                    after.as_secs_f64()
                ),
            ),
            ClientError::TimedOut { .. } => (
                ErrorCode::Connection,
                format!(
                    "{what}: no connection to the server at {at} within {} s: is `addipos serve` \
                     running there?",
                    CONNECT_TIMEOUT.as_secs()
                ),
            ),
            ClientError::Io(io) if io.kind() == std::io::ErrorKind::Interrupted => (
                ErrorCode::Connection,
                format!("{what}: the wait was given up"),
            ),
            ClientError::Io(io) => (
                ErrorCode::Connection,
                format!(
                    "{what}: the connection to the server at {at} failed ({io}): is `addipos \
                     serve` running there? The next call connects again"
                ),
            ),
            ClientError::Protocol(ProtocolError::Unauthorized) => (
                ErrorCode::Protocol,
                format!(
                    "{what}: the server at {at} asks for its access token: give it with \
                     ADDIPOS_TOKEN, ADDIPOS_TOKEN_FILE or the target option token_file=FILE \
                     (docs/host-api.md, \"Targets\")"
                ),
            ),
            ClientError::Protocol(p) => (
                ErrorCode::Protocol,
                format!("{what}: the server at {at} refused the request: {p}. {AGAIN}"),
            ),
            other => (
                ErrorCode::Protocol,
                format!(
                    "{what}: the server at {at} answered what the library cannot read: {other}. \
                     {AGAIN}"
                ),
            ),
        };
        // Whatever went wrong, the connection is not trusted any more:
        // its answers may be out of step with its requests.
        self.wire.disconnect();
        Error::new(code, text)
    }

    /// A protocol failure of an answer the library cannot take: the
    /// connection is dropped (the next call connects again).
    fn unreadable(&mut self, what: impl std::fmt::Display, ans: &Answer) -> Error {
        self.wire.disconnect();
        Error::new(
            ErrorCode::Protocol,
            format!(
                "{what}: the server at {} answered {ans:?}, which is not an answer to it. {AGAIN}",
                self.name
            ),
        )
    }

    /// Asks `INFO` and keeps the answer.
    fn refresh(&mut self) -> Result<EmulatorInfo> {
        let ans = self.exchange(&[info_request()], "INFO")?;
        self.keep_info(&ans[0])
    }

    fn keep_info(&mut self, ans: &Answer) -> Result<EmulatorInfo> {
        let Some(info) = EmulatorInfo::from_wire(ans) else {
            self.wire.disconnect();
            if let Answer::Protocol(p) = ans {
                return Err(self.failure(ClientError::Protocol(*p), "INFO"));
            }
            return Err(Error::new(
                ErrorCode::Protocol,
                format!(
                    "the server at {} does not answer INFO ({ans:?}): it is not an addipos serve \
                     of this version",
                    self.name
                ),
            ));
        };
        self.info = info;
        Ok(info)
    }

    /// Sends `reqs` in one write and reads their answers.
    fn exchange(&mut self, reqs: &[WireRequest], what: &str) -> Result<Vec<Answer>> {
        let out = self.wire.exchange(reqs);
        out.map_err(|e| self.wire_failure(e, what))
    }

    /// As [`exchange`](Self::exchange), given up as soon as `stop` says
    /// so (the connection is then dropped).
    fn exchange_until(
        &mut self,
        reqs: &[WireRequest],
        what: &str,
        stop: &dyn Fn() -> bool,
    ) -> Result<Vec<Answer>> {
        let out = self.wire.exchange_until(reqs, stop);
        out.map_err(|e| self.wire_failure(e, what))
    }

    /// The reply of the server to `req`, decoded; an answer of another
    /// shape than `req`'s (a value of the other type, a position to a
    /// write, ...) is never taken as a reply: `Protocol`, and the
    /// connection is dropped. A refusal of the protocol drops it too.
    fn reply(&mut self, req: &Request, ans: &Answer) -> Result<Reply> {
        let reply = Reply::from_wire(req.wire_op(), ans).filter(|r| fits(req, r));
        match reply {
            None => Err(self.unreadable(req, ans)),
            Some(r) => {
                if matches!(r, Reply::Protocol(_)) {
                    self.wire.disconnect();
                }
                Ok(r)
            }
        }
    }

    /// While recording: the shadow carries out `req` too; a different
    /// answer becomes a warning.
    fn follow(&mut self, req: &Request, reply: &Reply) {
        let Some(shadow) = self.shadow.as_mut() else {
            return;
        };
        let own = shadow.run(req);
        if own != *reply && !self.warned {
            self.warned = true;
            self.warning = Some(format!(
                "WARNING: the server answered {reply:?} where an emulator started fresh with its \
                 settings answers {own:?}: it had other clients, ran in real time or did not start \
                 fresh, so this trace does not replay as it stands"
            ));
        }
    }

    /// The cycles the server ran since the last look (its clock, other
    /// clients): run on the shadow and returned, for the recording.
    fn cycles_beside(&mut self) -> Result<u64> {
        let now = self.refresh()?.cycles;
        self.account(now);
        Ok(std::mem::take(&mut self.beside))
    }

    /// The server's executor has run `cycles`: those not accounted for
    /// yet are run on the shadow and kept for the recording.
    fn account(&mut self, cycles: u64) {
        let n = cycles.saturating_sub(self.accounted);
        self.accounted = self.accounted.max(cycles);
        if n > 0 {
            if let Some(shadow) = self.shadow.as_mut() {
                shadow.exec(Some(n));
            }
            self.beside += n;
        }
    }

    /// Sends `req`, with an `INFO` before it when `info` asks for one or
    /// a real-time recording needs the cycle it was served at. There a
    /// read (`READ`, `POS`, `QUEUE`, which change nothing) goes as `INFO`,
    /// the read, `INFO`, again until both `INFO`s name the same cycle (at
    /// most [`PIN_TRIES`] times), so that the recording puts it after
    /// exactly the cycles it followed.
    fn send(&mut self, req: &Request, info: bool) -> Result<(Option<EmulatorInfo>, Answer)> {
        self.send_as(req, req.to_wire(), info)
    }

    /// Sends `req` as `wire` (its guarded form, say): see
    /// [`send`](Self::send).
    fn send_as(
        &mut self,
        req: &Request,
        wire: WireRequest,
        info: bool,
    ) -> Result<(Option<EmulatorInfo>, Answer)> {
        let pin = self.shadow.is_some() && self.info.realtime.is_some();
        let what = req.to_string();
        if !pin && !info {
            let mut ans = self.exchange(&[wire], &what)?;
            return Ok((None, ans.swap_remove(0)));
        }
        let reads = matches!(req, Request::Read(..) | Request::Pos | Request::Queue);
        let mut reqs = vec![info_request(), wire];
        if pin && reads {
            reqs.push(info_request());
        }
        for tries in 1.. {
            let mut ans = self.exchange(&reqs, &what)?;
            let before = self.keep_info(&ans[0])?;
            let after = ans.get(2).and_then(EmulatorInfo::from_wire);
            if after.is_none_or(|a| a.cycles == before.cycles) || tries >= PIN_TRIES {
                if pin {
                    self.account(before.cycles);
                }
                return Ok((Some(before), ans.swap_remove(1)));
            }
        }
        Err(Error::new(ErrorCode::Internal, "no try"))
    }
}

impl Served {
    /// A write through a handle of Clean epoch `epoch`, as one `WRITE_IF`:
    /// the server carries it out only if it is still the server, in the
    /// epoch, the handle was issued in (`None`: it did not).
    fn write_in_epoch(
        &mut self,
        addr: uoi::ObjectAddress,
        value: uoi::Value,
        epoch: Epoch,
    ) -> Result<Option<Reply>> {
        let guarded = GuardedWrite {
            server: epoch.server,
            cleans: epoch.cleans,
            addr,
            value,
        };
        let req = Request::Write(addr, value);
        let (_, ans) = self.send_as(&req, guarded.to_wire(), false)?;
        match GuardedOutcome::from_wire(&ans) {
            Some(GuardedOutcome::Voided(info)) => {
                self.info = info;
                Ok(None)
            }
            Some(GuardedOutcome::Written(a)) => {
                let reply = self.reply(&req, &a)?;
                self.follow(&req, &reply);
                Ok(Some(reply))
            }
            None => Err(self.unreadable(&req, &ans)),
        }
    }
}

/// The Clean epoch an `INFO` answer names.
fn epoch_of(info: &EmulatorInfo) -> Epoch {
    Epoch {
        server: info.server,
        cleans: info.cleans,
    }
}

/// Said after a protocol failure.
const AGAIN: &str = "The connection is closed; the next call connects again";

/// An open that failed says so (there is no next call to connect again).
fn opening(e: Error, name: &str) -> Error {
    let text = e
        .message()
        .replace(" The next call connects again", " Nothing was opened");
    let text = text.replace(AGAIN, &format!("No connection to {name} was opened"));
    Error::new(e.code(), text)
}

/// Whether `reply` is of a shape that answers `req`: a value of the type
/// asked for to a read, a position to `POS`, ...; a refusal answers
/// anything.
fn fits(req: &Request, reply: &Reply) -> bool {
    match (req, reply) {
        (_, Reply::Access(_) | Reply::Protocol(_)) => true,
        (Request::Read(_, ty), Reply::Value(v)) => v.value_type() == *ty,
        (Request::Pos, Reply::Pos(_)) => true,
        (Request::Queue, Reply::Queue(_)) => true,
        (Request::Read(..) | Request::Pos | Request::Queue, _) => false,
        (Request::SpoolLog { .. }, Reply::Spool(..)) => true,
        (_, Reply::Ok) => true,
        _ => false,
    }
}

/// What an `EXEC`'s reply means for `tc_exec`: every answer but `Ok` is
/// an error; `Stopped` (the server shut down during the wait) its own.
fn exec_outcome(what: &str, server: &str, reply: Reply) -> Result<()> {
    match reply {
        Reply::Ok => Ok(()),
        Reply::Access(e) => Err(Error::access(e, what)),
        Reply::Protocol(ProtocolError::Stopped) => Err(Error::new(
            ErrorCode::Stopped,
            format!(
                "{what}: the server at {server} stopped the request before its end (it is \
                 shutting down): the motion did not run to its end; what ran stays run"
            ),
        )),
        Reply::Protocol(p) => Err(Error::new(
            ErrorCode::Protocol,
            format!("{what}: the server at {server} refused it: {p}. {AGAIN}"),
        )),
        other => Err(Error::new(
            ErrorCode::Protocol,
            format!("{what}: the server at {server} answered {other:?}. {AGAIN}"),
        )),
    }
}

/// The server as a runner of requests. The wire does not show what the
/// shared emulator spooled: the spooled elements are those of the shadow
/// emulator a recording runs, and the axes X, Y, Z are its own.
impl Runner for Served {
    type Error = Error;

    fn run(&mut self, req: &Request) -> Result<Reply> {
        let (_, ans) = self.send(req, false)?;
        let reply = self.reply(req, &ans)?;
        self.follow(req, &reply);
        if self.shadow.is_some() && matches!(req, Request::Exec(_)) {
            // The cycles our own EXEC ran are not the server's beside it.
            self.accounted = self.refresh()?.cycles;
        }
        Ok(reply)
    }

    fn take_spooled(&mut self) -> Result<Vec<SpoolRecord>> {
        Ok(self
            .shadow
            .as_mut()
            .map(Emulator::take_spool_log)
            .unwrap_or_default())
    }

    fn axis_nr(&mut self) -> Result<[u8; 3]> {
        Ok(self.shadow.as_ref().map_or([0, 1, 2], |s| s.tc().axis_nr()))
    }
}

impl Link for Served {
    fn describe(&self) -> String {
        self.name.clone()
    }

    fn record_header(&self) -> RecordHeader {
        RecordHeader {
            name: format!(
                "session recorded by libaddipos {} on the server at {}",
                env!("CARGO_PKG_VERSION"),
                self.name
            ),
            start: self.info.start,
            cycle_ms: self.info.cycle_s * 1e3,
            spool_capacity: usize::try_from(self.info.spool_capacity).unwrap_or(usize::MAX),
            note: "a served target: requests and answers as the wire gave them; the < lines are \
                   what an emulator of the library's own with the server's settings spooled on \
                   the same requests, and EXEC n lines the cycles the server ran beside them. It \
                   replays when this connection was the server's only client since its start \
                   (serve --no-persist); a warning comment says where it did not"
                .into(),
        }
    }

    fn realtime(&self) -> Option<f64> {
        self.info.realtime
    }

    fn cycle_s(&self) -> f64 {
        self.info.cycle_s
    }

    fn tick(&mut self) -> u64 {
        if self.shadow.is_none() {
            return 0;
        }
        self.cycles_beside().unwrap_or(0)
    }

    fn call_in_epoch(&mut self, req: &Request, epoch: Epoch) -> Result<Option<Reply>> {
        if let Request::Write(addr, value) = req {
            return self.write_in_epoch(*addr, *value, epoch);
        }
        if !matches!(req, Request::Read(..)) {
            if epoch_of(&self.refresh()?) != epoch {
                return Ok(None);
            }
            return self.run(req).map(Some);
        }
        let (info, ans) = self.send(req, true)?;
        if info.is_some_and(|i| epoch_of(&i) != epoch) {
            return Ok(None);
        }
        let reply = self.reply(req, &ans)?;
        self.follow(req, &reply);
        Ok(Some(reply))
    }

    fn clean_epoch(&mut self) -> Result<Epoch> {
        Ok(epoch_of(&self.refresh()?))
    }

    fn exec(
        &mut self,
        cycles: Option<u64>,
        limits: Limits<'_>,
        ran: &mut dyn FnMut(&Request),
    ) -> Result<()> {
        let req = Request::Exec(cycles);
        let what = format!("tc_exec {req}");
        // The wait ends at once when the connection is being closed or
        // the caller gives up (the connection is then dropped).
        let ans = self.exchange_until(&[req.to_wire()], &what, &|| limits.stopped());
        let ans = match ans {
            Err(e) => return Err(limits.check(&|| what.clone()).err().unwrap_or(e)),
            Ok(mut a) => a.swap_remove(0),
        };
        let reply = self.reply(&req, &ans)?;
        if self.info.realtime.is_none() {
            self.follow(&req, &reply);
            if self.shadow.is_some() {
                self.accounted = self.refresh()?.cycles;
            }
            if reply == Reply::Ok {
                ran(&req);
            }
        } else if self.shadow.is_some() {
            // In real time the server waits for its clock; what ran
            // meanwhile is the server's, written as the cycles it ran.
            let n = self.cycles_beside()?;
            if n > 0 {
                ran(&Request::Exec(Some(n)));
            }
        }
        exec_outcome(&what, &self.name, reply)
    }

    fn set_timeout(&mut self, timeout: Duration) -> Result<()> {
        // The client takes its request timeout when it connects.
        self.wire.set_request_timeout(timeout);
        Ok(())
    }

    fn set_spool_log(&mut self, on: bool) -> bool {
        if !on {
            self.shadow = None;
            return true;
        }
        if self.shadow.is_none() {
            // The server as it is now (a failure leaves the last look).
            let _ = self.refresh();
            let i = self.info;
            let cycle = CycleTime::from_secs(i.cycle_s).unwrap_or(CycleTime::DEFAULT);
            let capacity = tc_module::check_capacity(i.spool_capacity)
                .unwrap_or(tc_module::DEFAULT_SPOOL_CAPACITY);
            let mut shadow = Emulator::new(i.start, cycle).with_spool_capacity(capacity);
            shadow.set_spool_log(true);
            self.shadow = Some(shadow);
            self.accounted = i.cycles;
        }
        true
    }

    fn take_warning(&mut self) -> Option<String> {
        self.warning.take()
    }

    fn take_beside(&mut self) -> u64 {
        std::mem::take(&mut self.beside)
    }
}
