//! One connection: frames in, answers out, in order. Pipelined answers are
//! written in batches; the connection ends when the peer closes, on a
//! frame over the size limit, or when the watchdog closes it (idle, or the
//! server stopping) while it waits for a request.

use std::sync::Arc;

use futures_util::{SinkExt, StreamExt};
use tokio::io::AsyncWriteExt;
use tokio::net::tcp::{OwnedReadHalf, OwnedWriteHalf};
use tokio::net::TcpStream;
use tokio_util::codec::{FramedRead, FramedWrite};
use tracing::{debug, warn};

use super::halves::{ClosableRead, ClosableWrite};
use super::idle::{Activity, Closed};
use super::server::{Handler, Served, Session, Shared};
use crate::wire::{
    Answer, CodecError, ProtocolError, Rejected, Reply, Request, ServerCodec, MAX_FRAME, PREFIX_LEN,
};

/// Answers buffered before they are written out even if more requests wait.
const WRITE_BATCH: usize = 64 * 1024;

/// A decoded request with its id, or what to answer a frame that is not one.
type Incoming = Result<(u32, Request), Rejected>;

/// The answer frame for request `id` of op `op`.
pub(crate) fn reply(id: u32, op: u8, answer: Answer) -> Reply {
    Reply { id, op, answer }
}

/// Serves one accepted connection to its end.
pub(crate) async fn serve_connection<H: Handler>(
    stream: TcpStream,
    shared: Shared<H>,
    activity: Arc<Activity>,
) {
    let mut conn = Connection::new(stream, shared, activity);
    while let Some(item) = conn.next_request().await {
        let out = conn.answer(item).await;
        if conn.send(out).await.is_err() {
            break;
        }
    }
    conn.close().await;
}

/// The state of one connection.
struct Connection<H: Handler> {
    reader: FramedRead<ClosableRead<OwnedReadHalf>, ServerCodec>,
    writer: FramedWrite<ClosableWrite<OwnedWriteHalf>, ServerCodec>,
    shared: Shared<H>,
    /// This connection's own state; ends with it.
    session: H::Session,
    activity: Arc<Activity>,
}

impl<H: Handler> Connection<H> {
    fn new(stream: TcpStream, shared: Shared<H>, activity: Arc<Activity>) -> Self {
        let (r, w) = stream.into_split();
        let r = ClosableRead::new(r, Arc::clone(&activity));
        let w = ClosableWrite::new(w, Arc::clone(&activity));
        let mut writer = FramedWrite::new(w, ServerCodec);
        writer.set_backpressure_boundary(WRITE_BATCH);
        Self {
            // Room for the largest frame from the start.
            reader: FramedRead::with_capacity(r, ServerCodec, MAX_FRAME + PREFIX_LEN),
            writer,
            shared,
            session: H::Session::default(),
            activity,
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
                warn!(len, "frame too large, closing");
                let ans = Answer::Protocol(ProtocolError::FrameTooLarge);
                let _ = self.writer.send(reply(0, 0, ans)).await;
                None
            }
            Some(Err(CodecError::Io(_))) | None => {
                if self.activity.closed() == Some(Closed::Idle) {
                    debug!("idle timeout");
                }
                None
            }
        }
    }

    /// The answer to one frame: from the connection's session, or else
    /// from the shared handler.
    async fn answer(&mut self, item: Incoming) -> Reply {
        match item {
            Ok((id, req)) => {
                let op = req.op().code();
                let ans = match self.session.handle(req) {
                    Served::Here(ans) => ans,
                    Served::Shared(req) => self.shared.handle(req).await,
                };
                reply(id, op, ans)
            }
            Err(r) => {
                debug!(error = %r.error, "bad request");
                reply(r.id, r.op, Answer::Protocol(r.error))
            }
        }
    }

    /// Queues an answer, and writes the queue out unless another complete
    /// request is already buffered (its answer joins the batch).
    async fn send(&mut self, out: Reply) -> Result<(), CodecError> {
        self.writer.feed(out).await?;
        if !ServerCodec::has_frame(self.reader.read_buffer()) {
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
