//! What a call can fail with: the access errors of the object interface,
//! with their CANopen codes, and the library's own failures, with codes
//! of their own outside the CANopen range.

use uoi::AccessError;

/// Declares [`ErrorCode`] from ONE table: the access errors of the
/// object interface by name (their CANopen codes are [`AccessError`]'s,
/// never written again here), then the library's own codes. Each entry's
/// documentation is its meaning as the C header gives it
/// ([`ErrorCode::meaning`]): the header's `ADDIPOS_E_*` constants are
/// generated from this table (libaddipos/tests/header.rs), and the
/// Python package's classes are checked against it
/// (host/tests/python_codes.rs); decision 512.
macro_rules! error_codes {
    (
        access { $( $(#[doc = $adoc:literal])+ $a:ident, )+ }
        own { $( $(#[doc = $odoc:literal])+ $o:ident = $code:literal, )+ }
    ) => {
        uoi::code_list! {
            /// The number a failed call returns (the C ABI's `ADDIPOS_E_*`).
            /// The access errors keep their CANopen SDO abort codes (CiA 301,
            /// as in docs/objects.md); the library's own codes are
            /// `0xADD0_00xx`, outside every CANopen range.
            pub enum ErrorCode: u32 {
                $( $(#[doc = $adoc])+ $a = AccessError::$a.code(), )+
                $( $(#[doc = $odoc])+ $o = $code, )+
            }
        }

        impl ErrorCode {
            /// What the code means, in the words of its documentation
            /// (one line of text per line of it).
            pub const fn meaning(self) -> &'static str {
                match self {
                    $( Self::$a => concat!($($adoc, "\n"),+), )+
                    $( Self::$o => concat!($($odoc, "\n"),+), )+
                }
            }
        }

        impl From<AccessError> for ErrorCode {
            fn from(e: AccessError) -> Self {
                match e {
                    $( AccessError::$a => Self::$a, )+
                }
            }
        }
    };
}

error_codes! {
    access {
        /// Bus, device or index does not exist.
        NoObject,
        /// The index exists but the subindex does not.
        NoSubindex,
        /// The object cannot be read.
        WriteOnly,
        /// The object cannot be written.
        ReadOnly,
        /// The value type differs from the object's: an i32 object read with
        /// `uoi_read_double`, a double written with `uoi_write_int`, ...
        TypeMismatch,
        /// A value outside the object's range, a non-finite double, a coordinate
        /// beyond ±1e9, a feed too slow.
        Range,
        /// Refused in the current state (a faulted group, ...).
        State,
        /// No room: the spooler is full; run `tc_exec` and send it again.
        Full,
        /// The value could not be stored: nothing changed.
        Storage,
    }
    own {
        /// The handle was initialised before a Clean (Clean written 1), which
        /// rejects every TC object, or was released: initialise it again with
        /// `uoi_init`.
        StaleHandle = 0xADD0_0001,
        /// The null handle 0 was given.
        NullHandle = 0xADD0_0002,
        /// A NULL pointer, an axis or mask bit out of range, a bad target or
        /// path text.
        Argument = 0xADD0_0003,
        /// The connection is closed (or was never opened); a server target
        /// that refused the connection, went away or cannot be reached within
        /// 5 s (the next call connects again).
        Connection = 0xADD0_0004,
        /// The target cannot be opened by this version of the library
        /// (reserved: every target form of docs/host-api.md opens).
        NotSupported = 0xADD0_0005,
        /// `tc_exec` waited longer than the connection's timeout (30 s unless
        /// `addipos_set_timeout` says otherwise), or a server target did not
        /// answer a request within it; what ran stays run.
        Timeout = 0xADD0_0006,
        /// The handle was not issued by this connection.
        BadHandle = 0xADD0_0007,
        /// All 65535 handles of the connection are in use: release some with
        /// `uoi_clean_handle`.
        TooManyHandles = 0xADD0_0008,
        /// A recording could not be started (the file cannot be created, or the
        /// connection has carried out requests already).
        Record = 0xADD0_0009,
        /// A server target refused a request as malformed, or answered what
        /// the library cannot read (not an `addipos serve` of this version).
        Protocol = 0xADD0_000A,
        /// The server stopped the request before its end (`tc_exec` while
        /// `addipos serve` shuts down): the motion did not run to its end; what
        /// ran up to there stays run.
        Stopped = 0xADD0_000B,
        /// A fault inside the library; the connection may be in an unknown
        /// state: close it.
        Internal = 0xADD0_00FF,
    }
}

impl ErrorCode {
    /// The access error this code stands for, if it is one.
    pub fn access_error(self) -> Option<AccessError> {
        AccessError::from_code(self.code())
    }
}

/// A failed call: its code and what happened, in words (what a C program
/// gets from `addipos_error_text`).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct Error {
    code: ErrorCode,
    message: String,
}

impl Error {
    /// A failure with code `code`, explained by `message`.
    pub fn new(code: ErrorCode, message: impl Into<String>) -> Self {
        Self {
            code,
            message: message.into(),
        }
    }

    /// An access error of the object interface, in the words of `what`
    /// (the call and the object).
    pub fn access(e: AccessError, what: impl std::fmt::Display) -> Self {
        Self::new(e.into(), format!("{what}: {e}"))
    }

    /// A bad argument.
    pub fn argument(message: impl Into<String>) -> Self {
        Self::new(ErrorCode::Argument, message)
    }

    /// The code.
    pub fn code(&self) -> ErrorCode {
        self.code
    }

    /// What happened, in words.
    pub fn message(&self) -> &str {
        &self.message
    }
}

/// What a call returns.
pub type Result<T> = std::result::Result<T, Error>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn access_errors_keep_their_canopen_codes_and_names() {
        for &e in AccessError::ALL {
            let code = ErrorCode::from(e);
            assert_eq!(code.code(), e.code());
            assert_eq!(code.name(), e.name());
            assert_eq!(code.access_error(), Some(e));
        }
    }

    #[test]
    fn the_library_codes_lie_outside_the_canopen_range() {
        let own: Vec<ErrorCode> = ErrorCode::ALL
            .iter()
            .copied()
            .filter(|c| c.access_error().is_none())
            .collect();
        assert_eq!(own.len(), ErrorCode::ALL.len() - AccessError::ALL.len());
        for c in own {
            assert_eq!(c.code() >> 16, 0xADD0, "{c:?}");
        }
    }
}
