//! Compaction attempts held back after failures, and the warnings a
//! broken disk could repeat: the served store's backoff.

use std::time::{Duration, Instant};

use tracing::warn;
use uoi::LogLimit;

/// Pause after a failed compaction before the next attempt.
pub const FIRST_PAUSE: Duration = Duration::from_secs(1);

/// The longest pause between compaction attempts (after five failures in
/// a row: 1, 2, 4, 8, 16 s).
pub const LONGEST_PAUSE: Duration = Duration::from_secs(16);

/// At most one warning of a disk short of room per this time.
const LOW_SPACE_WARNING_EVERY: Duration = Duration::from_secs(60);

/// Compaction attempts held back after failures, and the warnings that a
/// broken disk could repeat.
#[derive(Debug)]
pub(super) struct Upkeep {
    /// Failed compactions in a row.
    pub(super) failures: u32,
    /// No compaction attempt before this.
    pub(super) next_try: Option<Instant>,
    /// The journal's size at the last look at the free space.
    pub(super) space_looked_at: Option<u64>,
    pub(super) compaction_warnings: LogLimit,
    pub(super) lost_journal_warnings: LogLimit,
    pub(super) low_space_warnings: LogLimit,
}

impl Default for Upkeep {
    fn default() -> Self {
        Self {
            failures: 0,
            next_try: None,
            space_looked_at: None,
            compaction_warnings: LogLimit::per_second(),
            lost_journal_warnings: LogLimit::per_second(),
            low_space_warnings: LogLimit::new(LOW_SPACE_WARNING_EVERY),
        }
    }
}

impl Upkeep {
    pub(super) fn may_try(&self, now: Instant) -> bool {
        self.next_try.is_none_or(|t| now >= t)
    }

    /// Records a failed attempt at `now`; the pause until the next one.
    pub(super) fn failed(&mut self, now: Instant) -> Duration {
        self.failures = self.failures.saturating_add(1);
        let doublings = (self.failures - 1).min(4);
        let pause = FIRST_PAUSE
            .saturating_mul(1 << doublings)
            .min(LONGEST_PAUSE);
        self.next_try = Some(now + pause);
        pause
    }

    /// A warning that the journal was deleted or replaced and made anew
    /// (rate-limited).
    pub(super) fn journal_made_anew(&self) {
        if let Some(suppressed) = self.lost_journal_warnings.allow() {
            warn!(
                suppressed,
                "the tool journal was deleted or replaced while in use; \
                 tool files rewritten from memory and the journal made anew"
            );
        }
    }
}
