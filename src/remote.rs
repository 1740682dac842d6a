//! A trace target on the far side of a connection: `replay --server`.

use tc_request::{Reply, Request, SpoolRecord};
use uoi::tcp::{BlockingClient, ClientError};
use uoi::{ObjectAddress, Value, ValueType};

use crate::trace::{replay_on, Mismatch, Target, Trace};

/// A trace target over the wire.
pub struct RemoteTarget {
    client: BlockingClient,
}

fn transport(e: impl std::fmt::Display) -> String {
    format!("(connection: {e})")
}

impl RemoteTarget {
    /// Connects to a server.
    pub fn connect(addr: &str) -> std::io::Result<Self> {
        Ok(Self {
            client: BlockingClient::connect(addr)?,
        })
    }

    /// One request on the wire, its reply decoded.
    pub fn call(&mut self, req: &Request) -> Result<Reply, ClientError> {
        let ans = self.client.call(&req.to_wire())?;
        Reply::from_wire(req.wire_op(), &ans)
            .ok_or_else(|| ClientError::Unexpected(format!("{ans:?}")))
    }

    /// A fresh emulator at the trace's start, with the spool log on.
    pub fn prepare(&mut self, trace: &Trace) -> Result<(), String> {
        let setup = Request::Setup {
            start: trace.start,
            cycle_s: trace.cycle.secs(),
            // A capacity is at most 1,000,000: it fits u64.
            spool_capacity: trace.spool_capacity as u64,
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
            let addr = ObjectAddress::new(tc_module::TC_BUS, 0, 2, sub);
            let v = self.client.read(addr, ValueType::I32).map_err(transport)?;
            *o = match v {
                Value::I32(i) => u8::try_from(i).unwrap_or(0),
                Value::F64(_) => 0,
            };
        }
        Ok(out)
    }
}

/// Replays a trace over the wire: a fresh emulator on the server, then the
/// same comparison as in-process.
pub fn replay_remote(trace: &Trace, target: &mut RemoteTarget) -> Vec<Mismatch> {
    if let Err(e) = target.prepare(trace) {
        return vec![Mismatch {
            file: trace.file.clone(),
            line: 0,
            request: "(setup)".into(),
            expected: "a fresh emulator".into(),
            got: e,
        }];
    }
    replay_on(trace, target)
}
