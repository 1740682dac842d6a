//! The socket halves as a connection's codecs see them.
//!
//! * [`ClosableRead`] ends, as at end of stream, once the watchdog has
//!   closed its connection (idle, or the server stopping). The close is
//!   looked at only when a read finds no input, so a request already on
//!   the socket costs nothing more, and the connection needs no second
//!   future raced against each read.
//! * [`PlainWrite`] writes with `write`, not `writev`: the answers wait in
//!   one contiguous buffer, and for a vectored write `tokio-util` first
//!   fills an array of 64 slices, which costs more than the frame itself.

use std::io;
use std::pin::Pin;
use std::sync::Arc;
use std::task::{Context, Poll};

use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};

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

/// `inner`, written without vectored writes.
#[derive(Debug)]
pub(crate) struct PlainWrite<W>(pub(crate) W);

impl<W: AsyncWrite + Unpin> AsyncWrite for PlainWrite<W> {
    fn poll_write(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &[u8],
    ) -> Poll<io::Result<usize>> {
        Pin::new(&mut self.get_mut().0).poll_write(cx, buf)
    }

    fn poll_flush(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.get_mut().0).poll_flush(cx)
    }

    fn poll_shutdown(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.get_mut().0).poll_shutdown(cx)
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

    fn activity() -> Arc<Activity> {
        super::super::idle::Watchdog::start(std::time::Duration::from_secs(3600), 4)
            .expect("thread")
            .watch()
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
        let mut w = PlainWrite(tx);
        assert!(!w.is_write_vectored());
        w.write_all(b"frame").await.expect("write");
        w.shutdown().await.expect("shutdown");
        let mut got = Vec::new();
        rx.read_to_end(&mut got).await.expect("read");
        assert_eq!(got, b"frame");
    }
}
