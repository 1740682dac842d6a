//! How connections share the handler: behind a lock ([`Locked`]), or
//! owned by one task that serves the jobs of every connection ([`own`]).
//! Either way a request is served slice by slice, and a long one neither
//! starves the others nor outlives its connection.

use std::any::Any;
use std::collections::VecDeque;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, TryLockError};

use futures_util::SinkExt;
use tokio::sync::{mpsc, oneshot};

use super::connection::AnswerSink;
use super::idle::Activity;
use super::server::{Core, Handler, Slice, Wait};
use crate::wire::{Answer, ProtocolError, Request};

/// A look at the handler between two requests (for
/// [`CoreHandle::inspect`](super::CoreHandle::inspect)).
pub(crate) type Look = Box<dyn FnOnce(&mut dyn Any) + Send>;

/// What the owner task is asked to serve: a request, the rest of one
/// whose wait is over, or a look at the handler.
pub(crate) enum Work {
    Request(Request),
    Resume(u64, bool),
    Look(Look),
}

type Job = (Work, oneshot::Sender<Answer>);

/// Most times a request with more slices to go yields to requests
/// waiting for the lock before it takes the next slice.
const YIELDS_TO_WAITING: usize = 1000;

/// New jobs the owner task serves in a row before it gives the next slice
/// to a job with more to go (so a steady stream of requests cannot starve a
/// long one).
const FRESH_BEFORE_REST: usize = 64;

/// The handler behind a lock, with a count of the requests waiting for it.
pub(crate) struct Locked<H> {
    handler: Mutex<H>,
    /// Requests blocked on the lock right now (a request with more slices
    /// to go lets them in first; the mutex itself is not fair).
    waiting: AtomicUsize,
}

impl<H: Handler> Locked<H> {
    /// One slice under the lock.
    fn slice(&self, req: Request) -> Slice {
        // The count of waiters is touched only when the lock is taken:
        // two shared atomic updates per request cost pipelined traffic
        // about a fifth of its rate.
        self.lock().handle_slice(req)
    }

    /// The handler, locked (the waiting count kept as in `slice`).
    fn lock(&self) -> std::sync::MutexGuard<'_, H> {
        match self.handler.try_lock() {
            Ok(h) => h,
            Err(TryLockError::Poisoned(p)) => p.into_inner(),
            Err(TryLockError::WouldBlock) => {
                self.waiting.fetch_add(1, Ordering::AcqRel);
                let h = self.handler.lock().unwrap_or_else(|p| p.into_inner());
                self.waiting.fetch_sub(1, Ordering::AcqRel);
                h
            }
        }
    }

    /// Between two slices: lets the requests waiting for the lock in
    /// (a bounded number of yields, so a steady stream cannot starve the
    /// long request).
    async fn let_others_in(&self) {
        tokio::task::yield_now().await;
        for _ in 0..YIELDS_TO_WAITING {
            if self.waiting.load(Ordering::Acquire) == 0 {
                return;
            }
            tokio::task::yield_now().await;
        }
    }
}

/// The shared handler.
pub(crate) enum Shared<H> {
    Lock(Arc<Locked<H>>),
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
    /// The handler shared as `core` says: behind a lock, or owned by a
    /// task spawned here (so called within the server's runtime).
    pub(crate) fn new(core: Core, handler: H) -> Self {
        match core {
            Core::Lock => Shared::Lock(Arc::new(Locked {
                handler: Mutex::new(handler),
                waiting: AtomicUsize::new(0),
            })),
            Core::Owner => {
                let (tx, rx) = mpsc::channel::<Job>(1024);
                tokio::spawn(own(handler, rx, tx.downgrade()));
                Shared::Owner(tx)
            }
        }
    }
    /// Answers one request with the shared handler, slice by slice; the
    /// lock is released and other tasks run between slices. When the
    /// connection is closed meanwhile (`closed`: idle, evicted, stopping)
    /// the rest of the request is dropped and `Busy` comes back (nobody
    /// reads it), so a closed connection never keeps the handler busy.
    /// With the lock core, the answers already queued in `sink` are sent
    /// before the request waits for something outside the handler
    /// ([`Slice::Wait`]): a pipelining client is not kept waiting for them
    /// behind it.
    pub(crate) async fn handle(
        &self,
        req: Request,
        closed: &Activity,
        mut sink: Option<&mut AnswerSink>,
    ) -> Answer {
        match self {
            Shared::Lock(m) => {
                // No await while locked: one slice is a plain call.
                let mut slice = m.slice(req);
                loop {
                    slice = match slice {
                        Slice::Done(answer) => return answer,
                        Slice::More(rest) => {
                            m.let_others_in().await;
                            if closed.closed().is_some() {
                                return Answer::Protocol(ProtocolError::Busy);
                            }
                            m.slice(rest)
                        }
                        // Resumed even if the connection closed meanwhile:
                        // the handler must learn how its wait ended.
                        Slice::Wait(Wait { done, token }) => {
                            if let Some(sink) = sink.as_deref_mut() {
                                // A failed flush shows again at the next
                                // send, which closes the connection.
                                let _ = sink.flush().await;
                            }
                            let ok = done.await.unwrap_or(false);
                            m.lock().resume(token, ok)
                        }
                    };
                }
            }
            // Boxed: its state (a channel and a race with the close) would
            // otherwise enlarge every request's future, lock core too.
            Shared::Owner(tx) => Box::pin(ask(tx, req, closed)).await,
        }
    }

