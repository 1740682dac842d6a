//! The client: async, and a small blocking wrapper. Connecting and every
//! call are bounded in time ([`ClientOptions`]); a client with an access
//! token presents it in a HELLO frame right after connecting.

use std::fmt::Display;
use std::io;
use std::time::Duration;

use futures_util::{SinkExt, StreamExt};
use tokio::net::tcp::{OwnedReadHalf, OwnedWriteHalf};
use tokio::net::{TcpStream, ToSocketAddrs};
use tokio_util::codec::{FramedRead, FramedWrite};

use super::access::AccessToken;
use crate::wire::{decode_answer, Answer, ClientCodec, CodecError, Op, ProtocolError, Request};
use crate::{AccessError, ObjectAddress, Value, ValueType};

/// How long a client waits, and what it presents.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ClientOptions {
    /// Longest wait for the connection (default 5 s).
    pub connect_timeout: Duration,
    /// Longest wait for the answers to one call or pipeline (default 30 s).
    pub request_timeout: Duration,
    /// The access token, presented in a HELLO frame on connecting.
    pub token: Option<AccessToken>,
}

impl Default for ClientOptions {
    fn default() -> Self {
        Self {
            connect_timeout: Duration::from_secs(5),
            request_timeout: Duration::from_secs(30),
            token: None,
        }
    }
}

/// What a client waited for in vain.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Waited {
    /// The connection.
    Connect,
    /// An answer.
    Answer,
}

impl std::fmt::Display for Waited {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Waited::Connect => "no connection to",
            Waited::Answer => "no answer from",
        })
    }
}

/// Why a call failed.
#[derive(Debug, thiserror::Error)]
pub enum ClientError {
    /// The connection failed.
    #[error("connection: {0}")]
    Io(#[from] io::Error),
    /// The object access was refused.
    #[error("{0}")]
    Access(AccessError),
    /// The server rejected the frame.
    #[error("protocol: {0}")]
    Protocol(ProtocolError),
    /// The answer does not fit the request.
    #[error("unexpected answer: {0}")]
    Unexpected(String),
    /// The server did not accept the connection, or did not answer, in
    /// time. After a call timed out the connection is out of step: later
    /// calls on it fail at once.
    #[error("{waited} {addr} within {} s", after.as_secs_f64())]
    TimedOut {
        /// What was waited for.
        waited: Waited,
        /// The server's address.
        addr: String,
        /// How long.
        after: Duration,
    },
}

impl From<CodecError> for ClientError {
    fn from(e: CodecError) -> Self {
        match e {
            CodecError::Io(e) => ClientError::Io(e),
            CodecError::FrameTooLarge(n) => ClientError::Unexpected(format!("frame of {n} bytes")),
        }
    }
}

/// An async connection to an object server.
pub struct Client {
    reader: FramedRead<OwnedReadHalf, ClientCodec>,
    writer: FramedWrite<OwnedWriteHalf, ClientCodec>,
    next_id: u32,
    /// The server's address, as given, for messages.
    addr: String,
    request_timeout: Duration,
    /// A call timed out: answers may still come, the ids are out of step.
    out_of_step: bool,
}

impl Client {
    /// Connects with the default [`ClientOptions`].
    pub async fn connect(addr: impl ToSocketAddrs + Display) -> Result<Self, ClientError> {
        Self::connect_with(addr, &ClientOptions::default()).await
    }

    /// Connects within `opts.connect_timeout`, and presents `opts.token`
    /// if there is one (`Protocol(Unauthorized)` if the server refuses it).
    pub async fn connect_with(
        addr: impl ToSocketAddrs + Display,
        opts: &ClientOptions,
    ) -> Result<Self, ClientError> {
        let name = addr.to_string();
        let s = tokio::time::timeout(opts.connect_timeout, TcpStream::connect(addr))
            .await
            .map_err(|_| ClientError::TimedOut {
                waited: Waited::Connect,
                addr: name.clone(),
                after: opts.connect_timeout,
            })??;
        s.set_nodelay(true)?;
        let (r, w) = s.into_split();
        let mut client = Self {
            reader: FramedRead::new(r, ClientCodec),
            writer: FramedWrite::new(w, ClientCodec),
            next_id: 1,
            addr: name,
            request_timeout: opts.request_timeout,
            out_of_step: false,
        };
        if let Some(token) = &opts.token {
            let hello = Request::Hello(bytes::Bytes::copy_from_slice(token.as_bytes()));
            match client.call(&hello).await? {
                Answer::Ok => {}
                other => return Err(answer_error(other)),
            }
        }
        Ok(client)
    }

    /// Runs `call` on this client within the request timeout.
    async fn bounded<T>(
        &mut self,
        call: impl AsyncFnOnce(&mut Self) -> Result<T, ClientError>,
    ) -> Result<T, ClientError> {
        if self.out_of_step {
            return Err(ClientError::Io(io::Error::new(
                io::ErrorKind::NotConnected,
                format!("{}: connection out of step after a timeout", self.addr),
            )));
        }
        let limit = self.request_timeout;
        match tokio::time::timeout(limit, call(self)).await {
            Ok(r) => r,
            Err(_) => {
                self.out_of_step = true;
                Err(ClientError::TimedOut {
                    waited: Waited::Answer,
                    addr: self.addr.clone(),
                    after: limit,
                })
            }
        }
    }

    /// Queues a request (not flushed); returns its id.
    pub async fn send(&mut self, req: &Request) -> Result<u32, ClientError> {
        let id = self.next_id;
        self.next_id = self.next_id.wrapping_add(1);
        self.writer.feed((id, req)).await?;
        Ok(id)
    }

