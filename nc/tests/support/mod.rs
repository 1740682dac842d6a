//! The engine behind the interpreter in tests: the TC module with the OTC
//! extension, answering requests as the emulator does.
#![allow(dead_code)]

use nc::run::{At, Controller};
use otc_ext::OtcExtension;
use tc_module::{CycleTime, TcModule, AXES};
use tc_request::{Reply, Request};
use uoi::wire::ProtocolError;
use uoi::ObjectBus;

/// The TC module with OTC, with every request it answered as text.
pub struct Engine {
    pub tc: TcModule<OtcExtension>,
    pub log: Vec<String>,
}

impl Engine {
    /// A fresh module at the origin with a spooler of `capacity` elements.
    pub fn with_capacity(capacity: usize) -> Self {
        let tc = TcModule::new([0.0; AXES], CycleTime::DEFAULT, OtcExtension::default());
        Engine {
            tc: tc.with_spool_capacity(capacity),
            log: Vec::new(),
        }
    }
}

impl Controller for Engine {
    fn call(&mut self, req: &Request, _at: At) -> Reply {
        let reply = match req {
            Request::Read(a, t) => self.tc.read_checked(*a, *t).into(),
            Request::Write(a, v) => self.tc.write_checked(*a, *v).into(),
            Request::Motion(m) => self.tc.command(m).into(),
            Request::Exec(n) => {
                self.tc.exec(*n);
                Reply::Ok
            }
            Request::Pos => Reply::Pos(self.tc.position()),
            Request::Queue => Reply::Queue(self.tc.queue_len() as u64),
            _ => Reply::Protocol(ProtocolError::UnknownOp),
        };
        match &reply {
            Reply::Access(e) => self.log.push(format!("{req} => err {}", e.name())),
            _ => self.log.push(req.to_string()),
        }
        reply
    }
}
