//! # otc-ext — OTC online wear compensation for the TC module
//!
//! Devices 3 and 4 of bus 1300 (`shared/spec/otc.md`). Not implemented yet:
//! this crate only reserves its place in the dependency chain
//! `uoi` ← `tc-module` ← `otc-ext` ← `addipos`.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub use tc_module;
