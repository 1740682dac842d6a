//! Trace text echoed in a report: long requests shortened.

use std::borrow::Cow;

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
