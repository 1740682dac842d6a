//! The tool data of a data directory as it is now, read without the lock
//! and without changing a byte (a server may be writing meanwhile).

use std::fmt;
use std::path::{Path, PathBuf};

use tool_store::{
    group_file_name, FsStorage, MemStorage, OpenReport, Storage, StoreError, Strictness, ToolStore,
    GROUPS, JOURNAL_FILE,
};

/// Reads tried before giving up when the files keep changing.
const ATTEMPTS: usize = 5;

/// The tool files of every group (`None`: no file) and the journal.
#[derive(PartialEq)]
struct Files(Vec<Option<Vec<u8>>>);

fn read_files(disk: &mut FsStorage) -> std::io::Result<Files> {
    GROUPS
        .map(|g| disk.read_file(&group_file_name(g)))
        .collect::<Result<_, _>>()
        .map(Files)
}

/// A copy in memory of the tool folder `dir` that is consistent: the tool
/// files are read before and after the journal and must be the same both
/// times (a compaction in between would pair old files with an emptied
/// journal). Opening the copy never touches the disk, so a torn journal
/// tail of a write in progress is left alone.
pub fn load(dir: &Path) -> Result<(ToolStore<MemStorage>, OpenReport), SnapshotError> {
    let mut disk = FsStorage::new(dir);
    let io = |what: &'static str| {
        move |error| SnapshotError::Unreadable {
            dir: dir.display().to_string(),
            what,
            error,
        }
    };
    for _ in 0..ATTEMPTS {
        let before = read_files(&mut disk).map_err(io("the tool files"))?;
        let journal = disk.read_journal().map_err(io(JOURNAL_FILE))?;
        if read_files(&mut disk).map_err(io("the tool files"))? != before {
            continue;
        }
        let mut copy = MemStorage::new();
        for (g, bytes) in GROUPS.zip(before.0) {
            if let Some(bytes) = bytes {
                copy.put_file(&group_file_name(g), bytes);
            }
        }
        *copy.journal_mut() = journal;
        return ToolStore::open(copy, Strictness::Strict).map_err(|e| store_error(dir, e).into());
    }
    Err(SnapshotError::KeptChanging(dir.display().to_string()))
}

/// Why the tool data of a data directory could not be read.
#[derive(Debug, thiserror::Error)]
pub enum SnapshotError {
    /// A file of the tool folder cannot be read.
    #[error("{dir}: reading {what}: {error}")]
    Unreadable {
        /// The tool folder.
        dir: String,
        /// What was read.
        what: &'static str,
        /// Why.
        error: std::io::Error,
    },
    /// The tool data is bad.
    #[error(transparent)]
    Store(#[from] StoreAt),
    /// The files changed at every try.
    #[error(
        "{0}: the tool files kept changing while being read (a server compacting?); try again"
    )]
    KeptChanging(String),
}

/// A store error of the tool folder `dir`, shown with the full path of
/// the file it names.
#[derive(Debug, thiserror::Error)]
pub struct StoreAt {
    dir: PathBuf,
    error: StoreError,
}

impl fmt::Display for StoreAt {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let dir = &self.dir;
        match &self.error {
            StoreError::File(p) => {
                write!(f, "{}:{}: {}", dir.join(&p.file).display(), p.line, p.error)
            }
            StoreError::Journal { file, error } => {
                write!(
                    f,
                    "{}:{}: {}",
                    dir.join(file).display(),
                    error.line,
                    error.error
                )
            }
            other => write!(f, "{}: {other}", dir.display()),
        }
    }
}

/// A store error with the full path of the file it names.
pub fn store_error(dir: &Path, error: StoreError) -> StoreAt {
    StoreAt {
        dir: dir.to_path_buf(),
        error,
    }
}

/// Notes for stderr about what opening found (a dropped torn tail,
/// skipped bad lines).
pub fn report_notes(dir: &Path, report: &OpenReport) -> Vec<String> {
    let mut notes = Vec::new();
    if let Some(t) = &report.torn_tail {
        notes.push(format!(
            "note: {}:{}: last journal record left out ({}): a write in progress or cut short by a crash",
            dir.join(JOURNAL_FILE).display(),
            t.line,
            t.reason
        ));
    }
    for e in &report.file_errors {
        let path = dir.join(&e.file);
        notes.push(format!(
            "note: {}:{}: skipped: {}",
            path.display(),
            e.line,
            e.error
        ));
    }
    for e in &report.journal_errors {
        let path = dir.join(JOURNAL_FILE);
        notes.push(format!(
            "note: {}:{}: skipped: {}",
            path.display(),
            e.line,
            e.error
        ));
    }
    notes
}
