//! Access errors of the UOI level.

/// Declares an error-code enum from ONE list: each variant's discriminant
/// is its code, its name is the variant's identifier, and `ALL` lists the
/// variants in table order. Used for the access errors here and the
/// protocol errors of the wire.
#[macro_export]
macro_rules! code_enum {
    (
        $(#[$meta:meta])*
        pub enum $name:ident {
            $( $(#[$vmeta:meta])* $variant:ident = $code:literal => $text:literal, )+
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[repr(u32)]
        pub enum $name {
            $( $(#[$vmeta])* $variant = $code, )+
        }

        impl ::std::fmt::Display for $name {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                write!(f, "{}: {}", self.name(), self.text())
            }
        }

        impl ::std::error::Error for $name {}

        impl $name {
            /// Every variant, in the order of its table.
            pub const ALL: &'static [$name] = &[$($name::$variant),+];

            /// The numeric code (the variant's discriminant).
            pub const fn code(self) -> u32 {
                self as u32
            }

            /// The variant with this code, if any.
            pub fn from_code(code: u32) -> Option<Self> {
                Self::ALL.iter().copied().find(|e| e.code() == code)
            }

            /// The name used in traces and docs (the variant's identifier).
            pub const fn name(self) -> &'static str {
                match self {
                    $($name::$variant => stringify!($variant),)+
                }
            }

            /// What the error means, in a few words.
            pub const fn text(self) -> &'static str {
                match self {
                    $($name::$variant => $text,)+
                }
            }

            /// The variant with this name (case-insensitive).
            pub fn from_name(name: &str) -> Option<Self> {
                Self::ALL.iter().copied().find(|e| e.name().eq_ignore_ascii_case(name))
            }
        }
    };
}

code_enum! {
    /// Why a UOI access failed. The values are the CANopen SDO abort codes
    /// (CiA 301); traces use the names. A write that fails changes nothing.
    pub enum AccessError {
        /// Bus, device or index does not exist.
        NoObject = 0x0602_0000 => "bus, device or index does not exist",
        /// The index exists but the subindex does not.
        NoSubindex = 0x0609_0011 => "the index exists but the subindex does not",
        /// Read of a write-only object.
        WriteOnly = 0x0601_0001 => "the object cannot be read",
        /// Write of a read-only object.
        ReadOnly = 0x0601_0002 => "the object cannot be written",
        /// The value type differs from the object's type.
        TypeMismatch = 0x0607_0010 => "the value type differs from the object's type",
        /// Value outside the object's range, or a non-finite double.
        Range = 0x0609_0030 => "value outside the object's range",
        /// Refused in the current state of the module.
        State = 0x0800_0022 => "refused in the current state",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_and_names_round_trip() {
        for &e in AccessError::ALL {
            assert_eq!(AccessError::from_code(e.code()), Some(e));
            assert_eq!(AccessError::from_name(e.name()), Some(e));
            assert_eq!(AccessError::from_name(&e.name().to_lowercase()), Some(e));
        }
        assert_eq!(AccessError::ALL.len(), 7);
        assert_eq!(AccessError::Range.code(), 0x06090030);
        assert_eq!(AccessError::State.name(), "State");
        assert_eq!(AccessError::from_code(0), None);
        assert_eq!(
            AccessError::Range.to_string(),
            "Range: value outside the object's range"
        );
    }
}
