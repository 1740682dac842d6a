//! When the journal is compacted: its bound.

/// When the journal is compacted: at `bytes` or `records`
/// ([`ToolStore::needs_compaction`](crate::ToolStore::needs_compaction)), or once it holds `least` bytes while
/// the disk has less free than compaction needs plus `low_space`
/// ([`ToolStore::short_of_room`](crate::ToolStore::short_of_room)).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CompactionBound {
    /// Journal size in bytes, at most.
    pub bytes: u64,
    /// Journal records, at most.
    pub records: u64,
    /// Free bytes on the disk, beyond what compaction needs, below which
    /// the journal is compacted early.
    pub low_space: u64,
    /// The least journal, in bytes, compacted early for room: a smaller
    /// one would free too little to be worth rewriting the tool files.
    pub least: u64,
}

impl Default for CompactionBound {
    /// 4 MiB or 100,000 records; early once the journal holds 16 KiB and
    /// the disk has less than 64 KiB free beyond what compaction needs. On
    /// a 256 KB volume (512 values in 16 groups) the journal
    /// is compacted at about 127 KB instead of filling the volume.
    fn default() -> Self {
        Self {
            bytes: 4 << 20,
            records: 100_000,
            low_space: 64 << 10,
            least: 16 << 10,
        }
    }
}
