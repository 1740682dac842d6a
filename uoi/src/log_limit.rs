//! A log line that an attacker (or a broken disk) could repeat thousands of
//! times a second is written at most once per interval; the lines left out
//! in between are counted and the count goes with the next line written.
//!
//! The limiter only decides: the caller writes the line with whatever
//! logger it uses, so this module needs neither an async runtime nor a
//! logging crate.
//!
//! ```
//! use std::time::{Duration, Instant};
//! use uoi::LogLimit;
//!
//! let refusals = LogLimit::per_second();
//! let t0 = Instant::now();
//! assert_eq!(refusals.allow_at(t0), Some(0)); // logged, nothing left out
//! assert_eq!(refusals.allow_at(t0), None); // left out, counted
//! assert_eq!(refusals.allow_at(t0 + Duration::from_millis(10)), None);
//! // A second later: logged, with the two left out since.
//! assert_eq!(refusals.allow_at(t0 + Duration::from_secs(1)), Some(2));
//! ```

use std::sync::{Mutex, PoisonError};
use std::time::{Duration, Instant};

/// At most one line of a kind per interval, counting the lines left out.
///
/// One limiter per kind of line (a refused write, a failed compaction, an
/// eviction): each kind gets its own line per interval. It may be shared
/// between threads.
#[derive(Debug)]
pub struct LogLimit {
    interval: Duration,
    state: Mutex<State>,
}

#[derive(Debug, Default)]
struct State {
    /// When the last line was written.
    last: Option<Instant>,
    /// Lines left out since.
    suppressed: u64,
}

impl LogLimit {
    /// At most one line per `interval`.
    pub fn new(interval: Duration) -> Self {
        Self {
            interval,
            state: Mutex::new(State::default()),
        }
    }

    /// At most one line a second: the rule for every line a flood can
    /// repeat.
    pub fn per_second() -> Self {
        Self::new(Duration::from_secs(1))
    }

    /// Whether a line may be written now: `Some(n)` with the number of
    /// lines left out since the last one written (say it in the line), or
    /// `None` if this one is to be left out (it is counted).
    pub fn allow(&self) -> Option<u64> {
        self.allow_at(Instant::now())
    }

    /// [`allow`](Self::allow) at the time `now`.
    pub fn allow_at(&self, now: Instant) -> Option<u64> {
        // A panic elsewhere while holding the lock leaves a valid state.
        let mut s = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        let due = s
            .last
            .is_none_or(|last| now.saturating_duration_since(last) >= self.interval);
        if due {
            s.last = Some(now);
            Some(std::mem::take(&mut s.suppressed))
        } else {
            s.suppressed += 1;
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flood_gives_one_line_per_interval_with_the_count_left_out() {
        let limit = LogLimit::per_second();
        let t0 = Instant::now();
        let ms = |n| t0 + Duration::from_millis(n);
        // 1,878 refusals in 0.23 s, then one more a second later.
        let written: Vec<u64> = (0..1878u64)
            .filter_map(|i| limit.allow_at(ms(i * 230 / 1878)))
            .collect();
        assert_eq!(written, [0]);
        assert_eq!(limit.allow_at(ms(1000)), Some(1877));
        assert_eq!(limit.allow_at(ms(1999)), None);
        assert_eq!(limit.allow_at(ms(2000)), Some(1));
        // Quiet for a while: the next line comes at once, nothing left out.
        assert_eq!(limit.allow_at(ms(9000)), Some(0));
    }

    #[test]
    fn kinds_are_limited_apart() {
        let (refused, compaction) = (LogLimit::per_second(), LogLimit::per_second());
        let t0 = Instant::now();
        assert_eq!(refused.allow_at(t0), Some(0));
        assert_eq!(compaction.allow_at(t0), Some(0));
        assert_eq!(refused.allow_at(t0), None);
    }

    #[test]
    fn a_clock_that_goes_back_leaves_lines_out() {
        let limit = LogLimit::per_second();
        let t0 = Instant::now() + Duration::from_secs(5);
        assert_eq!(limit.allow_at(t0), Some(0));
        assert_eq!(limit.allow_at(t0 - Duration::from_secs(3)), None);
    }
}
