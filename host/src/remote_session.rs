//! A conformance session on a server, over the one wire client
//! ([`WireClient`]): a fresh emulator of the connection's own (`SETUP`),
//! its spool log read over the wire. `addipos replay --server` replays
//! traces on it; it is a [`Runner`] like the emulator in the process
//! (decision 491).

use tc_objects::TcObject;
use tc_request::{AxisPos, Reply, Request, Runner, SpoolRecord};
use uoi::{Value, ValueType};

use crate::wire_client::{WireClient, WireError};

/// Why a request of a conformance session could not be carried out. Each
/// is written as a replay report shows it, in brackets after `err`.
#[derive(Debug, thiserror::Error)]
pub enum SessionError {
    /// The exchange with the server failed.
    #[error("(connection: {0})")]
    Wire(#[from] WireError),
    /// The connection of the session was lost before: a new one would be
    /// on the shared emulator, not on the session's.
    #[error("(connection: the session's connection was lost)")]
    Lost,
    /// The server answered the spool log with something else.
    #[error("(unexpected answer {0:?})")]
    Unexpected(Reply),
    /// The server refused `SETUP`.
    #[error("setup refused: {0:?}")]
    SetupRefused(Reply),
}

/// A conformance session: set up with [`set_up`](Self::set_up) before
/// each trace.
#[derive(Debug)]
pub struct RemoteSession {
    wire: WireClient,
    /// The connection the session was set up on.
    session: Option<u64>,
}

impl RemoteSession {
    /// A session over `wire` (connected, or connecting at its first
    /// exchange); nothing is set up yet.
    pub fn new(wire: WireClient) -> Self {
        Self {
            wire,
            session: None,
        }
    }

    /// The wire client beneath.
    pub fn wire(&mut self) -> &mut WireClient {
        &mut self.wire
    }

    /// A fresh emulator of this connection's own at `start`, with the
    /// cycle `cycle_s` (seconds) and a spooler of `spool_capacity`
    /// elements, its spool log on and empty. A lost connection is made
    /// again first.
    pub fn set_up(
        &mut self,
        start: AxisPos,
        cycle_s: f64,
        spool_capacity: u64,
    ) -> Result<(), SessionError> {
        let setup = Request::Setup {
            start,
            cycle_s,
            spool_capacity,
        };
        self.session = None;
        match self.wire.call(&setup)? {
            Reply::Ok => {}
            other => return Err(SessionError::SetupRefused(other)),
        }
        self.session = Some(self.wire.connections());
        self.take_spooled().map(|_| ())
    }

    /// The wire client, while the session's connection lasts.
    fn in_session(&mut self) -> Result<&mut WireClient, SessionError> {
        let same = self.wire.is_connected() && self.session == Some(self.wire.connections());
        if same || self.session.is_none() {
            Ok(&mut self.wire)
        } else {
            Err(SessionError::Lost)
        }
    }
}

impl Runner for RemoteSession {
    type Error = SessionError;

    fn run(&mut self, req: &Request) -> Result<Reply, SessionError> {
        Ok(self.in_session()?.call(req)?)
    }

    fn take_spooled(&mut self) -> Result<Vec<SpoolRecord>, SessionError> {
        let mut out = Vec::new();
        loop {
            match self.run(&Request::SpoolLog { logging: true })? {
                Reply::Spool(els, more) => {
                    out.extend(els);
                    if !more {
                        return Ok(out);
                    }
                }
                other => return Err(SessionError::Unexpected(other)),
            }
        }
    }

    fn axis_nr(&mut self) -> Result<[u8; 3], SessionError> {
        let mut out = [0u8; 3];
        for (sub, o) in (0u16..).zip(out.iter_mut()) {
            let addr = TcObject::AxisNr.sub(sub);
            let v = self.in_session()?.read(addr, ValueType::I32)?;
            *o = match v {
                Value::I32(i) => u8::try_from(i).unwrap_or(0),
                Value::F64(_) => 0,
            };
        }
        Ok(out)
    }
}
