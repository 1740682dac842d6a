//! The JSON form of the tool data, for scripts: one object per tool entry
//! with its group, index and fields in the bus unit (radius and laenge in
//! mm). Numbers are written shortest-exact and read back bit-identical.

use std::collections::{BTreeMap, HashMap};

use serde::{Deserialize, Serialize};
use tool_store::{FileField, ToolField, ToolKey, ToolValue, GROUPS};

use super::values::{Import, ToolSet};

/// The document: `{"entries": [...]}`.
#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ToolsJson {
    /// The tool entries, sorted by group and index.
    pub entries: Vec<EntryJson>,
}

/// One tool entry; a field left out on import keeps its value.
#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct EntryJson {
    /// Compensation group, 1..=32.
    pub group: u8,
    /// The entry (WKZINDEX), 0..=1023.
    pub entry: u16,
    /// Tool type: 0 milling, 1 turning, 2 grinding, 3 wire.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub typ: Option<i32>,
    /// Tool radius, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Tool length, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub laenge: Option<f64>,
    /// Wear constant, 0.1 µm/m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grinding_wear_const: Option<f64>,
    /// Largest infeed, 0.1 µm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grinding_max_infeed: Option<f64>,
    /// Disc tilt angle, 0.0001°.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grinding_disc_tilt_angle: Option<f64>,
}

impl EntryJson {
    /// The fields given, with their values.
    fn fields(&self) -> Vec<(ToolField, ToolValue)> {
        let f64s = [
            (ToolField::Radius, self.radius),
            (ToolField::Length, self.laenge),
            (ToolField::WearConst, self.grinding_wear_const),
            (ToolField::MaxInfeed, self.grinding_max_infeed),
            (ToolField::TiltAngle, self.grinding_disc_tilt_angle),
        ];
        let typ = self.typ.map(|v| (ToolField::ToolType, ToolValue::I32(v)));
        typ.into_iter()
            .chain(
                f64s.into_iter()
                    .filter_map(|(f, v)| Some((f, ToolValue::F64(v?)))),
            )
            .collect()
    }

    fn set(&mut self, field: ToolField, value: ToolValue) {
        let f = match value {
            ToolValue::F64(v) => Some(v),
            ToolValue::I32(_) => None,
        };
        match field {
            ToolField::ToolType => {
                self.typ = if let ToolValue::I32(v) = value {
                    Some(v)
                } else {
                    None
                }
            }
            ToolField::Radius => self.radius = f,
            ToolField::Length => self.laenge = f,
            ToolField::WearConst => self.grinding_wear_const = f,
            ToolField::MaxInfeed => self.grinding_max_infeed = f,
            ToolField::TiltAngle => self.grinding_disc_tilt_angle = f,
        }
    }
}

/// The entries holding `values`, every field of each (unset ones at their
/// default).
fn document(values: &[ToolSet]) -> ToolsJson {
    let mut entries: BTreeMap<(u8, u16), EntryJson> = BTreeMap::new();
    for &(group, key, value) in values {
        let entry = entries.entry((group, key.index)).or_insert_with(|| {
            let mut e = EntryJson {
                group,
                entry: key.index,
                ..EntryJson::default()
            };
            for f in ToolField::ALL {
                e.set(f, f.default_value());
            }
            e
        });
        entry.set(key.field, value);
    }
    ToolsJson {
        entries: entries.into_values().collect(),
    }
}

/// The JSON text of `values`, pretty-printed, with a final newline.
pub fn write(values: &[ToolSet]) -> String {
    // Serialising plain structs of numbers cannot fail.
    let mut text = serde_json::to_string_pretty(&document(values)).unwrap_or_default();
    text.push('\n');
    text
}

