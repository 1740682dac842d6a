//! Tool fields, their values and the conversion between the bus unit and
//! the file unit.
//!
//! Radius and length are kept in the file in 0.1 µm and on the bus in
//! interpolation units (mm): the file text is the bus value with the
//! decimal point moved four places. The shift is done on the decimal
//! text, never by a float multiplication, so every value reads back
//! bit-identical. The other fields have the same unit in both places.

use std::fmt;

use uoi::{Value, ValueType};

use crate::decimal::{self, Decimal};

pub use tc_objects::ToolField;

/// The value of one tool field, in the bus unit.
///
/// Two values are equal when their bits are: `-0.0` differs from `0.0`.
#[derive(Debug, Clone, Copy)]
pub enum ToolValue {
    /// An integer field (`typ`).
    I32(i32),
    /// A floating-point field.
    F64(f64),
}

impl PartialEq for ToolValue {
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (Self::I32(a), Self::I32(b)) => a == b,
            (Self::F64(a), Self::F64(b)) => a.to_bits() == b.to_bits(),
            _ => false,
        }
    }
}

impl Eq for ToolValue {}

impl fmt::Display for ToolValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::I32(v) => write!(f, "{v}"),
            Self::F64(v) => write!(f, "{v:?}"),
        }
    }
}

/// What is wrong with a field's value.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ValueError {
    /// The text is not a number of the field's kind.
    #[error("`{text}` is not {expected}")]
    NotANumber {
        /// The offending text.
        text: String,
        /// What was expected ("an integer", "a decimal number").
        expected: &'static str,
    },
    /// The number lies outside the field's range.
    #[error("{value} is out of range for {} (allowed: {range})", field.name())]
    OutOfRange {
        /// The field.
        field: ToolField,
        /// The value as written.
        value: String,
        /// The allowed range, in words.
        range: String,
    },
    /// An integer value for a floating-point field or the reverse.
    #[error("{} takes {expected}", field.name())]
    WrongKind {
        /// The field.
        field: ToolField,
        /// What the field takes.
        expected: &'static str,
    },
}

/// A tool field as the tool files know it: its name there (`wz[i].<name>`),
/// the shift between the bus unit and the file unit, and the check of a
/// value against the field's range, which is that of its object on the
/// bus (docs/objects.md).
pub trait FileField: Sized {
    /// The field's name in the files (`typ`, `radius`, ...).
    fn name(self) -> &'static str;
    /// The field called `name` in the files.
    fn from_name(name: &str) -> Option<Self>;
    /// The value of a field nobody has set: 0.
    fn default_value(self) -> ToolValue;
    /// The allowed range of the field, in words (the same on bus and file
    /// side, in the respective unit).
    fn range_text(self) -> String;
    /// Decimal places between the bus value and the file text: 4 for
    /// radius and length (mm on the bus, 0.1 µm in the file), else 0.
    fn file_shift(self) -> i32;
    /// Checks a bus value: the right kind and inside the field's range.
    fn check(self, value: ToolValue) -> Result<(), ValueError>;
    /// The file text of a bus value (radius and length shifted by four
    /// decimal places). The value is not range-checked here.
    fn to_file_text(self, value: ToolValue) -> String;
    /// The bus value written as `text` in a file, range-checked.
    fn parse_file_text(self, text: &str) -> Result<ToolValue, ValueError>;
}

impl FileField for ToolField {
    fn name(self) -> &'static str {
        match self {
            Self::ToolType => "typ",
            Self::Radius => "radius",
            Self::Length => "laenge",
            Self::WearConst => "grinding_wear_const",
            Self::MaxInfeed => "grinding_max_infeed",
            Self::TiltAngle => "grinding_disc_tilt_angle",
        }
    }

    fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|f| f.name() == name)
    }

    fn default_value(self) -> ToolValue {
        match self.value_type() {
            ValueType::I32 => ToolValue::I32(0),
            ValueType::F64 => ToolValue::F64(0.0),
        }
    }

    fn range_text(self) -> String {
        match self.file_shift() {
            0 => self.range().to_string(),
            _ => format!(
                "{} mm (the bus range of {})",
                self.range(),
                self.object_name()
            ),
        }
    }

    fn file_shift(self) -> i32 {
        match self {
            Self::Radius | Self::Length => 4,
            _ => 0,
        }
    }

    fn check(self, value: ToolValue) -> Result<(), ValueError> {
        let bus = match (self.value_type(), value) {
            (ValueType::I32, ToolValue::I32(v)) => Value::I32(v),
            (ValueType::F64, ToolValue::F64(v)) => Value::F64(v),
            _ => return Err(wrong_kind(self)),
        };
        if self.range().contains(bus) {
            Ok(())
        } else {
            Err(ValueError::OutOfRange {
                field: self,
                value: value.to_string(),
                range: self.range_text(),
            })
        }
    }

    fn to_file_text(self, value: ToolValue) -> String {
        match value {
            ToolValue::I32(v) => v.to_string(),
            ToolValue::F64(v) => match Decimal::from_f64(v) {
                Some(d) => d.shifted(self.file_shift()).to_text(),
                // Not finite: no file can hold it; `check` refuses it first.
                None => format!("{v}"),
            },
        }
    }

    fn parse_file_text(self, text: &str) -> Result<ToolValue, ValueError> {
        let value = match self.value_type() {
            ValueType::I32 => ToolValue::I32(text.parse().map_err(|_| ValueError::NotANumber {
                text: text.to_owned(),
                expected: "an integer",
            })?),
            ValueType::F64 => {
                let not_a_number = || ValueError::NotANumber {
                    text: text.to_owned(),
                    expected: "a decimal number",
                };
                let d = decimal::Decimal::parse(text).ok_or_else(not_a_number)?;
                ToolValue::F64(d.shifted(-self.file_shift()).to_f64())
            }
        };
        self.check(value).map_err(|e| match e {
            ValueError::OutOfRange { field, range, .. } => ValueError::OutOfRange {
                field,
                value: text.to_owned(),
                range,
            },
            other => other,
        })?;
        Ok(value)
    }
}

