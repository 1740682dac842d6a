//! Opening the tool data of a data directory for a server: the tool
//! folder locked for it, leftover temporary files removed, the tool files
//! loaded and the journal replayed (refusing bad lines, or skipping them
//! when asked), what was found logged, a copy kept of each file whose bad
//! lines were skipped before compaction drops them, and a journal already
//! past its bound compacted.

use std::collections::BTreeSet;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::time::Instant;

use tracing::{info, warn};

use crate::lock::{lock_exclusive, tools_dir, LockError};
use crate::{FsStorage, OpenReport, StoreError, Strictness, ToolStore, JOURNAL_FILE};

/// Why the tool data of a data directory could not be opened; each
/// message names the folder or file and, for a bad line, the way out.
#[derive(Debug, thiserror::Error)]
pub enum OpenError {
    /// The tool folder could not be created.
    #[error("cannot create {}: {source}", .dir.display())]
    Create {
        /// The tool folder.
        dir: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// A folder's entries could not be flushed to the disk.
    #[error("cannot flush {}: {source}", .dir.display())]
    Flush {
        /// The folder.
        dir: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// The tool folder's lock was not taken.
    #[error(transparent)]
    Lock(#[from] LockError),
    /// The tool files or the journal could not be loaded (a bad line
    /// when strict).
    #[error(
        "tool data in {}: {source} (fix or remove the line, or start with --ignore-bad-tools)",
        .dir.display()
    )]
    Load {
        /// The tool folder.
        dir: PathBuf,
        /// What the store found.
        source: StoreError,
    },
    /// The repair that drops skipped lines (a compaction) failed.
    #[error("tool data in {}: {source}", .dir.display())]
    Repair {
        /// The tool folder.
        dir: PathBuf,
        /// What the store found.
        source: StoreError,
    },
    /// A damaged file could not be copied before its bad lines are
    /// dropped.
    #[error(
        "cannot keep a copy of {} before dropping its bad lines: {source}",
        .file.display()
    )]
    KeepCopy {
        /// The damaged file.
        file: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
}

/// The tool data of a data directory, open and locked.
#[derive(Debug)]
pub struct OpenTools {
    /// The store on the tool folder, its values loaded.
    pub store: ToolStore<FsStorage>,
    /// The folder's lock: hold it while the store is used.
    pub lock: File,
}

/// Logs what opening found besides the values.
fn log_report(dir: &Path, report: &OpenReport) {
    info!(
        folder = %dir.display(),
        files = report.files_loaded.len(),
        journal_records = report.replayed,
        "tool data loaded"
    );
    for name in &report.removed_temporaries {
        info!("removed {name}, left over from a tool file replacement cut short");
    }
    if let Some(t) = &report.torn_tail {
        let what = match (&report.journal_copy, &report.journal_copy_failed) {
            (Some(copy), _) => format!(
                "dropped the last batch of the tool journal, cut by a crash before it was \
                 acknowledged (kept as it was in {copy})"
            ),
            (None, Some(why)) => format!(
                "dropped the last batch of the tool journal, cut by a crash before it was \
                 acknowledged; no copy kept: {why}"
            ),
            (None, None) => "dropped the torn last record of the tool journal".into(),
        };
        warn!(line = t.line, bytes = t.bytes, "{what}");
    }
    for e in &report.file_errors {
        warn!("skipped a bad tool file line: {e}");
    }
    for e in &report.journal_errors {
        warn!(
            "skipped a bad tool journal line: {JOURNAL_FILE}:{}: {}",
            e.line, e.error
        );
    }
}

/// Opens the tool data in `data_dir`: creates and locks its tool folder,
/// loads the files and replays the journal (`ignore_bad`: skipping bad
/// lines, which then leave the files, after a copy of each damaged file is
/// kept beside it). The error names the file and the line of a bad tool
/// file or journal record, and the way out.
pub fn open_tools(data_dir: &Path, ignore_bad: bool) -> Result<OpenTools, OpenError> {
    let dir = tools_dir(data_dir);
    let existed = dir.is_dir();
    std::fs::create_dir_all(&dir).map_err(|source| OpenError::Create {
        dir: dir.clone(),
        source,
    })?;
    if !existed {
        // The new folder's entry survives a power cut.
        flush(data_dir)?;
    }
    let lock = lock_exclusive(&dir)?;
    let strictness = if ignore_bad {
        Strictness::Lenient
    } else {
        Strictness::Strict
    };
    let (mut store, report) =
        ToolStore::open(FsStorage::new(&dir), strictness).map_err(|source| OpenError::Load {
            dir: dir.clone(),
            source,
        })?;
    log_report(&dir, &report);
    if !(report.file_errors.is_empty() && report.journal_errors.is_empty()) {
        // The skipped lines leave the files and the journal now, so they
        // are not reported again at every start; the evidence is kept.
        keep_damaged(&dir, &report)?;
        store
            .compact()
            .map_err(|source| OpenError::Repair { dir, source })?;
    }
    // A journal left past its bound (by a full disk, or an older version)
    // is compacted before the first write; a failure is logged.
    store.maintain_at(Instant::now());
    Ok(OpenTools { store, lock })
}

/// Keeps a copy of every file whose bad lines were skipped, as
/// `<name>.bad-<UTC time>` beside it, flushed to the disk, before the
/// repair drops the lines. A copy that cannot be made refuses the start.
fn keep_damaged(dir: &Path, report: &OpenReport) -> Result<(), OpenError> {
    let mut damaged: BTreeSet<&str> = report.file_errors.iter().map(|e| e.file.as_str()).collect();
    if !report.journal_errors.is_empty() {
        damaged.insert(JOURNAL_FILE);
    }
    let stamp = chrono::Utc::now().format("%Y%m%dT%H%M%SZ").to_string();
    for name in damaged {
        let copy = unused_name(dir, &format!("{name}.bad-{stamp}"));
        copy_durably(&dir.join(name), &copy).map_err(|source| OpenError::KeepCopy {
            file: dir.join(name),
            source,
        })?;
        warn!(
            "kept {name} as it was, bad lines and all, in {}",
            copy.display()
        );
    }
    flush(dir)
}

/// Flushes the entries of folder `dir` to the disk.
fn flush(dir: &Path) -> Result<(), OpenError> {
    File::open(dir)
        .and_then(|d| d.sync_all())
        .map_err(|source| OpenError::Flush {
            dir: dir.to_owned(),
            source,
        })
}

/// `dir/name`, or `dir/name-2`, `-3` ... if taken.
fn unused_name(dir: &Path, name: &str) -> PathBuf {
    let mut path = dir.join(name);
    let mut n = 2;
    while path.exists() {
        path = dir.join(format!("{name}-{n}"));
        n += 1;
    }
    path
}

/// Copies `from` to `to` and flushes the copy.
fn copy_durably(from: &Path, to: &Path) -> std::io::Result<()> {
    std::fs::copy(from, to)?;
    File::open(to)?.sync_all()
}
