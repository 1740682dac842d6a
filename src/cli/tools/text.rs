//! The export file: every group's tool values in one text file, one
//! `g<group> wz[<index>].<field> <value>` line each, in the tool files'
//! units (the journal's line without its checksum). Import also takes a
//! group's tool file in the manual's style (`wz[1].radius 300000`, no
//! group) when the group is given with `--group`.

use std::collections::HashMap;

use tool_store::{FileField, Record, ToolKey};

use super::values::{Import, ToolSet};

/// The header comment of an export file.
const HEADER: &str = "\
# addipos tool data (addipos tools export)
# g<group> wz[<index>].<field> <value>; fields not listed are 0.
# radius, laenge, grinding_max_infeed: 0.1 um; grinding_wear_const: 0.1 um/m;
# grinding_disc_tilt_angle: 0.0001 degree; typ: 0..3.
";

/// The export text of `values` (sorted by group, index, field).
pub fn write(values: &[ToolSet]) -> String {
    let mut out = HEADER.to_owned();
    for &(group, key, value) in values {
        out.push_str(&format!(
            "g{group} {key} {}\n",
            key.field.to_file_text(value)
        ));
    }
    out
}

/// Parses an import file named `file`: every bad line is reported as
/// `file:line: what`. Lines without a group belong to `group`; with
/// `group` given, lines of other groups are checked but left out.
pub fn parse(file: &str, text: &str, group: Option<u8>) -> Result<Import, Vec<String>> {
    let mut import = Import::default();
    let mut errors = Vec::new();
    let mut seen: HashMap<(u8, ToolKey), usize> = HashMap::new();
    for (n, raw) in text.lines().enumerate() {
        let line = n + 1;
        let code = raw.split_once('#').map_or(raw, |(code, _)| code).trim();
        if code.is_empty() {
            continue;
        }
        let parsed =
            parse_line(code, group).and_then(|(g, key, value)| match seen.insert((g, key), line) {
                Some(first) => Err(LineError::Duplicate {
                    group: g,
                    key,
                    first,
                }),
                None => Ok((g, key, value)),
            });
        match parsed {
            Ok(set) if group.is_none_or(|g| g == set.0) => import.values.push(set),
            Ok(_) => import.other_groups += 1,
            Err(e) => errors.push(format!("{file}:{line}: {e}")),
        }
    }
    if errors.is_empty() {
        Ok(import)
    } else {
        Err(errors)
    }
}

/// What is wrong with a line of a text import.
#[derive(Debug, thiserror::Error)]
enum LineError {
    /// Not a record line (the journal's parser says why).
    #[error(transparent)]
    Record(#[from] tool_store::RecordError),
    /// A line without a group, and no `--group`.
    #[error("no compensation group: write `g<group> {0}`, or give the group with --group")]
    NoGroup(String),
    /// A record, but no tool value.
    #[error("`{0}` is not a tool value (`[g<group>] wz[<index>].<field> <value>`)")]
    NotAValue(String),
    /// The same key set before.
    #[error("duplicate key g{group} {key} (first set on line {first})")]
    Duplicate {
        /// The group.
        group: u8,
        /// The key.
        key: ToolKey,
        /// The line it was first set on.
        first: usize,
    },
}

/// One line without comment: `[g<group>] wz[<index>].<field> <value>`.
fn parse_line(code: &str, group: Option<u8>) -> Result<ToolSet, LineError> {
    let first = code.split_whitespace().next().unwrap_or("");
    let prefixed = first
        .strip_prefix('g')
        .is_some_and(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()));
    let body = if prefixed {
        code.to_owned()
    } else {
        format!("g{} {code}", group.unwrap_or(1))
    };
    // The journal's own record parser, so an import takes exactly what a
    // tool file or journal line holds; it wants a checksummed line.
    let line = format!("{body} *{:08x}", crc32fast::hash(body.as_bytes()));
    match Record::decode(line.as_bytes())? {
        Record::Set { .. } if !prefixed && group.is_none() => {
            Err(LineError::NoGroup(code.to_string()))
        }
        Record::Set { group, key, value } => Ok((group, key, value)),
        _ => Err(LineError::NotAValue(code.to_string())),
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use tool_store::{ToolField, ToolValue};

    fn key(i: u16, f: ToolField) -> ToolKey {
        ToolKey::new(i, f).unwrap()
    }

    #[test]
    fn manual_style_lines_take_the_given_group() {
        let text = "# by hand\nwz[1].typ 2\nwz[1].radius 300000 # 30 mm\n\ng4 wz[2].laenge 0\n";
        let i = parse("t.wz", text, Some(3)).unwrap();
        assert_eq!(
            i.values,
            [
                (3, key(1, ToolField::ToolType), ToolValue::I32(2)),
                (3, key(1, ToolField::Radius), ToolValue::F64(30.0)),
            ]
        );
        assert_eq!(i.other_groups, 1);
    }

    #[test]
    fn every_bad_line_is_named() {
        let text = "g1 wz[1].typ 2\nrubbish\ng1 wz[1].colour 3\ng1 wz[1].typ 3\ng40 wz[1].typ 1\ng1 reset\nwz[2].typ 1\n";
        let errors = parse("t.txt", text, None).unwrap_err();
        let lines: Vec<_> = errors
            .iter()
            .map(|e| e.split(':').nth(1).unwrap())
            .collect();
        assert_eq!(lines, ["2", "3", "4", "5", "6", "7"], "{errors:#?}");
        assert!(
            errors[1].contains("unknown field `colour`"),
            "{}",
            errors[1]
        );
        assert!(errors[2].contains("duplicate key g1 wz[1].typ (first set on line 1)"));
        assert!(errors[5].contains("no compensation group"), "{}", errors[5]);
    }

    #[test]
    fn written_text_parses_back_bit_identical() {
        let values = vec![
            (1, key(0, ToolField::Radius), ToolValue::F64(0.1 + 0.2)),
            (1, key(0, ToolField::Length), ToolValue::F64(-0.0)),
            (32, key(1023, ToolField::MaxInfeed), ToolValue::F64(5e-324)),
        ];
        let back = parse("x", &write(&values), None).unwrap().values;
        assert_eq!(back, values);
    }
}
