//! The value a variable node holds in an address space, as it is stored:
//! no timestamps, no index range, the binary encoding.

use opcua::server::address_space::Variable;
use opcua::types::{DataEncoding, NumericRange, TimestampsToReturn, Variant};

/// What `v` holds now, `None` when it holds no value.
pub(crate) fn stored_value(v: &Variable) -> Option<Variant> {
    v.value(
        TimestampsToReturn::Neither,
        &NumericRange::None,
        &DataEncoding::Binary,
        0.0,
    )
    .value
}
