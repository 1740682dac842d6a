//! Another face of the same handler: requests submitted through the
//! server's `CoreHandle` are served by the handler the UOI connections
//! share, so each side sees the other's writes.

// Test helpers may stop loudly on a broken setup.
#![allow(clippy::expect_used, clippy::unwrap_used, clippy::panic)]

use std::time::Duration;

use uoi::tcp::{Client, Handler, Server, ServerConfig, Slice};
use uoi::wire::{Answer, Request};
use uoi::{AccessError, ObjectAddress, Value, ValueType};

/// One register at x/0/1/0; any other address does not exist.
#[derive(Default)]
struct Register(i32);

impl Handler for Register {
    type Session = ();
    type Rest = Request;

    fn open_session(&mut self) {}

    fn serve(&mut self, req: Request) -> Slice {
        Slice::Done(match req {
            Request::Read(a, _) if a.index == 1 => Answer::Value(Value::I32(self.0)),
            Request::Write(a, Value::I32(v)) if a.index == 1 => {
                self.0 = v;
                Answer::Ok
            }
            _ => Answer::Access(AccessError::NoObject),
        })
    }
}

fn reg() -> ObjectAddress {
    ObjectAddress::new(7, 0, 1, 0)
}

#[tokio::test]
async fn both_faces_see_each_other() {
    let cfg = ServerConfig {
        listen: "127.0.0.1:0".parse().expect("addr"),
        ..ServerConfig::default()
    };
    let server = Server::bind(cfg, Register::default()).await.expect("bind");
    let addr = server.local_addr().expect("addr");
    let handle = server.core();
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let run = tokio::spawn(server.run(async {
        let _ = stopped.await;
    }));
    let mut uoi = Client::connect(addr).await.expect("connect");
    // The other face writes; the UOI connection reads it.
    assert_eq!(
        handle.call(Request::Write(reg(), Value::I32(5))).await,
        Answer::Ok
    );
    assert_eq!(
        uoi.read(reg(), ValueType::I32).await.expect("read"),
        Value::I32(5)
    );
    // And the other way round.
    uoi.write(reg(), Value::I32(9)).await.expect("write");
    let read = Request::Read(reg(), ValueType::I32);
    assert_eq!(handle.call(read).await, Answer::Value(Value::I32(9)));
    // A look at the handler itself sees the same register, and a look
    // that takes it for another type finds nothing.
    let seen = handle
        .inspect(|h| h.downcast_mut::<Register>().map(|r| r.0))
        .await;
    assert_eq!(seen, Some(Some(9)));
    let other = handle
        .inspect(|h| h.downcast_mut::<String>().is_some())
        .await;
    assert_eq!(other, Some(false));
    let nowhere = Request::Read(ObjectAddress::new(7, 0, 2, 0), ValueType::I32);
    assert_eq!(
        handle.call(nowhere).await,
        Answer::Access(AccessError::NoObject)
    );
    drop(stop);
    tokio::time::timeout(Duration::from_secs(10), run)
        .await
        .expect("stops")
        .expect("task")
        .expect("run");
}
