//! Feed adaptation (docs/nc.md, "Feed"): `G10` (initial) keeps the
//! programmed feed, `G11` has the controller spool each corrected arc of
//! programmed radius `R >= RMIN` at `F * R'/R`; `#TANGFEED [RMIN=..]` sets
//! RMIN. Both are registers of the controller (FeedAdaption and
//! TangFeedRmin of correction group 1), written only when they change.

use uoi::Value;

use super::{objects, Interpreter, RunErrorKind};

/// What the program set, as last written to the controller.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct FeedAdaption {
    /// `G11` in force.
    on: bool,
    /// RMIN in mm.
    rmin: f64,
}

impl Interpreter<'_> {
    /// `G10` (false) or `G11` (true).
    pub(super) fn set_feed_adaption(&mut self, on: bool) -> Result<(), RunErrorKind> {
        if self.feed.on != on {
            self.write(objects::FEED_ADAPTION, Value::I32(i32::from(on)))?;
            self.feed.on = on;
        }
        Ok(())
    }

    /// `#TANGFEED [RMIN=rmin]` (0 when no RMIN is given).
    pub(super) fn set_tangfeed(&mut self, rmin: f64) -> Result<(), RunErrorKind> {
        if !(rmin >= 0.0) {
            return Err(RunErrorKind::TangFeedRmin(rmin));
        }
        if self.feed.rmin != rmin {
            self.write(objects::TANG_FEED_RMIN, Value::F64(rmin))?;
            self.feed.rmin = rmin;
        }
        Ok(())
    }
}
