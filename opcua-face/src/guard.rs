//! The door in front of the OPC UA library: clients connect here, and each
//! connection is relayed to the library through a stream inside the
//! process ([`Handover`]): the library listens on no port of its own, so
//! the door is the only way in. The door bounds what a client can make the server hold, where the library
//! alone does not:
//! * connections: at most [`Limits::connections`] in all and
//!   [`Limits::per_peer`] from one address, counted by the UOI server's
//!   own [`Places`];
//! * chunk size: every OPC UA TCP chunk header (8 bytes: type, chunk kind,
//!   size) is read, and a size over [`Limits::max_chunk`] closes the
//!   connection before the library buffers it;
//! * time: a chunk must arrive whole within [`Limits::chunk_time`], a
//!   silent client is closed after [`Limits::idle`], and a client that
//!   does not take its answers within [`Limits::write_stall`] is closed;
//! * sessions: a client must have sent [`ACTIVATED_MSGS`] final message
//!   chunks (`CreateSession` and `ActivateSession`, the least a working
//!   client sends after opening its channel) within [`Limits::activation`]
//!   of connecting, or it is closed: a connection whose session is created
//!   but never activated holds a place for seconds, not minutes (the door
//!   sees only chunk headers, encrypted or not, so it counts messages);
//! * back-pressure: while an answer waits for the client, no further
//!   request is read from it, so answers cannot pile up;
//! * publishing intervals: a chunk is passed on once it is whole, and on a
//!   channel without security a subscription's publishing interval above
//!   ten minutes is lowered to it (`publishing.rs`).
//!
//! A failed accept (no file descriptors left) is logged at most once a
//! second and retried after a pause, so it cannot flood the log.

use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;

use opcua::server::Stream;
use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::mpsc;
use tokio::time::{sleep, timeout, Instant};
use uoi::tcp::{PlaceLimits, Places};

use crate::publishing::Channel;

/// Size of an OPC UA TCP chunk header.
const HEADER: usize = 8;

/// Pause after a failed accept.
const ACCEPT_PAUSE: Duration = Duration::from_millis(100);

/// Bytes one in-process stream to the library buffers each way: a few
/// of the largest chunks.
const PIPE: usize = 256 * 1024;

/// Where the door hands the library each client it lets in: the
/// library's end of an in-process stream, and the client's address.
pub type Handover = mpsc::Sender<(Stream, SocketAddr)>;

/// Final message chunks (`MSG` … `F`) a client sends to create and
/// activate a session.
pub const ACTIVATED_MSGS: u32 = 2;

/// What one client may make the face hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Connections at once, from all clients.
    pub connections: usize,
    /// Connections at once from one address.
    pub per_peer: usize,
    /// Largest chunk, header included (the library's receive buffer).
    pub max_chunk: u32,
    /// Time for one chunk to arrive whole, from its first byte.
    pub chunk_time: Duration,
    /// A client silent this long is closed.
    pub idle: Duration,
    /// A client that takes no answer bytes this long is closed.
    pub write_stall: Duration,
    /// A client that has not sent [`ACTIVATED_MSGS`] messages this long
    /// after connecting (no session activated) is closed.
    pub activation: Duration,
}

impl Limits {
    /// The face's limits, for chunks of at most `max_chunk` bytes.
    pub fn new(max_chunk: u32) -> Self {
        Limits {
            connections: 64,
            per_peer: 16,
            max_chunk,
            chunk_time: Duration::from_secs(30),
            idle: Duration::from_secs(300),
            write_stall: Duration::from_secs(30),
            activation: Duration::from_secs(10),
        }
    }
}

/// The door's places for `limits`: every client connection open counts.
pub fn places(limits: &Limits) -> Arc<Places> {
    Places::new(PlaceLimits {
        all: limits.connections,
        per_peer: limits.per_peer,
        per_peer_on_loopback: true,
    })
}

