//! Access errors of the UOI level (uoi-map.md, "Access errors").

/// Why a UOI access failed. The codes are the CANopen SDO abort codes
/// (CiA 301) listed in uoi-map.md; traces use the names.
///
/// A write that fails changes nothing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
pub enum AccessError {
    /// Bus, device or index does not exist.
    #[error("NoObject: bus, device or index does not exist")]
    NoObject,
    /// The index exists but the subindex does not.
    #[error("NoSubindex: the index exists but the subindex does not")]
    NoSubindex,
    /// Read of a write-only object.
    #[error("WriteOnly: the object cannot be read")]
    WriteOnly,
    /// Write of a read-only object.
    #[error("ReadOnly: the object cannot be written")]
    ReadOnly,
    /// The value type differs from the object's type.
    #[error("TypeMismatch: the value type differs from the object's type")]
    TypeMismatch,
    /// Value outside the object's range, or a non-finite double.
    #[error("Range: value outside the object's range")]
    Range,
    /// Motion command refused: the correction group is faulted.
    #[error("State: refused in the current state (faulted group or position request)")]
    State,
}

impl AccessError {
    /// Every access error, in the order of the spec table.
    pub const ALL: [AccessError; 7] = [
        AccessError::NoObject,
        AccessError::NoSubindex,
        AccessError::WriteOnly,
        AccessError::ReadOnly,
        AccessError::TypeMismatch,
        AccessError::Range,
        AccessError::State,
    ];

    /// The CANopen-style abort code.
    pub const fn code(self) -> u32 {
        match self {
            AccessError::NoObject => 0x0602_0000,
            AccessError::NoSubindex => 0x0609_0011,
            AccessError::WriteOnly => 0x0601_0001,
            AccessError::ReadOnly => 0x0601_0002,
            AccessError::TypeMismatch => 0x0607_0010,
            AccessError::Range => 0x0609_0030,
            AccessError::State => 0x0800_0022,
        }
    }

    /// The error with this abort code, if any.
    pub fn from_code(code: u32) -> Option<Self> {
        Self::ALL.into_iter().find(|e| e.code() == code)
    }

    /// The name used in traces (`NoObject`, `Range`, ...).
    pub const fn name(self) -> &'static str {
        match self {
            AccessError::NoObject => "NoObject",
            AccessError::NoSubindex => "NoSubindex",
            AccessError::WriteOnly => "WriteOnly",
            AccessError::ReadOnly => "ReadOnly",
            AccessError::TypeMismatch => "TypeMismatch",
            AccessError::Range => "Range",
            AccessError::State => "State",
        }
    }

    /// The error with this trace name (case-insensitive).
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|e| e.name().eq_ignore_ascii_case(name))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_and_names_round_trip() {
        for e in AccessError::ALL {
            assert_eq!(AccessError::from_code(e.code()), Some(e));
            assert_eq!(AccessError::from_name(e.name()), Some(e));
            assert_eq!(AccessError::from_name(&e.name().to_lowercase()), Some(e));
        }
        assert_eq!(AccessError::Range.code(), 0x06090030);
        assert_eq!(AccessError::from_code(0), None);
    }
}
