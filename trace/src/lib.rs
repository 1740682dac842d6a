//! # trace — conformance traces of the TC emulator
//!
//! Traces (`*.trace`, trace format v1, docs/trace-format.md): the reader,
//! which parses headers, requests, expectations and spool lines line by
//! line, and the replayer, which runs each step as it is read, so a trace
//! of any length replays in bounded memory, on an in-process emulator or
//! over the wire ([`remote`]). An NC program run is written as a trace by
//! [`nc_run`].
//!
//! ```
//! use trace::{parse_trace, replay};
//!
//! let text = "@name demo\nR 1300/0/3/0 i => 17\nW 1300/1/1/8 i 1024 => err Range\n";
//! let trace = parse_trace("demo.trace", text).unwrap();
//! assert!(replay(&trace).is_empty());
//! ```

mod expect;
mod model;
pub mod nc_run;
mod parse;
pub mod remote;
mod replay;

use std::borrow::Cow;
use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};

pub use model::{Expect, Header, SpoolExpect, SpoolKind, Step, Trace, TraceError};
pub use parse::{parse_trace, TraceReader, DEFAULT_TOL, MAX_LINE_BYTES};
pub use replay::{
    format_record, fresh_emulator, replay, replay_on, replay_stream, Mismatch, Replayed, Target,
};

/// Longest text echoed whole in a report, in characters.
pub const MAX_ECHO_CHARS: usize = 120;

/// `text`, or its first [`MAX_ECHO_CHARS`] characters and `…` when it is
/// longer.
pub fn shorten(text: &str) -> Cow<'_, str> {
    match text.char_indices().nth(MAX_ECHO_CHARS) {
        None => Cow::Borrowed(text),
        Some((cut, _)) => Cow::Owned(format!("{}…", &text[..cut])),
    }
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
