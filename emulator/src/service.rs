//! The emulator behind the wire: the [`Handler`] the TCP server drives.
//! Requests are served as in [`crate::serving`]; a long `EXEC` is served
//! in slices, so the server can release the emulator in between, and a
//! write of tool data waits until it is on disk. The emulator-control ops
//! (`SETUP`, `SPOOL_LOG`) belong to a connection's conformance session
//! ([`crate::session`]), which the service opens for each connection and
//! counts: the emulator all connections share is never reset or logged by
//! a client.

use otc_ext::OtcExtension;
use tc_module::{AxisPos, CycleTime, TcExtension};
use uoi::tcp::{Handler, Slice};
use uoi::wire::ProtocolError;
use uoi::wire::{Answer, Request as WireRequest};
use uoi::AccessError;

use crate::serving::serve_slice;
use crate::session::{ConformanceSession, SessionPlaces};
use crate::tools::durable::ToolPersistence;
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
        Self {
            emu,
            tools: None,
            sessions: SessionPlaces::default(),
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

impl<E: TcExtension + Default> Handler for EmulatorService<E> {
    /// `SETUP` gives a connection an emulator of its own.
    type Session = ConformanceSession;

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
    fn serve(&mut self, req: WireRequest) -> Slice {
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
    use tc_request::Request;

    /// The answer of the shared service to `req`, served to its end.
    fn answer(s: &mut EmulatorService, req: WireRequest) -> Answer {
        s.serve(req).finish(|rest| s.serve(rest))
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
}
