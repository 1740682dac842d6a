//! The ERROR and STATUS registers of a compensation group
//! (docs/objects.md "ERROR bits" and "STATUS bits": device 1 sub 1 and
//! sub 3).

pub use tc_objects::{ErrorBits, StatusBits};
