//! Tool data that survives (docs/tool-files.md): the emulator's tool
//! entries as the tool store's records, durable-before-acknowledged writes
//! through the store's journal writer, and opening a data directory's
//! tool data for a served emulator.

pub mod durable;
pub mod entries;
pub mod open;
