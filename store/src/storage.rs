//! The storage trait: the only way the store reaches the disk.
//!
//! A store keeps its files in one directory: one tool file per group and
//! the journal. [`FsStorage`] is the real one on `std::fs`;
//! [`MemStorage`] keeps everything in memory and [`FaultyStorage`] wraps
//! another storage and makes chosen calls fail, for tests.

mod contract;
mod faulty;
mod fs;
mod memory;

pub use contract::{group_file_name, Storage, JOURNAL_FILE};
pub use faulty::{FaultKind, FaultyStorage, Op};
pub use fs::FsStorage;
pub use memory::MemStorage;
