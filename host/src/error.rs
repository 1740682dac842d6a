//! What a call can fail with: the access errors of the object interface,
//! with their CANopen codes, and the library's own failures, with codes
//! of their own outside the CANopen range.

use uoi::AccessError;

uoi::code_list! {
    /// The number a failed call returns (the C ABI's `ADDIPOS_E_*`). The
    /// access errors keep their CANopen SDO abort codes (CiA 301, as in
    /// docs/objects.md); the library's own codes are `0xADD0_00xx`, outside
    /// every CANopen range.
    pub enum ErrorCode: u32 {
        /// Bus, device or index does not exist.
        NoObject = 0x0602_0000,
        /// The index exists but the subindex does not.
        NoSubindex = 0x0609_0011,
        /// The object cannot be read.
        WriteOnly = 0x0601_0001,
        /// The object cannot be written.
        ReadOnly = 0x0601_0002,
        /// The value type differs from the object's type (also: reading
        /// an i32 object as a double).
        TypeMismatch = 0x0607_0010,
        /// A value outside the object's range.
        Range = 0x0609_0030,
        /// Refused in the current state.
        State = 0x0800_0022,
        /// No room: the spooler is full.
        Full = 0x0504_0005,
        /// The value could not be stored: nothing changed.
        Storage = 0x0800_0020,
        /// The handle was issued before a Clean, or released: initialise
        /// it again.
        StaleHandle = 0xADD0_0001,
        /// The null handle 0.
        NullHandle = 0xADD0_0002,
        /// A NULL pointer, an axis or mask bit out of range, a bad text.
        Argument = 0xADD0_0003,
        /// The connection is closed, lost, timed out or refused.
        Connection = 0xADD0_0004,
        /// The target cannot be opened by this version of the library
        /// (reserved).
        NotSupported = 0xADD0_0005,
        /// A wait (`tc_exec`), or a server's answer, took longer than the
        /// connection's timeout; what ran stays run.
        Timeout = 0xADD0_0006,
        /// Not a handle of this connection.
        BadHandle = 0xADD0_0007,
        /// Every one of the connection's handles is in use.
        TooManyHandles = 0xADD0_0008,
        /// A recording could not be started.
        Record = 0xADD0_0009,
        /// The server refused a request as malformed, or answered what
        /// the library cannot read; the TCP connection is closed (the
        /// next call connects again).
        Protocol = 0xADD0_000A,
        /// The server stopped the request before its end (it is shutting
        /// down); what ran up to there stays run.
        Stopped = 0xADD0_000B,
        /// A fault inside the library (a caught panic); the connection
        /// may be in an unknown state.
        Internal = 0xADD0_00FF,
    }
}

impl From<AccessError> for ErrorCode {
    fn from(e: AccessError) -> Self {
        match e {
            AccessError::NoObject => ErrorCode::NoObject,
            AccessError::NoSubindex => ErrorCode::NoSubindex,
            AccessError::WriteOnly => ErrorCode::WriteOnly,
            AccessError::ReadOnly => ErrorCode::ReadOnly,
            AccessError::TypeMismatch => ErrorCode::TypeMismatch,
            AccessError::Range => ErrorCode::Range,
            AccessError::State => ErrorCode::State,
            AccessError::Full => ErrorCode::Full,
            AccessError::Storage => ErrorCode::Storage,
        }
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
