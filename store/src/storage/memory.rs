//! Storage in memory, for tests and throw-away stores.

use super::Storage;
use std::collections::BTreeMap;
use std::io;

/// Tool files and journal held in memory; every call succeeds.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct MemStorage {
    files: BTreeMap<String, Vec<u8>>,
    journal: Vec<u8>,
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
        self.journal.extend_from_slice(bytes);
        Ok(())
    }

    fn sync_journal(&mut self) -> io::Result<()> {
        Ok(())
    }

    fn truncate_journal(&mut self, len: u64) -> io::Result<()> {
        self.journal
            .truncate(usize::try_from(len).unwrap_or(usize::MAX));
        Ok(())
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
}
