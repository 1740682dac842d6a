//! A door to the server's shared handler for another face of the same
//! object table (an OPC UA server, a fieldbus gateway): its requests are
//! served by the one handler the UOI connections share, under the same
//! lock, so every face sees every change at once.

use std::future::Future;
use std::pin::Pin;
use std::sync::Arc;

use super::handler::Handler;
use super::idle::Activity;
use super::shared::Shared;
use super::slices::{to_the_end, By};
use crate::wire::{Answer, ProtocolError, Request};

/// A boxed answer on its way.
type Pending<'a> = Pin<Box<dyn Future<Output = Answer> + Send + 'a>>;

/// What a [`CoreHandle`] submits to: the shared handler, of any type.
trait Submit: Send + Sync {
    fn submit(&self, req: Request) -> Pending<'_>;
}

impl<H: Handler> Submit for (Shared<H>, Activity) {
    fn submit(&self, req: Request) -> Pending<'_> {
        let (shared, activity) = self;
        Box::pin(async move {
            // Never `None`: nothing closes the activity of no connection.
            let first = shared.serve(req);
            to_the_end(By::Shared(shared), first, activity, &mut ())
                .await
                .unwrap_or(Answer::Protocol(ProtocolError::Busy))
        })
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
}
