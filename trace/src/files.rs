//! Trace files on disk: a folder's traces, one trace opened for reading
//! step by step, or read whole.

use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};

use crate::model::{Step, Trace, TraceError};
use crate::parse::TraceReader;

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
pub fn open_trace(path: &Path) -> Result<TraceReader<BufReader<File>>, String> {
    let name = path.display().to_string();
    let file = File::open(path).map_err(|e| format!("{name}: cannot read: {e}"))?;
    TraceReader::open(&name, BufReader::new(file)).map_err(|e| e.to_string())
}

/// Reads and parses one trace file as a whole; the error names the file
/// (and line).
pub fn load_trace(path: &Path) -> Result<Trace, String> {
    let mut reader = open_trace(path)?;
    let steps = reader
        .by_ref()
        .collect::<Result<Vec<Step>, TraceError>>()
        .map_err(|e| e.to_string())?;
    Ok(Trace {
        header: reader.header().clone(),
        steps,
    })
}

/// Every trace of a folder, parsed, in file-name order.
pub fn load_corpus(dir: &Path) -> Result<Vec<Trace>, String> {
    let files = trace_files(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    files.iter().map(|f| load_trace(f)).collect()
}
