//! What a run reports: the error that stops it, the faults the controller
//! signals while it goes on, and the warnings; each a kind a caller can
//! match, with where in the program it stands.

use std::fmt;

use tc_request::{Reply, Request};
use uoi::wire::ProtocolError;
use uoi::AccessError;

use crate::error::Location;

/// Something a run reports, and where in the program it stands: `None`
/// when it belongs to no block (a program without blocks, a jump the
/// interpreter cannot make).
#[derive(Debug, Clone, PartialEq)]
pub struct Located<K> {
    /// Line, block number and column of the word that caused it.
    pub location: Option<Location>,
    /// What happened.
    pub kind: K,
}

/// The error that stops a run, or a fault of the controller that the run
/// goes on after ([`super::Report::faults`]).
pub type RunError = Located<RunErrorKind>;

/// A construct run in a simpler way than the program asks.
pub type Warning = Located<WarningKind>;

impl<K: fmt::Display> fmt::Display for Located<K> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.location {
            Some(at) => write!(f, "{at}: {}", self.kind),
            None => write!(f, "{}", self.kind),
        }
    }
}

impl<K: fmt::Debug + fmt::Display> std::error::Error for Located<K> {}

/// What stopped a run (or, for [`RunErrorKind::Otc`], a fault it went on
/// after).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RunErrorKind {
    /// A parameter or variable read before it was set (`P3`,
    /// `V.P.NAME`); R parameters start at 0 and are always set.
    #[error("{name} is read before it was set")]
    Unset {
        /// The variable as the interpreter names it (`V.P.NAME`).
        name: String,
    },
    /// A `V.G.` variable this interpreter does not know.
    #[error("{name} is not a variable this interpreter knows")]
    UnknownVariable {
        /// The variable (`V.G.NAME`).
        name: String,
    },
    /// A read of a `V.S.` or `V.E.` variable.
    #[error("V.{scope}. variables are not implemented")]
    ScopeNotImplemented {
        /// The scope letter.
        scope: char,
    },
    /// A variable that cannot be written (`V.G.` other than
    /// `V.G.WZ_AKT.R`, `V.S.`, `V.E.`).
    #[error("{name} cannot be written here")]
    NotWritable {
        /// The variable.
        name: String,
    },
    /// A division by zero.
    #[error("division by zero")]
    DivisionByZero,
    /// An expression whose value (or a step of it) is not a finite number.
    #[error("the expression has no finite value")]
    NotFinite,
    /// A value that must be a whole `i32` number (`D`, `ACC_WEIGHT`, the
    /// OtcError bits) is not.
    #[error("{what} must be a whole number, not {value}")]
    NotWhole {
        /// What the value is for.
        what: &'static str,
        /// The value.
        value: f64,
    },
    /// A `D` word outside the data sets 0..255.
    #[error("D{d} is not a data set 0..255")]
    DataSet {
        /// The D number.
        d: i32,
    },
    /// `#set/#get ToolParam` with a line that is no data set 1..255.
    #[error("ToolParam line {line} is not a data set 1..255")]
    ToolParamLine {
        /// The line given.
        line: f64,
    },
    /// `#set/#get ToolParam` with a column outside 0..15.
    #[error("ToolParam column {column} is not a column 0..15")]
    ToolParamColumn {
        /// The column given.
        column: f64,
    },
    /// `#set ToolParam` on the data set of the running correction.
    #[error("#set ToolParam: data set D{line} is in use by the running TRC (G40 first)")]
    ToolParamInUse {
        /// The data set.
        line: f64,
    },
    /// An M function other than M30.
    #[error("M{0} is not implemented (only M30)")]
    MFunction(u32),
    /// G141, contour masking.
    #[error("G141 (contour masking) is not implemented")]
    ContourMasking,
    /// Axis words before any of G0, G1, G2, G3.
    #[error("axis words before any motion kind (G0, G1, G2, G3)")]
    NoMotionKind,
    /// Circle centre words with G0 or G1.
    #[error("I, J, K need G2 or G3")]
    CentreWithoutArc,
    /// `$FOR` with step 0.
    #[error("$FOR with step 0 never ends")]
    ForStepZero,
    /// The end of a loop without its start (blocks made by hand; the
    /// parser refuses it in a program).
    #[error("{end} without its {start}")]
    Unpaired {
        /// `$ENDFOR` or `$ENDWHILE`.
        end: &'static str,
        /// `$FOR` or `$WHILE`.
        start: &'static str,
    },
    /// A `$` control statement beside other words (blocks made by hand;
    /// the parser refuses it in a program).
    #[error("a $ control statement must stand alone in its block")]
    ControlNotAlone,
    /// More blocks executed than [`super::MAX_EXECUTED_BLOCKS`].
    #[error("more than {limit} blocks executed: endless loop?")]
    TooManyBlocks {
        /// The limit.
        limit: u64,
    },
    /// The controller refused a request with an access error other than
    /// `State` (`Range`, `ReadOnly`, ..).
    #[error("`{request}`: the controller answered {}", .error.name())]
    Refused {
        /// The request.
        request: Box<Request>,
        /// The controller's answer.
        error: AccessError,
    },
    /// The controller answered `State`: correction group 1 is faulted.
    #[error(
        "`{request}`: the controller answered State: correction group 1 is faulted{}",
        error_bits_text(.error_bits)
    )]
    Faulted {
        /// The request.
        request: Box<Request>,
        /// The names of the group's ERROR bits set, when they could be
        /// read (`CalcError`, `CenterError`, ..).
        error_bits: Option<Vec<String>>,
    },
    /// The request was refused by the protocol.
    #[error("`{request}`: refused: {error}")]
    Rejected {
        /// The request.
        request: Box<Request>,
        /// Why.
        error: ProtocolError,
    },
    /// An answer of another kind than the request asks for.
    #[error("{}", unexpected_text(.request, .reply))]
    UnexpectedReply {
        /// The request.
        request: Box<Request>,
        /// The answer.
        reply: Box<Reply>,
    },
    /// An OTC error bit newly set by a block: a fault, the run goes on.
    #[error("OTC error {name}")]
    Otc {
        /// The bit of OtcError.
        bit: i32,
        /// Its name, with its ISG error id where it has one
        /// (`ToolType (P-ERR-21391): ..`).
        name: &'static str,
    },
    /// A fault of the correction (KorrError, CalcError, PlaneError,
    /// CenterError) raised by the profile of the block it names: the run
    /// stops there (docs/nc.md, "Faults").
    #[error(
        "the correction faulted on this block's profile (ERROR: {}); nothing of it or of the \
         profile held with it was spooled",
        .bits.join(", ")
    )]
    CorrectionFault {
        /// The names of the ERROR bits set.
        bits: Vec<String>,
    },
    /// `R` with `G0`/`G1`, with `I J K`, or for a full circle.
    #[error("R (an arc's radius) {0}")]
    RadiusWord(&'static str),
    /// An arc by radius whose radius is shorter than half its chord.
    #[error("R{radius}: no arc of that radius joins start and end (the smallest is {half_chord})")]
    RadiusTooShort {
        /// The radius programmed.
        radius: f64,
        /// Half the chord: the smallest radius.
        half_chord: f64,
    },
    /// ISG 90191: G41/G42 while the correction runs, with G237 in force.
    #[error("G41/G42 while TRC runs with G237 in force (ISG 90191): deselect with G40 first")]
    PerpendicularReselect,
    /// ISG 21317: G238 programmed while the correction runs.
    #[error("G238 programmed while TRC runs (ISG 21317): G238 must be in force before G41/G42")]
    InsideCornerWhileRunning,
    /// A contour the G238 selection cannot run.
    #[error("G238: {0}")]
    InsideCorner(&'static str),
    /// An arc as the first motion after a G239 deselection.
    #[error(
        "an arc right after a G239 deselection: its programmed start is not where the tool \
         stands (program a line first)"
    )]
    ArcAfterG239,
    /// A `#TRC [..]` option: not in this emulator.
    #[error("#TRC option {0} is not in this emulator (docs/nc.md)")]
    TrcOption(String),
    /// `#TANGFEED [RMIN=..]` with a negative radius.
    #[error("#TANGFEED: RMIN must be 0 or more, not {0}")]
    TangFeedRmin(f64),
    /// A line the parser refuses (or a failed read), met by a run of a
    /// program that was not checked first.
    #[error("{0}")]
    Parse(String),
    /// A jump the checked program cannot need (a block released too
    /// early, a structure without its end): reported, never a panic.
    #[error("internal: {0}")]
    Internal(String),
}

