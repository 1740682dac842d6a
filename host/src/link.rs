//! What a connection talks to: the [`Link`] trait, the one runner of
//! requests of `tc-request` ([`Runner`]) with what a connection needs
//! beside it (time, Clean epochs, recording), and its embedded emulator
//! ([`Embedded`]), stepped or in real time. A server target (a running
//! `addipos serve`, `crate::served::Served`) is the second implementation
//! of the same trait (decision 490).

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use emulator::{Emulator, RealTimeClock};
use tc_module::ExecLeft;
use tc_request::{Reply, Request, Runner, SpoolRecord};

use crate::error::{Error, ErrorCode, Result};
use crate::handles::Epoch;
use crate::record::RecordHeader;
use crate::target::EmbeddedOptions;

/// Longest sleep of a real-time wait between two looks at the clock and
/// the queue (and at whether the connection is being closed).
const POLL: Duration = Duration::from_millis(2);

/// How long a wait may last, and the flag that ends it early.
#[derive(Debug, Clone, Copy)]
pub struct Limits<'a> {
    /// The wait ends with [`ErrorCode::Timeout`] once this has passed.
    pub deadline: Instant,
    /// Set when the connection is being closed: the wait ends with
    /// [`ErrorCode::Connection`].
    pub closing: &'a AtomicBool,
    /// Set by the caller to give the wait up (a Python program's Ctrl-C):
    /// the wait ends with [`ErrorCode::Timeout`].
    pub interrupt: &'a AtomicBool,
}

impl Limits<'_> {
    /// Whether the connection is being closed or the caller gives up.
    pub fn stopped(&self) -> bool {
        self.closing.load(Ordering::Relaxed) || self.interrupt.load(Ordering::Relaxed)
    }

    /// Whether the wait must end now; the error says why.
    pub fn check(&self, what: &dyn Fn() -> String) -> Result<()> {
        if self.closing.load(Ordering::Relaxed) {
            return Err(Error::new(
                ErrorCode::Connection,
                format!("{}: the connection is being closed", what()),
            ));
        }
        if self.interrupt.load(Ordering::Relaxed) {
            return Err(Error::new(
                ErrorCode::Timeout,
                format!(
                    "{}: the wait was given up by the caller (what ran stays run)",
                    what()
                ),
            ));
        }
        if Instant::now() >= self.deadline {
            return Err(Error::new(
                ErrorCode::Timeout,
                format!(
                    "{}: the connection's timeout passed (what ran stays run; call it again to go on \
                     waiting, or set a longer timeout)",
                    what()
                ),
            ));
        }
        Ok(())
    }
}

/// One target of a connection: a [`Runner`] (requests, spooled elements,
/// the axes X, Y, Z) with the library's errors, and what a connection
/// needs beside it. Every method is called with the connection's lock
/// held.
pub trait Link: Runner<Error = Error> + Send {
    /// The target, as a target string would name it.
    fn describe(&self) -> String;

    /// What the header of a recorded trace says about the target.
    fn record_header(&self) -> RecordHeader;

    /// The real-time factor, if the target runs in real time.
    fn realtime(&self) -> Option<f64>;

    /// The interpolation cycle in seconds.
    fn cycle_s(&self) -> f64;

    /// Runs what the wall clock owes (real time; at most one `EXEC`
    /// slice); returns how many cycles ran (0 when stepped).
    fn tick(&mut self) -> u64;

    /// The emulator's Clean epoch: its server and the Cleans carried out.
    fn clean_epoch(&mut self) -> Result<Epoch>;

    /// Carries out `req` if the emulator's Clean epoch is still `epoch`
    /// (that of the handle it goes through); `None`: a Clean (or a
    /// restart of the server) came since, and nothing was carried out
    /// that changes anything.
    fn call_in_epoch(&mut self, req: &Request, epoch: Epoch) -> Result<Option<Reply>> {
        if self.clean_epoch()? != epoch {
            return Ok(None);
        }
        self.run(req).map(Some)
    }

    /// How long one request may take (a server target; an embedded one
    /// answers at once).
    fn set_timeout(&mut self, _timeout: Duration) -> Result<()> {
        Ok(())
    }

    /// A warning for the recording, once (a server target whose answers
    /// differ from a fresh emulator's).
    fn take_warning(&mut self) -> Option<String> {
        None
    }

    /// Cycles the target ran beside this connection's requests, found
    /// while carrying out the last one (a server in real time), which the
    /// recording writes as `EXEC n` before it.
    fn take_beside(&mut self) -> u64 {
        0
    }

    /// `tc_exec`: `cycles` cycles, or until the spooler is empty
    /// (`None`); stepped, or waited for in real time. Hands `ran` every
    /// request it carried out on the emulator, as a trace would repeat
    /// it.
    fn exec(
        &mut self,
        cycles: Option<u64>,
        limits: Limits<'_>,
        ran: &mut dyn FnMut(&Request),
    ) -> Result<()>;

    /// Logs spooled elements from now on (`on`), or stops; whether the
    /// target can.
    fn set_spool_log(&mut self, on: bool) -> bool;
}

/// An emulator inside this process, stepped or with a real-time clock.
#[derive(Debug)]
pub struct Embedded {
    emu: Emulator,
    clock: Option<RealTimeClock>,
    opts: EmbeddedOptions,
}