    /// Sends what is queued.
    pub async fn flush(&mut self) -> Result<(), ClientError> {
        Ok(SinkExt::<(u32, &Request)>::flush(&mut self.writer).await?)
    }

    /// Receives the next answer, to a request of op `op`. Not bounded in
    /// time: [`call`](Self::call) and [`pipeline`](Self::pipeline) are.
    pub async fn recv(&mut self, op: Op) -> Result<(u32, Answer), ClientError> {
        let body = match self.reader.next().await {
            Some(frame) => frame?,
            None => return Err(io::Error::from(io::ErrorKind::UnexpectedEof).into()),
        };
        decode_answer(body, op).ok_or_else(|| ClientError::Unexpected("undecodable answer".into()))
    }

    /// One request, one answer, within the request timeout.
    pub async fn call(&mut self, req: &Request) -> Result<Answer, ClientError> {
        self.bounded(async |c: &mut Self| c.call_unbounded(req).await)
            .await
    }

    async fn call_unbounded(&mut self, req: &Request) -> Result<Answer, ClientError> {
        let id = self.send(req).await?;
        self.flush().await?;
        let (got, ans) = self.recv(req.op()).await?;
        if got != id {
            return Err(ClientError::Unexpected(format!(
                "answer to request {got}, expected {id}"
            )));
        }
        Ok(ans)
    }

    /// Sends all requests, then reads all answers (in order), within the
    /// request timeout.
    pub async fn pipeline(&mut self, reqs: &[Request]) -> Result<Vec<Answer>, ClientError> {
        self.bounded(async |c: &mut Self| c.pipeline_unbounded(reqs).await)
            .await
    }

    async fn pipeline_unbounded(&mut self, reqs: &[Request]) -> Result<Vec<Answer>, ClientError> {
        let first = self.next_id;
        for r in reqs {
            self.send(r).await?;
        }
        self.flush().await?;
        let mut out = Vec::with_capacity(reqs.len());
        for (k, r) in reqs.iter().enumerate() {
            let (id, ans) = self.recv(r.op()).await?;
            let want = first.wrapping_add(k as u32);
            if id != want {
                return Err(ClientError::Unexpected(format!(
                    "answer to request {id}, expected {want}"
                )));
            }
            out.push(ans);
        }
        Ok(out)
    }

    /// Reads an object.
    pub async fn read(&mut self, addr: ObjectAddress, ty: ValueType) -> Result<Value, ClientError> {
        match self.call(&Request::Read(addr, ty)).await? {
            Answer::Value(v) => Ok(v),
            other => Err(answer_error(other)),
        }
    }

    /// Writes an object.
    pub async fn write(&mut self, addr: ObjectAddress, v: Value) -> Result<(), ClientError> {
        match self.call(&Request::Write(addr, v)).await? {
            Answer::Ok => Ok(()),
            other => Err(answer_error(other)),
        }
    }
}

/// The error an unexpected answer stands for.
pub fn answer_error(a: Answer) -> ClientError {
    match a {
        Answer::Access(e) => ClientError::Access(e),
        Answer::Protocol(e) => ClientError::Protocol(e),
        other => ClientError::Unexpected(format!("{other:?}")),
    }
}

/// How often [`BlockingClient::pipeline_until`] asks whether to give up.
pub const STOP_POLL: Duration = Duration::from_millis(5);

/// A blocking client: an async [`Client`] on its own small runtime.
pub struct BlockingClient {
    rt: tokio::runtime::Runtime,
    inner: Client,
}

impl BlockingClient {
    /// Connects with the default [`ClientOptions`].
    pub fn connect(addr: &str) -> Result<Self, ClientError> {
        Self::connect_with(addr, &ClientOptions::default())
    }

    /// Connects with `opts` (see [`Client::connect_with`]).
    pub fn connect_with(addr: &str, opts: &ClientOptions) -> Result<Self, ClientError> {
        let rt = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()?;
        let inner = rt.block_on(Client::connect_with(addr, opts))?;
        Ok(Self { rt, inner })
    }

    /// One request, one answer.
    pub fn call(&mut self, req: &Request) -> Result<Answer, ClientError> {
        self.rt.block_on(self.inner.call(req))
    }

    /// Sends all requests, then reads all answers.
    pub fn pipeline(&mut self, reqs: &[Request]) -> Result<Vec<Answer>, ClientError> {
        self.rt.block_on(self.inner.pipeline(reqs))
    }

    /// As [`pipeline`](Self::pipeline), given up as soon as `stop`
    /// answers true (it is asked every [`STOP_POLL`]): then an `Io` error
    /// of kind `Interrupted`, and the connection is out of step (later
    /// calls on it fail at once).
    pub fn pipeline_until(
        &mut self,
        reqs: &[Request],
        stop: &dyn Fn() -> bool,
    ) -> Result<Vec<Answer>, ClientError> {
        let inner = &mut self.inner;
        self.rt.block_on(async {
            let watch = async {
                while !stop() {
                    tokio::time::sleep(STOP_POLL).await;
                }
            };
            tokio::select! {
                r = inner.pipeline(reqs) => r,
                () = watch => {
                    inner.out_of_step = true;
                    Err(ClientError::Io(io::Error::new(
                        io::ErrorKind::Interrupted,
                        "the wait was given up by the caller",
                    )))
                }
            }
        })
    }

    /// Reads an object.
    pub fn read(&mut self, addr: ObjectAddress, ty: ValueType) -> Result<Value, ClientError> {
        self.rt.block_on(self.inner.read(addr, ty))
    }

    /// Writes an object.
    pub fn write(&mut self, addr: ObjectAddress, v: Value) -> Result<(), ClientError> {
        self.rt.block_on(self.inner.write(addr, v))
    }
}
