//! The tool store: the group files and the journal together, the current
//! tool values in memory, never ahead of what is durable on disk.
//!
//! Compaction (folding the journal into the tool files) is in
//! [`compaction`]; keeping a served store healthy (compaction when due,
//! with a pause after failures, a full disk) in [`upkeep`].

use crate::field::{FileField, ToolValue};
use crate::file::{parse_group_file_lenient, ParseError};
use crate::journal::{self, encode_batch, JournalError, Record, TornTail};
use crate::storage::{FsStorage, Storage, JOURNAL_FILE};
use crate::table::{GroupTable, ToolKey, GROUPS};
use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

mod bound;
mod compaction;
mod error;
mod pause;
mod state;
mod upkeep;

pub use crate::storage::group_file_name;
pub use bound::CompactionBound;
use error::io_error;
pub use error::StoreError;
pub use pause::{FIRST_PAUSE, LONGEST_PAUSE};
pub use state::ToolStore;

/// How to treat bad lines when opening.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Strictness {
    /// Any bad line of a tool file or the journal (other than a torn
    /// tail) refuses the open.
    Strict,
    /// Bad lines are skipped and reported in the [`OpenReport`].
    Lenient,
}

/// What opening found besides the values.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct OpenReport {
    /// Tool files read (group numbers).
    pub files_loaded: Vec<u8>,
    /// Journal records replayed.
    pub replayed: usize,
    /// The torn last journal record or batch, dropped (and cut off the
    /// journal).
    pub torn_tail: Option<TornTail>,
    /// Where the journal was kept before a torn batch was cut off it.
    pub journal_copy: Option<String>,
    /// Why no copy could be kept (a full disk, say): the torn batch, never
    /// acknowledged, was cut off all the same (decision 527).
    pub journal_copy_failed: Option<String>,
    /// Temporary files of a replacement cut short, removed.
    pub removed_temporaries: Vec<String>,
    /// Bad tool file lines skipped (lenient open only).
    pub file_errors: Vec<ParseError>,
    /// Bad journal lines skipped (lenient open only; they stay in the
    /// journal until the next [`ToolStore::compact`]).
    pub journal_errors: Vec<JournalError>,
}

impl ToolStore<FsStorage> {
    /// Opens the store kept in the directory `dir` (created on the first
    /// write).
    pub fn open_dir(
        dir: impl Into<PathBuf>,
        strictness: Strictness,
    ) -> Result<(Self, OpenReport), StoreError> {
        Self::open(FsStorage::new(dir), strictness)
    }
}

impl<S: Storage> ToolStore<S> {
    /// Removes leftover temporary files, loads every group's tool file,
    /// replays the journal on top, drops a torn last record (cutting it off
    /// the journal so later appends follow good records).
    pub fn open(mut storage: S, strictness: Strictness) -> Result<(Self, OpenReport), StoreError> {
        let mut report = OpenReport {
            removed_temporaries: storage
                .remove_temporaries()
                .map_err(io_error("removing leftover temporary files"))?,
            ..OpenReport::default()
        };
        let (mut groups, mut files, mut dirty) =
            (BTreeMap::new(), BTreeMap::new(), BTreeSet::new());
        for group in GROUPS {
            let name = group_file_name(group);
            let read = storage.read_file(&name);
            let Some(bytes) = read.map_err(io_error(format!("reading {name}")))? else {
                continue;
            };
            let (table, mut errors) =
                parse_group_file_lenient(&name, &String::from_utf8_lossy(&bytes));
            if strictness == Strictness::Strict && !errors.is_empty() {
                return Err(errors.swap_remove(0).into());
            }
            if !errors.is_empty() {
                // Rewritten at the next compaction, without the bad lines.
                dirty.insert(group);
            }
            report.file_errors.append(&mut errors);
            report.files_loaded.push(group);
            groups.insert(group, table);
            files.insert(group, bytes.len() as u64);
        }
        let mut store = Self {
            files,
            dirty,
            storage,
            groups,
            journal_len: 0,
            journal_records: 0,
            bound: CompactionBound::default(),
            poisoned: false,
            lost: false,
            upkeep: pause::Upkeep::default(),
        };
        store.replay_journal(strictness, &mut report)?;
        Ok((store, report))
    }

