//! Conformance traces (`*.trace`, trace format v1, docs/trace-format.md):
//! the parser and the replayer.

mod expect;
mod model;
mod parse;
mod replay;

pub use model::{Expect, SpoolExpect, SpoolKind, Step, Trace, TraceError};
pub use parse::parse_trace;
pub use replay::{format_record, replay, replay_on, Mismatch, Target};

/// The `*.trace` files of a folder, sorted by name.
pub fn trace_files(dir: &std::path::Path) -> std::io::Result<Vec<std::path::PathBuf>> {
    let mut files: Vec<std::path::PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "trace"))
        .collect();
    files.sort();
    Ok(files)
}

/// Reads and parses one trace file; the error names the file (and line).
pub fn load_trace(path: &std::path::Path) -> Result<Trace, String> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| format!("{name}: cannot read: {e}"))?;
    parse_trace(&name, &text).map_err(|e| e.to_string())
}

/// Every trace of a folder, parsed, in file-name order.
pub fn load_corpus(dir: &std::path::Path) -> Result<Vec<Trace>, String> {
    let files = trace_files(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    files.iter().map(|f| load_trace(f)).collect()
}
