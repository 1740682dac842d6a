//! The real storage: a directory on the local file system.

use super::contract::{is_temporary, temporary_name, Storage, JOURNAL_FILE};
use std::fs::{self, File, OpenOptions};
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};

/// Tool files and journal in one directory, created on the first write.
///
/// Every change of the directory's entries is made durable with an fsync
/// of the directory: after a tool file is renamed into place, after
/// leftover temporary files are removed, after the journal is created
/// (at its first sync), after the directory itself is created (its
/// parent).
#[derive(Debug)]
pub struct FsStorage {
    dir: PathBuf,
    journal: Option<File>,
    /// The journal or directory was just created: the next sync also
    /// syncs the directory so the new entry survives a power cut.
    dir_dirty: bool,
    /// The file-system calls made, in order (tests check the order).
    #[cfg(test)]
    calls: Vec<FsCall>,
}

/// A file-system call of [`FsStorage`] that makes something durable or
/// changes the directory, as the tests see them.
#[derive(Debug, Clone, PartialEq, Eq)]
enum FsCall {
    /// fsync of a file (by name).
    SyncFile(String),
    /// A rename (from, to).
    Rename(String, String),
    /// A file removed.
    Remove(String),
    /// The journal opened with create, where it did not exist.
    CreateJournal,
    /// fdatasync of the journal.
    SyncJournal,
    /// fsync of a directory (its path).
    SyncDir(PathBuf),
}

impl FsStorage {
    /// Storage in `dir` (need not exist yet).
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        Self {
            dir: dir.into(),
            journal: None,
            dir_dirty: false,
            #[cfg(test)]
            calls: Vec::new(),
        }
    }

    /// Notes a call (kept in tests only).
    #[cfg(test)]
    fn note(&mut self, call: impl FnOnce() -> FsCall) {
        self.calls.push(call());
    }

    /// Notes a call (kept in tests only).
    #[cfg(not(test))]
    fn note(&mut self, _: impl FnOnce() -> FsCall) {}

    /// fsync of a directory: makes its entries (creations, renames,
    /// removals) durable.
    fn sync_dir(&mut self, dir: &Path) -> io::Result<()> {
        self.note(|| FsCall::SyncDir(dir.to_path_buf()));
        File::open(dir)?.sync_all()
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
            let parent = parent.to_path_buf();
            self.sync_dir(&parent)?;
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
                if !path.exists() {
                    self.dir_dirty = true;
                    self.note(|| FsCall::CreateJournal);
                }
                OpenOptions::new().create(true).append(true).open(path)?
            }
        };
        Ok(self.journal.insert(file))
    }
}

