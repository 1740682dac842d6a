//! Trace text echoed in a report: long requests shortened, and control
//! characters written as escapes, so that a report is safe on a terminal
//! and in an XML 1.0 file.

use std::borrow::Cow;
use std::fmt::Write as _;

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

/// Whether `c` is shown as an escape: control characters (C0 but tab and
/// line feed, DEL, C1) and the two noncharacters XML 1.0 forbids.
fn needs_escape(c: char) -> bool {
    (c.is_control() && c != '\t' && c != '\n') || c == '\u{fffe}' || c == '\u{ffff}'
}

/// `text` with every control character (NUL, ESC, a carriage return ...;
/// tab and line feed stay) written as `\xNN` (`\u{NNNN}` above 0xFF): a
/// trace's bytes or file name echoed in a report cannot drive a terminal
/// or break an XML file (docs/trace-format.md).
pub fn printable(text: &str) -> Cow<'_, str> {
    if !text.chars().any(needs_escape) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        match u32::from(c) {
            _ if !needs_escape(c) => out.push(c),
            n if n <= 0xff => {
                let _ = write!(out, "\\x{n:02x}");
            }
            n => {
                let _ = write!(out, "\\u{{{n:04x}}}");
            }
        }
    }
    Cow::Owned(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_become_escapes() {
        assert_eq!(printable("LIN X1\tY2\n"), "LIN X1\tY2\n");
        assert_eq!(
            printable("a\u{0}b\u{1}\u{2}\u{1b}[31m\r\u{7f}\u{85}\u{fffe}"),
            "a\\x00b\\x01\\x02\\x1b[31m\\x0d\\x7f\\x85\\u{fffe}"
        );
        assert!(matches!(printable("plain"), Cow::Borrowed(_)));
    }
}
