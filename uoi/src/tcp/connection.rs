//! One connection: frames in, answers out, in order. Pipelined answers are
//! written in batches; the connection ends when the peer closes, on a
//! frame over the size limit, on a request from a peer that has not
//! presented the access token, or when the watchdog closes it (idle,
//! answers not taken, evicted to make room for a new connection when the
//! server is full, or the server stopping).

use std::net::SocketAddr;
use std::sync::Arc;

use futures_util::{SinkExt, StreamExt};
use tokio::io::AsyncWriteExt;
use tokio::net::tcp::{OwnedReadHalf, OwnedWriteHalf};
use tokio::net::TcpStream;
use tokio_util::codec::{Encoder, FramedRead, FramedWrite};
use tracing::{debug, warn};

use super::access::{is_hello_payload, AccessToken};
use super::floods::FloodLogs;
use super::halves::{ClosableRead, ClosableWrite};
use super::handler::{Handler, Session, Slice};
use super::idle::{Activity, Closed};
use super::shared::Shared;
use super::slices::{to_the_end, By, Caller, Cut};
use crate::wire::{
    Answer, CodecError, Op, ProtocolError, Rejected, Reply, Request, ServerCodec, MAX_FRAME,
    PREFIX_LEN,
};

/// Answers buffered before they are written out even if more requests wait.
const WRITE_BATCH: usize = 64 * 1024;

/// A decoded request with its id, or what to answer a frame that is not one.
type Incoming = Result<(u32, Request), Rejected>;

/// Where a connection's answers go.
type AnswerSink = FramedWrite<ClosableWrite<OwnedWriteHalf>, ServerCodec>;

/// Where a connection's requests come from.
type RequestSource = FramedRead<ClosableRead<OwnedReadHalf>, ServerCodec>;

/// A connection as the caller of a long request: its answer sink, and its
/// socket's reading side watched for the client leaving.
struct Serving<'a> {
    writer: &'a mut AnswerSink,
    reader: &'a RequestSource,
}

impl Caller for Serving<'_> {
    /// The answers already queued leave.
    async fn before_wait(&mut self) {
        // A failed flush shows again at the next send, which closes the
        // connection.
        let _ = self.writer.flush().await;
    }

    fn left(&self) -> bool {
        self.reader.get_ref().peer_left()
    }
}

/// The answer frame for request `id` of op `op`.
pub(crate) fn reply(id: u32, op: u8, answer: Answer) -> Reply {
    Reply { id, op, answer }
}

/// What a connection lets through: everything once its peer is
/// authorized (it needs no token, or has presented it in a HELLO frame).
#[derive(Debug)]
pub(crate) struct Gatekeeper {
    /// The server's token; `None` when it asks none.
    token: Option<AccessToken>,
    authorized: bool,
    /// The peer, for the log.
    peer: SocketAddr,
    /// The server's limits on lines a client can make it repeat.
    logs: Arc<FloodLogs>,
}

/// Whether a connection goes on after an answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Then {
    GoOn,
    Close,
}

impl Gatekeeper {
    /// A gate for `peer`, `authorized` already or to present `token`;
    /// its log lines limited by `logs`.
    pub(crate) fn new(
        token: Option<AccessToken>,
        authorized: bool,
        peer: SocketAddr,
        logs: Arc<FloodLogs>,
    ) -> Self {
        Self {
            token,
            authorized,
            peer,
            logs,
        }
    }

    /// HELLO: `Ok` for the server's token, or, when the server asks none,
    /// for a well-formed payload (empty, or shaped like a token), else
    /// `BadPayload` (the connection stays open); `Unauthorized`, and the
    /// connection closed, for a wrong token (also from a peer that needs
    /// none: its client is misconfigured).
    fn hello(&mut self, presented: &[u8]) -> (Answer, Then) {
        match &self.token {
            Some(t) if !t.matches(presented) => {
                if let Some(suppressed) = self.logs.wrong_token.allow() {
                    warn!(peer = %self.peer, suppressed, "wrong access token, closing");
                }
                (Answer::Protocol(ProtocolError::Unauthorized), Then::Close)
            }
            None if !is_hello_payload(presented) => {
                (Answer::Protocol(ProtocolError::BadPayload), Then::GoOn)
            }
            _ => {
                self.authorized = true;
                (Answer::Ok, Then::GoOn)
            }
        }
    }
}

