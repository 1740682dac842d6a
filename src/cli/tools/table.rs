//! `tools show`: a table for people, one row per tool entry that differs
//! from its defaults, every field in the bus unit.

use std::collections::BTreeMap;

use tool_store::{FileField, ToolField, ToolValue};

use super::values::ToolSet;

/// The unit of each field on the bus, as printed under its name.
fn unit(field: ToolField) -> &'static str {
    match field {
        ToolField::ToolType => "0..3",
        ToolField::Radius | ToolField::Length => "mm",
        ToolField::WearConst => "0.1 um/m",
        ToolField::MaxInfeed => "0.1 um",
        ToolField::TiltAngle => "0.0001 deg",
    }
}

/// The table text: a header row of field names, a row of units, then one
/// row per entry, columns right-aligned.
pub fn write(values: &[ToolSet]) -> String {
    let mut entries: BTreeMap<(u8, u16), [ToolValue; 6]> = BTreeMap::new();
    for &(group, key, value) in values {
        let row = entries
            .entry((group, key.index))
            .or_insert(ToolField::ALL.map(ToolField::default_value));
        if let Some(at) = ToolField::ALL.iter().position(|f| *f == key.field) {
            row[at] = value;
        }
    }
    let mut rows: Vec<Vec<String>> = Vec::new();
    let names = ToolField::ALL.iter().map(|f| f.name().to_owned());
    rows.push(
        ["group", "entry"]
            .map(String::from)
            .into_iter()
            .chain(names)
            .collect(),
    );
    let units = ToolField::ALL.iter().map(|f| unit(*f).to_owned());
    rows.push(
        [String::new(), String::new()]
            .into_iter()
            .chain(units)
            .collect(),
    );
    for ((group, index), fields) in entries {
        let cells = fields.iter().map(ToString::to_string);
        rows.push(
            [group.to_string(), index.to_string()]
                .into_iter()
                .chain(cells)
                .collect(),
        );
    }
    align(&rows)
}

/// Rows as text, each column right-aligned to its widest cell.
fn align(rows: &[Vec<String>]) -> String {
    let columns = rows.first().map_or(0, Vec::len);
    let widths: Vec<usize> = (0..columns)
        .map(|c| rows.iter().map(|r| r[c].chars().count()).max().unwrap_or(0))
        .collect();
    let mut out = String::new();
    for row in rows {
        let cells: Vec<String> = row
            .iter()
            .zip(&widths)
            .map(|(cell, w)| format!("{cell:>w$}"))
            .collect();
        out.push_str(cells.join("  ").trim_end());
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use tool_store::ToolKey;

    #[test]
    fn one_row_per_entry_with_every_field() {
        let key = |i, f| ToolKey::new(i, f).unwrap();
        let values = [
            (1, key(1, ToolField::ToolType), ToolValue::I32(2)),
            (1, key(1, ToolField::Radius), ToolValue::F64(30.0)),
            (12, key(1023, ToolField::Length), ToolValue::F64(-0.5)),
        ];
        let text = write(&values);
        let lines: Vec<Vec<&str>> = text
            .lines()
            .map(|l| l.split_whitespace().collect())
            .collect();
        assert_eq!(lines[0][..4], ["group", "entry", "typ", "radius"]);
        assert_eq!(lines[1][..3], ["0..3", "mm", "mm"]);
        assert_eq!(
            lines[2],
            ["1", "1", "2", "30.0", "0.0", "0.0", "0.0", "0.0"]
        );
        assert_eq!(
            lines[3],
            ["12", "1023", "0", "0.0", "-0.5", "0.0", "0.0", "0.0"]
        );
        assert_eq!(lines.len(), 4);
    }
}
