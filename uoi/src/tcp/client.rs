//! The client: async, and a small blocking wrapper.

use std::io;

use futures_util::{SinkExt, StreamExt};
use tokio::net::tcp::{OwnedReadHalf, OwnedWriteHalf};
use tokio::net::{TcpStream, ToSocketAddrs};
use tokio_util::codec::{FramedRead, FramedWrite};

use crate::wire::{decode_answer, Answer, ClientCodec, CodecError, Op, ProtocolError, Request};
use crate::{AccessError, ObjectAddress, Value, ValueType};

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
}

impl Client {
    /// Connects.
    pub async fn connect(addr: impl ToSocketAddrs) -> io::Result<Self> {
        let s = TcpStream::connect(addr).await?;
        s.set_nodelay(true)?;
        let (r, w) = s.into_split();
        Ok(Self {
            reader: FramedRead::new(r, ClientCodec),
            writer: FramedWrite::new(w, ClientCodec),
            next_id: 1,
        })
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

    /// Receives the next answer, to a request of op `op`.
    pub async fn recv(&mut self, op: Op) -> Result<(u32, Answer), ClientError> {
        let body = match self.reader.next().await {
            Some(frame) => frame?,
            None => return Err(io::Error::from(io::ErrorKind::UnexpectedEof).into()),
        };
        decode_answer(body, op).ok_or_else(|| ClientError::Unexpected("undecodable answer".into()))
    }

    /// One request, one answer.
    pub async fn call(&mut self, req: &Request) -> Result<Answer, ClientError> {
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

    /// Sends all requests, then reads all answers (in order).
    pub async fn pipeline(&mut self, reqs: &[Request]) -> Result<Vec<Answer>, ClientError> {
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

/// A blocking client: an async [`Client`] on its own small runtime.
pub struct BlockingClient {
    rt: tokio::runtime::Runtime,
    inner: Client,
}

impl BlockingClient {
    /// Connects.
    pub fn connect(addr: &str) -> io::Result<Self> {
        let rt = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()?;
        let inner = rt.block_on(Client::connect(addr))?;
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

    /// Reads an object.
    pub fn read(&mut self, addr: ObjectAddress, ty: ValueType) -> Result<Value, ClientError> {
        self.rt.block_on(self.inner.read(addr, ty))
    }

    /// Writes an object.
    pub fn write(&mut self, addr: ObjectAddress, v: Value) -> Result<(), ClientError> {
        self.rt.block_on(self.inner.write(addr, v))
    }
}
