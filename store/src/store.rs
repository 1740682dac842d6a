//! The tool store: the group files and the journal together, the current
//! tool values in memory, never ahead of what is durable on disk.

use crate::field::{FileField, ToolValue};
use crate::file::{parse_group_file_lenient, write_group_file, ParseError};
use crate::journal::{self, encode_batch, JournalError, Record, RecordError, TornTail};
use crate::storage::{FsStorage, Storage, JOURNAL_FILE};
use crate::table::{GroupTable, ToolKey, GROUPS};
use std::collections::{BTreeMap, BTreeSet};
use std::io;
use std::path::PathBuf;

/// The tool file name of a group: `group01.wz` .. `group32.wz`.
pub fn group_file_name(group: u8) -> String {
    format!("group{group:02}.wz")
}

/// How to treat bad lines when opening.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Strictness {
    /// Any bad line of a tool file or the journal (other than a torn
    /// tail) refuses the open.
    Strict,
    /// Bad lines are skipped and reported in the [`OpenReport`].
    Lenient,
}

/// When [`ToolStore::needs_compaction`] says yes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CompactionBound {
    /// Journal size in bytes.
    pub bytes: u64,
    /// Journal records.
    pub records: u64,
}

impl Default for CompactionBound {
    /// 4 MiB or 100,000 records, whichever comes first.
    fn default() -> Self {
        Self {
            bytes: 4 << 20,
            records: 100_000,
        }
    }
}

/// What opening found besides the values.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct OpenReport {
    /// Tool files read (group numbers).
    pub files_loaded: Vec<u8>,
    /// Journal records replayed.
    pub replayed: usize,
    /// The torn last journal record, dropped (and cut off the journal).
    pub torn_tail: Option<TornTail>,
    /// Bad tool file lines skipped (lenient open only).
    pub file_errors: Vec<ParseError>,
    /// Bad journal lines skipped (lenient open only; they stay in the
    /// journal until the next [`ToolStore::compact`]).
    pub journal_errors: Vec<JournalError>,
}

/// Why a store operation failed.
#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    /// The disk refused: what was being done and the system's error.
    #[error("{what}: {source}")]
    Io {
        /// What was being done ("appending to the journal", ...).
        what: String,
        /// The system's error.
        source: io::Error,
    },
    /// A tool file has a bad line (strict open).
    #[error(transparent)]
    File(#[from] ParseError),
    /// The journal has a bad record before its last line (strict open).
    #[error("{file}:{}: {}", .error.line, .error.error)]
    Journal {
        /// The journal's file name.
        file: &'static str,
        /// The bad line.
        error: JournalError,
    },
    /// A record given to `append` is invalid (nothing was written).
    #[error("record {index} of the batch: {error}")]
    Invalid {
        /// Its position in the batch, from 0.
        index: usize,
        /// What is wrong.
        error: RecordError,
    },
    /// An earlier failed append could not be undone on disk: appends are
    /// refused until a successful [`ToolStore::compact`] or a reopen.
    #[error("the journal could not be repaired after a failed write; compact or reopen")]
    Poisoned,
}

fn io_error(what: impl Into<String>) -> impl FnOnce(io::Error) -> StoreError {
    let what = what.into();
    move |source| StoreError::Io { what, source }
}

/// The durable tool values of every compensation group.
#[derive(Debug)]
pub struct ToolStore<S> {
    storage: S,
    groups: BTreeMap<u8, GroupTable>,
    /// Groups that have a tool file on disk.
    files: BTreeSet<u8>,
    journal_len: u64,
    journal_records: u64,
    bound: CompactionBound,
    poisoned: bool,
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
    /// Loads every group's tool file, replays the journal on top, drops a
    /// torn last record (cutting it off the journal so later appends
    /// follow good records).
    pub fn open(mut storage: S, strictness: Strictness) -> Result<(Self, OpenReport), StoreError> {
        let mut report = OpenReport::default();
        let mut groups = BTreeMap::new();
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
            report.file_errors.append(&mut errors);
            report.files_loaded.push(group);
            groups.insert(group, table);
        }
        let mut store = Self {
            files: report.files_loaded.iter().copied().collect(),
            storage,
            groups,
            journal_len: 0,
            journal_records: 0,
            bound: CompactionBound::default(),
            poisoned: false,
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
            Strictness::Strict => journal::replay(&bytes).map_err(|error| StoreError::Journal {
                file: JOURNAL_FILE,
                error,
            })?,
            Strictness::Lenient => journal::replay_lenient(&bytes),
        };
        for record in &replay.records {
            self.apply(record);
        }
        if replay.torn_tail.is_some() {
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

    /// Uses `bound` for [`needs_compaction`](Self::needs_compaction).
    pub fn with_compaction_bound(mut self, bound: CompactionBound) -> Self {
        self.bound = bound;
        self
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
        let bytes = encode_batch(records);
        let written = self
            .storage
            .append_journal(&bytes)
            .map_err(io_error(format!("appending to {JOURNAL_FILE}")))
            .and_then(|()| {
                self.storage
                    .sync_journal()
                    .map_err(io_error(format!("syncing {JOURNAL_FILE}")))
            });
        if let Err(e) = written {
            self.roll_back();
            return Err(e);
        }
        records.iter().for_each(|r| self.apply(r));
        self.journal_len += bytes.len() as u64;
        self.journal_records += records.len() as u64;
        Ok(())
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
                self.groups.entry(group).or_default().set(key, value)
            }
            Record::ResetGroup { group } => {
                self.groups.remove(&group);
            }
            Record::Clean => self.groups.clear(),
        }
    }

    /// True once the journal has grown past the compaction bound.
    pub fn needs_compaction(&self) -> bool {
        self.journal_len >= self.bound.bytes || self.journal_records >= self.bound.records
    }

    /// Journal size in bytes and records since the last compaction.
    pub fn journal_size(&self) -> (u64, u64) {
        (self.journal_len, self.journal_records)
    }

    /// Writes every group's tool file from the current values (each one
    /// atomically) and then empties the journal. A group whose values are
    /// all default gets a file with only the header if it had a file.
    /// A crash in between is harmless: replaying the journal over the new
    /// files gives the same values. Success also clears a poisoned store.
    pub fn compact(&mut self) -> Result<(), StoreError> {
        let wanted: BTreeSet<u8> = self
            .groups
            .iter()
            .filter(|(_, t)| !t.is_empty())
            .map(|(&g, _)| g)
            .chain(self.files.iter().copied())
            .collect();
        let empty = GroupTable::new();
        for group in wanted {
            let name = group_file_name(group);
            let text = write_group_file(group, self.groups.get(&group).unwrap_or(&empty));
            self.storage
                .write_file_atomic(&name, text.as_bytes())
                .map_err(io_error(format!("writing {name}")))?;
            self.files.insert(group);
        }
        if let Err(source) = self.storage.truncate_journal(0) {
            self.poisoned = true;
            return Err(io_error(format!("emptying {JOURNAL_FILE}"))(source));
        }
        self.journal_len = 0;
        self.journal_records = 0;
        self.poisoned = false;
        Ok(())
    }

    /// The storage.
    pub fn storage(&self) -> &S {
        &self.storage
    }

    /// Gives the storage back (to reopen it in a test).
    pub fn into_storage(self) -> S {
        self.storage
    }
}

#[cfg(test)]
mod tests;
