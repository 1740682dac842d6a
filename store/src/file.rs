//! Tool files: one per compensation group, one `wz[i].field value` per
//! line in the file unit, `#` comments and blank lines allowed.

use crate::field::{FileField, ToolField, ToolValue, ValueError};
use crate::table::{GroupTable, ToolKey, TOOL_ENTRIES};
use std::collections::HashMap;
use std::fmt;

/// What is wrong with one line of a tool file or journal.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LineError {
    /// The line is not `wz[<index>].<field> <value>` (truncated or garbage).
    #[error("{0}")]
    Malformed(String),
    /// The index is not in 0..=1023.
    #[error("index {0} is out of range (0..={max})", max = TOOL_ENTRIES - 1)]
    IndexOutOfRange(String),
    /// No field has this name.
    #[error("unknown field `{0}`")]
    UnknownField(String),
    /// The value is not a number of the field's kind or out of its range.
    #[error(transparent)]
    Value(#[from] ValueError),
    /// The same `wz[i].field` appears twice in one file.
    #[error("duplicate key {key} (first set on line {first_line})")]
    Duplicate {
        /// The key.
        key: ToolKey,
        /// The line that set it first.
        first_line: usize,
    },
}

/// A bad line of a tool file: where it is and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{file}:{line}: {error}")]
pub struct ParseError {
    /// The file's name as given to the parser.
    pub file: String,
    /// Line number, counting from 1.
    pub line: usize,
    /// What is wrong.
    pub error: LineError,
}

/// The text of one line without its comment, trimmed.
pub(crate) fn strip_comment(line: &str) -> &str {
    line.split_once('#').map_or(line, |(code, _)| code).trim()
}

/// Parses `wz[<index>].<field> <value>` (no comment, trimmed) into a key
/// and a bus value.
pub(crate) fn parse_assignment(text: &str) -> Result<(ToolKey, ToolValue), LineError> {
    let mut words = text.split_whitespace();
    let key_text = words.next().unwrap_or("");
    let Some(value_text) = words.next() else {
        return Err(LineError::Malformed(format!("`{key_text}` has no value")));
    };
    let key = parse_key(key_text)?;
    if let Some(extra) = words.next() {
        return Err(LineError::Malformed(format!(
            "unexpected `{extra}` after the value (comments start with #)"
        )));
    }
    Ok((key, key.field.parse_file_text(value_text)?))
}

/// Parses `wz[<index>].<field>`.
fn parse_key(text: &str) -> Result<ToolKey, LineError> {
    let malformed = || {
        LineError::Malformed(format!(
            "expected `wz[<index>].<field> <value>`, found `{text}`"
        ))
    };
    let inner = text.strip_prefix("wz[").ok_or_else(malformed)?;
    let (index_text, rest) = inner.split_once(']').ok_or_else(malformed)?;
    let name = rest.strip_prefix('.').ok_or_else(malformed)?;
    if index_text.is_empty() || !index_text.bytes().all(|b| b.is_ascii_digit()) {
        return Err(malformed());
    }
    let field = ToolField::from_name(name).ok_or_else(|| LineError::UnknownField(name.into()))?;
    index_text
        .parse::<u16>()
        .ok()
        .and_then(|i| ToolKey::new(i, field))
        .ok_or_else(|| LineError::IndexOutOfRange(index_text.into()))
}

/// The line `wz[i].field value` for a bus value, without a newline.
pub(crate) fn format_assignment(key: ToolKey, value: ToolValue) -> String {
    format!("{key} {}", key.field.to_file_text(value))
}

/// Parses a group's tool file; the first bad line is the error.
pub fn parse_group_file(file: &str, text: &str) -> Result<GroupTable, ParseError> {
    let (table, mut errors) = parse_group_file_lenient(file, text);
    if errors.is_empty() {
        Ok(table)
    } else {
        Err(errors.swap_remove(0))
    }
}

/// Parses a group's tool file, skipping bad lines: the table of the good
/// lines and every bad line's error, in line order. Of a duplicate key the
/// first line counts.
pub fn parse_group_file_lenient(file: &str, text: &str) -> (GroupTable, Vec<ParseError>) {
    let mut table = GroupTable::new();
    let mut errors = Vec::new();
    let mut seen: HashMap<ToolKey, usize> = HashMap::new();
    for (n, raw) in text.lines().enumerate() {
        let line = n + 1;
        let code = strip_comment(raw);
        if code.is_empty() {
            continue;
        }
        let result = parse_assignment(code).and_then(|(key, value)| match seen.get(&key) {
            Some(&first_line) => Err(LineError::Duplicate { key, first_line }),
            None => Ok((key, value)),
        });
        match result {
            Ok((key, value)) => {
                seen.insert(key, line);
                table.set(key, value);
            }
            Err(error) => errors.push(ParseError {
                file: file.to_owned(),
                line,
                error,
            }),
        }
    }
    (table, errors)
}