/// Parses a JSON import file named `file`, checking every entry; entries
/// of other groups than `group` (when given) are checked but left out.
pub fn parse(file: &str, text: &str, group: Option<u8>) -> Result<Import, Vec<String>> {
    let doc: ToolsJson = serde_json::from_str(text).map_err(|e| {
        let msg = e.to_string();
        let at = format!(" at line {} column {}", e.line(), e.column());
        let msg = msg.strip_suffix(&at).unwrap_or(&msg);
        vec![format!("{file}:{}:{}: {msg}", e.line(), e.column())]
    })?;
    let mut import = Import::default();
    let mut errors = Vec::new();
    let mut seen: HashMap<(u8, u16), usize> = HashMap::new();
    for (n, e) in doc.entries.iter().enumerate() {
        let here = format!(
            "{file}: entries[{n}] (group {}, entry {})",
            e.group, e.entry
        );
        match check_entry(e, n, &mut seen) {
            Err(what) => errors.push(format!("{here}: {what}")),
            Ok(sets) if group.is_none_or(|g| g == e.group) => import.values.extend(sets),
            Ok(_) => import.other_groups += 1,
        }
    }
    if errors.is_empty() {
        Ok(import)
    } else {
        Err(errors)
    }
}

/// What is wrong with an entry of a JSON import.
#[derive(Debug, thiserror::Error)]
enum EntryError {
    /// The group is not one.
    #[error("group out of range (1..=32)")]
    Group,
    /// The entry is not one.
    #[error("entry out of range (0..=1023)")]
    Entry,
    /// The same group and entry given before.
    #[error("duplicate entry (first given in entries[{first}])")]
    Duplicate {
        /// The index of the first.
        first: usize,
    },
    /// A value out of its field's range.
    #[error("{field}: {error}")]
    Value {
        /// The field's name.
        field: &'static str,
        /// Why.
        error: tool_store::ValueError,
    },
}

/// The values of one entry, range-checked; a second entry with the same
/// group and index is an error.
fn check_entry(
    e: &EntryJson,
    n: usize,
    seen: &mut HashMap<(u8, u16), usize>,
) -> Result<Vec<ToolSet>, EntryError> {
    if !GROUPS.contains(&e.group) {
        return Err(EntryError::Group);
    }
    if let Some(first) = seen.insert((e.group, e.entry), n) {
        return Err(EntryError::Duplicate { first });
    }
    let mut sets = Vec::new();
    for (field, value) in e.fields() {
        let key = ToolKey::new(e.entry, field).ok_or(EntryError::Entry)?;
        field.check(value).map_err(|error| EntryError::Value {
            field: field.name(),
            error,
        })?;
        sets.push((e.group, key, value));
    }
    Ok(sets)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn written_json_parses_back_bit_identical() {
        let key = |i, f| ToolKey::new(i, f).unwrap();
        let values = vec![
            (2, key(7, ToolField::ToolType), ToolValue::I32(2)),
            (2, key(7, ToolField::Radius), ToolValue::F64(0.1 + 0.2)),
            (2, key(7, ToolField::Length), ToolValue::F64(-0.0)),
            (9, key(0, ToolField::MaxInfeed), ToolValue::F64(5e-324)),
        ];
        let back = parse("x", &write(&values), None).unwrap().values;
        // The entry comes back with every field, the unset ones at 0.
        let set: Vec<_> = back
            .into_iter()
            .filter(|s| s.2 != s.1.field.default_value())
            .collect();
        assert_eq!(set, values);
    }

    #[test]
    fn bad_entries_are_named() {
        let text = r#"{"entries": [
            {"group": 1, "entry": 1, "typ": 9},
            {"group": 1, "entry": 1},
            {"group": 33, "entry": 1},
            {"group": 1, "entry": 1024, "radius": 1.0}
        ]}"#;
        let errors = parse("t.json", text, None).unwrap_err();
        assert_eq!(errors.len(), 4, "{errors:#?}");
        assert!(errors[0].starts_with("t.json: entries[0] (group 1, entry 1): typ:"));
        assert!(errors[1].contains("duplicate entry (first given in entries[0])"));
        let e = parse(
            "t.json",
            "{\"entries\": [\n{\"group\": 1, \"entry\": 1, \"color\": 2}]}",
            None,
        )
        .unwrap_err();
        assert!(e[0].starts_with("t.json:2:"), "{e:?}");
        assert!(e[0].contains("unknown field `color`"), "{e:?}");
    }
}
