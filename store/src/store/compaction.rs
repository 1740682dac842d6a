//! Compaction: the journal folded into the tool files, and when it is due.
//!
//! The journal may grow to a few times the size of the tool files, never
//! more than a fixed bound, and always to a small floor: on a small volume
//! it then cannot eat the room that compaction needs to write the files.

use super::{io_error, StoreError, ToolStore};
use crate::file::write_group_file;
use crate::storage::{Storage, JOURNAL_FILE};
use crate::table::GroupTable;

/// When [`ToolStore::needs_compaction`] says yes: once the journal reaches
/// `bytes`, or `records`, or `live_factor` times the size of the tool
/// files (but never below `floor` bytes), whichever comes first.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CompactionBound {
    /// Journal size in bytes, at most.
    pub bytes: u64,
    /// Journal records, at most.
    pub records: u64,
    /// Journal size as a multiple of the tool files' size.
    pub live_factor: u64,
    /// Journal size in bytes below which the multiple does not apply.
    pub floor: u64,
}

impl Default for CompactionBound {
    /// 4 MiB or 100,000 records, or 4 times the tool files but at least
    /// 64 KiB: a store of 512 values (about 19 KB of tool files) compacts
    /// at about 76 KB of journal, so it and the files fit a 256 KB volume
    /// with room to spare for the compaction's new files.
    fn default() -> Self {
        Self {
            bytes: 4 << 20,
            records: 100_000,
            live_factor: 4,
            floor: 64 << 10,
        }
    }
}

impl CompactionBound {
    /// The journal size that calls for compaction when the tool files
    /// hold `live` bytes.
    pub fn journal_limit(&self, live: u64) -> u64 {
        self.bytes
            .min(self.floor.max(self.live_factor.saturating_mul(live)))
    }
}

impl<S: Storage> ToolStore<S> {
    /// Uses `bound` for [`needs_compaction`](Self::needs_compaction).
    pub fn with_compaction_bound(mut self, bound: CompactionBound) -> Self {
        self.bound = bound;
        self
    }

    /// True once the journal has grown past the compaction bound.
    pub fn needs_compaction(&self) -> bool {
        let limit = self.bound.journal_limit(self.files_size());
        self.journal_records > 0
            && (self.journal_len >= limit || self.journal_records >= self.bound.records)
    }

    /// Journal size in bytes and records since the last compaction.
    pub fn journal_size(&self) -> (u64, u64) {
        (self.journal_len, self.journal_records)
    }

    /// The tool files' size in bytes, as last read or written.
    pub fn files_size(&self) -> u64 {
        self.files.values().sum()
    }

    /// Rewrites the tool file of every group changed since its file was
    /// written (each file atomically) and then empties the journal. A
    /// group whose values are all default gets a file with only the header
    /// if it had a file. A crash in between is harmless: replaying the
    /// journal over the new files gives the same values. Success also
    /// clears a poisoned store.
    ///
    /// If the journal was deleted or replaced meanwhile, every group's
    /// file is rewritten ([`compact_all`](Self::compact_all)): the changes
    /// since the last compaction are gone from the disk with it.
    pub fn compact(&mut self) -> Result<(), StoreError> {
        let all = !self.journal_in_place() || self.lost;
        self.rewrite(all)
    }

    /// As [`compact`](Self::compact), rewriting every group's file that
    /// has values or exists: the tool data made whole again from memory.
    pub fn compact_all(&mut self) -> Result<(), StoreError> {
        self.rewrite(true)
    }

    /// The texts of the tool files to write: every group that has values
    /// or a file, changed ones only unless `all`.
    fn plan(&self, all: bool) -> Vec<(u8, String)> {
        let empty = GroupTable::new();
        let has_values = self
            .groups
            .iter()
            .filter(|(_, t)| !t.is_empty())
            .map(|(&g, _)| g);
        let mut groups: Vec<u8> = has_values.chain(self.files.keys().copied()).collect();
        groups.sort_unstable();
        groups.dedup();
        groups
            .into_iter()
            .filter(|g| all || self.dirty.contains(g))
            .map(|g| {
                (
                    g,
                    write_group_file(g, self.groups.get(&g).unwrap_or(&empty)),
                )
            })
            .collect()
    }

    fn rewrite(&mut self, all: bool) -> Result<(), StoreError> {
        let plan = self.plan(all);
        let needs = plan.iter().map(|(_, t)| t.len() as u64).max().unwrap_or(0);
        for (group, text) in plan {
            let file = super::group_file_name(group);
            self.storage
                .write_file_atomic(&file, text.as_bytes())
                .map_err(|source| StoreError::Compaction {
                    file,
                    needs,
                    journal: self.journal_len,
                    source,
                })?;
            self.files.insert(group, text.len() as u64);
            self.dirty.remove(&group);
        }
        if let Err(source) = self.storage.truncate_journal(0) {
            self.poisoned = true;
            return Err(io_error(format!("emptying {JOURNAL_FILE}"))(source));
        }
        // Groups left are back at their defaults and have no file.
        self.dirty.clear();
        self.lost &= !all;
        self.journal_len = 0;
        self.journal_records = 0;
        self.poisoned = false;
        Ok(())
    }
}