/// The text of a group's tool file: a header comment, then one line per
/// value that differs from its default, sorted by index, then field.
pub fn write_group_file(group: u8, table: &GroupTable) -> String {
    let mut out = Header(group).to_string();
    for (key, value) in table.iter() {
        out.push_str(&format_assignment(key, value));
        out.push('\n');
    }
    out
}

/// The header comment of a tool file.
struct Header(u8);

impl fmt::Display for Header {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "# addipos tool data, compensation group {}", self.0)?;
        writeln!(f, "# wz[<index>].<field> <value>; unset fields are 0.")?;
        writeln!(
            f,
            "# radius, laenge, grinding_max_infeed: 0.1 um; grinding_wear_const: 0.1 um/m;"
        )?;
        writeln!(f, "# grinding_disc_tilt_angle: 0.0001 degree; typ: 0..3.")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn key(i: u16, f: ToolField) -> ToolKey {
        ToolKey::new(i, f).unwrap()
    }

    fn error_of(text: &str) -> ParseError {
        parse_group_file("group01.wz", text).unwrap_err()
    }

    #[test]
    fn hand_written_file_in_the_manuals_style_loads() {
        let text = "\
# Tool data, written by hand
wz[1].typ              2
wz[1].laenge           500000
wz[1].radius           300000   # 30 mm
# Wear constant : Unit 0.1 um/m
wz[1].grinding_wear_const 100000

\t wz[1].grinding_max_infeed\t200000
wz[1].grinding_disc_tilt_angle 0
";
        let t = parse_group_file("group01.wz", text).unwrap();
        assert_eq!(t.get(key(1, ToolField::ToolType)), ToolValue::I32(2));
        assert_eq!(t.get(key(1, ToolField::Radius)), ToolValue::F64(30.0));
        assert_eq!(t.get(key(1, ToolField::Length)), ToolValue::F64(50.0));
        let wear = t.get(key(1, ToolField::WearConst));
        assert_eq!(wear, ToolValue::F64(100000.0));
        let infeed = t.get(key(1, ToolField::MaxInfeed));
        assert_eq!(infeed, ToolValue::F64(200000.0));
        assert_eq!(t.len(), 5);
    }

    #[test]
    fn example_of_the_user_docs_loads() {
        let docs = include_str!("../../docs/tool-files.md");
        let start = docs.find("```\n# grinding disc").unwrap() + 4;
        let len = docs[start..].find("```").unwrap();
        let t = parse_group_file("docs", &docs[start..start + len]).unwrap();
        assert_eq!(t.get(key(1, ToolField::Radius)), ToolValue::F64(30.0));
        assert_eq!(t.len(), 5, "the tilt angle 0 is the default");
    }

    #[test]
    fn unknown_field_is_reported_with_line() {
        let e = error_of("wz[1].typ 2\n\nwz[1].gueltig 1\n");
        assert_eq!(e.line, 3);
        assert_eq!(e.error, LineError::UnknownField("gueltig".into()));
        assert_eq!(e.to_string(), "group01.wz:3: unknown field `gueltig`");
    }

    #[test]
    fn index_out_of_range_is_reported() {
        let e = error_of("# x\nwz[1024].radius 1\n");
        assert_eq!(
            (e.line, e.error),
            (2, LineError::IndexOutOfRange("1024".into()))
        );
        let e = error_of("wz[99999999999].radius 1\n");
        assert!(matches!(e.error, LineError::IndexOutOfRange(_)));
    }

    #[test]
    fn value_not_a_number_is_reported() {
        let e = error_of("wz[0].radius 12x\n");
        assert!(matches!(
            e.error,
            LineError::Value(ValueError::NotANumber { .. })
        ));
        assert!(
            e.to_string().contains("`12x` is not a decimal number"),
            "{e}"
        );
    }

    #[test]
    fn value_out_of_range_is_reported_with_range() {
        let e = error_of("wz[0].typ 4\n");
        assert_eq!(
            e.to_string(),
            "group01.wz:1: 4 is out of range for typ (allowed: 0..=3)"
        );
        let e = error_of("wz[0].grinding_wear_const -1\n");
        assert!(matches!(
            e.error,
            LineError::Value(ValueError::OutOfRange { .. })
        ));
        let e = error_of("wz[0].grinding_disc_tilt_angle 450001\n");
        assert!(e.to_string().contains("-450000..=450000"), "{e}");
    }

    #[test]
    fn duplicate_key_is_reported_with_both_lines() {
        let e = error_of("wz[3].radius 1\nwz[3].laenge 1\nwz[3].radius 2\n");
        let k = key(3, ToolField::Radius);
        assert_eq!(e.line, 3);
        assert_eq!(
            e.error,
            LineError::Duplicate {
                key: k,
                first_line: 1
            }
        );
    }

    #[test]
    fn truncated_and_garbage_lines_are_reported() {
        for (text, what) in [
            ("wz[1].radius\n", "has no value"),
            ("wz[1].radi", "has no value"),
            ("wz[1\n", "has no value"),
            ("hello world\n", "expected"),
            ("wz[a].radius 1\n", "expected"),
            ("wz[1]radius 1\n", "expected"),
            ("wz[1].typ 2 grinding tool\n", "unexpected `grinding`"),
        ] {
            let e = error_of(text);
            assert!(matches!(e.error, LineError::Malformed(_)), "{text:?}: {e}");
            assert!(e.to_string().contains(what), "{text:?}: {e}");
        }
    }

    #[test]
    fn lenient_parse_skips_bad_lines_and_reports_them() {
        let text = "wz[1].typ 2\nwz[1].bad 1\nwz[2].typ 9\nwz[1].typ 3\nwz[2].radius 10\n";
        let (t, errors) = parse_group_file_lenient("g", text);
        let lines: Vec<_> = errors.iter().map(|e| e.line).collect();
        assert_eq!(lines, [2, 3, 4]);
        assert_eq!(t.get(key(1, ToolField::ToolType)), ToolValue::I32(2));
        assert_eq!(t.get(key(2, ToolField::Radius)), ToolValue::F64(0.001));
        assert_eq!(t.len(), 2);
    }

    #[test]
    fn written_file_has_header_and_only_set_fields_sorted() {
        let mut t = GroupTable::new();
        t.set(key(9, ToolField::ToolType), ToolValue::I32(2));
        t.set(key(1, ToolField::WearConst), ToolValue::F64(100000.0));
        t.set(key(1, ToolField::Radius), ToolValue::F64(30.0));
        t.set(key(1, ToolField::Length), ToolValue::F64(-0.0));
        let text = write_group_file(3, &t);
        let body: Vec<_> = text.lines().filter(|l| !l.starts_with('#')).collect();
        assert!(text.starts_with("# addipos tool data, compensation group 3\n"));
        assert_eq!(
            body,
            [
                "wz[1].radius 300000",
                "wz[1].laenge -0",
                "wz[1].grinding_wear_const 100000",
                "wz[9].typ 2"
            ]
        );
    }

    fn any_value(field: ToolField) -> BoxedStrategy<ToolValue> {
        match field {
            ToolField::ToolType => (0..=3).prop_map(ToolValue::I32).boxed(),
            ToolField::WearConst => (0.0..1e9).prop_map(ToolValue::F64).boxed(),
            ToolField::TiltAngle => (-450000.0..=450000.0).prop_map(ToolValue::F64).boxed(),
            _ => prop_oneof![Just(-0.0), -1e9..1e9]
                .prop_map(ToolValue::F64)
                .boxed(),
        }
    }

    /// A random table: up to 40 set fields.
    pub(crate) fn any_table() -> impl Strategy<Value = GroupTable> {
        let entry = (
            0..TOOL_ENTRIES,
            proptest::sample::select(ToolField::ALL.to_vec()),
        )
            .prop_flat_map(|(i, f)| any_value(f).prop_map(move |v| (key(i, f), v)));
        proptest::collection::vec(entry, 0..40).prop_map(|entries| {
            let mut t = GroupTable::new();
            for (k, v) in entries {
                t.set(k, v);
            }
            t
        })
    }

    proptest! {
        #[test]
        fn write_then_parse_gives_the_same_table(t in any_table()) {
            let text = write_group_file(7, &t);
            prop_assert_eq!(parse_group_file("g", &text), Ok(t));
        }
    }
}
