//! Opening the tool data for `serve`: the data directory locked for this
//! server, the tool files loaded and the journal replayed (refusing bad
//! lines, or skipping them when asked), the values loaded into the
//! emulator, and the journal's writer started.

use std::fs::File;
use std::path::Path;

use tool_store::{FsStorage, OpenReport, Strictness, ToolStore, JOURNAL_FILE};
use tracing::{info, warn};

use super::durable::Durable;
use super::entries::load;
use super::lock::{lock_exclusive, tools_dir};
use super::writer::Writer;
use crate::service::EmulatorService;

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

/// Opens the tool data in `data_dir` for `service`: locks the folder,
/// loads it into the emulator and makes every later tool write durable.
/// Returns the lock, to hold while serving. The error names the file and
/// the line of a bad tool file or journal record.
pub fn open_tools(
    service: &mut EmulatorService,
    data_dir: &Path,
    ignore_bad: bool,
) -> Result<File, String> {
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
    load(service.emulator_mut().tc_mut(), store.values());
    let writer = Writer::start(store).map_err(|e| format!("cannot start the tool writer: {e}"))?;
    let tools = Box::new(Durable::new(writer));
    service.set_tools(tools);
    Ok(lock)
}