    /// Replays the journal into the loaded tables.
    fn replay_journal(
        &mut self,
        strictness: Strictness,
        report: &mut OpenReport,
    ) -> Result<(), StoreError> {
        let bytes = self
            .storage
            .read_journal()
            .map_err(io_error(format!("reading {JOURNAL_FILE}")))?;
        let replay = match strictness {
            Strictness::Strict => {
                crate::replay::replay(&bytes).map_err(|error| StoreError::Journal {
                    file: JOURNAL_FILE,
                    error,
                })?
            }
            Strictness::Lenient => crate::replay::replay_lenient(&bytes),
        };
        for record in &replay.records {
            self.apply(record);
        }
        if let Some(torn) = &replay.torn_tail {
            if torn.reason == journal::RecordError::TornBatch {
                // A start after a power cut must not fail for want of
                // room for the copy: the batch was never acknowledged.
                match self.keep_journal_copy(&bytes) {
                    Ok(name) => report.journal_copy = Some(name),
                    Err(e) => report.journal_copy_failed = Some(e.to_string()),
                }
            }
            self.storage
                .truncate_journal(replay.valid_len)
                .map_err(io_error(format!(
                    "cutting the torn tail off {JOURNAL_FILE}"
                )))?;
        }
        self.journal_len = replay.valid_len;
        self.journal_records = (replay.records.len() + replay.skipped.len()) as u64;
        report.replayed = replay.records.len();
        report.torn_tail = replay.torn_tail;
        report.journal_errors = replay.skipped;
        Ok(())
    }

    /// Keeps the journal as it was, before a torn batch is cut off it,
    /// as `journal.wzj.torn-<UTC time>` beside it (made durable); returns
    /// the copy's name.
    fn keep_journal_copy(&mut self, bytes: &[u8]) -> Result<String, StoreError> {
        let stamp = chrono::Utc::now().format("%Y%m%dT%H%M%SZ");
        let mut name = format!("{JOURNAL_FILE}.torn-{stamp}");
        let mut n = 2;
        while self
            .storage
            .read_file(&name)
            .map_err(io_error(format!("reading {name}")))?
            .is_some()
        {
            name = format!("{JOURNAL_FILE}.torn-{stamp}-{n}");
            n += 1;
        }
        self.storage
            .write_file_atomic(&name, bytes)
            .map_err(io_error(format!(
                "keeping a copy of {JOURNAL_FILE} as {name} before cutting off its torn last batch"
            )))?;
        Ok(name)
    }

    /// The value of `key` in `group` (the field's default if never set).
    pub fn get(&self, group: u8, key: ToolKey) -> ToolValue {
        self.groups
            .get(&group)
            .map_or(key.field.default_value(), |t| t.get(key))
    }

    /// The table of `group`; `None` if every field of it is at its default.
    pub fn group(&self, group: u8) -> Option<&GroupTable> {
        self.groups.get(&group).filter(|t| !t.is_empty())
    }

