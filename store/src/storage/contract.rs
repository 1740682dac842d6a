//! The contract every storage keeps: the [`Storage`] trait, the journal's
//! name and the temporary files a replacement writes. The storages beside
//! this module implement it; it imports none of them.

use std::io;

/// The journal's file name inside the store's directory.
pub const JOURNAL_FILE: &str = "journal.wzj";

/// Durable storage of tool files and the journal.
///
/// The store calls these in a fixed pattern: append, then sync, then a
/// look whether the journal is still in place, before a change counts;
/// after a failed append or sync it truncates the journal back to its
/// length before the call.
pub trait Storage {
    /// The whole content of the file `name`, `None` if it does not exist.
    fn read_file(&mut self, name: &str) -> io::Result<Option<Vec<u8>>>;

    /// Replaces the file `name` atomically and durably: a reader (after a
    /// crash, too) sees either the old or the new content. On disk: write
    /// a temporary file, fsync it, rename it over `name`, fsync the
    /// directory.
    fn write_file_atomic(&mut self, name: &str, bytes: &[u8]) -> io::Result<()>;

    /// The journal's content, empty if there is none.
    fn read_journal(&mut self) -> io::Result<Vec<u8>>;

    /// Appends `bytes` at the journal's end (not yet durable).
    fn append_journal(&mut self, bytes: &[u8]) -> io::Result<()>;

    /// Makes every appended byte durable (fdatasync; the directory too if
    /// the journal was just created).
    fn sync_journal(&mut self) -> io::Result<()>;

    /// Cuts the journal to `len` bytes and makes that durable.
    fn truncate_journal(&mut self, len: u64) -> io::Result<()>;

    /// Whether the journal this storage appends to is still the file its
    /// name leads to: not deleted, not replaced by another file (on disk:
    /// the open file's device and inode are those of the path, and it
    /// still has a link). If not, the storage lets go of it: the next
    /// append creates the journal anew under its name, and appends made
    /// since it went are lost with it.
    fn journal_in_place(&mut self) -> io::Result<bool>;

    /// Bytes free for the files on their volume (what an unprivileged
    /// writer may still use); `None` where that cannot be known.
    fn available_space(&mut self) -> io::Result<Option<u64>>;

    /// Removes the temporary files a replacement cut short left behind
    /// (`group01.wz.tmp` after a crash or a full disk in
    /// [`write_file_atomic`](Self::write_file_atomic)); returns their names.
    fn remove_temporaries(&mut self) -> io::Result<Vec<String>>;
}

/// The tool file name of a group: `group01.wz` .. `group32.wz`.
pub fn group_file_name(group: u8) -> String {
    format!("group{group:02}.wz")
}

/// The temporary file [`Storage::write_file_atomic`] writes `name` into
/// before renaming it.
pub fn temporary_name(name: &str) -> String {
    format!("{name}.tmp")
}

/// Whether `name` is the temporary file of a tool file
/// (`group01.wz.tmp` .. `group32.wz.tmp`): what
/// [`Storage::remove_temporaries`] removes, and nothing else.
pub fn is_temporary(name: &str) -> bool {
    let Some(digits) = name
        .strip_prefix("group")
        .and_then(|n| n.strip_suffix(".wz.tmp"))
    else {
        return false;
    };
    digits.len() == 2 && digits.bytes().all(|b| b.is_ascii_digit())
}

impl<S: Storage + ?Sized> Storage for Box<S> {
    fn read_file(&mut self, name: &str) -> io::Result<Option<Vec<u8>>> {
        (**self).read_file(name)
    }
    fn write_file_atomic(&mut self, name: &str, bytes: &[u8]) -> io::Result<()> {
        (**self).write_file_atomic(name, bytes)
    }
    fn read_journal(&mut self) -> io::Result<Vec<u8>> {
        (**self).read_journal()
    }
    fn append_journal(&mut self, bytes: &[u8]) -> io::Result<()> {
        (**self).append_journal(bytes)
    }
    fn sync_journal(&mut self) -> io::Result<()> {
        (**self).sync_journal()
    }
    fn truncate_journal(&mut self, len: u64) -> io::Result<()> {
        (**self).truncate_journal(len)
    }
    fn journal_in_place(&mut self) -> io::Result<bool> {
        (**self).journal_in_place()
    }
    fn available_space(&mut self) -> io::Result<Option<u64>> {
        (**self).available_space()
    }
    fn remove_temporaries(&mut self) -> io::Result<Vec<String>> {
        (**self).remove_temporaries()
    }
}
