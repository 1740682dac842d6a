//! Feed adaptation (docs/nc.md, "Feed"): `G10` (initial) keeps the
//! programmed feed, `G11` has the controller spool each corrected arc of
//! programmed radius `R >= RMIN` at `F * R'/R`; `#TANGFEED [RMIN=..]` sets
//! RMIN. Both travel in one request (`FEED_ADAPT on rmin`), sent only when
//! one of them changes.

use tc_request::Request;

use super::trc_state::FeedAdaption;
use super::{Interpreter, RunErrorKind};

impl Interpreter<'_> {
    /// `G10` (false) or `G11` (true).
    pub(super) fn set_feed_adaption(&mut self, on: bool) -> Result<(), RunErrorKind> {
        let rmin = self.feed.rmin;
        self.send_feed_adaption(FeedAdaption { on, rmin })
    }

    /// `#TANGFEED [RMIN=rmin]` (0 when no RMIN is given).
    pub(super) fn set_tangfeed(&mut self, rmin: f64) -> Result<(), RunErrorKind> {
        if rmin.is_nan() || rmin < 0.0 {
            return Err(RunErrorKind::TangFeedRmin(rmin));
        }
        let on = self.feed.on;
        self.send_feed_adaption(FeedAdaption { on, rmin })
    }

    fn send_feed_adaption(&mut self, new: FeedAdaption) -> Result<(), RunErrorKind> {
        if new.on == self.feed.on && new.rmin == self.feed.rmin {
            return Ok(());
        }
        let (on, rmin) = (new.on, new.rmin);
        self.send(&Request::FeedAdaption { on, rmin })?;
        self.feed = new;
        Ok(())
    }
}
