//! The OPC UA status of every refusal of the object server: an access
//! error of the table (one match, so a new access error cannot go
//! unmapped), or the object server's own protocol error.

use opcua::types::StatusCode;
use uoi::wire::ProtocolError;
use uoi::AccessError;

/// The status an OPC UA client gets for `error`.
pub fn access_status(error: AccessError) -> StatusCode {
    match error {
        // Also a non-finite double: outside every range.
        AccessError::Range => StatusCode::BadOutOfRange,
        AccessError::ReadOnly => StatusCode::BadNotWritable,
        AccessError::WriteOnly => StatusCode::BadNotReadable,
        AccessError::TypeMismatch => StatusCode::BadTypeMismatch,
        AccessError::NoObject | AccessError::NoSubindex => StatusCode::BadNodeIdUnknown,
        AccessError::State => StatusCode::BadInvalidState,
        // No room now (the spooler is full): a resource to wait for.
        AccessError::Full => StatusCode::BadResourceUnavailable,
        // The disk refused the value; nothing changed.
        AccessError::Storage => StatusCode::BadDeviceFailure,
    }
}

/// The status of a request the object server did not serve at all.
pub fn protocol_status(error: ProtocolError) -> StatusCode {
    match error {
        // The server is stopping (its owner task is gone).
        ProtocolError::Busy => StatusCode::BadServerHalted,
        _ => StatusCode::BadInternalError,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_access_error_has_a_bad_status_of_its_own_kind() {
        for &e in AccessError::ALL {
            assert!(access_status(e).is_bad(), "{e:?}");
        }
        let expected = [
            (AccessError::Range, StatusCode::BadOutOfRange),
            (AccessError::ReadOnly, StatusCode::BadNotWritable),
            (AccessError::WriteOnly, StatusCode::BadNotReadable),
            (AccessError::TypeMismatch, StatusCode::BadTypeMismatch),
            (AccessError::NoObject, StatusCode::BadNodeIdUnknown),
            (AccessError::NoSubindex, StatusCode::BadNodeIdUnknown),
            (AccessError::State, StatusCode::BadInvalidState),
            (AccessError::Full, StatusCode::BadResourceUnavailable),
            (AccessError::Storage, StatusCode::BadDeviceFailure),
        ];
        for (e, status) in expected {
            assert_eq!(access_status(e), status, "{e:?}");
        }
    }
}
