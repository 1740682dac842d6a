//! The trace syntax of a request (docs/trace-format.md): parsing, one function
//! per verb, and writing it back; a spooled element as a `<` line.

mod error;
mod format;
mod spooled;
mod verbs;
mod words;

pub use error::TextError;
pub use format::{write_axis_words, write_letters};
pub use spooled::{centre_offset, format_record, format_record_fed};
pub use verbs::{parse_dir, parse_request};
pub use words::{
    parse_addr, parse_axis, parse_f64, parse_int, parse_type, parse_words, Allow, TextResult, Words,
};
