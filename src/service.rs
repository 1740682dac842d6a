//! The emulator behind the wire: the [`Handler`] the TCP server drives.
//! Object accesses (READ, WRITE) go straight to the emulator; the TC side's
//! own ops are decoded with `tc-request`, run, and answered with the
//! reply's wire form.

use std::collections::VecDeque;

use otc_ext::OtcExtension;
use tc_module::limits::check_point;
use tc_module::spooler::check_capacity;
use tc_module::{AxisPos, CycleTime, ExecLeft, TcExtension};
use tc_request::wire::SPOOL_BATCH;
use tc_request::{Reply, Request, SpoolRecord};
use uoi::tcp::{Handler, Slice};
use uoi::wire::{Answer, Request as WireRequest};
use uoi::AccessError;

use crate::Emulator;

/// The emulator as the TCP server's handler (extension `E`: OTC; a test
/// model in tests).
#[derive(Debug)]
pub struct EmulatorService<E: TcExtension = OtcExtension> {
    emu: Emulator<E>,
    /// Logged elements not yet handed out by `SPOOL_LOG`.
    pending: VecDeque<SpoolRecord>,
    /// The configured spooler capacity (a `SETUP` asking for 0 gets it).
    spool_capacity: usize,
}

impl EmulatorService {
    /// Serves a fresh emulator at `start` with cycle `cycle`.
    pub fn new(start: AxisPos, cycle: CycleTime) -> Self {
        Self::with_emulator(Emulator::new(start, cycle))
    }
}

impl<E: TcExtension + Default> EmulatorService<E> {
    /// Serves `emu` (its spooler capacity is the configured one).
    pub fn with_emulator(emu: Emulator<E>) -> Self {
        Self {
            spool_capacity: emu.tc().spooler().capacity(),
            emu,
            pending: VecDeque::new(),
        }
    }

    /// The same service with spoolers of `capacity` elements (checked by
    /// `check_capacity` where it comes from outside).
    pub fn with_spool_capacity(self, capacity: usize) -> Self {
        Self {
            emu: self.emu.with_spool_capacity(capacity),
            pending: self.pending,
            spool_capacity: capacity,
        }
    }

    /// Carries out one request, to its end.
    pub fn run(&mut self, req: &Request) -> Reply {
        match *req {
            Request::Setup {
                start,
                cycle_s,
                spool_capacity,
            } => self.setup(start, cycle_s, spool_capacity),
            Request::SpoolLog { logging } => self.spool_log(logging),
            ref other => self.emu.run(other),
        }
    }

    /// `SETUP`: a fresh emulator; `Range` for a start, cycle or capacity
    /// out of limits (capacity 0: the configured one).
    fn setup(&mut self, start: AxisPos, cycle_s: f64, capacity: u64) -> Reply {
        let Some((cycle, capacity)) = self.setup_values(&start, cycle_s, capacity) else {
            return Reply::Access(AccessError::Range);
        };
        let emu = Emulator::with_extension(start, cycle, E::default());
        self.emu = emu.with_spool_capacity(capacity);
        self.pending.clear();
        Reply::Ok
    }

    /// The checked cycle and capacity of a `SETUP`, if all is in limits.
    fn setup_values(&self, start: &AxisPos, cycle_s: f64, cap: u64) -> Option<(CycleTime, usize)> {
        check_point(start).ok()?;
        let cycle = CycleTime::from_secs(cycle_s).ok()?;
        let capacity = match cap {
            0 => self.spool_capacity,
            n => check_capacity(n).ok()?,
        };
        Some((cycle, capacity))
    }

    /// One slice of a request: `EXEC` runs slice by slice
    /// ([`TcModule::exec_slice`](tc_module::TcModule::exec_slice)); what
    /// is left of it comes back as `Err(rest)`, to continue with
    /// `EXEC rest`. Any other request is one slice.
    pub fn run_slice(&mut self, req: &Request) -> Result<Reply, Option<u64>> {
        match *req {
            Request::Exec(cycles) => match self.emu.exec_slice(cycles) {
                ExecLeft::Done => Ok(Reply::Ok),
                ExecLeft::Rest(rest) => Err(rest),
            },
            ref other => Ok(self.run(other)),
        }
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

impl<E: TcExtension + Default> Handler for EmulatorService<E> {
    /// Object accesses go straight to the object layer; the TC side's own
    /// ops are decoded by `tc-request` and run by the emulator.
    fn handle(&mut self, req: WireRequest) -> Answer {
        let mut req = req;
        loop {
            match self.handle_slice(req) {
                Slice::Done(answer) => return answer,
                Slice::More(rest) => req = rest,
            }
        }
    }

    /// As `handle`, but a long `EXEC` comes back in slices.
    fn handle_slice(&mut self, req: WireRequest) -> Slice {
        let answer = match req {
            WireRequest::Read(a, ty) => match self.emu.read(a, ty) {
                Ok(v) => Answer::Value(v),
                Err(e) => Answer::Access(e),
            },
            WireRequest::Write(a, v) => match self.emu.write(a, v) {
                Ok(()) => Answer::Ok,
                Err(e) => Answer::Access(e),
            },
            ext => match Request::from_wire(&ext) {
                Ok(r) => match self.run_slice(&r) {
                    Ok(reply) => reply.to_wire(),
                    Err(rest) => return Slice::More(Request::Exec(rest).to_wire()),
                },
                Err(e) => Answer::Protocol(e),
            },
        };
        Slice::Done(answer)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setup(svc: &mut EmulatorService, cycle_s: f64, spool_capacity: u64) -> Reply {
        svc.run(&Request::Setup {
            start: [0.0; 8],
            cycle_s,
            spool_capacity,
        })
    }

    #[test]
    fn setup_refuses_cycles_that_make_steps_vanish_and_bad_capacities() {
        let mut svc = EmulatorService::new([0.0; 8], CycleTime::DEFAULT).with_spool_capacity(20);
        let range = Reply::Access(AccessError::Range);
        assert_eq!(setup(&mut svc, 5e-324, 0), range);
        assert_eq!(setup(&mut svc, 1e-7, 0), range);
        assert_eq!(setup(&mut svc, 1e-3, 7), range);
        assert_eq!(setup(&mut svc, 1e-3, 0), Reply::Ok);
        assert_eq!(
            svc.emu.tc().spooler().capacity(),
            20,
            "0: the configured one"
        );
        assert_eq!(setup(&mut svc, 1e-6, 8), Reply::Ok);
        assert_eq!(svc.emu.tc().spooler().capacity(), 8);
        assert_eq!(setup(&mut svc, 1e-3, 0), Reply::Ok);
        assert_eq!(svc.emu.tc().spooler().capacity(), 20);
    }
}
