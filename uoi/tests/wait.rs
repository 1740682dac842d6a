//! A request that waits for something outside the handler (a durable
//! write, in `addipos`): the server awaits it without holding the
//! handler, so other clients are answered meanwhile, and resumes it with
//! how the wait ended, on both cores.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

mod common;

use std::io::Write;
use std::net::TcpStream;
use std::sync::mpsc;
use std::sync::{Arc, Mutex};

use common::{connect, local, read_answer, read_frame, read_head, serve_with};
use tokio::sync::oneshot;
use uoi::tcp::{Core, Handler, ServerConfig, Slice, Wait};
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

impl Handler for Waiting {
    type Session = ();

    fn handle(&mut self, req: Request) -> Answer {
        match req {
            Request::Read(a, _) => Answer::Value(Value::I32(i32::from(a.index))),
            _ => Answer::Ok,
        }
    }

    fn handle_slice(&mut self, req: Request) -> Slice {
        match req {
            Request::Read(a, _) if a.index == 9 => {
                let (tx, rx) = oneshot::channel();
                self.next += 1;
                let w = self.waits.lock().unwrap();
                w.send((self.next, tx)).unwrap();
                Slice::Wait(Wait {
                    done: rx,
                    token: self.next,
                })
            }
            other => Slice::Done(self.handle(other)),
        }
    }

    fn resume(&mut self, token: u64, ok: bool) -> Slice {
        Slice::Done(if ok {
            Answer::Value(Value::I32(1000 + token as i32))
        } else {
            Answer::Access(AccessError::State)
        })
    }
}

fn read(s: &mut TcpStream, index: u16) {
    s.write_all(&read_frame(index)).expect("send");
}

fn waits_resume_without_holding_the_handler(core: Core) {
    let (wtx, wrx) = mpsc::channel();
    let handler = Waiting {
        next: 0,
        waits: Arc::new(Mutex::new(wtx)),
    };
    let (addr, _stop) = serve_with(ServerConfig { core, ..local() }, handler);
    let mut waiter = connect(addr);
    read(&mut waiter, 9);
    let (token, done) = wrx.recv().expect("the request waits");
    // Another client is answered while the first one waits.
    let mut other = connect(addr);
    read(&mut other, 5);
    assert_eq!(read_answer(&mut other), (5, 5));
    done.send(true).unwrap();
    assert_eq!(read_answer(&mut waiter), (9, 1000 + token as i32));
    // A wait that fails (its sender dropped) is resumed as failed.
    read(&mut waiter, 9);
    let (_, done) = wrx.recv().expect("the request waits");
    drop(done);
    assert_eq!(read_head(&mut waiter).2, AccessError::State.code());
}

#[test]
fn lock_core_serves_others_while_a_request_waits() {
    waits_resume_without_holding_the_handler(Core::Lock);
}

#[test]
fn owner_core_serves_others_while_a_request_waits() {
    waits_resume_without_holding_the_handler(Core::Owner);
}

/// Pipelined requests that wait: the answers already made leave before a
/// request waits, so the client is not kept waiting for them (lock core).
#[test]
fn answers_made_leave_before_a_request_waits() {
    let (wtx, wrx) = mpsc::channel();
    let handler = Waiting {
        next: 0,
        waits: Arc::new(Mutex::new(wtx)),
    };
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
