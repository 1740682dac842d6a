//! Durable tool data of the TC emulator.
//!
//! One tool file per compensation group in the `wz[i].field value` style
//! of the controller manuals, plus an append-only journal of changes with
//! a checksum per record. [`ToolStore`] loads the files, replays the
//! journal, appends durably and compacts the journal back into the files.
//! Only the [`Storage`] trait touches the disk, so tests can inject faults.
//! The format is described for users in `docs/tool-files.md`.
//!
//! For a server it also holds the tool folder's lock ([`lock_exclusive`]), opening a
//! data directory's tool data ([`open_tools`]) and the journal's one
//! writer thread with group commit ([`Writer`]): this crate is the only
//! one that touches tool files.

mod decimal;
mod field;
mod file;
mod journal;
mod lock;
mod open;
mod replay;
mod storage;
mod store;
mod table;
mod writer;

pub use field::{FileField, ToolField, ToolValue, ValueError};
pub use file::{
    parse_group_file, parse_group_file_lenient, write_group_file, LineError, ParseError,
};
pub use journal::{JournalError, Record, RecordError, Replay, TornTail};
pub use lock::{lock_exclusive, tools_dir, LockError, LOCK_FILE, TOOLS_DIR};
pub use open::{open_tools, OpenError, OpenTools};
pub use replay::replay as replay_journal;
pub use storage::{FaultKind, FaultyStorage, FsStorage, MemStorage, Op, Storage, JOURNAL_FILE};
pub use store::{
    group_file_name, CompactionBound, OpenReport, StoreError, Strictness, ToolStore, FIRST_PAUSE,
    LONGEST_PAUSE,
};
pub use table::{GroupTable, ToolKey, GROUPS, TOOL_ENTRIES};
pub use writer::{Done, DurableLog, Writer, MAX_BATCH, QUEUE};
