//! Tool data that survives, for a served emulator: the tool data of a
//! data directory opened and locked by the tool store, its values loaded
//! into the emulator, and the journal's writer started so every later
//! tool write is durable before it is answered. What serves the emulator
//! takes the persistence ([`EmulatorService::open_tools`]); this module
//! knows nothing of it (the crate's modules import one way).
//!
//! [`EmulatorService::open_tools`]: crate::EmulatorService::open_tools

use std::fs::File;
use std::path::Path;

use tool_store::{FsStorage, ToolStore, Writer};

use super::durable::Durable;
use super::entries::load;
use crate::Emulator;

/// Why the tool data of a data directory could not be opened.
#[derive(Debug, thiserror::Error)]
pub enum OpenToolsError {
    /// A tool file or journal record is bad, or the folder is locked or
    /// unreadable: the tool store's message, naming the file and line.
    #[error("{0}")]
    Store(#[source] tool_store::OpenError),
    /// The journal's writer thread did not start.
    #[error("cannot start the tool writer: {0}")]
    Writer(#[source] std::io::Error),
}

/// Tool data opened: the folder's lock, to hold while serving, and the
/// persistence every later tool write goes through.
#[derive(Debug)]
pub struct OpenedTools {
    /// The lock of the data directory.
    pub lock: File,
    /// Durable tool writes through the journal's writer.
    pub durable: Durable<ToolStore<FsStorage>>,
}

/// Opens the tool data in `data_dir` for `emu`: locks the folder, loads
/// it into the emulator and starts the journal's writer.
pub fn open_durable(
    emu: &mut Emulator,
    data_dir: &Path,
    ignore_bad: bool,
) -> Result<OpenedTools, OpenToolsError> {
    let open = tool_store::open_tools(data_dir, ignore_bad).map_err(OpenToolsError::Store)?;
    load(emu.tc_mut(), open.store.values());
    let writer = Writer::start(open.store).map_err(OpenToolsError::Writer)?;
    Ok(OpenedTools {
        lock: open.lock,
        durable: Durable::new(writer),
    })
}
