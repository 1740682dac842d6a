//! The socket halves as a connection's codecs see them.
//!
//! * [`ClosableRead`] ends, as at end of stream, once the watchdog has
//!   closed its connection (idle, evicted, or the server stopping), and
//!   tells, without reading, whether its client has gone (while a long
//!   request is served, nothing is read):
//!   nothing more is read from the socket, though frames already in the
//!   connection's read buffer are still taken and answered. The close is a flag looked at
//!   before a read and a waker woken by the close, so the connection needs
//!   no second future raced against each read.
//! * [`ClosableWrite`] writes with `write`, not `writev` (the answers wait
//!   in one contiguous buffer, and for a vectored write `tokio-util` first
//!   fills an array of 64 slices, which costs more than the frame itself);
//!   it tells the watchdog when answers wait on a full socket and when a
//!   batch has left in full (progress), and a write blocked by a client
//!   that does not read fails once the connection is closed.

use std::io;
use std::pin::Pin;
use std::sync::Arc;
use std::task::{Context, Poll};

use futures_util::FutureExt;
use tokio::io::{AsyncRead, AsyncWrite, Interest, ReadBuf};
use tokio::net::tcp::OwnedReadHalf;

use super::idle::Activity;

/// `inner`, ending when `activity` is closed.
#[derive(Debug)]
pub(crate) struct ClosableRead<R> {
    inner: R,
    activity: Arc<Activity>,
}

impl<R> ClosableRead<R> {
    /// Reads `inner` until `activity` is closed.
    pub(crate) fn new(inner: R, activity: Arc<Activity>) -> Self {
        Self { inner, activity }
    }
}

impl ClosableRead<OwnedReadHalf> {
    /// Whether the client has gone: its socket has reached end of stream
    /// (the client closed it, or shut down its sending side) or reports an
    /// error, as far as the runtime has seen so far. Looks without reading,
    /// so requests it already sent stay where they are; never waits.
    pub(crate) fn peer_left(&self) -> bool {
        let interest = Interest::READABLE | Interest::ERROR;
        match self.inner.ready(interest).now_or_never() {
            Some(Ok(ready)) => ready.is_read_closed() || ready.is_error(),
            Some(Err(_)) => true,
            None => false,
        }
    }
}

impl<R: AsyncRead + Unpin> AsyncRead for ClosableRead<R> {
    fn poll_read(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &mut ReadBuf<'_>,
    ) -> Poll<io::Result<()>> {
        let this = self.get_mut();
        if this.activity.closed().is_some() {
            return Poll::Ready(Ok(()));
        }
        match Pin::new(&mut this.inner).poll_read(cx, buf) {
            Poll::Pending => this.activity.poll_closed(cx).map(|_| Ok(())),
            ready => ready,
        }
    }
}

/// `inner`, written without vectored writes, reporting to the watchdog and
/// failing once it has closed the connection: a client that stops reading
/// its answers blocks the writes, and the close must end them too.
#[derive(Debug)]
pub(crate) struct ClosableWrite<W> {
    inner: W,
    activity: Arc<Activity>,
}

impl<W> ClosableWrite<W> {
    /// Writes to `inner` until `activity` is closed.
    pub(crate) fn new(inner: W, activity: Arc<Activity>) -> Self {
        Self { inner, activity }
    }

    /// The socket half, to shut it down.
    pub(crate) fn into_inner(self) -> W {
        self.inner
    }
}

/// The error of a write on a connection the watchdog closed.
fn closed_error() -> io::Error {
    io::Error::new(io::ErrorKind::TimedOut, "connection closed by the server")
}

impl<W> ClosableWrite<W> {
    /// `Pending` from the socket (the answers are stuck): still pending
    /// unless the connection was closed meanwhile (then an error; the task
    /// is woken by the close).
    fn pending<T>(&self, cx: &mut Context<'_>) -> Poll<io::Result<T>> {
        self.activity.write_stuck();
        match self.activity.poll_closed(cx) {
            Poll::Ready(_) => Poll::Ready(Err(closed_error())),
            Poll::Pending => Poll::Pending,
        }
    }
}

impl<W: AsyncWrite + Unpin> AsyncWrite for ClosableWrite<W> {
    fn poll_write(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &[u8],
    ) -> Poll<io::Result<usize>> {
        let this = self.get_mut();
        match Pin::new(&mut this.inner).poll_write(cx, buf) {
            Poll::Pending => this.pending(cx),
            ready => ready,
        }
    }