/// A value of the other kind than `field` takes.
fn wrong_kind(field: ToolField) -> ValueError {
    let expected = match field.value_type() {
        ValueType::I32 => "an integer",
        ValueType::F64 => "a decimal number",
    };
    ValueError::WrongKind { field, expected }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn round_trip(field: ToolField, v: f64) -> f64 {
        let text = field.to_file_text(ToolValue::F64(v));
        match field.parse_file_text(&text) {
            Ok(ToolValue::F64(back)) => back,
            other => panic!("{v:?} -> {text} -> {other:?}"),
        }
    }

    #[test]
    fn names_round_trip() {
        for f in ToolField::ALL {
            assert_eq!(ToolField::from_name(f.name()), Some(f));
        }
        assert_eq!(ToolField::from_name("gueltig"), None);
    }

    #[test]
    fn radius_file_text_is_bus_value_times_ten_thousand() {
        let text = |v| ToolField::Radius.to_file_text(ToolValue::F64(v));
        assert_eq!(text(30.0), "300000");
        assert_eq!(text(0.1), "1000");
        assert_eq!(text(123456.789), "1234567890");
        assert_eq!(text(0.00001), "0.1");
        assert_eq!(text(-0.0), "-0");
        assert_eq!(text(1e-300), "1e-296");
        assert_eq!(
            ToolField::Radius.parse_file_text("300000"),
            Ok(ToolValue::F64(30.0))
        );
    }

    #[test]
    fn edge_values_read_back_bit_identical() {
        let edges = [
            0.0,
            -0.0,
            1e-300,
            -1e-300,
            0.1,
            123456.789,
            1e9,
            -1e9,
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
            0.30000000000000004,
        ];
        for v in edges {
            for f in [ToolField::Radius, ToolField::MaxInfeed] {
                if f == ToolField::Radius && v.abs() > tc_objects::MAX_COORD {
                    continue;
                }
                assert_eq!(
                    round_trip(f, v).to_bits(),
                    v.to_bits(),
                    "{} {v:?}",
                    f.name()
                );
            }
        }
    }

    #[test]
    fn ranges_per_field() {
        let f = |v| ToolValue::F64(v);
        assert!(ToolField::ToolType.check(ToolValue::I32(3)).is_ok());
        assert!(ToolField::ToolType.check(ToolValue::I32(4)).is_err());
        assert!(ToolField::ToolType.check(ToolValue::I32(-1)).is_err());
        assert!(ToolField::ToolType.check(f(2.0)).is_err());
        assert!(ToolField::Radius.check(ToolValue::I32(2)).is_err());
        assert!(ToolField::WearConst.check(f(-1e-9)).is_err());
        assert!(ToolField::WearConst.check(f(-0.0)).is_ok());
        assert!(ToolField::TiltAngle.check(f(450_000.0)).is_ok());
        assert!(ToolField::TiltAngle.check(f(450_000.1)).is_err());
        assert!(ToolField::Radius.check(f(f64::NAN)).is_err());
        assert!(ToolField::Length.check(f(f64::INFINITY)).is_err());
    }

    #[test]
    fn bad_file_text_is_refused() {
        for text in [
            "", "abc", "1.2.3", "nan", "inf", "1e", "--1", "0x10", "1_000",
        ] {
            assert!(
                matches!(
                    ToolField::Radius.parse_file_text(text),
                    Err(ValueError::NotANumber { .. })
                ),
                "{text}"
            );
        }
        assert!(matches!(
            ToolField::ToolType.parse_file_text("2.0"),
            Err(ValueError::NotANumber { .. })
        ));
        assert!(matches!(
            ToolField::ToolType.parse_file_text("7"),
            Err(ValueError::OutOfRange { .. })
        ));
        // 1e13 in 0.1 µm is 1e9 mm, the bus limit; beyond is refused.
        assert!(matches!(
            ToolField::Radius.parse_file_text("1e13"),
            Ok(ToolValue::F64(v)) if v == 1e9
        ));
        assert!(matches!(
            ToolField::Radius.parse_file_text("1.0000000001e13"),
            Err(ValueError::OutOfRange { .. })
        ));
        assert!(matches!(
            ToolField::Radius.parse_file_text("1e313"),
            Err(ValueError::OutOfRange { .. })
        ));
        assert!(matches!(
            ToolField::Length.parse_file_text("1e9999"),
            Err(ValueError::OutOfRange { .. })
        ));
        assert!(matches!(
            ToolField::TiltAngle.parse_file_text("-450001"),
            Err(ValueError::OutOfRange { .. })
        ));
    }

    proptest! {
        #[test]
        fn any_bus_value_reads_back_bit_identical(v in -1e9f64..=1e9f64) {
            for f in [ToolField::Radius, ToolField::Length, ToolField::MaxInfeed] {
                prop_assert_eq!(round_trip(f, v).to_bits(), v.to_bits());
            }
        }

        #[test]
        fn any_finite_bits_read_back_bit_identical(bits in any::<u64>()) {
            let v = f64::from_bits(bits);
            // Every finite value within the bus range (tiny and subnormal
            // ones included: the shift works on their decimal text).
            prop_assume!(v.is_finite() && v.abs() <= tc_objects::MAX_COORD);
            prop_assert_eq!(round_trip(ToolField::Radius, v).to_bits(), bits);
        }
    }
}
