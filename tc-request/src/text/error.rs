//! What is wrong with a piece of trace-syntax text: one typed error, its
//! message the one a user reads (the CLI and trace replay print it as it
//! is; docs/decisions.md, decision 486).

use uoi::AddressParseError;

/// What is wrong with a request, a word or a number in trace syntax.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TextError {
    /// Not an integer.
    #[error("bad integer `{0}`")]
    BadInteger(String),
    /// An integer outside the i32 range.
    #[error("integer `{0}` out of range")]
    IntegerOutOfRange(String),
    /// Not a number.
    #[error("bad number `{0}`")]
    BadNumber(String),
    /// Not an object address.
    #[error(transparent)]
    Address(#[from] AddressParseError),
    /// Not a type letter.
    #[error("bad type `{0}` (want i or d)")]
    BadType(String),
    /// Not an axis letter.
    #[error("bad axis `{0}`")]
    BadAxis(String),
    /// An empty word.
    #[error("empty word")]
    EmptyWord,
    /// A word the line may not carry.
    #[error("unexpected word `{0}`")]
    UnexpectedWord(String),
    /// A word given twice (its letter).
    #[error("word `{0}` given twice")]
    WordTwice(char),
    /// A word without a number.
    #[error("word `{0}` has no number")]
    NoNumber(String),
    /// Nothing to parse.
    #[error("empty request")]
    EmptyRequest,
    /// A verb that is no request.
    #[error("unknown request `{0}`")]
    UnknownRequest(String),
    /// A token after a complete request (the token, the verb).
    #[error("unexpected `{0}` after {1}")]
    Trailing(String, String),
    /// A request without what it needs: how it is written.
    #[error("{0}")]
    Usage(&'static str),
    /// `SSF` without its axis and function.
    #[error("SSF needs an axis and a function: `SSF X {flush}`", flush = crate::SSF_FLUSH)]
    SsfUsage,
    /// An `EXEC` cycle count beyond the largest.
    #[error(
        "cycle count `{0}` too large (at most {max}; `EXEC` alone runs until the spooler is empty)",
        max = crate::MAX_EXEC_CYCLES
    )]
    CyclesTooMany(String),
    /// An `EXEC` cycle count that is no count.
    #[error("bad cycle count `{0}`")]
    BadCycles(String),
    /// `FEED_ADAPT` switched neither on nor off.
    #[error("FEED_ADAPT: `{0}` is not 0 or 1")]
    NotOnOff(String),
}

/// The message, for callers that keep errors as text (the trace reader).
impl From<TextError> for String {
    fn from(e: TextError) -> Self {
        e.to_string()
    }
}