    /// The codec flushes the socket once its buffer is written out in
    /// full: the batch has left, which is progress.
    fn poll_flush(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        let this = self.get_mut();
        match Pin::new(&mut this.inner).poll_flush(cx) {
            Poll::Pending => this.pending(cx),
            Poll::Ready(Ok(())) => {
                this.activity.written();
                Poll::Ready(Ok(()))
            }
            err => err,
        }
    }

    fn poll_shutdown(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.get_mut().inner).poll_shutdown(cx)
    }

    fn is_write_vectored(&self) -> bool {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tcp::idle::Closed;
    use tokio::io::{AsyncReadExt, AsyncWriteExt};

    const HOUR: std::time::Duration = std::time::Duration::from_secs(3600);

    fn activity() -> Arc<Activity> {
        super::super::idle::Watchdog::start(HOUR, HOUR, HOUR, 4)
            .expect("thread")
            .watch(crate::tcp::places::test_seat([127, 0, 0, 1].into()))
    }

    #[tokio::test]
    async fn reads_until_closed_then_ends() {
        let (mut tx, rx) = tokio::io::duplex(64);
        let act = activity();
        let mut r = ClosableRead::new(rx, Arc::clone(&act));
        tx.write_all(b"abc").await.expect("write");
        let mut buf = [0u8; 8];
        assert_eq!(r.read(&mut buf).await.expect("read"), 3);
        act.close(Closed::Stop);
        // Input sent after the close is not read: the stream has ended.
        tx.write_all(b"def").await.expect("write");
        assert_eq!(r.read(&mut buf).await.expect("read"), 0);
    }

    #[tokio::test]
    async fn a_waiting_read_ends_when_closed() {
        let (_tx, rx) = tokio::io::duplex(64);
        let act = activity();
        let mut r = ClosableRead::new(rx, Arc::clone(&act));
        let closer = tokio::spawn(async move {
            tokio::task::yield_now().await;
            act.close(Closed::Idle);
        });
        let mut buf = [0u8; 8];
        assert_eq!(r.read(&mut buf).await.expect("read"), 0);
        closer.await.expect("closer");
    }

    #[tokio::test]
    async fn plain_write_passes_everything_on_and_is_not_vectored() {
        let (tx, mut rx) = tokio::io::duplex(64);
        let mut w = ClosableWrite::new(tx, activity());
        assert!(!w.is_write_vectored());
        w.write_all(b"frame").await.expect("write");
        w.shutdown().await.expect("shutdown");
        let mut got = Vec::new();
        rx.read_to_end(&mut got).await.expect("read");
        assert_eq!(got, b"frame");
    }
}

#[cfg(test)]
mod write_tests {
    use super::*;
    use crate::tcp::idle::{Closed, Watchdog};
    use tokio::io::AsyncWriteExt;

    fn seat() -> crate::tcp::places::Seat {
        crate::tcp::places::test_seat([127, 0, 0, 1].into())
    }

    const HOUR: std::time::Duration = std::time::Duration::from_secs(3600);

    #[tokio::test]
    async fn a_blocked_write_ends_when_closed() {
        let dog = Watchdog::start(HOUR, HOUR, HOUR, 4).expect("thread");
        let act = dog.watch(seat());
        // A peer that never reads: 16 bytes of room.
        let (tx, _rx) = tokio::io::duplex(16);
        let mut w = ClosableWrite::new(tx, Arc::clone(&act));
        w.write_all(&[0; 16]).await.expect("room for 16 bytes");
        let closer = tokio::spawn(async move {
            tokio::task::yield_now().await;
            act.close(Closed::Idle);
        });
        let err = w
            .write_all(&[0; 16])
            .await
            .expect_err("blocked, then closed");
        assert_eq!(err.kind(), io::ErrorKind::TimedOut);
        closer.await.expect("closer");
    }

    /// Bytes trickling out are no progress; the batch leaving in full is.
    #[tokio::test]
    async fn only_a_batch_written_out_in_full_counts_as_progress() {
        use tokio::io::AsyncReadExt;
        let dog = Watchdog::start(HOUR, HOUR, HOUR, 4).expect("thread");
        let act = dog.watch(seat());
        let (tx, mut rx) = tokio::io::duplex(4);
        let mut w = ClosableWrite::new(tx, Arc::clone(&act));
        let reader = tokio::spawn(async move {
            let mut b = [0u8; 1];
            while rx.read(&mut b).await.is_ok_and(|n| n > 0) {}
        });
        w.write_all(&[7; 64])
            .await
            .expect("written a few bytes at a time");
        assert_eq!(act.progress_count(), 0);
        w.flush().await.expect("flush");
        assert_eq!(act.progress_count(), 1);
        drop(w);
        reader.await.expect("reader");
    }
}