/// ` (ERROR: CalcError, ..)` when the bits could be read.
fn error_bits_text(bits: &Option<Vec<String>>) -> String {
    match bits {
        Some(names) => format!(" (ERROR: {})", names.join(", ")),
        None => String::new(),
    }
}

fn unexpected_text(request: &Request, reply: &Reply) -> String {
    match request {
        Request::Read(addr, _) => format!("R {addr}: unexpected answer {reply:?}"),
        Request::Pos => format!("POS answered {reply:?}"),
        other => format!("`{other}`: unexpected answer {reply:?}"),
    }
}

/// A construct run in a simpler way than the program asks.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum WarningKind {
    /// A `T` word: the TC module has no tool magazine.
    #[error(
        "T accepted without effect: the TC module has no tool magazine; D selects the tool data"
    )]
    ToolWord,
    /// G139, G236 or G05 run as G138: their geometry is given only in
    /// the manual's figures.
    #[error("{word} runs as G138: its geometry is given only in figures (docs/nc.md)")]
    SelectionRule {
        /// `G139`, `G236` or `G05`.
        word: &'static str,
    },
    /// ISG 21316: G05 while G238 is in force is ignored.
    #[error("G05 while G238 is in force is ignored (ISG 21316)")]
    TangentialIgnored,
    /// A `D` word while the correction runs, for a data set the D table
    /// has no values for: the running radius stays.
    #[error(
        "D{d} while TRC runs: the tool entry cannot change, and the D table has no values \
         for D{d}; the running radius stays"
    )]
    ToolDataKept {
        /// The D number.
        d: u32,
    },
}
