//! `addipos objects`: the object reference of bus 1300 (Markdown), which
//! `docs/objects.md` is.

use super::Outcome;

/// Runs `addipos objects`.
pub fn cmd_objects() -> Outcome {
    print!("{}", emulator::object_reference());
    Ok(())
}
