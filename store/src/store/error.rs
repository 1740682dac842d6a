//! Why a store operation failed.

use crate::file::ParseError;
use crate::journal::{JournalError, RecordError};
use crate::storage::JOURNAL_FILE;
use std::io;

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
    /// The journal has a bad complete record (strict open).
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
    /// refused until a successful [`ToolStore::compact`](crate::ToolStore::compact) or a reopen.
    #[error("the journal could not be repaired after a failed write; compact or reopen")]
    Poisoned,
    /// Compaction could not write a tool file; what the disk needs.
    #[error(
        "writing {file}: {source} (to compact, the disk needs {needs} bytes free for the \
         tool files; compacting then frees the journal's {journal} bytes)"
    )]
    Compaction {
        /// The tool file.
        file: String,
        /// Bytes free on the disk that compaction needs: the new tool
        /// files, and the largest one once more (each is written beside
        /// the old one, then renamed over it).
        needs: u64,
        /// The journal's size, freed once compaction is done.
        journal: u64,
        /// The system's error.
        source: io::Error,
    },
    /// The journal was deleted or replaced while in use (the batch went
    /// into a file that is gone) and could not be made anew from memory.
    #[error("{JOURNAL_FILE} was deleted or replaced while in use: {0}")]
    JournalLost(String),
}

impl StoreError {
    /// Whether the disk refused for want of room (no space left, quota
    /// exceeded): compaction may free it.
    pub fn is_disk_full(&self) -> bool {
        let source = match self {
            Self::Io { source, .. } | Self::Compaction { source, .. } => source,
            _ => return false,
        };
        matches!(
            source.kind(),
            io::ErrorKind::StorageFull | io::ErrorKind::QuotaExceeded
        )
    }
}

pub(super) fn io_error(what: impl Into<String>) -> impl FnOnce(io::Error) -> StoreError {
    let what = what.into();
    move |source| StoreError::Io { what, source }
}
