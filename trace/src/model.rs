//! A parsed trace: its header, its requests and what each must answer and
//! spool.

use std::fmt;

use tc_module::DEFAULT_SPOOL_CAPACITY;
use tc_module::{ArcDir, AxisPos, AxisWords, CycleTime, AXES};
use tc_request::text::{write_axis_words, write_letters};
use tc_request::Request;
use uoi::AccessError;

/// A malformed trace line.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{file}:{line}: {message}")]
pub struct TraceError {
    /// The trace file.
    pub file: String,
    /// 1-based line number.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

/// What the controller must answer.
#[derive(Debug, Clone, PartialEq)]
pub enum Expect {
    /// No `=>`: the request must succeed; the answer is not checked.
    Success,
    /// `=> ok`.
    Ok,
    /// `=> err NAME`.
    Err(AccessError),
    /// `=> 5` / `=> 0x1f` for an `i` read.
    Int(i32),
    /// `=> 2.5` for a `d` read, within `@tol`.
    Double(f64),
    /// `=> X.. Y..` for `POS`: named axes within `@tol`.
    Pos(AxisWords),
    /// `=> n` for `QUEUE`.
    Queue(usize),
}

/// Line or arc in a spool expectation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpoolKind {
    /// `< LIN` (or `< RAP`).
    Line,
    /// `< CIR CW|CCW`.
    Arc(ArcDir),
}

/// One `<` line: an element the request must have spooled.
#[derive(Debug, Clone, PartialEq)]
pub struct SpoolExpect {
    /// Line number.
    pub line: usize,
    /// Line or arc.
    pub kind: SpoolKind,
    /// End point words; unnamed axes keep the element's start value.
    pub words: AxisWords,
    /// Centre offsets I J K from the element's start.
    pub centre: [Option<f64>; 3],
    /// `F`: its feed in units/min, compared only where it is named.
    pub feed: Option<f64>,
}

/// One request with its expectations.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    /// Line number of the request.
    pub line: usize,
    /// The request text (comment stripped).
    pub text: String,
    /// The request.
    pub request: Request,
    /// The answer expected.
    pub expect: Expect,
    /// The complete list of elements it must spool.
    pub spool: Vec<SpoolExpect>,
}

/// Default `@tol`: absolute tolerance for doubles.
pub const DEFAULT_TOL: f64 = 1e-6;

/// What the header lines of a trace set, and the file it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Header {
    /// The file it came from.
    pub file: String,
    /// `@name`.
    pub name: Option<String>,
    /// `@tol`: absolute tolerance for doubles.
    pub tol: f64,
    /// `@start`: initial machine position.
    pub start: AxisPos,
    /// `@cycle`: the interpolation cycle.
    pub cycle: CycleTime,
    /// `@spool`: the spooler capacity (default 100,000 elements).
    pub spool_capacity: usize,
}

impl Header {
    /// The header of a trace without header lines: tolerance 1e-6, the
    /// machine at 0, the default cycle and spooler; `file` names it.
    pub fn new(file: &str) -> Self {
        Self {
            file: file.to_string(),
            name: None,
            tol: DEFAULT_TOL,
            start: [0.0; AXES],
            cycle: CycleTime::DEFAULT,
            spool_capacity: DEFAULT_SPOOL_CAPACITY,
        }
    }
}

/// A trace parsed as a whole (the replayer of files reads them step by
/// step instead, see [`super::TraceReader`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    /// Its header.
    pub header: Header,
    /// The requests.
    pub steps: Vec<Step>,
}

impl fmt::Display for SpoolExpect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.kind {
            SpoolKind::Line => write!(f, "LIN")?,
            SpoolKind::Arc(d) => write!(f, "CIR {}", d.keyword())?,
        }
        write_axis_words(f, &self.words)?;
        write_letters(f, &['I', 'J', 'K'], &self.centre)?;
        write_letters(f, &['F'], &[self.feed])
    }
}
