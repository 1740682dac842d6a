//! The trace syntax of a request (docs/trace-format.md): parsing, one function
//! per verb, and writing it back.

mod error;
mod format;
mod verbs;
mod words;

pub use error::TextError;
pub use format::{write_axis_words, write_letters};
pub use verbs::{parse_dir, parse_request};
pub use words::{
    parse_addr, parse_axis, parse_f64, parse_int, parse_type, parse_words, Allow, TextResult, Words,
};
