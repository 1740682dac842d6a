//! A storage that fails on purpose: the n-th call of an operation fails,
//! or writes only part of its bytes.

use super::Storage;
use std::io;

/// An operation of [`Storage`] that can be made to fail.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Op {
    /// [`Storage::read_file`] and [`Storage::read_journal`].
    Read,
    /// [`Storage::write_file_atomic`].
    WriteFile,
    /// [`Storage::append_journal`].
    Append,
    /// [`Storage::sync_journal`].
    Sync,
    /// [`Storage::truncate_journal`].
    Truncate,
}

/// How a call fails.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FaultKind {
    /// The call does nothing and returns an error.
    Fail,
    /// Only the first `n` bytes are appended, then an error (a short
    /// write); for other operations the same as `Fail`.
    Short(usize),
}

#[derive(Debug, Clone, Copy)]
struct Fault {
    op: Op,
    call: usize,
    sticky: bool,
    kind: FaultKind,
}

/// Wraps a storage and fails chosen calls (counted from 1 per operation).
#[derive(Debug)]
pub struct FaultyStorage<S> {
    inner: S,
    faults: Vec<Fault>,
    calls: [usize; 5],
}

impl<S: Storage> FaultyStorage<S> {
    /// `inner` without faults yet.
    pub fn new(inner: S) -> Self {
        Self {
            inner,
            faults: Vec::new(),
            calls: [0; 5],
        }
    }

    /// The `call`-th call of `op` (from 1) fails as `kind`.
    pub fn fail_at(mut self, op: Op, call: usize, kind: FaultKind) -> Self {
        self.faults.push(Fault {
            op,
            call,
            sticky: false,
            kind,
        });
        self
    }

    /// The `call`-th call of `op` and every later one fail (a disk that
    /// broke for good).
    pub fn fail_from(mut self, op: Op, call: usize) -> Self {
        self.faults.push(Fault {
            op,
            call,
            sticky: true,
            kind: FaultKind::Fail,
        });
        self
    }

    /// How many times `op` was called.
    pub fn calls(&self, op: Op) -> usize {
        self.calls[op as usize]
    }

    /// The wrapped storage (what "the disk" holds).
    pub fn into_inner(self) -> S {
        self.inner
    }

    /// Counts a call of `op` and tells whether it fails.
    fn fault(&mut self, op: Op) -> Option<FaultKind> {
        self.calls[op as usize] += 1;
        let n = self.calls[op as usize];
        self.faults
            .iter()
            .find(|f| f.op == op && (f.call == n || (f.sticky && n > f.call)))
            .map(|f| f.kind)
    }
}

fn injected(op: Op) -> io::Error {
    io::Error::other(format!("injected fault in {op:?}"))
}

impl<S: Storage> Storage for FaultyStorage<S> {
    fn read_file(&mut self, name: &str) -> io::Result<Option<Vec<u8>>> {
        match self.fault(Op::Read) {
            Some(_) => Err(injected(Op::Read)),
            None => self.inner.read_file(name),
        }
    }

    fn write_file_atomic(&mut self, name: &str, bytes: &[u8]) -> io::Result<()> {
        match self.fault(Op::WriteFile) {
            Some(_) => Err(injected(Op::WriteFile)),
            None => self.inner.write_file_atomic(name, bytes),
        }
    }

    fn read_journal(&mut self) -> io::Result<Vec<u8>> {
        match self.fault(Op::Read) {
            Some(_) => Err(injected(Op::Read)),
            None => self.inner.read_journal(),
        }
    }

    fn append_journal(&mut self, bytes: &[u8]) -> io::Result<()> {
        match self.fault(Op::Append) {
            Some(FaultKind::Short(n)) => {
                self.inner.append_journal(&bytes[..n.min(bytes.len())])?;
                Err(injected(Op::Append))
            }
            Some(FaultKind::Fail) => Err(injected(Op::Append)),
            None => self.inner.append_journal(bytes),
        }
    }

    fn sync_journal(&mut self) -> io::Result<()> {
        match self.fault(Op::Sync) {
            Some(_) => Err(injected(Op::Sync)),
            None => self.inner.sync_journal(),
        }
    }

    fn truncate_journal(&mut self, len: u64) -> io::Result<()> {
        match self.fault(Op::Truncate) {
            Some(_) => Err(injected(Op::Truncate)),
            None => self.inner.truncate_journal(len),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::storage::MemStorage;

    #[test]
    fn nth_call_fails_and_short_write_leaves_a_prefix() {
        let mut s = FaultyStorage::new(MemStorage::new())
            .fail_at(Op::Append, 2, FaultKind::Short(3))
            .fail_at(Op::Sync, 1, FaultKind::Fail);
        s.append_journal(b"first\n").unwrap();
        assert!(s.append_journal(b"second\n").is_err());
        assert!(s.sync_journal().is_err());
        s.sync_journal().unwrap();
        assert_eq!((s.calls(Op::Append), s.calls(Op::Sync)), (2, 2));
        assert_eq!(s.into_inner().journal(), b"first\nsec");
    }

    #[test]
    fn fail_from_keeps_failing() {
        let mut s = FaultyStorage::new(MemStorage::new()).fail_from(Op::WriteFile, 2);
        s.write_file_atomic("a", b"1").unwrap();
        assert!(s.write_file_atomic("a", b"2").is_err());
        assert!(s.write_file_atomic("a", b"3").is_err());
        assert_eq!(s.into_inner().file("a"), Some(&b"1"[..]));
    }
}
