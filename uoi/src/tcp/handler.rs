//! The contract between the server and what it serves: one [`Handler`]
//! that every connection shares, a [`Session`] that each connection keeps
//! for itself, and the [`Slice`] either of them serves at a time.
//!
//! This module imports nothing from the rest of `tcp`: the server is built
//! on it, never the other way round.

use tokio::sync::oneshot;

use crate::wire::{Answer, ProtocolError, Request};

/// What serves the requests: the emulator, in `addipos`. HELLO frames
/// are answered by the connection itself and never reach it.
pub trait Handler: Send + 'static {
    /// What each connection keeps for itself (`()` for nothing); it
    /// continues its long requests with the same [`Handler::Rest`].
    type Session: Session<Self::Rest>;

    /// The rest of a request that needs more slices, as the handler keeps
    /// it ([`Slice::More`]): resumed by [`Handler::proceed`] as it is,
    /// never decoded again (docs/decisions.md, decision 482). A handler
    /// whose requests all take one slice may name any type (`Request`).
    type Rest: Send + 'static;

    /// The session of a connection just accepted; the connection drops it
    /// when it ends. A handler that bounds what sessions may take counts
    /// them here (no other connection ever sees the session).
    fn open_session(&mut self) -> Self::Session;

    /// Serves one slice of `req`: its answer, the rest of it to serve
    /// later, or a wait. The server releases the handler between slices,
    /// so requests of other connections are served in between and
    /// shutdown is not held up by a long request.
    fn serve(&mut self, req: Request) -> Slice<Self::Rest>;

    /// Serves the next slice of a request from the rest its last slice
    /// left ([`Slice::More`]). Default (a handler that never leaves a rest
    /// is never asked): `Busy`.
    fn proceed(&mut self, _rest: Self::Rest) -> Slice<Self::Rest> {
        Slice::Done(Answer::Protocol(ProtocolError::Busy))
    }

    /// Continues a request that waited ([`Slice::Wait`]) once its wait is
    /// over; `ok` says whether what it waited for succeeded. Always called,
    /// even when the request's connection has closed meanwhile. Default
    /// (a handler that never waits is never asked): `Busy`.
    fn resume(&mut self, _token: u64, _ok: bool) -> Slice<Self::Rest> {
        Slice::Done(Answer::Protocol(ProtocolError::Busy))
    }
}

/// The state one connection keeps for itself: opened by the handler
/// ([`Handler::open_session`]) when the connection is accepted, dropped
/// when it ends, seen by no other connection. It is asked first whether
/// it [`takes`](Session::takes) each of its connection's requests; those
/// it takes it serves slice by slice in the connection's own task, the
/// others go to the shared handler. `R`: the rest of a request that needs
/// more slices (its handler's [`Handler::Rest`]).
pub trait Session<R = Request>: Send + 'static {
    /// Whether this session serves `req` (else the shared handler does).
    fn takes(&self, req: &Request) -> bool;

    /// Serves one slice of a request it takes, as [`Handler::serve`].
    fn serve(&mut self, req: Request) -> Slice<R>;

    /// Serves the next slice from a rest, as [`Handler::proceed`].
    /// Default: `Busy`.
    fn proceed(&mut self, _rest: R) -> Slice<R> {
        Slice::Done(Answer::Protocol(ProtocolError::Busy))
    }

    /// Continues a request that waited, as [`Handler::resume`]. Default:
    /// `Busy`.
    fn resume(&mut self, _token: u64, _ok: bool) -> Slice<R> {
        Slice::Done(Answer::Protocol(ProtocolError::Busy))
    }
}

/// No state of its own: every request goes to the shared handler.
impl<R: Send + 'static> Session<R> for () {
    fn takes(&self, _req: &Request) -> bool {
        false
    }

    /// Never asked (it takes nothing).
    fn serve(&mut self, _req: Request) -> Slice<R> {
        Slice::Done(Answer::Protocol(ProtocolError::Busy))
    }
}

/// What one slice of a request left; `R`: the rest of a request that
/// needs more slices, in its handler's own type ([`Handler::Rest`]).
#[derive(Debug)]
pub enum Slice<R = Request> {
    /// The request is complete: its answer.
    Done(Answer),
    /// The rest of the request, to serve as a further slice
    /// ([`Handler::proceed`]; other tasks run, and the request stops if
    /// its connection is closed, in between).
    More(R),
    /// The request waits for something outside the handler (a durable
    /// write): the server awaits it without holding the handler, so other
    /// requests are served meanwhile, then calls `resume` with the wait's
    /// token.
    Wait(Wait),
}

impl<R> Slice<R> {
    /// The answer of a request served to its end without a runtime: this
    /// slice, then each rest served by `next`. A wait cannot be awaited
    /// here; it is answered `Busy`.
    pub fn finish(self, mut next: impl FnMut(R) -> Slice<R>) -> Answer {
        let mut slice = self;
        loop {
            slice = match slice {
                Slice::Done(answer) => return answer,
                Slice::More(rest) => next(rest),
                Slice::Wait(_) => return Answer::Protocol(ProtocolError::Busy),
            };
        }
    }
}

/// What a request waits for (see [`Slice::Wait`]).
#[derive(Debug)]
pub struct Wait {
    /// Says whether it succeeded; a sender dropped unsent counts as a
    /// failure.
    pub done: oneshot::Receiver<bool>,
    /// The handler's own number for the request, given back to
    /// `resume`.
    pub token: u64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ObjectAddress, Value, ValueType};

    fn read(device: u16) -> Request {
        Request::Read(ObjectAddress::new(7, device, 0, 0), ValueType::I32)
    }

    /// Counts down the device number, one slice each, then answers.
    fn count_down(req: Request) -> Slice {
        match req {
            Request::Read(a, _) if a.device == 0 => Slice::Done(Answer::Value(Value::I32(7))),
            Request::Read(a, _) => Slice::More(read(a.device - 1)),
            _ => Slice::Done(Answer::Ok),
        }
    }

    #[test]
    fn finish_serves_every_slice_and_answers_a_wait_busy() {
        let mut slices = 0;
        let answer = count_down(read(5)).finish(|rest| {
            slices += 1;
            count_down(rest)
        });
        assert_eq!(answer, Answer::Value(Value::I32(7)));
        assert_eq!(slices, 5);
        let (_tx, done) = oneshot::channel();
        let wait = Slice::Wait(Wait { done, token: 1 });
        assert_eq!(
            wait.finish(count_down),
            Answer::Protocol(ProtocolError::Busy)
        );
    }
}
