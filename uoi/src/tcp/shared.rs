//! The handler every connection shares, behind a lock: each slice of a
//! request locks it briefly (no await while it is held), and a request
//! with more slices to go lets the requests waiting for the lock in
//! before it takes its next slice.

use std::any::Any;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, TryLockError};

use super::handler::{Handler, Slice};
use crate::wire::Request;

/// A look at the handler between two requests (for
/// [`CoreHandle::inspect`](super::CoreHandle::inspect)).
pub(crate) type Look = Box<dyn FnOnce(&mut dyn Any) + Send>;

/// The handler behind a lock, with a count of the requests waiting for it.
struct Locked<H> {
    handler: Mutex<H>,
    /// Requests blocked on the lock right now (a request with more slices
    /// to go lets them in first; the mutex itself is not fair).
    waiting: AtomicUsize,
}

/// The shared handler (cloned for each connection).
pub(crate) struct Shared<H>(Arc<Locked<H>>);

impl<H> Clone for Shared<H> {
    fn clone(&self) -> Self {
        Self(Arc::clone(&self.0))
    }
}

impl<H: Handler> Shared<H> {
    /// `handler`, to share.
    pub(crate) fn new(handler: H) -> Self {
        Self(Arc::new(Locked {
            handler: Mutex::new(handler),
            waiting: AtomicUsize::new(0),
        }))
    }

    /// The handler, locked. The count of waiters is touched only when the
    /// lock is contended: two shared atomic updates per request cost
    /// pipelined traffic about a fifth of its rate.
    fn lock(&self) -> MutexGuard<'_, H> {
        let locked = &self.0;
        match locked.handler.try_lock() {
            Ok(h) => h,
            Err(TryLockError::Poisoned(p)) => p.into_inner(),
            Err(TryLockError::WouldBlock) => {
                locked.waiting.fetch_add(1, Ordering::AcqRel);
                let h = locked.handler.lock().unwrap_or_else(|p| p.into_inner());
                locked.waiting.fetch_sub(1, Ordering::AcqRel);
                h
            }
        }
    }

    /// The session of a connection just accepted.
    pub(crate) fn open_session(&self) -> H::Session {
        self.lock().open_session()
    }

    /// One slice of `req`, under the lock.
    pub(crate) fn serve(&self, req: Request) -> Slice<H::Rest> {
        self.lock().serve(req)
    }

    /// The next slice of a request from its rest, under the lock.
    pub(crate) fn proceed(&self, rest: H::Rest) -> Slice<H::Rest> {
        self.lock().proceed(rest)
    }

    /// The rest of a request whose wait is over, under the lock.
    pub(crate) fn resume(&self, token: u64, ok: bool) -> Slice<H::Rest> {
        self.lock().resume(token, ok)
    }

    /// Runs `look` on the handler, under the lock.
    pub(crate) fn look(&self, look: Look) {
        look(&mut *self.lock());
    }

    /// Whether requests are waiting for the lock right now.
    pub(crate) fn contended(&self) -> bool {
        self.0.waiting.load(Ordering::Acquire) > 0
    }
}
