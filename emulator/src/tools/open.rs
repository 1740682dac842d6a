//! Tool data that survives, for a served emulator: the tool data of a
//! data directory opened and locked by the tool store, its values loaded
//! into the emulator, and the journal's writer started so every later
//! tool write is durable before it is answered.

use std::fs::File;
use std::path::Path;

use tool_store::Writer;

use super::durable::Durable;
use super::entries::load;
use crate::service::EmulatorService;

/// Opens the tool data in `data_dir` for `service`: locks the folder,
/// loads it into the emulator and makes every later tool write durable.
/// Returns the lock, to hold while serving. The error names the file and
/// the line of a bad tool file or journal record.
pub fn open_tools(
    service: &mut EmulatorService,
    data_dir: &Path,
    ignore_bad: bool,
) -> Result<File, String> {
    let open = tool_store::open_tools(data_dir, ignore_bad)?;
    load(service.emulator_mut().tc_mut(), open.store.values());
    let writer =
        Writer::start(open.store).map_err(|e| format!("cannot start the tool writer: {e}"))?;
    service.set_tools(Box::new(Durable::new(writer)));
    Ok(open.lock)
}
