//! The one wire client of `addipos serve` (docs/protocol.md): the host
//! library's served target (`crate::served`), `addipos call` and
//! `replay --server` (`crate::remote_session`) all talk through it
//! (decision 491).
//!
//! * Every exchange is bounded in time: the connection by the options'
//!   connect timeout, the answers by their request timeout.
//! * A failed exchange drops the connection (its answers may be out of
//!   step with its requests); the next exchange connects again.
//! * A connection opened before a `fork` is not used by the child.
//! * `INFO` (op `0x23`, [`EmulatorInfo`]) is one call away ([`WireClient::info`]).
//!
//! Its errors are typed ([`WireError`]); each user words them for its own
//! readers (the host library's messages with the error codes, the CLI's
//! lines).

use std::net::SocketAddr;
use std::time::Duration;

use emulator::info_op::info_request;
use emulator::{parse_address, EmulatorInfo};
use tc_objects::TcObject;
use tc_request::{Reply, Request};
use uoi::tcp::{answer_error, BlockingClient, ClientError, ClientOptions};
use uoi::wire::{Answer, ProtocolError, Request as WireRequest};
use uoi::{ObjectAddress, Value, ValueType};

/// Why an exchange with a server failed.
#[derive(Debug, thiserror::Error)]
pub enum WireError {
    /// The address is not one (`parse_address`'s reason).
    #[error("{0}")]
    Address(#[source] emulator::AddressError),
    /// No connection could be made (or the server refused the token).
    #[error(transparent)]
    Connect(ClientError),
    /// The connection failed, timed out or was given up during an
    /// exchange, or the server refused its frames.
    #[error(transparent)]
    Exchange(ClientError),
    /// The connection was opened by another process (before a `fork`).
    #[error("this connection was opened by process {pid} before a fork")]
    Forked {
        /// The process that opened it.
        pid: u32,
    },
    /// An answer that is not one to the request sent.
    #[error("unexpected answer: {0:?}")]
    Unexpected(Answer),
}

impl WireError {
    /// The client's error beneath, if the connection or the server's
    /// frames are what failed.
    pub fn client_error(&self) -> Option<&ClientError> {
        match self {
            WireError::Connect(e) | WireError::Exchange(e) => Some(e),
            _ => None,
        }
    }
}

/// A connection to a server, made again when the last exchange lost it.
pub struct WireClient {
    /// The address as the user gave it.
    name: String,
    addr: SocketAddr,
    opts: ClientOptions,
    /// The process that opened the connection.
    pid: u32,
    client: Option<BlockingClient>,
    /// Connections made so far (a new one is a new session on the server).
    connections: u64,
}

impl std::fmt::Debug for WireClient {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "WireClient({})", self.name)
    }
}

impl WireClient {
    /// A client of the server at `address` (as `parse_address` reads it)
    /// with `opts`; it connects at its first exchange.
    pub fn new(address: &str, opts: ClientOptions) -> Result<Self, WireError> {
        let addr = parse_address(address).map_err(WireError::Address)?;
        Ok(Self {
            name: address.to_string(),
            addr,
            opts,
            pid: std::process::id(),
            client: None,
            connections: 0,
        })
    }

    /// A client of the server at `address`, connected now.
    pub fn connect(address: &str, opts: ClientOptions) -> Result<Self, WireError> {
        let mut c = Self::new(address, opts)?;
        c.client()?;
        Ok(c)
    }

