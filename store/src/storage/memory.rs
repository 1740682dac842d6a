//! Storage in memory, for tests and throw-away stores.

use super::contract::{is_temporary, Storage};
use std::collections::BTreeMap;
use std::io;

/// Tool files and journal held in memory; every call succeeds.
///
/// The journal can be deleted or replaced under the store, as a user can
/// do on disk: the store keeps appending to the file it has open (the
/// `orphan`) until it notices ([`Storage::journal_in_place`]).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct MemStorage {
    files: BTreeMap<String, Vec<u8>>,
    /// The journal under its name: what a restart reads.
    journal: Vec<u8>,
    /// The journal the store still appends to after its name went.
    orphan: Option<Vec<u8>>,
}

impl MemStorage {
    /// Empty storage.
    pub fn new() -> Self {
        Self::default()
    }

    /// The content of the file `name`, if written.
    pub fn file(&self, name: &str) -> Option<&[u8]> {
        self.files.get(name).map(Vec::as_slice)
    }

    /// Puts a file in place (as if a user had written it).
    pub fn put_file(&mut self, name: &str, bytes: impl Into<Vec<u8>>) {
        self.files.insert(name.to_owned(), bytes.into());
    }

    /// The journal's bytes.
    pub fn journal(&self) -> &[u8] {
        &self.journal
    }

    /// The journal's bytes, to damage them in a test.
    pub fn journal_mut(&mut self) -> &mut Vec<u8> {
        &mut self.journal
    }

    /// Deletes the journal under the store (`rm journal.wzj`): its name
    /// leads to nothing, the store's appends go to the deleted file.
    pub fn delete_journal(&mut self) {
        self.replace_journal(Vec::new());
    }

    /// Puts `bytes` under the journal's name as a new file (`mv other
    /// journal.wzj`); the store's appends go to the file it replaced.
    pub fn replace_journal(&mut self, bytes: impl Into<Vec<u8>>) {
        let old = std::mem::replace(&mut self.journal, bytes.into());
        self.orphan.get_or_insert(old);
    }

    /// The journal the store appends to.
    fn open_journal(&mut self) -> &mut Vec<u8> {
        self.orphan.as_mut().unwrap_or(&mut self.journal)
    }
}

impl Storage for MemStorage {
    fn read_file(&mut self, name: &str) -> io::Result<Option<Vec<u8>>> {
        Ok(self.files.get(name).cloned())
    }

    fn write_file_atomic(&mut self, name: &str, bytes: &[u8]) -> io::Result<()> {
        self.put_file(name, bytes);
        Ok(())
    }

    fn read_journal(&mut self) -> io::Result<Vec<u8>> {
        Ok(self.journal.clone())
    }

    fn append_journal(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.open_journal().extend_from_slice(bytes);
        Ok(())
    }

    fn sync_journal(&mut self) -> io::Result<()> {
        Ok(())
    }

    fn truncate_journal(&mut self, len: u64) -> io::Result<()> {
        self.open_journal()
            .truncate(usize::try_from(len).unwrap_or(usize::MAX));
        Ok(())
    }

    fn journal_in_place(&mut self) -> io::Result<bool> {
        Ok(self.orphan.take().is_none())
    }

    /// Memory has no volume to run full.
    fn available_space(&mut self) -> io::Result<Option<u64>> {
        Ok(None)
    }

    fn remove_temporaries(&mut self) -> io::Result<Vec<String>> {
        let names: Vec<String> = self
            .files
            .keys()
            .filter(|n| is_temporary(n))
            .cloned()
            .collect();
        names.iter().for_each(|n| {
            self.files.remove(n);
        });
        Ok(names)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holds_files_and_journal() {
        let mut s = MemStorage::new();
        s.write_file_atomic("a", b"1").unwrap();
        assert_eq!(s.read_file("a").unwrap(), Some(b"1".to_vec()));
        assert_eq!(s.read_file("b").unwrap(), None);
        s.append_journal(b"xy").unwrap();
        s.append_journal(b"z").unwrap();
        s.truncate_journal(2).unwrap();
        assert_eq!(s.read_journal().unwrap(), b"xy");
    }

    #[test]
    fn a_deleted_journal_keeps_taking_appends_until_noticed() {
        let mut s = MemStorage::new();
        s.append_journal(b"a\n").unwrap();
        s.delete_journal();
        s.append_journal(b"b\n").unwrap();
        assert_eq!(s.read_journal().unwrap(), b"", "the name leads nowhere");
        assert!(!s.journal_in_place().unwrap());
        assert!(s.journal_in_place().unwrap(), "noticed once");
        s.append_journal(b"c\n").unwrap();
        assert_eq!(s.journal(), b"c\n");
        s.replace_journal(&b"x\n"[..]);
        s.append_journal(b"d\n").unwrap();
        assert_eq!(s.journal(), b"x\n");
        assert!(!s.journal_in_place().unwrap());
    }
}