    /// Runs `look` on the handler between two requests: under the lock,
    /// or as a job of the owner task (not at all once it has stopped).
    pub(crate) async fn look(&self, look: Look) {
        match self {
            Shared::Lock(m) => look(&mut *m.lock()),
            Shared::Owner(tx) => {
                let (atx, arx) = oneshot::channel();
                if tx.send((Work::Look(look), atx)).await.is_ok() {
                    let _ = arx.await;
                }
            }
        }
    }
}

/// The owner task: serves the jobs of every connection; a job with more
/// slices to go waits behind the jobs that arrived meanwhile; a job that
/// waits comes back as a [`Work::Resume`] once its wait is over.
async fn own<H: Handler>(mut h: H, mut rx: mpsc::Receiver<Job>, me: mpsc::WeakSender<Job>) {
    let mut later: VecDeque<Job> = VecDeque::new();
    let mut fresh = 0;
    loop {
        let turn = if fresh >= FRESH_BEFORE_REST {
            fresh = 0;
            later.pop_front()
        } else {
            None
        };
        let job = match turn.map_or_else(|| rx.try_recv().map(|j| (j, true)), |j| Ok((j, false))) {
            Ok((job, new)) => {
                fresh += usize::from(new);
                job
            }
            Err(_) => match later.pop_front() {
                Some(job) => job,
                None => match rx.recv().await {
                    Some(job) => job,
                    None => return,
                },
            },
        };
        let (work, answer) = job;
        let slice = match work {
            Work::Request(req) => h.handle_slice(req),
            Work::Resume(token, ok) => h.resume(token, ok),
            Work::Look(look) => {
                look(&mut h);
                Slice::Done(Answer::Ok)
            }
        };
        match slice {
            Slice::Done(a) => {
                let _ = answer.send(a);
            }
            // The rest waits its turn, unless its connection is gone.
            Slice::More(rest) if !answer.is_closed() => {
                later.push_back((Work::Request(rest), answer));
                tokio::task::yield_now().await;
            }
            Slice::More(_) => {}
            Slice::Wait(wait) => resume_after(wait, answer, me.clone()),
        }
    }
}

/// Sends the rest of a waiting job back to the owner task once its wait is
/// over (even if its connection is gone: the handler must learn how the
/// wait ended).
fn resume_after(wait: Wait, answer: oneshot::Sender<Answer>, me: mpsc::WeakSender<Job>) {
    tokio::spawn(async move {
        let ok = wait.done.await.unwrap_or(false);
        if let Some(tx) = me.upgrade() {
            let _ = tx.send((Work::Resume(wait.token, ok), answer)).await;
        }
    });
}

/// Hands a request to the owner task and waits for its answer, or until
/// the connection is closed (the owner task then drops the rest of it).
async fn ask(tx: &mpsc::Sender<Job>, req: Request, closed: &Activity) -> Answer {
    let (atx, arx) = oneshot::channel();
    if tx.send((Work::Request(req), atx)).await.is_err() {
        return Answer::Protocol(ProtocolError::Busy);
    }
    let gone = std::future::poll_fn(|cx| closed.poll_closed(cx));
    tokio::select! {
        answer = arx => answer.unwrap_or(Answer::Protocol(ProtocolError::Busy)),
        _ = gone => Answer::Protocol(ProtocolError::Busy),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ObjectAddress, Value, ValueType};
    use std::sync::atomic::AtomicU64;

    /// READ of index 0 never ends (counted per slice); any other READ is
    /// answered at once.
    struct Endless(Arc<AtomicU64>);

    impl Handler for Endless {
        type Session = ();
        fn handle(&mut self, _req: Request) -> Answer {
            Answer::Ok
        }
        fn handle_slice(&mut self, req: Request) -> Slice {
            match req {
                Request::Read(a, _) if a.index == 0 => {
                    self.0.fetch_add(1, Ordering::Relaxed);
                    Slice::More(req)
                }
                _ => Slice::Done(Answer::Value(Value::I32(1))),
            }
        }
    }

    fn read(index: u16) -> Request {
        Request::Read(ObjectAddress::new(1, 0, index, 0), ValueType::I32)
    }

    #[tokio::test]
    async fn a_stream_of_new_jobs_cannot_starve_a_long_one() {
        let slices = Arc::new(AtomicU64::new(0));
        let (tx, rx) = mpsc::channel::<Job>(2048);
        let owner = tokio::spawn(own(Endless(Arc::clone(&slices)), rx, tx.downgrade()));
        let (long_tx, _long_rx) = oneshot::channel();
        tx.try_send((Work::Request(read(0)), long_tx))
            .expect("queued");
        let answers: Vec<_> = (0..1000)
            .map(|_| {
                let (atx, arx) = oneshot::channel();
                tx.try_send((Work::Request(read(5)), atx)).expect("queued");
                arx
            })
            .collect();
        for a in answers {
            assert_eq!(a.await.expect("answered"), Answer::Value(Value::I32(1)));
        }
        // The long job had a slice after every 64 new ones at least.
        assert!(slices.load(Ordering::Relaxed) >= 1000 / 64, "{slices:?}");
        drop(tx);
        drop(_long_rx);
        owner.await.expect("the owner task ends once nobody waits");
    }
}
