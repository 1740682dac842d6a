//! Opening the tool data of a data directory for a server: the tool
//! folder locked for it, the tool files loaded and the journal replayed
//! (refusing bad lines, or skipping them when asked), what was found
//! logged, and skipped lines compacted away.

use std::fs::File;
use std::path::Path;

use tracing::{info, warn};

use crate::lock::{lock_exclusive, tools_dir};
use crate::{FsStorage, OpenReport, Strictness, ToolStore, JOURNAL_FILE};

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
    if let Some(t) = &report.torn_tail {
        warn!(
            line = t.line,
            bytes = t.bytes,
            "dropped the torn last record of the tool journal"
        );
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
/// lines, which then leave the files). The error names the file and the
/// line of a bad tool file or journal record, and the way out.
pub fn open_tools(data_dir: &Path, ignore_bad: bool) -> Result<OpenTools, String> {
    let dir = tools_dir(data_dir);
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let lock = lock_exclusive(&dir).map_err(|e| e.to_string())?;
    let strictness = if ignore_bad {
        Strictness::Lenient
    } else {
        Strictness::Strict
    };
    let (mut store, report) = ToolStore::open(FsStorage::new(&dir), strictness).map_err(|e| {
        format!(
            "tool data in {}: {e} (fix or remove the line, or start with --ignore-bad-tools)",
            dir.display()
        )
    })?;
    log_report(&dir, &report);
    if !(report.file_errors.is_empty() && report.journal_errors.is_empty()) {
        // The skipped lines leave the files and the journal now, so they
        // are not reported again at every start.
        store
            .compact()
            .map_err(|e| format!("tool data in {}: {e}", dir.display()))?;
    }
    Ok(OpenTools { store, lock })
}