/// The file may be read but not written.
fn read_only(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::PermissionDenied | io::ErrorKind::ReadOnlyFilesystem
    )
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
        let tmp_name = temporary_name(name);
        let tmp = self.dir.join(&tmp_name);
        self.note(|| FsCall::SyncFile(tmp_name.clone()));
        self.note(|| FsCall::Rename(tmp_name.clone(), name.to_owned()));
        let replaced = File::create(&tmp)
            .and_then(|mut file| {
                file.write_all(bytes)?;
                file.sync_all()
            })
            .and_then(|()| fs::rename(&tmp, self.dir.join(name)));
        if let Err(e) = replaced {
            // A full disk must not keep the half file: it holds room.
            let _ = fs::remove_file(&tmp);
            return Err(e);
        }
        let dir = self.dir.clone();
        self.sync_dir(&dir)
    }

    /// Reads the journal through the file later appends go to, so that a
    /// deletion from now on is seen ([`Storage::journal_in_place`]) even
    /// before the first append. Where the journal may not be written
    /// (a read-only folder), it is only read.
    fn read_journal(&mut self) -> io::Result<Vec<u8>> {
        let path = self.dir.join(JOURNAL_FILE);
        let mut file = match OpenOptions::new().read(true).append(true).open(&path) {
            Ok(file) => file,
            Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
            Err(e) if read_only(&e) => return Ok(read_optional(&path)?.unwrap_or_default()),
            Err(e) => return Err(e),
        };
        let mut bytes = Vec::new();
        file.read_to_end(&mut bytes)?;
        self.journal = Some(file);
        Ok(bytes)
    }

    fn append_journal(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.journal()?.write_all(bytes)
    }

    fn sync_journal(&mut self) -> io::Result<()> {
        self.journal()?.sync_data()?;
        self.note(|| FsCall::SyncJournal);
        if self.dir_dirty {
            let dir = self.dir.clone();
            self.sync_dir(&dir)?;
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

    fn journal_in_place(&mut self) -> io::Result<bool> {
        let Some(file) = &self.journal else {
            // Nothing open: the next append opens what the name leads to.
            return Ok(true);
        };
        let open = file.metadata()?;
        let named = match fs::metadata(self.dir.join(JOURNAL_FILE)) {
            Ok(m) => Some(m),
            Err(e) if e.kind() == io::ErrorKind::NotFound => None,
            Err(e) => return Err(e),
        };
        let in_place = named.is_some_and(|named| same_file(&open, &named));
        if !in_place {
            self.journal = None;
        }
        Ok(in_place)
    }

    fn available_space(&mut self) -> io::Result<Option<u64>> {
        free_space(&self.dir)
    }

    fn remove_temporaries(&mut self) -> io::Result<Vec<String>> {
        let entries = match fs::read_dir(&self.dir) {
            Ok(entries) => entries,
            Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
            Err(e) => return Err(e),
        };
        let mut removed = Vec::new();
        for entry in entries {
            let name = entry?.file_name().to_string_lossy().into_owned();
            if is_temporary(&name) && fs::remove_file(self.dir.join(&name)).is_ok() {
                self.note(|| FsCall::Remove(name.clone()));
                removed.push(name);
            }
        }
        if !removed.is_empty() {
            // The removals stay removed after a power cut.
            let dir = self.dir.clone();
            self.sync_dir(&dir)?;
        }
        removed.sort();
        Ok(removed)
    }
}

/// Bytes an unprivileged writer may still use on the volume of `dir`
/// (statvfs: available blocks times the fragment size); `None` before the
/// folder exists.
#[cfg(unix)]
fn free_space(dir: &Path) -> io::Result<Option<u64>> {
    match rustix::fs::statvfs(dir) {
        Ok(st) => Ok(Some(st.f_bavail.saturating_mul(st.f_frsize))),
        Err(rustix::io::Errno::NOENT) => Ok(None),
        Err(e) => Err(e.into()),
    }
}

/// Unknown without statvfs.
#[cfg(not(unix))]
fn free_space(_dir: &Path) -> io::Result<Option<u64>> {
    Ok(None)
}

/// Whether the open file `open` is the file `named` (the metadata of a
/// path) and still has a name.
#[cfg(unix)]
fn same_file(open: &fs::Metadata, named: &fs::Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    open.nlink() > 0 && open.dev() == named.dev() && open.ino() == named.ino()
}

/// Without device and inode numbers, only a deletion is seen: the name
/// leads to a file at all.
#[cfg(not(unix))]
fn same_file(_open: &fs::Metadata, _named: &fs::Metadata) -> bool {
    true
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

    #[test]
    fn a_deleted_or_replaced_journal_is_not_in_place_and_is_created_anew() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = FsStorage::new(dir.path());
        assert!(s.journal_in_place().unwrap(), "nothing open yet");
        s.append_journal(b"one\n").unwrap();
        s.sync_journal().unwrap();
        assert!(s.journal_in_place().unwrap());
        let path = dir.path().join(JOURNAL_FILE);
        fs::remove_file(&path).unwrap();
        assert!(!s.journal_in_place().unwrap(), "deleted");
        s.append_journal(b"two\n").unwrap();
        s.sync_journal().unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"two\n", "created anew");
        // Replaced by another file under the same name.
        fs::write(dir.path().join("other"), b"x\n").unwrap();
        fs::rename(dir.path().join("other"), &path).unwrap();
        assert!(!s.journal_in_place().unwrap(), "replaced");
        s.append_journal(b"three\n").unwrap();
        s.sync_journal().unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"x\nthree\n");
        assert!(s.journal_in_place().unwrap());
    }

    /// A journal deleted after it was read but before
    /// the first append held records; the storage must see it is gone.
    #[test]
    fn a_journal_deleted_after_reading_is_not_in_place() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(JOURNAL_FILE);
        fs::write(&path, b"old\n").unwrap();
        let mut s = FsStorage::new(dir.path());
        assert_eq!(s.read_journal().unwrap(), b"old\n");
        fs::remove_file(&path).unwrap();
        s.append_journal(b"new\n").unwrap();
        s.sync_journal().unwrap();
        assert!(!s.journal_in_place().unwrap());
    }

    #[test]
    fn free_space_is_known_once_the_folder_exists() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = FsStorage::new(dir.path().join("tools"));
        assert_eq!(s.available_space().unwrap(), None);
        fs::create_dir(s.dir()).unwrap();
        let free = s.available_space().unwrap();
        assert!(cfg!(not(unix)) || free.is_some_and(|f| f > 0), "{free:?}");
    }

    /// Every change of the directory's entries is followed by an fsync
    /// of the directory; a file is synced before it is renamed into place.
    #[test]
    fn creations_renames_and_removals_are_made_durable_in_the_directory() {
        let dir = tempfile::tempdir().unwrap();
        let tools = dir.path().join("tools");
        let mut s = FsStorage::new(&tools);
        s.write_file_atomic("group01.wz", b"one\n").unwrap();
        let tmp = "group01.wz.tmp".to_string();
        assert_eq!(
            s.calls,
            [
                FsCall::SyncDir(dir.path().to_path_buf()),
                FsCall::SyncFile(tmp.clone()),
                FsCall::Rename(tmp, "group01.wz".into()),
                FsCall::SyncDir(tools.clone()),
            ],
            "the folder's creation, then the file synced, renamed, the folder synced"
        );
        s.calls.clear();
        s.append_journal(b"a\n").unwrap();
        s.sync_journal().unwrap();
        s.append_journal(b"b\n").unwrap();
        s.sync_journal().unwrap();
        assert_eq!(
            s.calls,
            [
                FsCall::CreateJournal,
                FsCall::SyncJournal,
                FsCall::SyncDir(tools.clone()),
                FsCall::SyncJournal,
            ],
            "a new journal's entry is synced once, at its first sync"
        );
        s.calls.clear();
        fs::remove_file(tools.join(JOURNAL_FILE)).unwrap();
        assert!(!s.journal_in_place().unwrap());
        s.append_journal(b"c\n").unwrap();
        s.sync_journal().unwrap();
        assert_eq!(
            s.calls,
            [
                FsCall::CreateJournal,
                FsCall::SyncJournal,
                FsCall::SyncDir(tools.clone()),
            ],
            "a journal made anew too"
        );
        s.calls.clear();
        fs::write(tools.join("group02.wz.tmp"), b"half").unwrap();
        assert_eq!(s.remove_temporaries().unwrap(), ["group02.wz.tmp"]);
        assert_eq!(
            s.calls,
            [
                FsCall::Remove("group02.wz.tmp".into()),
                FsCall::SyncDir(tools.clone()),
            ],
            "a removal, then the folder synced"
        );
    }

    #[test]
    fn leftover_temporaries_are_removed_and_nothing_else() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = FsStorage::new(dir.path().join("tools"));
        assert_eq!(s.remove_temporaries().unwrap(), Vec::<String>::new());
        fs::create_dir_all(s.dir()).unwrap();
        for name in [
            "group01.wz.tmp",
            "group32.wz.tmp",
            "notes.tmp",
            "group01.wz",
        ] {
            fs::write(s.dir().join(name), b"").unwrap();
        }
        assert_eq!(
            s.remove_temporaries().unwrap(),
            ["group01.wz.tmp", "group32.wz.tmp"]
        );
        let mut left: Vec<_> = fs::read_dir(s.dir())
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        left.sort();
        assert_eq!(left, ["group01.wz", "notes.tmp"]);
    }
}
