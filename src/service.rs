//! The emulator behind the wire: the [`Handler`] the TCP server drives.
//! Object accesses (READ, WRITE) go straight to the emulator; the TC side's
//! own ops are decoded with `tc-request`, run, and answered with the
//! reply's wire form. The emulator-control ops (`SETUP`, `SPOOL_LOG`)
//! belong to a connection's conformance session ([`crate::session`]): the
//! emulator all connections share is never reset or logged by a client.

use tc_module::AxisPos;
use tc_request::Request;
use uoi::tcp::Handler;
use uoi::wire::{Answer, Request as WireRequest};
use uoi::AccessError;

use crate::session::ConformanceSession;
use crate::Emulator;

/// The emulator all connections share, as the TCP server's handler.
#[derive(Debug)]
pub struct EmulatorService {
    emu: Emulator,
}

impl EmulatorService {
    /// Serves a fresh emulator at `start` with cycle `cycle_s`.
    pub fn new(start: AxisPos, cycle_s: f64) -> Self {
        Self {
            emu: Emulator::new(start, cycle_s),
        }
    }
}

/// An emulator-control op: not the emulator's to serve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Control {
    /// `SETUP`.
    Setup,
    /// `SPOOL_LOG` with its logging flag.
    SpoolLog(bool),
}

/// Answers `req` on `emu`: object accesses straight, the TC side's own ops
/// decoded by `tc-request` and run. An emulator-control op (`SETUP`,
/// `SPOOL_LOG`) is handed back, for the caller to serve.
pub(crate) fn serve(emu: &mut Emulator, req: WireRequest) -> Result<Answer, Control> {
    Ok(match req {
        WireRequest::Read(a, ty) => match emu.read(a, ty) {
            Ok(v) => Answer::Value(v),
            Err(e) => Answer::Access(e),
        },
        WireRequest::Write(a, v) => match emu.write(a, v) {
            Ok(()) => Answer::Ok,
            Err(e) => Answer::Access(e),
        },
        ext => match Request::from_wire(&ext) {
            Ok(Request::Setup { .. }) => return Err(Control::Setup),
            Ok(Request::SpoolLog { logging }) => return Err(Control::SpoolLog(logging)),
            Ok(r) => emu.run(&r).to_wire(),
            Err(e) => Answer::Protocol(e),
        },
    })
}

impl Handler for EmulatorService {
    /// `SETUP` gives a connection an emulator of its own.
    type Session = ConformanceSession;

    /// Serves the shared emulator; `SPOOL_LOG` (and a `SETUP`, which a
    /// connection's session always takes first) is refused with `State`:
    /// only a conformance session has a spool log.
    fn handle(&mut self, req: WireRequest) -> Answer {
        serve(&mut self.emu, req).unwrap_or(Answer::Access(AccessError::State))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tc_request::text::parse_request;

    #[test]
    fn the_shared_emulator_never_logs() {
        let mut s = EmulatorService::new([0.0; 8], 1e-3);
        let on = Request::SpoolLog { logging: true }.to_wire();
        assert_eq!(s.handle(on), Answer::Access(AccessError::State));
        let lin = parse_request("LIN X1").expect("LIN").to_wire();
        assert_eq!(s.handle(lin), Answer::Ok);
        assert!(s.emu.take_spool_log().is_empty());
        assert_eq!(s.emu.queue_len(), 1);
    }
}
