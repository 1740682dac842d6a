//! The ERROR and STATUS registers of a compensation group (docs/objects.md,
//! device 1 sub 1 and sub 3): their bits are part of the object vocabulary.

pub use tc_objects::{ErrorBits, StatusBits};
