//! Tool data that survives (issue 10): the emulator's tool entries mapped
//! to the tool store's records, and the writer that makes them durable
//! before a write is answered.

pub mod durable;
pub mod entries;
pub mod lock;
pub mod open;
pub mod writer;
