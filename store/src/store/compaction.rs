//! Compaction: the journal folded into the tool files, and when it is due.
//!
//! The journal is compacted at a fixed bound, and earlier when the disk
//! runs short of room: so on a small volume it cannot eat the room that
//! compaction needs to write the tool files.

use super::bound::CompactionBound;
use super::error::{io_error, StoreError};
use super::state::ToolStore;
use crate::file::write_group_file;
use crate::storage::group_file_name;
use crate::storage::{Storage, JOURNAL_FILE};
use crate::table::GroupTable;

/// Room a file takes on disk beyond its bytes, at most: file systems
/// allocate whole blocks (4 KiB on the usual ones, tmpfs included).
const BLOCK: u64 = 4096;

/// The most bytes one value takes in a tool file: the longest entry and
/// field name (`wz[1023].grinding_disc_tilt_angle `, 34) and number
/// (`-1.2345678901234567e-300`, 24), with room to spare.
const LINE_BYTES: u64 = 64;

/// The header of a tool file, at most.
const HEADER_BYTES: u64 = 320;

impl<S: Storage> ToolStore<S> {
    /// Uses `bound` for [`needs_compaction`](Self::needs_compaction) and
    /// [`short_of_room`](Self::short_of_room).
    pub fn with_compaction_bound(mut self, bound: CompactionBound) -> Self {
        self.bound = bound;
        self
    }

    /// True once the journal has grown past the compaction bound.
    pub fn needs_compaction(&self) -> bool {
        self.journal_records > 0
            && (self.journal_len >= self.bound.bytes || self.journal_records >= self.bound.records)
    }

    /// True if the journal holds at least [`CompactionBound::least`] and
    /// the disk's `free` bytes are less than compaction needs
    /// ([`compaction_room`](Self::compaction_room)) plus
    /// [`CompactionBound::low_space`]: compaction then frees the journal's
    /// room while there is still room to write the files.
    pub fn short_of_room(&self, free: u64) -> bool {
        let wanted = self.compaction_room().saturating_add(self.bound.low_space);
        self.journal_len >= self.bound.least && free < wanted
    }

    /// The room compaction needs on the disk now, estimated from memory
    /// in whole blocks: every new tool file (a group without one) stays
    /// beside the others, and each file is written beside its old one
    /// (the largest counts once).
    pub fn compaction_room(&self) -> u64 {
        let (mut new_files, mut largest) = (0u64, 0u64);
        for group in self.to_rewrite(self.lost) {
            let values = self.groups.get(&group).map_or(0, GroupTable::len) as u64;
            let bytes = HEADER_BYTES + LINE_BYTES * values;
            let size = bytes.div_ceil(BLOCK) * BLOCK;
            largest = largest.max(size);
            if !self.files.contains_key(&group) {
                new_files += size;
            }
        }
        new_files + largest
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

    /// The groups whose tool files compaction writes: every group that has
    /// values or a file, changed ones only unless `all`.
    fn to_rewrite(&self, all: bool) -> Vec<u8> {
        let has_values = self
            .groups
            .iter()
            .filter(|(_, t)| !t.is_empty())
            .map(|(&g, _)| g);
        let mut groups: Vec<u8> = has_values.chain(self.files.keys().copied()).collect();
        groups.sort_unstable();
        groups.dedup();
        groups.retain(|g| all || self.dirty.contains(g));
        groups
    }

    /// The texts of the tool files to write.
    fn plan(&self, all: bool) -> Vec<(u8, String)> {
        let empty = GroupTable::new();
        self.to_rewrite(all)
            .into_iter()
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
        // The new files stay; each is written beside its old one.
        let len = |t: &String| t.len() as u64;
        let new_files: u64 = plan
            .iter()
            .filter(|(g, _)| !self.files.contains_key(g))
            .map(|(_, t)| len(t))
            .sum();
        let needs = new_files + plan.iter().map(|(_, t)| len(t)).max().unwrap_or(0);
        for (group, text) in plan {
            let file = group_file_name(group);
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
