//! A trace target on the far side of a connection: `replay --server`.

use tc_objects::TcObject;
use tc_request::{Reply, Request, SpoolRecord};
use uoi::tcp::{BlockingClient, ClientError, ClientOptions};
use uoi::wire::ProtocolError;
use uoi::{Value, ValueType};

use crate::model::{Header, Trace};
use crate::replay::{replay_on, Mismatch, Target};

/// A trace target over the wire.
pub struct RemoteTarget {
    client: BlockingClient,
}

fn transport(e: impl std::fmt::Display) -> String {
    format!("(connection: {e})")
}

impl RemoteTarget {
    /// Connects to a server with the default options (timeouts, no token).
    pub fn connect(addr: &str) -> Result<Self, ClientError> {
        Self::connect_with(addr, &ClientOptions::default())
    }

    /// Connects to a server within `opts.connect_timeout`, presenting
    /// `opts.token` if given; every call waits at most `opts.request_timeout`.
    pub fn connect_with(addr: &str, opts: &ClientOptions) -> Result<Self, ClientError> {
        Ok(Self {
            client: BlockingClient::connect_with(addr, opts)?,
        })
    }

    /// Checks that `addr` is a UOI server, on a connection of its own that
    /// waits at most `opts.connect_timeout` for the connection and for an
    /// answer (the HELLO of `opts.token`, then a read of AxisNr X): a
    /// server that is silent fails within that bound, one that answers
    /// something else (an HTTP server) at once. An access error or a
    /// protocol answer is a UOI answer: `Ok`, except `Unauthorized`.
    pub fn probe(addr: &str, opts: &ClientOptions) -> Result<(), ClientError> {
        let quick = ClientOptions {
            request_timeout: opts.connect_timeout,
            ..opts.clone()
        };
        let mut client = BlockingClient::connect_with(addr, &quick)?;
        match client.read(TcObject::AxisNr.sub(0), ValueType::I32) {
            Ok(_) | Err(ClientError::Access(_)) => Ok(()),
            Err(ClientError::Protocol(p)) if p != ProtocolError::Unauthorized => Ok(()),
            Err(e) => Err(e),
        }
    }

    /// One request on the wire, its reply decoded.
    pub fn call(&mut self, req: &Request) -> Result<Reply, ClientError> {
        let ans = self.client.call(&req.to_wire())?;
        Reply::from_wire(req.wire_op(), &ans)
            .ok_or_else(|| ClientError::Unexpected(format!("{ans:?}")))
    }

    /// A fresh emulator of this connection's own (a conformance session)
    /// at the trace's start, with the spool log on.
    pub fn prepare(&mut self, header: &Header) -> Result<(), String> {
        let setup = Request::Setup {
            start: header.start,
            cycle_s: header.cycle.secs(),
            // A capacity is at most 1,000,000: it fits u64.
            spool_capacity: header.spool_capacity as u64,
        };
        match self.call(&setup).map_err(transport)? {
            Reply::Ok => {}
            other => return Err(format!("setup refused: {other:?}")),
        }
        self.take_spooled().map(|_| ())
    }
}

impl Target for RemoteTarget {
    fn run(&mut self, req: &Request) -> Result<Reply, String> {
        self.call(req).map_err(transport)
    }

    fn take_spooled(&mut self) -> Result<Vec<SpoolRecord>, String> {
        let mut out = Vec::new();
        loop {
            match self.run(&Request::SpoolLog { logging: true })? {
                Reply::Spool(els, more) => {
                    out.extend(els);
                    if !more {
                        return Ok(out);
                    }
                }
                other => return Err(format!("(unexpected answer {other:?})")),
            }
        }
    }

    fn axis_nr(&mut self) -> Result<[u8; 3], String> {
        let mut out = [0u8; 3];
        for (sub, o) in (0u16..).zip(out.iter_mut()) {
            let addr = TcObject::AxisNr.sub(sub);
            let v = self.client.read(addr, ValueType::I32).map_err(transport)?;
            *o = match v {
                Value::I32(i) => u8::try_from(i).unwrap_or(0),
                Value::F64(_) => 0,
            };
        }
        Ok(out)
    }
}

/// Replays a trace over the wire: a fresh conformance session on the
/// server, then the same comparison as in-process.
pub fn replay_remote(trace: &Trace, target: &mut RemoteTarget) -> Vec<Mismatch> {
    if let Err(e) = target.prepare(&trace.header) {
        return vec![setup_failed(&trace.header, e)];
    }
    replay_on(trace, target)
}

/// The report of a server that could not set up a fresh emulator.
pub fn setup_failed(header: &Header, e: String) -> Mismatch {
    Mismatch {
        file: header.file.clone(),
        line: 0,
        request: "(setup)".into(),
        expected: "a fresh emulator".into(),
        got: e,
    }
}