    /// Checks that `address` is a UOI server, on a connection of its own
    /// that waits at most `opts.connect_timeout` for the connection and
    /// for an answer (the HELLO of `opts.token`, then a read of AxisNr
    /// X): a server that is silent fails within that bound, one that
    /// answers something else (an HTTP server) at once. An access error
    /// or a protocol answer is a UOI answer: `Ok`, except `Unauthorized`
    /// (decision 312).
    pub fn probe(address: &str, opts: &ClientOptions) -> Result<(), ClientError> {
        let quick = ClientOptions {
            request_timeout: opts.connect_timeout,
            ..opts.clone()
        };
        let mut client = BlockingClient::connect_with(address, &quick)?;
        match client.read(TcObject::AxisNr.sub(0), ValueType::I32) {
            Ok(_) | Err(ClientError::Access(_)) => Ok(()),
            Err(ClientError::Protocol(p)) if p != ProtocolError::Unauthorized => Ok(()),
            Err(e) => Err(e),
        }
    }

    /// The address as the user gave it.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Sets how long the answers of one exchange may take; the connection
    /// is made again with it.
    pub fn set_request_timeout(&mut self, timeout: Duration) {
        self.opts.request_timeout = timeout;
        self.client = None;
    }

    /// Drops the connection: the next exchange connects again.
    pub fn disconnect(&mut self) {
        self.client = None;
    }

    /// Connections made so far: a server's session (a conformance
    /// emulator, say) lasts as long as one connection.
    pub fn connections(&self) -> u64 {
        self.connections
    }

    /// Whether a connection is open.
    pub fn is_connected(&self) -> bool {
        self.client.is_some()
    }

    /// The connection, made now if the last exchange lost it.
    fn client(&mut self) -> Result<&mut BlockingClient, WireError> {
        if self.pid != std::process::id() {
            return Err(WireError::Forked { pid: self.pid });
        }
        let client = match self.client.take() {
            Some(c) => c,
            None => {
                let c = BlockingClient::connect_with(&self.addr.to_string(), &self.opts)
                    .map_err(WireError::Connect)?;
                self.connections += 1;
                c
            }
        };
        Ok(self.client.insert(client))
    }

    /// Sends `reqs` in one write and reads their answers.
    pub fn exchange(&mut self, reqs: &[WireRequest]) -> Result<Vec<Answer>, WireError> {
        let out = self.client()?.pipeline(reqs);
        out.map_err(|e| self.lost(e))
    }

    /// As [`exchange`](Self::exchange), given up as soon as `stop` says
    /// so (the connection is then dropped).
    pub fn exchange_until(
        &mut self,
        reqs: &[WireRequest],
        stop: &dyn Fn() -> bool,
    ) -> Result<Vec<Answer>, WireError> {
        let out = self.client()?.pipeline_until(reqs, stop);
        out.map_err(|e| self.lost(e))
    }

    /// A failed exchange: the connection is not trusted any more.
    fn lost(&mut self, e: ClientError) -> WireError {
        self.client = None;
        WireError::Exchange(e)
    }

    /// One request; its answer decoded as a reply to it.
    pub fn call(&mut self, req: &Request) -> Result<Reply, WireError> {
        let ans = self.one(req.to_wire())?;
        Reply::from_wire(req.wire_op(), &ans).ok_or(WireError::Unexpected(ans))
    }

    /// Reads an object; an access error or a refusal is the client's
    /// error of that answer.
    pub fn read(&mut self, addr: ObjectAddress, ty: ValueType) -> Result<Value, WireError> {
        match self.one(WireRequest::Read(addr, ty))? {
            Answer::Value(v) => Ok(v),
            other => Err(WireError::Exchange(answer_error(other))),
        }
    }

    /// The server's `INFO`; `Unexpected` when it does not answer one (it
    /// is not an `addipos serve` of this version).
    pub fn info(&mut self) -> Result<EmulatorInfo, WireError> {
        let ans = self.one(info_request())?;
        EmulatorInfo::from_wire(&ans).ok_or(WireError::Unexpected(ans))
    }

    /// One wire request, one answer.
    fn one(&mut self, req: WireRequest) -> Result<Answer, WireError> {
        let mut ans = self.exchange(std::slice::from_ref(&req))?;
        ans.pop()
            .ok_or_else(|| WireError::Exchange(ClientError::Unexpected("no answer".into())))
    }
}