/// Accepts clients on `public` and relays each to the library, handed
/// over on `library`, within `limits` and the door's `places`, until the
/// task is dropped.
pub async fn serve(public: TcpListener, library: Handover, limits: Limits, places: Arc<Places>) {
    let mut last_complaint: Option<Instant> = None;
    loop {
        let (client, peer) = match public.accept().await {
            Ok(accepted) => accepted,
            Err(e) => {
                if last_complaint.is_none_or(|t| t.elapsed() >= Duration::from_secs(1)) {
                    tracing::warn!("OPC UA face cannot accept a connection: {e}");
                    last_complaint = Some(Instant::now());
                }
                sleep(ACCEPT_PAUSE).await;
                continue;
            }
        };
        let place = match places.take(peer.ip()) {
            Ok(place) => place,
            Err(full) => {
                tracing::debug!(%peer, "OPC UA connection refused: {full} reached");
                continue;
            }
        };
        let library = library.clone();
        tokio::spawn(async move {
            let _place = place;
            let (server, handed) = tokio::io::duplex(PIPE);
            if library.send((Box::new(handed), peer)).await.is_ok() {
                let _ = client.set_nodelay(true);
                if let Err(why) = relay(client, server, &limits).await {
                    tracing::debug!(%peer, "OPC UA connection closed: {why}");
                }
            }
        });
    }
}

/// Why the door closed a connection (logged at debug level).
#[derive(Debug, thiserror::Error)]
enum Closed {
    /// A chunk's header gave a size outside the limits.
    #[error("a chunk of {size} bytes (at most {max})")]
    ChunkTooLarge {
        /// The size the header gave, bytes.
        size: u32,
        /// The largest chunk taken, bytes.
        max: u32,
    },
    /// Reading from or writing to either side failed.
    #[error(transparent)]
    Io(#[from] std::io::Error),
    /// The library took no request within the write stall.
    #[error("the server takes no requests")]
    ServerStalled,
    /// The client took no answer within the write stall.
    #[error("the client takes no answers")]
    ClientStalled,
    /// No session was activated within the activation time.
    #[error("no session activated in time")]
    NotActivated,
    /// A chunk begun did not arrive whole within the chunk time.
    #[error("a chunk did not arrive in time")]
    ChunkLate,
    /// The client sent nothing for the idle time.
    #[error("the client was silent too long")]
    Silent,
}

/// Follows the chunks of what a client sends; each is passed on once it
/// is whole (at most the largest chunk is held).
#[derive(Debug, Default)]
struct Chunks {
    header: [u8; HEADER],
    have: usize,
    left: usize,
    started: Option<Instant>,
    /// Final message chunks seen whole.
    messages: u32,
    /// The chunk under way, header included.
    chunk: Vec<u8>,
    /// The secure channel the chunks belong to.
    channel: Channel,
}

impl Chunks {
    /// Takes `bytes` from the client and appends the chunks they complete
    /// to `whole`; an error names a chunk too large.
    fn take(&mut self, mut bytes: &[u8], max: u32, whole: &mut Vec<u8>) -> Result<(), Closed> {
        while !bytes.is_empty() {
            if self.started.is_none() {
                self.started = Some(Instant::now());
            }
            if self.have < HEADER {
                let n = (HEADER - self.have).min(bytes.len());
                self.header[self.have..self.have + n].copy_from_slice(&bytes[..n]);
                self.chunk.extend_from_slice(&bytes[..n]);
                self.have += n;
                bytes = &bytes[n..];
                if self.have == HEADER {
                    let size = u32::from_le_bytes([
                        self.header[4],
                        self.header[5],
                        self.header[6],
                        self.header[7],
                    ]);
                    if !(HEADER as u32..=max).contains(&size) {
                        return Err(Closed::ChunkTooLarge { size, max });
                    }
                    self.left = size as usize - HEADER;
                }
            } else {
                let n = self.left.min(bytes.len());
                self.chunk.extend_from_slice(&bytes[..n]);
                self.left -= n;
                bytes = &bytes[n..];
            }
            if self.have == HEADER && self.left == 0 {
                self.chunk_done(whole);
            }
        }
        Ok(())
    }

    /// A chunk is whole: counted, looked at, appended to `whole`; the
    /// next one starts.
    fn chunk_done(&mut self, whole: &mut Vec<u8>) {
        let message = u32::from(self.header[..4] == *b"MSGF");
        self.messages = self.messages.saturating_add(message);
        self.channel.look(&mut self.chunk);
        whole.append(&mut self.chunk);
        self.have = 0;
        self.started = None;
    }

