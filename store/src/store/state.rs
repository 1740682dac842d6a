//! The tool store's state: the struct every part of the store works on
//! (its methods are in the parent module, [`compaction`](super::compaction)
//! and [`upkeep`](super::upkeep)).

use super::bound::CompactionBound;
use super::pause::Upkeep;
use crate::table::GroupTable;
use std::collections::{BTreeMap, BTreeSet};

/// The durable tool values of every compensation group.
#[derive(Debug)]
pub struct ToolStore<S> {
    pub(super) storage: S,
    pub(super) groups: BTreeMap<u8, GroupTable>,
    /// Groups that have a tool file on disk, and its size in bytes.
    pub(super) files: BTreeMap<u8, u64>,
    /// Groups whose values changed since their file was written (or
    /// whose file has lines to drop): what compaction rewrites.
    pub(super) dirty: BTreeSet<u8>,
    pub(super) journal_len: u64,
    pub(super) journal_records: u64,
    pub(super) bound: CompactionBound,
    pub(super) poisoned: bool,
    /// The journal was deleted or replaced since the tool files were last
    /// all written: the next compaction rewrites every file.
    pub(super) lost: bool,
    /// Compaction attempts held back after failures; warnings limited.
    pub(super) upkeep: Upkeep,
}
