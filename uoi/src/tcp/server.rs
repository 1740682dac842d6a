//! The tokio object server: one task per connection, all connections share
//! one handler (behind a lock, or owned by one task), pipelined requests
//! answered in order.

use std::future::Future;
use std::io;
use std::net::SocketAddr;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use tokio::time::Instant;

use futures_util::{SinkExt, StreamExt};
use tokio::io::AsyncWriteExt;
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{mpsc, oneshot, watch, Semaphore};
use tokio::task::JoinSet;
use tokio_util::codec::{FramedRead, FramedWrite};
use tracing::{debug, info, warn};

use crate::wire::{
    Answer, CodecError, ProtocolError, Rejected, Reply, Request, ServerCodec, MAX_FRAME, PREFIX_LEN,
};

/// Answers buffered before they are written out even if more requests wait.
const WRITE_BATCH: usize = 64 * 1024;

/// What serves the requests: the emulator, in `addipos`.
pub trait Handler: Send + 'static {
    /// Answers one request.
    fn handle(&mut self, req: Request) -> Answer;
}

/// How connections share the handler.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Core {
    /// A mutex around the handler; each request locks it briefly.
    #[default]
    Lock,
    /// One task owns the handler; connections send it requests over a channel.
    Owner,
}

/// Server settings.
#[derive(Debug, Clone)]
pub struct ServerConfig {
    /// Address to listen on (default `127.0.0.1:1300`).
    pub listen: SocketAddr,
    /// Allow a non-loopback listen address.
    pub allow_remote: bool,
    /// Connections served at once; more are answered `Busy` and closed.
    pub max_connections: usize,
    /// A connection with no complete request for this long is closed.
    pub idle_timeout: Duration,
    /// Lock or owner task.
    pub core: Core,
}

impl Default for ServerConfig {
    fn default() -> Self {
        Self {
            listen: SocketAddr::from(([127, 0, 0, 1], 1300)),
            allow_remote: false,
            max_connections: 256,
            idle_timeout: Duration::from_secs(300),
            core: Core::Lock,
        }
    }
}

type Job = (Request, oneshot::Sender<Answer>);

/// The shared handler.
enum Shared<H> {
    Lock(Arc<Mutex<H>>),
    Owner(mpsc::Sender<Job>),
}

impl<H> Clone for Shared<H> {
    fn clone(&self) -> Self {
        match self {
            Shared::Lock(m) => Shared::Lock(Arc::clone(m)),
            Shared::Owner(tx) => Shared::Owner(tx.clone()),
        }
    }
}

impl<H: Handler> Shared<H> {
    async fn handle(&self, req: Request) -> Answer {
        match self {
            Shared::Lock(m) => {
                let mut h = m.lock().unwrap_or_else(|p| p.into_inner());
                h.handle(req)
            }
            Shared::Owner(tx) => {
                let (atx, arx) = oneshot::channel();
                if tx.send((req, atx)).await.is_err() {
                    return Answer::Protocol(ProtocolError::Busy);
                }
                arx.await.unwrap_or(Answer::Protocol(ProtocolError::Busy))
            }
        }
    }
}

/// A bound server, ready to run.
pub struct Server<H> {
    listener: TcpListener,
    cfg: ServerConfig,
    shared: Shared<H>,
}

impl<H: Handler> Server<H> {
    /// Binds the listen address. A non-loopback address is refused unless
    /// `allow_remote` is set.
    pub async fn bind(cfg: ServerConfig, handler: H) -> io::Result<Self> {
        if !cfg.listen.ip().is_loopback() && !cfg.allow_remote {
            return Err(io::Error::new(
                io::ErrorKind::PermissionDenied,
                format!(
                    "{} is not a loopback address: listening there needs --allow-remote",
                    cfg.listen
                ),
            ));
        }
        let listener = TcpListener::bind(cfg.listen).await?;
        let shared = match cfg.core {
            Core::Lock => Shared::Lock(Arc::new(Mutex::new(handler))),
            Core::Owner => {
                let (tx, mut rx) = mpsc::channel::<Job>(1024);
                let mut h = handler;
                tokio::spawn(async move {
                    while let Some((req, answer)) = rx.recv().await {
                        let _ = answer.send(h.handle(req));
                    }
                });
                Shared::Owner(tx)
            }
        };
        Ok(Self {
            listener,
            cfg,
            shared,
        })
    }

    /// The address actually bound (port 0 picks a free port).
    pub fn local_addr(&self) -> io::Result<SocketAddr> {
        self.listener.local_addr()
    }

