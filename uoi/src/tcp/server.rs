//! The tokio object server: one task per connection, all connections share
//! one handler (behind a lock, or owned by one task), pipelined requests
//! answered in order.

use std::future::Future;
use std::io;
use std::net::SocketAddr;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use tokio::time::Instant;

use tokio::io::{AsyncReadExt, AsyncWriteExt, BufReader, BufWriter};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{mpsc, oneshot, watch, Semaphore};
use tokio::task::JoinSet;
use tracing::{debug, info, warn};

use crate::wire::{
    decode_request, encode_answer, Answer, ProtocolError, Request, MAX_FRAME, PREFIX_LEN,
};

/// What serves the requests: the emulator, in `addipos`.
pub trait Handler: Send + 'static {
    /// Answers one request.
    fn handle(&mut self, req: &Request) -> Answer;
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
                h.handle(&req)
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
                        let _ = answer.send(h.handle(&req));
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

async fn refuse(mut stream: TcpStream) {
    let mut out = Vec::new();
    encode_answer(0, 0, &Answer::Protocol(ProtocolError::Busy), &mut out);
    let _ = stream.write_all(&out).await;
    let _ = stream.shutdown().await;
}

async fn serve_connection<H: Handler>(
    stream: TcpStream,
    shared: Shared<H>,
    idle: Duration,
    mut stop: watch::Receiver<bool>,
) {
    let (r, w) = stream.into_split();
    let mut r = BufReader::with_capacity(MAX_FRAME + PREFIX_LEN, r);
    let mut w = BufWriter::with_capacity(64 * 1024, w);
    let mut body = Vec::with_capacity(256);
    let mut out = Vec::with_capacity(256);
    // One timer for the connection, moved on only when it fires: a request
    // costs a clock read, not a timer update.
    let mut last = Instant::now();
    let watchdog = tokio::time::sleep(idle);
    tokio::pin!(watchdog);
    // Registered once, not on every wait.
    let stopped = stop.changed();
    tokio::pin!(stopped);
    loop {
        let mut prefix = [0u8; PREFIX_LEN];
        if r.buffer().len() >= PREFIX_LEN {
            // Pipelined: the next prefix is already here.
            if r.read_exact(&mut prefix).await.is_err() {
                break;
            }
        } else {
            let got = loop {
                tokio::select! {
                    res = r.read_exact(&mut prefix) => break res.is_ok(),
                    () = &mut watchdog => {
                        if last.elapsed() >= idle {
                            debug!("idle timeout");
                            break false;
                        }
                        watchdog.as_mut().reset(last + idle);
                    }
                    _ = &mut stopped => break false,
                }
            };
            if !got {
                break; // closed, half a frame then closed, idle, or shutdown
            }
        }
        let len = u32::from_le_bytes(prefix) as usize;
        if len > MAX_FRAME {
            warn!(len, "frame too large, closing");
            out.clear();
            encode_answer(
                0,
                0,
                &Answer::Protocol(ProtocolError::FrameTooLarge),
                &mut out,
            );
            let _ = w.write_all(&out).await;
            break;
        }
        body.resize(len, 0);
        let complete = if r.buffer().len() >= len {
            r.read_exact(&mut body).await.is_ok()
        } else {
            matches!(
                tokio::time::timeout(idle, r.read_exact(&mut body)).await,
                Ok(Ok(_))
            )
        };
        if !complete {
            break;
        }
        last = Instant::now();
        let (id, op, answer) = match decode_request(&body) {
            Ok((id, req)) => (id, req.op() as u8, shared.handle(req).await),
            Err((id, op, e)) => {
                debug!(error = %e, "bad request");
                (id, op, Answer::Protocol(e))
            }
        };
        out.clear();
        encode_answer(id, op, &answer, &mut out);
        if w.write_all(&out).await.is_err() {
            break;
        }
        // Answer pipelined requests in batches: flush when nothing more waits.
        if r.buffer().is_empty() && w.flush().await.is_err() {
            break;
        }
    }
    let _ = w.flush().await;
    let _ = w.shutdown().await;
}
