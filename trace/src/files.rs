//! Trace files on disk: a folder's traces, one trace opened for reading
//! step by step, or read whole.

use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};

use crate::model::{Step, Trace, TraceError};
use crate::parse::TraceReader;

/// Why a trace file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum TraceFileError {
    /// The file (or the folder) could not be read.
    #[error("{name}: cannot read: {source}")]
    Unreadable {
        /// The file, as shown.
        name: String,
        /// Why.
        source: std::io::Error,
    },
    /// The folder could not be listed.
    #[error("{name}: {source}")]
    Folder {
        /// The folder, as shown.
        name: String,
        /// Why.
        source: std::io::Error,
    },
    /// A line of the trace is malformed (or could not be read).
    #[error(transparent)]
    Malformed(#[from] TraceError),
}

/// The `*.trace` files of a folder, sorted by name.
pub fn trace_files(dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "trace"))
        .collect();
    files.sort();
    Ok(files)
}

/// Opens a trace file and reads its header; the error names the file (and
/// line).
pub fn open_trace(path: &Path) -> Result<TraceReader<BufReader<File>>, TraceFileError> {
    let name = path.display().to_string();
    let file = match File::open(path) {
        Ok(f) => f,
        Err(source) => return Err(TraceFileError::Unreadable { name, source }),
    };
    Ok(TraceReader::open(&name, BufReader::new(file))?)
}

/// Reads and parses one trace file as a whole; the error names the file
/// (and line).
pub fn load_trace(path: &Path) -> Result<Trace, TraceFileError> {
    let mut reader = open_trace(path)?;
    let steps = reader.by_ref().collect::<Result<Vec<Step>, TraceError>>()?;
    Ok(Trace {
        header: reader.header().clone(),
        steps,
    })
}

/// Every trace of a folder, parsed, in file-name order.
pub fn load_corpus(dir: &Path) -> Result<Vec<Trace>, TraceFileError> {
    let files = trace_files(dir).map_err(|source| TraceFileError::Folder {
        name: dir.display().to_string(),
        source,
    })?;
    files.iter().map(|f| load_trace(f)).collect()
}