/// Serves one accepted connection to its end.
pub(crate) async fn serve_connection<H: Handler>(
    stream: TcpStream,
    shared: Shared<H>,
    activity: Arc<Activity>,
    gate: Gatekeeper,
) {
    let mut conn = Connection::new(stream, shared, activity, gate);
    while let Some(item) = conn.next_request().await {
        let (out, then) = match conn.answer(item) {
            Answered::Now(out, then) => (out, then),
            // Rare (a long request, or one that waits): boxed, so that its
            // state does not enlarge the future every request moves.
            Answered::Later(rest) => Box::pin(conn.finish(rest)).await,
        };
        if conn.send(out).await.is_err() || then == Then::Close {
            break;
        }
    }
    conn.close().await;
}

/// The answer to one frame, or the request its first slice left
/// unfinished (`R`: the handler's rest of a request).
enum Answered<R> {
    /// The answer frame, and whether the connection goes on.
    Now(Reply, Then),
    /// A request with more slices to go, or waiting.
    Later(Unfinished<R>),
}

/// A request its first slice did not finish.
struct Unfinished<R> {
    id: u32,
    op: u8,
    /// Its connection's session serves it (else the shared handler).
    by_session: bool,
    /// What its last slice left: more to serve, or a wait.
    slice: Slice<R>,
}

/// The state of one connection.
struct Connection<H: Handler> {
    reader: RequestSource,
    writer: AnswerSink,
    shared: Shared<H>,
    /// This connection's own state; ends with it.
    session: H::Session,
    activity: Arc<Activity>,
    gate: Gatekeeper,
}

impl<H: Handler> Connection<H> {
    fn new(
        stream: TcpStream,
        shared: Shared<H>,
        activity: Arc<Activity>,
        gate: Gatekeeper,
    ) -> Self {
        let (r, w) = stream.into_split();
        let r = ClosableRead::new(r, Arc::clone(&activity));
        let w = ClosableWrite::new(w, Arc::clone(&activity));
        let mut writer = FramedWrite::new(w, ServerCodec);
        writer.set_backpressure_boundary(WRITE_BATCH);
        Self {
            // Room for the largest frame from the start.
            reader: FramedRead::with_capacity(r, ServerCodec, MAX_FRAME + PREFIX_LEN),
            writer,
            session: shared.open_session(),
            shared,
            activity,
            gate,
        }
    }

    /// Waits for the next complete frame. `None` when the connection is to
    /// end: closed by the peer (possibly in the middle of a frame), broken,
    /// a frame over the size limit (answered first), or closed by the
    /// watchdog.
    async fn next_request(&mut self) -> Option<Incoming> {
        match self.reader.next().await {
            Some(Ok(item)) => {
                self.activity.progress();
                Some(item)
            }
            Some(Err(CodecError::FrameTooLarge(len))) => {
                if let Some(suppressed) = self.gate.logs.too_large.allow() {
                    warn!(peer = %self.gate.peer, len, suppressed, "frame too large, closing");
                }
                let ans = Answer::Protocol(ProtocolError::FrameTooLarge);
                let _ = self.writer.send(reply(0, 0, ans)).await;
                None
            }
            Some(Err(CodecError::Io(_))) | None => {
                match self.activity.closed() {
                    Some(Closed::Idle) => debug!("idle timeout"),
                    Some(Closed::Write) => debug!("answers not taken: write timeout"),
                    Some(Closed::Evicted) => {
                        debug!("closed to make room for a new connection: quiet longest")
                    }
                    _ => {}
                }
                None
            }
        }
    }

