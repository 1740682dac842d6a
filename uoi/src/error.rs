//! Access errors of the UOI level.

/// Declares a `#[repr]` enum whose discriminants are its codes, from ONE
/// list: `ALL` (the variants in table order), `code()`, `from_code()` and
/// `name()` (the variant's identifier, as traces and docs write it).
#[macro_export]
macro_rules! code_list {
    (
        $(#[$meta:meta])*
        pub enum $name:ident: $repr:ident {
            $( $(#[$vmeta:meta])* $variant:ident = $code:expr, )+
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[repr($repr)]
        pub enum $name {
            $( $(#[$vmeta])* $variant = $code, )+
        }

        impl $name {
            /// Every variant, in the order of its table.
            pub const ALL: &'static [$name] = &[$($name::$variant),+];

            /// The numeric code (the variant's discriminant).
            pub const fn code(self) -> $repr {
                self as $repr
            }

            /// The variant with this code, if any.
            pub fn from_code(code: $repr) -> Option<Self> {
                Self::ALL.iter().copied().find(|e| e.code() == code)
            }

            /// The name used in traces and docs (the variant's identifier).
            pub const fn name(self) -> &'static str {
                match self {
                    $($name::$variant => stringify!($variant),)+
                }
            }
        }
    };
}

/// Declares an error-code enum (u32 codes) from ONE list of
/// `Variant = code => "meaning"`: everything [`code_list!`] gives, plus
/// `text()`, `from_name()`, `Display` and `Error`. Used for the access
/// errors here and the protocol errors of the wire.
#[macro_export]
macro_rules! code_enum {
    (
        $(#[$meta:meta])*
        pub enum $name:ident {
            $( $(#[$vmeta:meta])* $variant:ident = $code:literal => $text:literal, )+
        }
    ) => {
        $crate::code_list! {
            $(#[$meta])*
            pub enum $name: u32 {
                $( $(#[$vmeta])* $variant = $code, )+
            }
        }

        impl $name {
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

        impl ::std::fmt::Display for $name {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                write!(f, "{}: {}", self.name(), self.text())
            }
        }

        impl ::std::error::Error for $name {}
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
        /// No room to take it now (a queue or store of the module is
        /// full): nothing changed; send it again once room is made.
        Full = 0x0504_0005 => "no room for it now: nothing changed",
        /// The value could not be stored durably (the disk refused it);
        /// nothing changed.
        Storage = 0x0800_0020 => "the value could not be stored: nothing changed",
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
        assert_eq!(AccessError::ALL.len(), 9);
        assert_eq!(AccessError::Full.code(), 0x0504_0005);
        assert_eq!(AccessError::Range.code(), 0x06090030);
        assert_eq!(AccessError::State.name(), "State");
        assert_eq!(AccessError::from_code(0), None);
        assert_eq!(
            AccessError::Range.to_string(),
            "Range: value outside the object's range"
        );
    }
}