    /// When the chunk under way must be whole, if one is.
    fn deadline(&self, limits: &Limits) -> Option<Instant> {
        self.started.map(|t| t + limits.chunk_time)
    }
}

/// Relays one connection until either side closes or a limit is hit.
async fn relay(
    mut client: TcpStream,
    mut server: impl AsyncRead + AsyncWrite + Unpin,
    limits: &Limits,
) -> Result<(), Closed> {
    let mut chunks = Chunks::default();
    let mut whole = Vec::with_capacity(16 * 1024);
    let mut from_client = vec![0u8; 16 * 1024];
    let mut from_server = vec![0u8; 16 * 1024];
    let activate_by = Instant::now() + limits.activation;
    loop {
        let now = Instant::now();
        let idle_end = now + limits.idle;
        let mut end = chunks
            .deadline(limits)
            .map_or(idle_end, |d| d.min(idle_end));
        if chunks.messages < ACTIVATED_MSGS {
            end = end.min(activate_by);
        }
        tokio::select! {
            read = client.read(&mut from_client) => {
                let n = read?;
                if n == 0 {
                    return Ok(());
                }
                whole.clear();
                chunks.take(&from_client[..n], limits.max_chunk, &mut whole)?;
                timeout(limits.write_stall, server.write_all(&whole))
                    .await
                    .map_err(|_| Closed::ServerStalled)??;
            }
            read = server.read(&mut from_server) => {
                let n = read?;
                if n == 0 {
                    return Ok(());
                }
                // While this answer waits for the client, nothing more is
                // read from it.
                timeout(limits.write_stall, client.write_all(&from_server[..n]))
                    .await
                    .map_err(|_| Closed::ClientStalled)??;
            }
            () = tokio::time::sleep_until(end) => {
                return Err(if end == activate_by && chunks.messages < ACTIVATED_MSGS {
                    Closed::NotActivated
                } else if end < idle_end {
                    Closed::ChunkLate
                } else {
                    Closed::Silent
                });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;

    /// A library that echoes every connection handed to it.
    fn echo() -> Handover {
        let (handover, mut handed) = mpsc::channel::<(Stream, SocketAddr)>(4);
        tokio::spawn(async move {
            while let Some((s, _)) = handed.recv().await {
                tokio::spawn(async move {
                    let (mut r, mut w) = tokio::io::split(s);
                    let _ = tokio::io::copy(&mut r, &mut w).await;
                });
            }
        });
        handover
    }

    async fn door(limits: Limits) -> SocketAddr {
        let public = TcpListener::bind("127.0.0.1:0").await.unwrap();
        let addr = public.local_addr().unwrap();
        tokio::spawn(serve(public, echo(), limits, places(&limits)));
        addr
    }

    fn chunk(kind: &[u8; 4], body: usize) -> Vec<u8> {
        let mut c = kind.to_vec();
        c.extend_from_slice(&((HEADER + body) as u32).to_le_bytes());
        c.resize(HEADER + body, 7);
        c
    }

    /// Sends `bytes` and reads as many back (the echo), or `None` when
    /// the door closed the connection.
    async fn round(s: &mut TcpStream, bytes: &[u8]) -> Option<Vec<u8>> {
        s.write_all(bytes).await.ok()?;
        let mut back = vec![0u8; bytes.len()];
        let guard = Duration::from_secs(20);
        match timeout(guard, s.read_exact(&mut back))
            .await
            .expect("hang guard")
        {
            Ok(_) => Some(back),
            Err(_) => None,
        }
    }

    #[tokio::test]
    async fn chunks_within_the_size_pass_whole_sent_in_any_pieces() {
        let addr = door(Limits::new(1024)).await;
        let mut s = TcpStream::connect(addr).await.unwrap();
        let mut two = chunk(b"HELF", 20);
        two.extend(chunk(b"MSGF", 1016));
        for piece in [&two[..3], &two[3..30]] {
            s.write_all(piece).await.unwrap();
        }
        // The first chunk is whole: it passes; the second waits for its rest.
        let mut first = vec![0u8; 28];
        let guard = Duration::from_secs(20);
        timeout(guard, s.read_exact(&mut first))
            .await
            .unwrap()
            .unwrap();
        assert_eq!(first, two[..28]);
        assert_eq!(
            round(&mut s, &two[30..]).await.as_deref(),
            Some(&two[28..two.len() - 2])
        );
        let mut last = [0u8; 2];
        timeout(guard, s.read_exact(&mut last))
            .await
            .unwrap()
            .unwrap();
        assert_eq!(last, two[two.len() - 2..]);
    }

    #[tokio::test]
    async fn a_chunk_announced_too_large_closes_the_connection() {
        let addr = door(Limits::new(1024)).await;
        let mut s = TcpStream::connect(addr).await.unwrap();
        let mut big = b"HELF".to_vec();
        big.extend_from_slice(&0xFFFF_FFF0u32.to_le_bytes());
        assert_eq!(round(&mut s, &big).await, None);
        let mut s = TcpStream::connect(addr).await.unwrap();
        let mut tiny = b"MSGF".to_vec();
        tiny.extend_from_slice(&3u32.to_le_bytes());
        assert_eq!(round(&mut s, &tiny).await, None);
    }

    #[tokio::test]
    async fn connections_beyond_the_limit_per_peer_are_closed() {
        let limits = Limits {
            per_peer: 2,
            ..Limits::new(1024)
        };
        let addr = door(limits).await;
        let hello = chunk(b"HELF", 4);
        let mut kept = Vec::new();
        for _ in 0..2 {
            let mut s = TcpStream::connect(addr).await.unwrap();
            assert!(round(&mut s, &hello).await.is_some());
            kept.push(s);
        }
        let mut third = TcpStream::connect(addr).await.unwrap();
        assert_eq!(round(&mut third, &hello).await, None);
        // A place comes back when a connection closes.
        drop(kept.pop());
        let mut again = None;
        for _ in 0..200 {
            let mut s = TcpStream::connect(addr).await.unwrap();
            if round(&mut s, &hello).await.is_some() {
                again = Some(s);
                break;
            }
            sleep(Duration::from_millis(10)).await;
        }
        assert!(again.is_some());
        assert!(round(&mut kept[0], &hello).await.is_some());
    }

    /// A client that opens a channel and creates a
    /// session but never activates it (one message) is closed after the
    /// activation time; one that sends both messages stays.
    #[tokio::test]
    async fn a_session_never_activated_does_not_hold_a_place() {
        let limits = Limits {
            activation: Duration::from_millis(300),
            ..Limits::new(1024)
        };
        let addr = door(limits).await;
        let mut lazy = TcpStream::connect(addr).await.unwrap();
        let mut busy = TcpStream::connect(addr).await.unwrap();
        let mut start = chunk(b"HELF", 20);
        start.extend(chunk(b"OPNF", 40));
        start.extend(chunk(b"MSGF", 40));
        assert!(round(&mut lazy, &start).await.is_some());
        assert!(round(&mut busy, &start).await.is_some());
        assert!(round(&mut busy, &chunk(b"MSGF", 40)).await.is_some());
        sleep(Duration::from_millis(600)).await;
        assert_eq!(round(&mut lazy, &chunk(b"MSGF", 40)).await, None);
        assert!(round(&mut busy, &chunk(b"MSGF", 40)).await.is_some());
    }

    #[tokio::test]
    async fn a_chunk_that_never_completes_is_closed() {
        let limits = Limits {
            chunk_time: Duration::from_millis(200),
            ..Limits::new(1024)
        };
        let addr = door(limits).await;
        let mut s = TcpStream::connect(addr).await.unwrap();
        let half = &chunk(b"MSGF", 100)[..50];
        s.write_all(half).await.unwrap();
        let mut rest = [0u8; 1];
        let read = timeout(Duration::from_secs(20), s.read(&mut rest));
        assert_eq!(read.await.expect("hang guard").unwrap_or(0), 0);
    }

    #[tokio::test]
    async fn a_client_that_takes_no_answers_is_closed() {
        // A library that answers without end.
        let (inner, mut handed) = mpsc::channel::<(Stream, SocketAddr)>(4);
        tokio::spawn(async move {
            while let Some((mut s, _)) = handed.recv().await {
                tokio::spawn(async move {
                    let block = vec![1u8; 64 * 1024];
                    while s.write_all(&block).await.is_ok() {}
                });
            }
        });
        let public = TcpListener::bind("127.0.0.1:0").await.unwrap();
        let addr = public.local_addr().unwrap();
        let limits = Limits {
            write_stall: Duration::from_millis(200),
            ..Limits::new(1024)
        };
        tokio::spawn(serve(public, inner, limits, places(&limits)));
        let mut s = TcpStream::connect(addr).await.unwrap();
        sleep(Duration::from_millis(600)).await;
        // What the door passed on before it gave up is bounded by the
        // sockets' buffers; then the connection ends.
        let mut got = 0usize;
        let mut buf = vec![0u8; 64 * 1024];
        loop {
            let read = timeout(Duration::from_secs(20), s.read(&mut buf));
            match read.await.expect("hang guard") {
                Ok(0) | Err(_) => break,
                Ok(n) => got += n,
            }
        }
        assert!(got < 64 * 1024 * 1024, "{got}");
    }
}
