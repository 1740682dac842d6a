//! A request served to its end, slice by slice, by a connection's session
//! or by the shared handler: the one loop for whatever a request's first
//! slice left (more slices, or a wait), for a connection's requests and for
//! those of another face through a [`CoreHandle`](super::CoreHandle). A
//! connection serves the first slice itself, in line: most requests take
//! one slice and never come here.
//!
//! Between two slices other tasks run (and, for the shared handler, the
//! requests waiting for its lock first), and the request stops once its
//! connection is closed — by the server (stopping) or by its client (end
//! of stream or an error on the socket) — so a long request neither
//! starves the others nor outlives its connection. Each slice served is
//! progress: a request being served is never idle. A request that waits
//! ([`Slice::Wait`]) is awaited without holding the handler.

use std::future::Future;

use super::handler::{Handler, Session, Slice, Wait};
use super::idle::{Activity, Closed};
use super::shared::Shared;
use crate::wire::Answer;

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
    fn proceed(&mut self, rest: H::Rest) -> Slice<H::Rest> {
        match self {
            By::Session(s) => s.proceed(rest),
            By::Shared(s) => s.proceed(rest),
        }
    }

    fn resume(&mut self, token: u64, ok: bool) -> Slice<H::Rest> {
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

/// What a request's caller does for it: a connection sends the answers
/// it already has before the request waits, and says when its client has
/// left.
pub(crate) trait Caller: Send {
    /// Done before each wait.
    fn before_wait(&mut self) -> impl Future<Output = ()> + Send;

    /// Whether the client has gone (end of stream, or an error, on its
    /// socket): nobody is left to take the answer.
    fn left(&self) -> bool;
}

/// Nothing to do before a wait, and nobody who could leave.
impl Caller for () {
    async fn before_wait(&mut self) {}

    fn left(&self) -> bool {
        false
    }
}

/// Why a request was not served to its end.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Cut {
    /// The server closed its connection (stopping, or the answers stuck).
    Closed(Closed),
    /// Its client left.
    Left,
}

/// Serves a request to its end with `by`, from what its last slice left
/// (`slice`); `caller` is told before the request waits. Every slice is
/// progress of `activity`. Cut short when `activity` is closed (stopping)
/// or the caller's client has left before the request is done: the rest of
/// it is dropped at the next slice boundary, so a closed connection never
/// keeps the handler busy.
pub(crate) async fn to_the_end<H: Handler>(
    mut by: By<'_, H>,
    mut slice: Slice<H::Rest>,
    activity: &Activity,
    caller: &mut impl Caller,
) -> Result<Answer, Cut> {
    loop {
        slice = match slice {
            Slice::Done(answer) => return Ok(answer),
            Slice::More(rest) => {
                activity.progress();
                by.let_others_run().await;
                if let Some(why) = activity.closed() {
                    return Err(Cut::Closed(why));
                }
                if caller.left() {
                    return Err(Cut::Left);
                }
                by.proceed(rest)
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