impl Embedded {
    /// A fresh emulator with `opts`; its clock (in real time) starts now.
    pub fn new(opts: EmbeddedOptions) -> Self {
        let emu = Emulator::new(opts.start, opts.cycle).with_spool_capacity(opts.spool_capacity);
        let clock = opts.realtime.map(|f| RealTimeClock::new(f, opts.cycle));
        Self { emu, clock, opts }
    }

    /// Runs `cycles` stepped, slice by slice, until done or a limit ends
    /// it; `ran` gets the request that was carried out (the cycles that
    /// ran, when it was cut short).
    fn exec_stepped(
        &mut self,
        cycles: Option<u64>,
        limits: Limits<'_>,
        ran: &mut dyn FnMut(&Request),
    ) -> Result<()> {
        let before = self.emu.tc().executor().cycles();
        let mut rest = cycles;
        loop {
            match self.emu.exec_slice(rest) {
                ExecLeft::Done => {
                    ran(&Request::Exec(cycles));
                    return Ok(());
                }
                ExecLeft::Rest(r) => rest = r,
            }
            let what = || format!("tc_exec {}", Request::Exec(cycles));
            if let Err(e) = limits.check(&what) {
                let done = match (cycles, rest) {
                    (Some(n), Some(r)) => n - r.min(n),
                    _ => self.emu.tc().executor().cycles().saturating_sub(before),
                };
                ran(&Request::Exec(Some(done)));
                return Err(e);
            }
        }
    }

    /// Waits, in real time, until `cycles` more cycles have passed or
    /// (`None`) the spooler is empty, never running ahead of the clock.
    fn exec_waited(
        &mut self,
        cycles: Option<u64>,
        limits: Limits<'_>,
        ran: &mut dyn FnMut(&Request),
    ) -> Result<()> {
        let mut catch_up = |me: &mut Self| {
            let n = me.tick();
            if n > 0 {
                ran(&Request::Exec(Some(n)));
            }
        };
        catch_up(self);
        let target = cycles.map(|n| self.passed().saturating_add(n));
        loop {
            let done = match target {
                Some(t) => self.passed() >= t,
                None => self.emu.queue_len() == 0,
            };
            if done {
                return Ok(());
            }
            limits.check(&|| format!("tc_exec {} (real time)", Request::Exec(cycles)))?;
            let wake = target
                .and_then(|t| self.clock.as_ref().and_then(|c| c.instant_of(t)))
                .unwrap_or_else(Instant::now)
                .min(Instant::now() + POLL)
                .min(limits.deadline);
            std::thread::sleep(wake.saturating_duration_since(Instant::now()));
            catch_up(self);
        }
    }

    /// Cycles the clock has run (0 when stepped).
    fn passed(&self) -> u64 {
        self.clock.as_ref().map_or(0, RealTimeClock::passed)
    }
}

impl Link for Embedded {
    fn describe(&self) -> String {
        match self.opts.realtime {
            None => "embedded".into(),
            Some(f) => format!("embedded:realtime={}", f.get()),
        }
    }

    fn record_header(&self) -> RecordHeader {
        let note = match self.opts.realtime {
            None => "an embedded emulator, stepped: EXEC lines are the program's tc_exec calls"
                .to_string(),
            Some(f) => format!(
                "an embedded emulator in real time (factor {}): the cycles that passed between \
                 calls are written as EXEC n, so the replay is stepped and deterministic",
                f.get()
            ),
        };
        RecordHeader {
            name: format!(
                "session recorded by libaddipos {}",
                env!("CARGO_PKG_VERSION")
            ),
            start: self.opts.start,
            cycle_ms: self.opts.cycle_ms,
            spool_capacity: self.opts.spool_capacity,
            note,
        }
    }

    fn realtime(&self) -> Option<f64> {
        self.opts.realtime.map(|f| f.get())
    }

    fn cycle_s(&self) -> f64 {
        self.opts.cycle.secs()
    }

    fn tick(&mut self) -> u64 {
        match &mut self.clock {
            Some(c) => c.catch_up(&mut self.emu, Instant::now()),
            None => 0,
        }
    }

    fn clean_epoch(&mut self) -> Result<Epoch> {
        Ok(Epoch::from(self.emu.clean_epoch()))
    }

    fn exec(
        &mut self,
        cycles: Option<u64>,
        limits: Limits<'_>,
        ran: &mut dyn FnMut(&Request),
    ) -> Result<()> {
        if self.clock.is_some() {
            self.exec_waited(cycles, limits, ran)
        } else {
            self.exec_stepped(cycles, limits, ran)
        }
    }

    fn set_spool_log(&mut self, on: bool) -> bool {
        self.emu.set_spool_log(on);
        true
    }
}

/// The embedded emulator runs every request itself (it never fails).
impl Runner for Embedded {
    type Error = Error;

    fn run(&mut self, req: &Request) -> Result<Reply> {
        Ok(self.emu.run(req))
    }

    fn take_spooled(&mut self) -> Result<Vec<SpoolRecord>> {
        Ok(self.emu.take_spool_log())
    }

    fn axis_nr(&mut self) -> Result<[u8; 3]> {
        Ok(self.emu.tc().axis_nr())
    }
}
