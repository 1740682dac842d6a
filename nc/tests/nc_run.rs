//! The NC runner (`nc::nc_run`) on a runner of requests that fails: the
//! run stops there and says why; on one that answers, every request is
//! handed on with what it spooled.

// Test helpers may stop loudly.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use nc::nc_run::{run_checked_nc, run_nc, Exchange, NcRunError};
use tc_request::{Reply, Request, Runner, SpoolRecord};

/// A lost connection, as a test's runner reports it.
#[derive(Debug, thiserror::Error)]
#[error("the line went dead after {0} requests")]
struct Dead(usize);

/// Answers `Ok` (a position to `POS`) to its first `lives` requests, then
/// fails every one.
struct Fading {
    lives: usize,
    ran: Vec<Request>,
}

impl Runner for Fading {
    type Error = Dead;

    fn run(&mut self, req: &Request) -> Result<Reply, Dead> {
        if self.ran.len() >= self.lives {
            return Err(Dead(self.ran.len()));
        }
        self.ran.push(req.clone());
        Ok(match req {
            Request::Pos => Reply::Pos([0.0; tc_request::AXES]),
            _ => Reply::Ok,
        })
    }

    fn take_spooled(&mut self) -> Result<Vec<SpoolRecord>, Dead> {
        Ok(Vec::new())
    }

    fn axis_nr(&mut self) -> Result<[u8; 3], Dead> {
        Ok([0, 1, 2])
    }
}

const PROGRAM: &str = "N10 G01 X10 Y0 F600\nN20 X20\nN30 X30\nN40 X40\nM30\n";

#[test]
fn a_runner_that_fails_stops_the_run_with_its_error() {
    let mut target = Fading {
        lives: 2,
        ran: Vec::new(),
    };
    let e = run_nc(&mut target, PROGRAM).unwrap_err();
    assert_eq!(e.to_string(), "the line went dead after 2 requests");
    // Nothing is sent once the target failed.
    assert_eq!(target.ran.len(), 2);
}

#[test]
fn a_failed_target_is_told_apart_from_a_failed_output() {
    let mut target = Fading {
        lives: 1,
        ran: Vec::new(),
    };
    let mut sink = |_: Exchange, _: [u8; 3]| Ok(());
    let e = run_checked_nc(&mut target, PROGRAM.as_bytes(), &[], &mut sink).unwrap_err();
    assert!(matches!(e, NcRunError::Target(Dead(1))), "{e}");
    let mut target = Fading {
        lives: 100,
        ran: Vec::new(),
    };
    let mut full = |_: Exchange, _: [u8; 3]| Err(std::io::Error::other("disk full"));
    let e = run_checked_nc(&mut target, PROGRAM.as_bytes(), &[], &mut full).unwrap_err();
    assert!(matches!(e, NcRunError::Output(_)), "{e}");
    assert_eq!(e.to_string(), "disk full");
}

#[test]
fn every_request_reaches_a_runner_that_answers() {
    let mut target = Fading {
        lives: usize::MAX,
        ran: Vec::new(),
    };
    let run = run_nc(&mut target, PROGRAM).unwrap();
    assert_eq!(run.exchanges.len(), target.ran.len());
    assert!(run
        .exchanges
        .iter()
        .zip(&target.ran)
        .all(|(x, r)| x.request == *r));
    assert_eq!(run.position, Some([0.0; tc_request::AXES]));
}
