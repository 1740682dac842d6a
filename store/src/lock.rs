//! The lock on a data directory's tool folder: a server holds it while it
//! serves; `tools import` takes it too, so the two never write at once.

use std::fs::{File, OpenOptions, TryLockError};
use std::io;
use std::path::{Path, PathBuf};

/// The folder of the tool files inside a data directory.
pub const TOOLS_DIR: &str = "tools";

/// The lock file inside the tool folder.
pub const LOCK_FILE: &str = ".lock";

/// The tool folder of the data directory `data_dir`.
pub fn tools_dir(data_dir: &Path) -> PathBuf {
    data_dir.join(TOOLS_DIR)
}

/// Why the lock was not taken.
#[derive(Debug, thiserror::Error)]
pub enum LockError {
    /// Another process (a running server, another import) holds it.
    #[error(
        "{0} is locked: a server (or another import) is using this data directory; \
         stop it first, or change the values over the bus"
    )]
    Busy(PathBuf),
    /// The lock file could not be opened or locked.
    #[error("cannot lock {0}: {1}")]
    Io(PathBuf, io::Error),
}

/// Takes the exclusive lock of the tool folder `dir` (which must exist)
/// without waiting; it is held until the returned file is dropped.
///
/// The lock is the operating system's advisory file lock (`flock` on
/// Unix): it goes away with the process that holds it, even on a crash,
/// so a stale lock file never blocks anyone.
pub fn lock_exclusive(dir: &Path) -> Result<File, LockError> {
    let path = dir.join(LOCK_FILE);
    let file = OpenOptions::new()
        .create(true)
        .write(true)
        .truncate(false)
        .open(&path)
        .map_err(|e| LockError::Io(path.clone(), e))?;
    match file.try_lock() {
        Ok(()) => Ok(file),
        Err(TryLockError::WouldBlock) => Err(LockError::Busy(path)),
        Err(TryLockError::Error(e)) => Err(LockError::Io(path, e)),
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn second_lock_is_refused_until_the_first_is_dropped() {
        let dir = std::env::temp_dir().join(format!("addipos-lock-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let held = lock_exclusive(&dir).unwrap();
        assert!(matches!(lock_exclusive(&dir), Err(LockError::Busy(_))));
        drop(held);
        assert!(lock_exclusive(&dir).is_ok());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
