//! Keeping a served store healthy: the journal's writer thread calls these.
//!
//! * compaction when the journal is due, early when the disk runs short
//!   of room, and at shutdown;
//! * a failed compaction is not tried again at once: the next attempt
//!   waits [`FIRST_PAUSE`], doubled after each further failure up to
//!   [`LONGEST_PAUSE`], so a full disk costs a few attempts a minute, not
//!   one per write;
//! * a write refused for want of room first compacts (when not paused),
//!   which frees the journal's room, and is then written again;
//! * a journal left with a half record that could not be cut off
//!   (poisoned) is compacted before the next write;
//! * their warnings come at most once a second per kind (a disk short of
//!   room: once a minute), with the count of those left out.

use std::time::Instant;

use tracing::{info, warn};

use super::error::StoreError;
use super::state::ToolStore;
use crate::journal::Record;
use crate::storage::Storage;
use crate::writer::DurableLog;

/// The free space is looked at again once the journal grew this much
/// since the last look (a statvfs costs about as much as 1 % of a
/// fast fdatasync; free space matters here in steps of 64 KiB).
const SPACE_LOOK_EVERY: u64 = 4 << 10;

impl<S: Storage> ToolStore<S> {
    /// Appends `records` as a served store does at the time `now`: if the
    /// journal is poisoned, or the disk refused for want of room while the
    /// journal holds something, compacts first (unless paused after a
    /// failed compaction) and writes the batch again.
    pub fn append_at(&mut self, records: &[Record], now: Instant) -> Result<(), StoreError> {
        match self.append(records) {
            Err(StoreError::Poisoned) if self.upkeep.may_try(now) => {
                self.try_compact(now)?;
                self.append(records)
            }
            Err(e) if e.is_disk_full() && self.journal_len > 0 && self.upkeep.may_try(now) => {
                // Compaction frees the journal's room; the refusal stands
                // if it fails (its own warning says what the disk needs).
                match self.try_compact(now) {
                    Ok(()) => self.append(records),
                    Err(_) => Err(e),
                }
            }
            other => other,
        }
    }

    /// Compacts if the journal is due, or the disk is short of room
    /// ([`short_of_room`](Self::short_of_room)), and compaction is not
    /// paused after failures, at the time `now`.
    pub fn maintain_at(&mut self, now: Instant) {
        if !self.upkeep.may_try(now) {
            return;
        }
        if !self.needs_compaction() {
            let looked = self.upkeep.space_looked_at;
            let grown = looked.is_none_or(|at| self.journal_len.abs_diff(at) >= SPACE_LOOK_EVERY);
            if self.journal_len < self.bound.least || !grown {
                return;
            }
            self.upkeep.space_looked_at = Some(self.journal_len);
            // A failed look at the free space leaves it to the bound.
            let Some(free) = self.storage.available_space().ok().flatten() else {
                return;
            };
            if !self.short_of_room(free) {
                return;
            }
            if let Some(suppressed) = self.upkeep.low_space_warnings.allow_at(now) {
                warn!(
                    free_bytes = free,
                    journal_bytes = self.journal_len,
                    suppressed,
                    "the disk of the tool data is nearly full; compacting the tool journal early"
                );
            }
        }
        // A failure is logged and paused by `try_compact`.
        let _ = self.try_compact(now);
    }

    /// When the next compaction attempt may come, if paused.
    pub fn compaction_paused_until(&self) -> Option<Instant> {
        self.upkeep.next_try
    }

    /// Compacts; a failure pauses further attempts and is logged (at most
    /// once a second).
    fn try_compact(&mut self, now: Instant) -> Result<(), StoreError> {
        match self.compact() {
            Ok(()) => {
                self.upkeep.failures = 0;
                self.upkeep.next_try = None;
                Ok(())
            }
            Err(e) => {
                let pause = self.upkeep.failed(now);
                if let Some(suppressed) = self.upkeep.compaction_warnings.allow_at(now) {
                    warn!(
                        error = %e,
                        journal_bytes = self.journal_len,
                        failures = self.upkeep.failures,
                        retry_in_s = pause.as_secs(),
                        suppressed,
                        "tool journal not compacted"
                    );
                }
                Err(e)
            }
        }
    }
}

impl<S: Storage + Send + std::fmt::Debug + 'static> DurableLog for ToolStore<S> {
    fn append(&mut self, records: &[Record]) -> Result<(), StoreError> {
        self.append_at(records, Instant::now())
    }

    fn maintain(&mut self) {
        self.maintain_at(Instant::now());
    }

    /// At shutdown compaction is tried whatever the pause.
    fn close(&mut self) {
        match self.compact() {
            Ok(()) => info!("tool data saved to the tool files"),
            Err(e) => warn!(error = %e, "tool files not rewritten; the journal keeps every change"),
        }
    }
}

#[cfg(test)]
mod tests;
