//! A request served to its end, slice by slice, by a connection's session
//! or by the shared handler: the one loop for whatever a request's first
//! slice left (more slices, or a wait), for a connection's requests and for
//! those of another face through a [`CoreHandle`](super::CoreHandle). A
//! connection serves the first slice itself, in line: most requests take
//! one slice and never come here.
//!
//! Between two slices other tasks run (and, for the shared handler, the
//! requests waiting for its lock first), and the request stops once its
//! connection is closed, so a long request neither starves the others nor
//! outlives its connection. A request that waits ([`Slice::Wait`]) is
//! awaited without holding the handler.

use std::future::Future;

use super::handler::{Handler, Session, Slice, Wait};
use super::idle::Activity;
use super::shared::Shared;
use crate::wire::{Answer, Request};

/// Most times a request with more slices to go yields to requests
/// waiting for the lock before it takes the next slice (so a steady
/// stream of them cannot starve it).
const YIELDS_TO_WAITING: usize = 1000;

/// Who serves a request.
pub(crate) enum By<'a, H: Handler> {
    /// The connection's own session.
    Session(&'a mut H::Session),
    /// The handler all connections share.
    Shared(&'a Shared<H>),
}

impl<H: Handler> By<'_, H> {
    fn serve(&mut self, req: Request) -> Slice {
        match self {
            By::Session(s) => s.serve(req),
            By::Shared(s) => s.serve(req),
        }
    }

    fn resume(&mut self, token: u64, ok: bool) -> Slice {
        match self {
            By::Session(s) => s.resume(token, ok),
            By::Shared(s) => s.resume(token, ok),
        }
    }

    /// Between two slices: lets other tasks run, and the requests waiting
    /// for the shared handler's lock in first (a bounded number of
    /// yields).
    async fn let_others_run(&mut self) {
        tokio::task::yield_now().await;
        if let By::Shared(shared) = self {
            for _ in 0..YIELDS_TO_WAITING {
                if !shared.contended() {
                    return;
                }
                tokio::task::yield_now().await;
            }
        }
    }
}

/// What a request's caller does before the request waits for something
/// outside the handler: a connection sends the answers it already has.
pub(crate) trait BeforeWait: Send {
    /// Done before each wait.
    fn before_wait(&mut self) -> impl Future<Output = ()> + Send;
}

/// Nothing to do before a wait.
impl BeforeWait for () {
    async fn before_wait(&mut self) {}
}

/// Serves a request to its end with `by`, from what its last slice left
/// (`slice`); `caller` is told before the request waits. `None` when
/// `activity` is closed (idle, evicted, stopping) before the request is
/// done: the rest of it is dropped, so a closed connection never keeps the
/// handler busy.
pub(crate) async fn to_the_end<H: Handler>(
    mut by: By<'_, H>,
    mut slice: Slice,
    activity: &Activity,
    caller: &mut impl BeforeWait,
) -> Option<Answer> {
    loop {
        slice = match slice {
            Slice::Done(answer) => return Some(answer),
            Slice::More(rest) => {
                by.let_others_run().await;
                if activity.closed().is_some() {
                    return None;
                }
                by.serve(rest)
            }
            // Resumed even if the connection closed meanwhile: the
            // handler must learn how its wait ended.
            Slice::Wait(Wait { done, token }) => {
                caller.before_wait().await;
                let ok = done.await.unwrap_or(false);
                by.resume(token, ok)
            }
        };
    }
}