    /// Every value that differs from its default, as `(group, key, value)`
    /// sorted by group, index, field.
    pub fn values(&self) -> impl Iterator<Item = (u8, ToolKey, ToolValue)> + '_ {
        self.groups
            .iter()
            .flat_map(|(&g, t)| t.iter().map(move |(k, v)| (g, k, v)))
    }

    /// Writes `records` to the journal and syncs it once (one batch, one
    /// fdatasync); only then are they applied in memory. On any error the
    /// values stay as before the call and the journal is cut back to its
    /// length before the call.
    ///
    /// If the journal was deleted or replaced meanwhile, the batch went
    /// into a file that is gone: every tool file is rewritten from memory
    /// (which holds only durable values), the journal made anew, and the
    /// batch written into it; if that fails, the batch is refused.
    pub fn append(&mut self, records: &[Record]) -> Result<(), StoreError> {
        if self.poisoned {
            return Err(StoreError::Poisoned);
        }
        for (index, record) in records.iter().enumerate() {
            record
                .check()
                .map_err(|error| StoreError::Invalid { index, error })?;
        }
        if records.is_empty() {
            return Ok(());
        }
        if self.lost {
            // An earlier loss not yet repaired.
            self.recover()?;
        }
        let mut bytes = self.batch_bytes(records);
        self.write_batch(&bytes)?;
        if !self.journal_in_place() {
            self.recover()?;
            bytes = self.batch_bytes(records);
            self.write_batch(&bytes)?;
            if !self.journal_in_place() {
                return Err(StoreError::JournalLost(
                    "and again while it was made anew".into(),
                ));
            }
        }
        records.iter().for_each(|r| self.apply(r));
        self.journal_len += bytes.len() as u64;
        self.journal_records += records.len() as u64;
        Ok(())
    }

    /// The bytes of one batch of `records`; an empty journal's first
    /// batch starts with the line that marks a journal of batches.
    fn batch_bytes(&self, records: &[Record]) -> Vec<u8> {
        let batch = encode_batch(records);
        if self.journal_len > 0 {
            return batch;
        }
        let mut bytes = journal::format_line().into_bytes();
        bytes.extend_from_slice(&batch);
        bytes
    }

    /// After the journal was lost: every tool file rewritten from memory
    /// (which holds only durable values) and the journal made anew.
    fn recover(&mut self) -> Result<(), StoreError> {
        self.compact_all().map_err(|e| {
            StoreError::JournalLost(format!("rewriting the tool files from memory: {e}"))
        })?;
        self.upkeep.journal_made_anew();
        Ok(())
    }

    /// Appends `bytes` and syncs them; on failure cuts the journal back.
    fn write_batch(&mut self, bytes: &[u8]) -> Result<(), StoreError> {
        let written = self
            .storage
            .append_journal(bytes)
            .map_err(io_error(format!(
                "appending {} bytes to {JOURNAL_FILE}",
                bytes.len()
            )))
            .and_then(|()| {
                self.storage
                    .sync_journal()
                    .map_err(io_error(format!("syncing {JOURNAL_FILE}")))
            });
        if written.is_err() {
            self.roll_back();
        }
        written
    }

    /// Whether the journal is still the file under its name; a failed
    /// look counts as no (the remedy, a rewrite from memory, is safe).
    /// A no is remembered until every tool file is rewritten.
    fn journal_in_place(&mut self) -> bool {
        let in_place = self.storage.journal_in_place().unwrap_or(false);
        self.lost |= !in_place;
        in_place
    }

    /// Cuts the journal back after a failed append; if even that fails,
    /// refuses appends until compaction or reopen.
    fn roll_back(&mut self) {
        if self.storage.truncate_journal(self.journal_len).is_err() {
            self.poisoned = true;
        }
    }

    fn apply(&mut self, record: &Record) {
        match *record {
            Record::Set { group, key, value } => {
                self.groups.entry(group).or_default().set(key, value);
                self.dirty.insert(group);
            }
            Record::ResetGroup { group } => {
                self.groups.remove(&group);
                self.dirty.insert(group);
            }
            Record::Clean => {
                self.dirty
                    .extend(self.groups.keys().chain(self.files.keys()));
                self.groups.clear();
            }
        }
    }

    /// The storage.
    pub fn storage(&self) -> &S {
        &self.storage
    }

    /// The storage, to act on the disk behind the store's back in a test.
    pub fn storage_mut(&mut self) -> &mut S {
        &mut self.storage
    }

    /// Gives the storage back (to reopen it in a test).
    pub fn into_storage(self) -> S {
        self.storage
    }
}

#[cfg(test)]
mod tests;
