//! The real storage: a directory on the local file system.

use super::{Storage, JOURNAL_FILE};
use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// Tool files and journal in one directory, created on the first write.
#[derive(Debug)]
pub struct FsStorage {
    dir: PathBuf,
    journal: Option<File>,
    /// The journal or directory was just created: the next sync also
    /// syncs the directory so the new entry survives a power cut.
    dir_dirty: bool,
}

impl FsStorage {
    /// Storage in `dir` (need not exist yet).
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        Self {
            dir: dir.into(),
            journal: None,
            dir_dirty: false,
        }
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Creates the directory if needed, syncing its parent so it stays.
    fn ensure_dir(&mut self) -> io::Result<()> {
        if self.dir.is_dir() {
            return Ok(());
        }
        fs::create_dir_all(&self.dir)?;
        if let Some(parent) = self.dir.parent().filter(|p| !p.as_os_str().is_empty()) {
            sync_dir(parent)?;
        }
        Ok(())
    }

    /// The open journal, opened (and created) in append mode if needed.
    fn journal(&mut self) -> io::Result<&mut File> {
        let file = match self.journal.take() {
            Some(file) => file,
            None => {
                self.ensure_dir()?;
                let path = self.dir.join(JOURNAL_FILE);
                self.dir_dirty |= !path.exists();
                OpenOptions::new().create(true).append(true).open(path)?
            }
        };
        Ok(self.journal.insert(file))
    }
}

/// fsync of a directory: makes its entries (creations, renames) durable.
fn sync_dir(dir: &Path) -> io::Result<()> {
    File::open(dir)?.sync_all()
}

fn read_optional(path: &Path) -> io::Result<Option<Vec<u8>>> {
    match fs::read(path) {
        Ok(bytes) => Ok(Some(bytes)),
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(e),
    }
}

impl Storage for FsStorage {
    fn read_file(&mut self, name: &str) -> io::Result<Option<Vec<u8>>> {
        read_optional(&self.dir.join(name))
    }

    fn write_file_atomic(&mut self, name: &str, bytes: &[u8]) -> io::Result<()> {
        self.ensure_dir()?;
        let tmp = self.dir.join(format!("{name}.tmp"));
        let mut file = File::create(&tmp)?;
        file.write_all(bytes)?;
        file.sync_all()?;
        drop(file);
        fs::rename(&tmp, self.dir.join(name))?;
        sync_dir(&self.dir)
    }

    fn read_journal(&mut self) -> io::Result<Vec<u8>> {
        Ok(read_optional(&self.dir.join(JOURNAL_FILE))?.unwrap_or_default())
    }

    fn append_journal(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.journal()?.write_all(bytes)
    }

    fn sync_journal(&mut self) -> io::Result<()> {
        self.journal()?.sync_data()?;
        if self.dir_dirty {
            sync_dir(&self.dir)?;
            self.dir_dirty = false;
        }
        Ok(())
    }

    fn truncate_journal(&mut self, len: u64) -> io::Result<()> {
        if len == 0 && !self.dir.join(JOURNAL_FILE).exists() {
            return Ok(());
        }
        let file = self.journal()?;
        file.set_len(len)?;
        self.sync_journal()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn journal_appends_syncs_and_truncates() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = FsStorage::new(dir.path().join("tools"));
        assert_eq!(s.read_journal().unwrap(), b"");
        s.truncate_journal(0).unwrap();
        s.append_journal(b"abc\n").unwrap();
        s.append_journal(b"def\n").unwrap();
        s.sync_journal().unwrap();
        assert_eq!(s.read_journal().unwrap(), b"abc\ndef\n");
        s.truncate_journal(4).unwrap();
        s.append_journal(b"xyz\n").unwrap();
        s.sync_journal().unwrap();
        assert_eq!(
            FsStorage::new(s.dir()).read_journal().unwrap(),
            b"abc\nxyz\n"
        );
    }

    #[test]
    fn files_are_replaced_whole_and_missing_ones_read_as_none() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = FsStorage::new(dir.path().join("a/b"));
        assert_eq!(s.read_file("group01.wz").unwrap(), None);
        s.write_file_atomic("group01.wz", b"one\n").unwrap();
        s.write_file_atomic("group01.wz", b"two\n").unwrap();
        assert_eq!(s.read_file("group01.wz").unwrap(), Some(b"two\n".to_vec()));
        let names: Vec<_> = fs::read_dir(s.dir())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["group01.wz"]);
    }
}
