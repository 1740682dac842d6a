//! A door to the server's shared handler for another face of the same
//! object table (an OPC UA server, a fieldbus gateway): its requests are
//! served by the one handler the UOI connections share, under the same
//! lock, so every face sees every change at once.

use std::any::Any;
use std::future::Future;
use std::pin::Pin;
use std::sync::Arc;

use super::handler::Handler;
use super::idle::Activity;
use super::shared::{Look, Shared};
use super::slices::{to_the_end, By};
use crate::wire::{Answer, ProtocolError, Request};

/// A boxed answer on its way.
type Pending<'a> = Pin<Box<dyn Future<Output = Answer> + Send + 'a>>;

/// A look on its way.
type Looking<'a> = Pin<Box<dyn Future<Output = ()> + Send + 'a>>;

/// What a [`CoreHandle`] submits to: the shared handler, of any type.
trait Submit: Send + Sync {
    fn submit(&self, req: Request) -> Pending<'_>;
    fn look(&self, look: Look) -> Looking<'_>;
}

impl<H: Handler> Submit for (Shared<H>, Activity) {
    fn submit(&self, req: Request) -> Pending<'_> {
        let (shared, activity) = self;
        Box::pin(async move {
            // Never cut: nothing closes the activity of no connection.
            let first = shared.serve(req);
            to_the_end(By::Shared(shared), first, activity, &mut ())
                .await
                .unwrap_or(Answer::Protocol(ProtocolError::Stopped))
        })
    }

    fn look(&self, look: Look) -> Looking<'_> {
        self.0.look(look);
        Box::pin(std::future::ready(()))
    }
}

/// Submits requests to a server's shared handler from outside the UOI
/// connections (cloned freely; from [`Server::core`](super::Server::core)).
///
/// A request is served like one of a connection: slice by slice, a
/// durable write answered once it is on disk. The handler lives as long
/// as a handle does.
#[derive(Clone)]
pub struct CoreHandle {
    inner: Arc<dyn Submit>,
}

impl std::fmt::Debug for CoreHandle {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("CoreHandle")
    }
}

impl CoreHandle {
    /// A handle of `shared`.
    pub(crate) fn new<H: Handler>(shared: Shared<H>) -> Self {
        Self {
            inner: Arc::new((shared, Activity::unwatched())),
        }
    }

    /// Serves `req` with the shared handler and gives its answer (a HELLO,
    /// which the connections answer themselves, is not for a handle).
    pub async fn call(&self, req: Request) -> Answer {
        self.inner.submit(req).await
    }

    /// Runs `f` on the shared handler (as `dyn Any`: downcast it to the
    /// handler's type) between two requests, under the same lock, and gives
    /// what it returns: for a face that shows more
    /// than single objects (a whole tool table) without a request per
    /// value. `None` once the server has stopped. Keep `f` short: every
    /// connection waits for it.
    pub async fn inspect<T: Send + 'static>(
        &self,
        f: impl FnOnce(&mut dyn Any) -> T + Send + 'static,
    ) -> Option<T> {
        let (tx, rx) = tokio::sync::oneshot::channel();
        let look: Look = Box::new(move |h| {
            let _ = tx.send(f(h));
        });
        self.inner.look(look).await;
        rx.await.ok()
    }
}
