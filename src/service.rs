//! The emulator behind the wire: the [`Handler`] the TCP server drives.
//! Object accesses (READ, WRITE) go straight to the emulator; the TC side's
//! own ops are decoded with `tc-request`, run, and answered with the
//! reply's wire form.

use std::collections::VecDeque;

use tc_module::{AxisPos, MAX_COORD};
use tc_request::wire::SPOOL_BATCH;
use tc_request::{Reply, Request, SpoolRecord};
use uoi::tcp::Handler;
use uoi::wire::{Answer, Request as WireRequest};
use uoi::AccessError;

use crate::Emulator;

/// Longest interpolation cycle a `SETUP` may ask for, in seconds.
pub const MAX_CYCLE_S: f64 = 1.0;

/// The emulator as the TCP server's handler.
#[derive(Debug)]
pub struct EmulatorService {
    emu: Emulator,
    /// Logged elements not yet handed out by `SPOOL_LOG`.
    pending: VecDeque<SpoolRecord>,
}

impl EmulatorService {
    /// Serves a fresh emulator at `start` with cycle `cycle_s`.
    pub fn new(start: AxisPos, cycle_s: f64) -> Self {
        Self {
            emu: Emulator::new(start, cycle_s),
            pending: VecDeque::new(),
        }
    }

    /// Carries out one request.
    pub fn run(&mut self, req: &Request) -> Reply {
        match *req {
            Request::Setup { start, cycle_s } => self.setup(start, cycle_s),
            Request::SpoolLog { logging } => self.spool_log(logging),
            ref other => self.emu.run(other),
        }
    }

    /// `SETUP`: a fresh emulator; `Range` for a start or cycle out of limits.
    fn setup(&mut self, start: AxisPos, cycle_s: f64) -> Reply {
        let ok = start.iter().all(|v| v.is_finite() && v.abs() <= MAX_COORD)
            && cycle_s.is_finite()
            && cycle_s > 0.0
            && cycle_s <= MAX_CYCLE_S;
        if !ok {
            return Reply::Access(AccessError::Range);
        }
        *self = Self::new(start, cycle_s);
        Reply::Ok
    }

    /// `SPOOL_LOG`: one batch of the logged elements; logging on or off.
    fn spool_log(&mut self, logging: bool) -> Reply {
        self.pending.extend(self.emu.take_spool_log());
        self.emu.set_spool_log(logging);
        let n = self.pending.len().min(SPOOL_BATCH);
        let batch: Vec<SpoolRecord> = self.pending.drain(..n).collect();
        Reply::Spool(batch, !self.pending.is_empty())
    }
}

impl Handler for EmulatorService {
    /// Object accesses go straight to the object layer; the TC side's own
    /// ops are decoded by `tc-request` and run by the emulator.
    fn handle(&mut self, req: WireRequest) -> Answer {
        match req {
            WireRequest::Read(a, ty) => match self.emu.read(a, ty) {
                Ok(v) => Answer::Value(v),
                Err(e) => Answer::Access(e),
            },
            WireRequest::Write(a, v) => match self.emu.write(a, v) {
                Ok(()) => Answer::Ok,
                Err(e) => Answer::Access(e),
            },
            ext => match Request::from_wire(&ext) {
                Ok(r) => self.run(&r).to_wire(),
                Err(e) => Answer::Protocol(e),
            },
        }
    }
}
