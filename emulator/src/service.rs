//! The emulator behind the wire: the [`Handler`] the TCP server drives.
//! Object accesses (READ, WRITE) go straight to the emulator; the TC side's
//! own ops are decoded with `tc-request`, run, and answered with the
//! reply's wire form. A long `EXEC` is served in slices, so the server can
//! release the emulator in between. The emulator-control ops (`SETUP`,
//! `SPOOL_LOG`) belong to a connection's conformance session
//! ([`crate::session`]): the emulator all connections share is never reset
//! or logged by a client.

use otc_ext::OtcExtension;
use tc_module::{AxisPos, CycleTime, ExecLeft, TcExtension};
use tc_request::Request;
use uoi::tcp::{Handler, Slice};
use uoi::wire::ProtocolError;
use uoi::wire::{Answer, Request as WireRequest};
use uoi::AccessError;

use crate::session::ConformanceSession;
use crate::tools::durable::ToolPersistence;
use crate::Emulator;

/// The emulator all connections share, as the TCP server's handler
/// (extension `E`: OTC; a test model in tests).
#[derive(Debug)]
pub struct EmulatorService<E: TcExtension = OtcExtension> {
    emu: Emulator<E>,
    /// Where tool data is kept durably; `None`: in memory only.
    tools: Option<Tools<E>>,
}

impl EmulatorService {
    /// Serves a fresh emulator at `start` with cycle `cycle`.
    pub fn new(start: AxisPos, cycle: CycleTime) -> Self {
        Self::with_emulator(Emulator::new(start, cycle))
    }
}

impl<E: TcExtension + Default> EmulatorService<E> {
    /// Serves `emu`.
    pub fn with_emulator(emu: Emulator<E>) -> Self {
        Self { emu, tools: None }
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
        Self {
            emu: self.emu.with_spool_capacity(capacity),
            ..self
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

/// An emulator-control op: not the emulator's to serve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Control {
    /// `SETUP`.
    Setup,
    /// `SPOOL_LOG` with its logging flag.
    SpoolLog(bool),
}

/// Serves one slice of `req` on `emu`: object accesses straight, the TC
/// side's own ops decoded by `tc-request` and run; an `EXEC` runs one
/// slice ([`TcModule::exec_slice`](tc_module::TcModule::exec_slice)) and
/// hands back the rest. An emulator-control op is handed back, for the
/// caller to serve.
pub(crate) fn serve_slice<E: TcExtension>(
    emu: &mut Emulator<E>,
    req: WireRequest,
) -> Result<Slice, Control> {
    let answer = match req {
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
            Ok(Request::Exec(cycles)) => match emu.exec_slice(cycles) {
                ExecLeft::Done => Answer::Ok,
                ExecLeft::Rest(rest) => return Ok(Slice::More(Request::Exec(rest).to_wire())),
            },
            Ok(r) => emu.run(&r).to_wire(),
            Err(e) => Answer::Protocol(e),
        },
    };
    Ok(Slice::Done(answer))
}

/// Serves `req` on `emu` to its end (every slice of it).
pub(crate) fn serve<E: TcExtension>(
    emu: &mut Emulator<E>,
    req: WireRequest,
) -> Result<Answer, Control> {
    let mut req = req;
    loop {
        match serve_slice(emu, req)? {
            Slice::Done(answer) => return Ok(answer),
            Slice::More(rest) => req = rest,
            // `serve_slice` never waits.
            Slice::Wait(_) => return Ok(Answer::Protocol(ProtocolError::Busy)),
        }
    }
}

impl<E: TcExtension + Default> Handler for EmulatorService<E> {
    /// `SETUP` gives a connection an emulator of its own.
    type Session = ConformanceSession;

    /// Serves the shared emulator; `SPOOL_LOG` (and a `SETUP`, which a
    /// connection's session always takes first) is refused with `State`:
    /// only a conformance session has a spool log.
    fn handle(&mut self, req: WireRequest) -> Answer {
        serve(&mut self.emu, req).unwrap_or(Answer::Access(AccessError::State))
    }

    /// As `handle`, but a long `EXEC` comes back in slices, and a write
    /// that changes tool data waits until it is on disk.
    fn handle_slice(&mut self, req: WireRequest) -> Slice {
        let tools = self.tools.as_mut().and_then(|t| t.0.as_mut());
        if let (Some(t), WireRequest::Write(a, v)) = (tools, &req) {
            if let Some(slice) = t.serve(&mut self.emu, *a, *v) {
                return slice;
            }
        }
        serve_slice(&mut self.emu, req).unwrap_or(Slice::Done(Answer::Access(AccessError::State)))
    }

    /// A tool write is on disk (or refused): applied and answered.
    fn resume(&mut self, token: u64, ok: bool) -> Slice {
        match self.tools.as_mut().and_then(|t| t.0.as_mut()) {
            Some(t) => t.resume(&mut self.emu, token, ok),
            None => Slice::Done(Answer::Protocol(ProtocolError::Busy)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tc_request::text::parse_request;

    #[test]
    fn the_shared_emulator_never_logs() {
        let mut s = EmulatorService::new([0.0; 8], CycleTime::DEFAULT);
        let on = Request::SpoolLog { logging: true }.to_wire();
        assert_eq!(s.handle(on), Answer::Access(AccessError::State));
        let lin = parse_request("LIN X1").expect("LIN").to_wire();
        assert_eq!(s.handle(lin), Answer::Ok);
        assert!(s.emu.take_spool_log().is_empty());
        assert_eq!(s.emu.queue_len(), 1);
    }
}
