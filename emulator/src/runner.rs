//! The emulator as a [`Runner`]: trace replay, the NC runner and the
//! host library's embedded target run their requests on it through the
//! one trait of `tc-request` (decision 490). It never fails.

use std::convert::Infallible;

use tc_request::{Reply, Request, Runner, SpoolRecord};

use crate::emulator::Emulator;

impl Runner for Emulator {
    type Error = Infallible;

    fn run(&mut self, req: &Request) -> Result<Reply, Infallible> {
        Ok(Emulator::run(self, req))
    }

    fn take_spooled(&mut self) -> Result<Vec<SpoolRecord>, Infallible> {
        Ok(self.take_spool_log())
    }

    fn axis_nr(&mut self) -> Result<[u8; 3], Infallible> {
        Ok(self.tc().axis_nr())
    }
}
