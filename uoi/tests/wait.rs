//! A request that waits for something outside the handler (a durable
//! write, in `addipos`): the server awaits it without holding the
//! handler, so other clients are answered meanwhile, and resumes it with
//! how the wait ended; the same for a request a connection's session
//! takes.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;

use std::io::Write;
use std::net::TcpStream;
use std::sync::mpsc;
use std::sync::{Arc, Mutex};

use common::{connect, index_of, local, read_answer, read_frame, read_head, serve_with};
use tokio::sync::oneshot;
use uoi::tcp::{Handler, Session, Slice, Wait};
use uoi::wire::{Answer, Request};
use uoi::{AccessError, Value};

/// The senders of the waits handed out, for the test to complete.
type Waits = Arc<Mutex<mpsc::Sender<(u64, oneshot::Sender<bool>)>>>;

/// READ of index 9 waits; once resumed it answers its token (ok) or
/// `State` (failed). Any other READ is answered with its index at once.
struct Waiting {
    next: u64,
    waits: Waits,
}

impl Waiting {
    /// A wait handed to the test, with its token.
    fn wait(&mut self) -> Slice {
        let (tx, rx) = oneshot::channel();
        self.next += 1;
        let w = self.waits.lock().unwrap();
        w.send((self.next, tx)).unwrap();
        Slice::Wait(Wait {
            done: rx,
            token: self.next,
        })
    }

    /// The answer of the wait `token` once it ended.
    fn resumed(token: u64, ok: bool) -> Slice {
        Slice::Done(if ok {
            Answer::Value(Value::I32(1000 + token as i32))
        } else {
            Answer::Access(AccessError::State)
        })
    }
}

impl Handler for Waiting {
    /// A session that takes READs of index 8 and waits for them the same way.
    type Session = Waiting;
    type Rest = Request;

    fn open_session(&mut self) -> Waiting {
        Waiting {
            next: 100,
            waits: Arc::clone(&self.waits),
        }
    }

    fn serve(&mut self, req: Request) -> Slice {
        match req {
            Request::Read(a, _) if a.index == 9 => self.wait(),
            other => Slice::Done(index_of(&other)),
        }
    }

    fn resume(&mut self, token: u64, ok: bool) -> Slice {
        Self::resumed(token, ok)
    }
}

impl Session for Waiting {
    fn takes(&self, req: &Request) -> bool {
        matches!(req, Request::Read(a, _) if a.index == 8)
    }

    fn serve(&mut self, _req: Request) -> Slice {
        self.wait()
    }

    fn resume(&mut self, token: u64, ok: bool) -> Slice {
        Self::resumed(token, ok)
    }
}

fn waiting() -> (Waiting, mpsc::Receiver<(u64, oneshot::Sender<bool>)>) {
    let (wtx, wrx) = mpsc::channel();
    let handler = Waiting {
        next: 0,
        waits: Arc::new(Mutex::new(wtx)),
    };
    (handler, wrx)
}

fn read(s: &mut TcpStream, index: u16) {
    s.write_all(&read_frame(index)).expect("send");
}

/// A request of `index` waits while another client is answered, and is
/// resumed with how its wait ended.
fn waits_resume_without_holding_the_handler(index: u16) {
    let (handler, wrx) = waiting();
    let (addr, _stop) = serve_with(local(), handler);
    let mut waiter = connect(addr);
    read(&mut waiter, index);
    let (token, done) = wrx.recv().expect("the request waits");
    // Another client is answered while the first one waits.
    let mut other = connect(addr);
    read(&mut other, 5);
    assert_eq!(read_answer(&mut other), (5, 5));
    done.send(true).unwrap();
    assert_eq!(
        read_answer(&mut waiter),
        (u32::from(index), 1000 + token as i32)
    );
    // A wait that fails (its sender dropped) is resumed as failed.
    read(&mut waiter, index);
    let (_, done) = wrx.recv().expect("the request waits");
    drop(done);
    assert_eq!(read_head(&mut waiter).2, AccessError::State.code());
}

#[test]
fn others_are_served_while_a_request_waits() {
    waits_resume_without_holding_the_handler(9);
}

#[test]
fn others_are_served_while_a_request_of_a_session_waits() {
    waits_resume_without_holding_the_handler(8);
}

/// Pipelined requests that wait: the answers already made leave before a
/// request waits, so the client is not kept waiting for them.
#[test]
fn answers_made_leave_before_a_request_waits() {
    let (handler, wrx) = waiting();
    let (addr, _stop) = serve_with(local(), handler);
    let mut c = connect(addr);
    let frames: Vec<u8> = (0..20).flat_map(|_| read_frame(9)).collect();
    c.write_all(&frames).expect("send");
    // The first wait ends at once; the second only once the client has
    // its first answer (it would never come if answers waited for the
    // whole pipeline).
    let (t1, done1) = wrx.recv().expect("first waits");
    done1.send(true).unwrap();
    let (_, done2) = wrx.recv().expect("second waits");
    assert_eq!(read_answer(&mut c), (9, 1000 + t1 as i32));
    done2.send(true).unwrap();
    for _ in 2..20 {
        let (_, done) = wrx.recv().expect("waits");
        done.send(true).unwrap();
    }
    for _ in 1..20 {
        assert_eq!(read_answer(&mut c).0, 9);
    }
}
