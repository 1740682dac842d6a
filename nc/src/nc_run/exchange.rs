//! One request of an NC run on a target, with its answer and what it
//! spooled: what the runner hands on and the trace text is written from.

use tc_request::{Reply, Request, SpoolRecord};

use crate::run::At;

/// One request of the run, its answer and what it spooled.
#[derive(Debug, Clone)]
pub struct Exchange {
    /// The block it came from.
    pub at: At,
    /// The request.
    pub request: Request,
    /// The answer.
    pub reply: Reply,
    /// Elements it spooled.
    pub spooled: Vec<SpoolRecord>,
}