    /// Serves until `shutdown` completes, then stops accepting, lets every
    /// connection finish the request it is on, and returns.
    pub async fn run(self, shutdown: impl Future<Output = ()>) -> io::Result<()> {
        let Server {
            listener,
            cfg,
            shared,
        } = self;
        info!(listen = %listener.local_addr()?, max_connections = cfg.max_connections, core = ?cfg.core, "serving UOI");
        let permits = Arc::new(Semaphore::new(cfg.max_connections));
        let (stop_tx, stop_rx) = watch::channel(false);
        let mut tasks = JoinSet::new();
        tokio::pin!(shutdown);
        loop {
            tokio::select! {
                () = &mut shutdown => break,
                accepted = listener.accept() => {
                    let (stream, peer) = match accepted {
                        Ok(a) => a,
                        Err(e) => {
                            warn!(error = %e, "accept failed");
                            tokio::time::sleep(Duration::from_millis(10)).await;
                            continue;
                        }
                    };
                    let _ = stream.set_nodelay(true);
                    match permits.clone().try_acquire_owned() {
                        Ok(permit) => {
                            let shared = shared.clone();
                            let stop = stop_rx.clone();
                            let idle = cfg.idle_timeout;
                            tasks.spawn(async move {
                                debug!(%peer, "connected");
                                serve_connection(stream, shared, idle, stop).await;
                                debug!(%peer, "disconnected");
                                drop(permit);
                            });
                        }
                        Err(_) => {
                            warn!(%peer, "connection limit reached, refusing");
                            tasks.spawn(refuse(stream));
                        }
                    }
                }
                Some(_) = tasks.join_next(), if !tasks.is_empty() => {}
            }
        }
        info!("shutting down: finishing open connections");
        let _ = stop_tx.send(true);
        let drain = async { while tasks.join_next().await.is_some() {} };
        if tokio::time::timeout(Duration::from_secs(5), drain)
            .await
            .is_err()
        {
            warn!("connections still open after 5 s; closing them");
        }
        Ok(())
    }
}

async fn refuse(stream: TcpStream) {
    let mut w = FramedWrite::new(stream, ServerCodec);
    let _ = w
        .send(reply(0, 0, Answer::Protocol(ProtocolError::Busy)))
        .await;
    let _ = w.into_inner().shutdown().await;
}

fn reply(id: u32, op: u8, answer: Answer) -> Reply {
    Reply { id, op, answer }
}

/// What ended the wait for the next frame.
enum Next {
    Frame(Option<Result<Incoming, CodecError>>),
    Idle,
    Stop,
}

type Incoming = Result<(u32, Request), Rejected>;

async fn serve_connection<H: Handler>(
    stream: TcpStream,
    shared: Shared<H>,
    idle: Duration,
    mut stop: watch::Receiver<bool>,
) {
    let (r, w) = stream.into_split();
    let mut reader = FramedRead::with_capacity(r, ServerCodec, MAX_FRAME + PREFIX_LEN);
    let mut writer = FramedWrite::new(w, ServerCodec);
    writer.set_backpressure_boundary(WRITE_BATCH);
    // One timer for the connection, moved on only when it fires: a request
    // costs a clock read, not a timer update.
    let mut last = Instant::now();
    let watchdog = tokio::time::sleep(idle);
    tokio::pin!(watchdog);
    // Registered once, not on every wait.
    let stopped = stop.changed();
    tokio::pin!(stopped);
    loop {
        let next = tokio::select! {
            biased;
            f = reader.next() => Next::Frame(f),
            () = &mut watchdog => {
                if last.elapsed() < idle {
                    watchdog.as_mut().reset(last + idle);
                    continue;
                }
                Next::Idle
            }
            _ = &mut stopped => Next::Stop,
        };
        let item = match next {
            Next::Frame(Some(Ok(item))) => item,
            Next::Frame(Some(Err(CodecError::FrameTooLarge(len)))) => {
                warn!(len, "frame too large, closing");
                let ans = Answer::Protocol(ProtocolError::FrameTooLarge);
                let _ = writer.send(reply(0, 0, ans)).await;
                break;
            }
            // Closed, half a frame then closed, a broken connection.
            Next::Frame(_) => break,
            Next::Idle => {
                debug!("idle timeout");
                break;
            }
            Next::Stop => break,
        };
        last = Instant::now();
        let out = match item {
            Ok((id, req)) => {
                let op = req.op().code();
                reply(id, op, shared.handle(req).await)
            }
            Err(r) => {
                debug!(error = %r.error, "bad request");
                reply(r.id, r.op, Answer::Protocol(r.error))
            }
        };
        if writer.feed(out).await.is_err() {
            break;
        }
        // Answer pipelined requests in batches: flush when nothing more waits.
        if reader.read_buffer().is_empty() && writer.flush().await.is_err() {
            break;
        }
    }
    let _ = writer.flush().await;
    let _ = writer.into_inner().shutdown().await;
}