    /// The answer to one frame, or what its first slice left: a request
    /// goes to the connection's session if it takes it, else to the
    /// shared handler. A peer not yet authorized gets `Unauthorized` for
    /// anything but HELLO, and the connection is closed.
    fn answer(&mut self, item: Incoming) -> Answered<H::Rest> {
        let (out, then) = match item {
            Ok((id, Request::Hello(token))) => {
                let (ans, then) = self.gate.hello(&token);
                if ans == Answer::Ok && self.gate.token.is_some() {
                    // It has shown the token: a newcomer may not take its
                    // place.
                    self.activity.trust();
                }
                (reply(id, Op::Hello.code(), ans), then)
            }
            Ok((id, req)) if !self.gate.authorized => {
                if let Some(suppressed) = self.gate.logs.before_token.allow() {
                    warn!(peer = %self.gate.peer, suppressed, "request before the access token, closing");
                }
                let ans = Answer::Protocol(ProtocolError::Unauthorized);
                (reply(id, req.op().code(), ans), Then::Close)
            }
            Err(r) if !self.gate.authorized => {
                if let Some(suppressed) = self.gate.logs.before_token.allow() {
                    warn!(peer = %self.gate.peer, suppressed, "bad frame before the access token, closing");
                }
                let ans = Answer::Protocol(ProtocolError::Unauthorized);
                (reply(r.id, r.op, ans), Then::Close)
            }
            Ok((id, req)) => {
                let op = req.op().code();
                let by_session = self.session.takes(&req);
                let slice = if by_session {
                    self.session.serve(req)
                } else {
                    self.shared.serve(req)
                };
                match slice {
                    Slice::Done(ans) => {
                        self.activity.trust();
                        (reply(id, op, ans), Then::GoOn)
                    }
                    slice => {
                        return Answered::Later(Unfinished {
                            id,
                            op,
                            by_session,
                            slice,
                        })
                    }
                }
            }
            Err(r) => {
                debug!(error = %r.error, "bad request");
                (reply(r.id, r.op, Answer::Protocol(r.error)), Then::GoOn)
            }
        };
        Answered::Now(out, then)
    }

    /// The answer to a request its first slice left unfinished, served
    /// slice by slice. The answers already queued leave before the request
    /// waits for something outside the handler: a pipelining client is not
    /// kept waiting for them behind it. When the server closes the
    /// connection (stopping) before the request is done, the rest of it is
    /// dropped, the request is answered `Stopped` and the connection ends;
    /// when the client has left, the rest is dropped and the connection
    /// ends without an answer.
    async fn finish(&mut self, rest: Unfinished<H::Rest>) -> (Reply, Then) {
        let by = if rest.by_session {
            By::Session(&mut self.session)
        } else {
            By::Shared(&self.shared)
        };
        let mut caller = Serving {
            writer: &mut self.writer,
            reader: &self.reader,
        };
        match to_the_end(by, rest.slice, &self.activity, &mut caller).await {
            Ok(ans) => {
                self.activity.trust();
                (reply(rest.id, rest.op, ans), Then::GoOn)
            }
            Err(Cut::Left) => {
                debug!(peer = %self.gate.peer, "client left during a request: stopped it");
                // Nobody reads the answer; it is sent all the same, and the
                // connection ends.
                let stopped = Answer::Protocol(ProtocolError::Stopped);
                (reply(rest.id, rest.op, stopped), Then::Close)
            }
            Err(Cut::Closed(_)) => {
                let stopped = Answer::Protocol(ProtocolError::Stopped);
                (reply(rest.id, rest.op, stopped), Then::Close)
            }
        }
    }

    /// Queues an answer, and writes the queue out unless another complete
    /// request is already buffered (its answer joins the batch) and the
    /// batch is not full. The answer is encoded straight into the
    /// writer's buffer: the sink's readiness step would only repeat the
    /// batch check.
    async fn send(&mut self, out: Reply) -> Result<(), CodecError> {
        ServerCodec.encode(out, self.writer.write_buffer_mut())?;
        let full = self.writer.write_buffer().len() >= WRITE_BATCH;
        if full || !ServerCodec::has_frame(self.reader.read_buffer()) {
            self.writer.flush().await?;
        }
        Ok(())
    }

    /// Writes out what is queued and closes the sending side.
    async fn close(self) {
        let mut writer = self.writer;
        let _ = writer.flush().await;
        let _ = writer.into_inner().into_inner().shutdown().await;
    }
}
