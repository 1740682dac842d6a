//! A storage that fails on purpose: the n-th call of an operation fails,
//! or writes only part of its bytes; or a small volume that runs full.

use super::contract::Storage;
use std::collections::BTreeMap;
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
    /// [`Storage::journal_in_place`] (failing: the look itself fails).
    Check,
}

/// How a call fails.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FaultKind {
    /// The call does nothing and returns an error.
    Fail,
    /// Only the first `n` bytes are appended, then an error (a short
    /// write); for other operations the same as `Fail`.
    Short(usize),
    /// The call does nothing and returns "no space left on device"
    /// ([`io::ErrorKind::StorageFull`]).
    Full,
    /// The power fails during an append: of its bytes, the disk keeps
    /// only those from `at` on, with NUL bytes before them where the
    /// earlier part was never written (`later`: what a file system that
    /// persisted the file's new size and its later blocks leaves), or
    /// only the first `at` (not `later`). The call fails, and so does
    /// every later call of any operation: the machine is off, nothing is
    /// cleaned up. For other operations the same as `Fail`.
    PowerCut {
        /// Where the kept part starts (`later`) or ends.
        at: usize,
        /// Whether the later part is kept (else the earlier).
        later: bool,
    },
}

#[derive(Debug, Clone, Copy)]
struct Fault {
    op: Op,
    call: usize,
    sticky: bool,
    kind: FaultKind,
}

/// What a small volume holds: its size and the bytes of each file on it.
#[derive(Debug, Clone, Default)]
struct Volume {
    capacity: u64,
    files: BTreeMap<String, u64>,
    journal: u64,
}

impl Volume {
    fn used(&self) -> u64 {
        self.files.values().sum::<u64>() + self.journal
    }

    fn free(&self) -> u64 {
        self.capacity.saturating_sub(self.used())
    }
}

/// Wraps a storage and fails chosen calls (counted from 1 per operation),
/// or stands for a volume of a given size that refuses what does not fit
/// as a full disk does.
#[derive(Debug)]
pub struct FaultyStorage<S> {
    inner: S,
    faults: Vec<Fault>,
    calls: [usize; 6],
    volume: Option<Volume>,
    /// A power cut happened: every call fails.
    off: bool,
}

impl<S: Storage> FaultyStorage<S> {
    /// `inner` without faults yet.
    pub fn new(inner: S) -> Self {
        Self {
            inner,
            faults: Vec::new(),
            calls: [0; 6],
            volume: None,
            off: false,
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

    /// The files live on a volume of `bytes`: a file replacement that does
    /// not fit beside the old file, and the part of an append that does
    /// not fit, fail with "no space left on device" (the part that fits
    /// is appended, as a file system does). The files' sizes are learnt
    /// as the store reads them.
    pub fn with_capacity(mut self, bytes: u64) -> Self {
        self.set_capacity(bytes);
        self
    }

    /// Makes the volume `bytes` large: less than [`used`](Self::used)
    /// stands for a disk that something else filled, more for room made.
    pub fn set_capacity(&mut self, bytes: u64) {
        self.volume.get_or_insert_with(Volume::default).capacity = bytes;
    }

    /// Bytes the tool files and the journal take on the volume.
    pub fn used(&self) -> u64 {
        self.volume.as_ref().map_or(0, Volume::used)
    }

    /// How many times `op` was called.
    pub fn calls(&self, op: Op) -> usize {
        self.calls[op as usize]
    }

    /// The wrapped storage (what "the disk" holds).
    pub fn into_inner(self) -> S {
        self.inner
    }

    /// The wrapped storage, to act on "the disk" behind the store's back.
    pub fn inner_mut(&mut self) -> &mut S {
        &mut self.inner
    }

    /// Whether a power cut has happened (every call fails since).
    pub fn is_off(&self) -> bool {
        self.off
    }

    /// Counts a call of `op` and tells whether it fails.
    fn fault(&mut self, op: Op) -> Option<FaultKind> {
        self.calls[op as usize] += 1;
        if self.off {
            return Some(FaultKind::Fail);
        }
        let n = self.calls[op as usize];
        self.faults
            .iter()
            .find(|f| f.op == op && (f.call == n || (f.sticky && n > f.call)))
            .map(|f| f.kind)
    }
}

fn injected(op: Op, kind: FaultKind) -> io::Error {
    match kind {
        FaultKind::Full => full(),
        _ => io::Error::other(format!("injected fault in {op:?}")),
    }
}

fn full() -> io::Error {
    io::Error::new(io::ErrorKind::StorageFull, "no space left on device")
}

fn len(bytes: &[u8]) -> u64 {
    bytes.len() as u64
}

impl<S: Storage> Storage for FaultyStorage<S> {
    fn read_file(&mut self, name: &str) -> io::Result<Option<Vec<u8>>> {
        if let Some(kind) = self.fault(Op::Read) {
            return Err(injected(Op::Read, kind));
        }
        let read = self.inner.read_file(name)?;
        if let (Some(v), Some(bytes)) = (&mut self.volume, &read) {
            v.files.insert(name.to_owned(), len(bytes));
        }
        Ok(read)
    }

    fn write_file_atomic(&mut self, name: &str, bytes: &[u8]) -> io::Result<()> {
        if let Some(kind) = self.fault(Op::WriteFile) {
            return Err(injected(Op::WriteFile, kind));
        }
        // The new file is written beside the old one, then renamed over it.
        if self.volume.as_ref().is_some_and(|v| v.free() < len(bytes)) {
            return Err(full());
        }
        self.inner.write_file_atomic(name, bytes)?;
        if let Some(v) = &mut self.volume {
            v.files.insert(name.to_owned(), len(bytes));
        }
        Ok(())
    }

    fn read_journal(&mut self) -> io::Result<Vec<u8>> {
        if let Some(kind) = self.fault(Op::Read) {
            return Err(injected(Op::Read, kind));
        }
        let bytes = self.inner.read_journal()?;
        if let Some(v) = &mut self.volume {
            v.journal = len(&bytes);
        }
        Ok(bytes)
    }

    fn append_journal(&mut self, bytes: &[u8]) -> io::Result<()> {
        let fault = self.fault(Op::Append);
        if let Some(FaultKind::PowerCut { at, later }) = fault {
            self.off = true;
            let at = at.min(bytes.len());
            let kept = if later {
                let mut torn = vec![0u8; at];
                torn.extend_from_slice(&bytes[at..]);
                torn
            } else {
                bytes[..at].to_vec()
            };
            self.inner.append_journal(&kept)?;
            return Err(injected(Op::Append, FaultKind::Fail));
        }
        let (fits, error) = match fault {
            Some(FaultKind::Short(n)) => (
                n.min(bytes.len()),
                Some(injected(Op::Append, FaultKind::Fail)),
            ),
            Some(kind) => (0, Some(injected(Op::Append, kind))),
            None => (bytes.len(), None),
        };
        let room = self.volume.as_ref().map_or(u64::MAX, Volume::free);
        let (fits, error) = match usize::try_from(room) {
            Ok(room) if room < fits => (room, Some(full())),
            _ => (fits, error),
        };
        if fits > 0 || error.is_none() {
            self.inner.append_journal(&bytes[..fits])?;
        }
        if let Some(v) = &mut self.volume {
            v.journal += fits as u64;
        }
        error.map_or(Ok(()), Err)
    }

    fn sync_journal(&mut self) -> io::Result<()> {
        match self.fault(Op::Sync) {
            Some(kind) => Err(injected(Op::Sync, kind)),
            None => self.inner.sync_journal(),
        }
    }

    fn truncate_journal(&mut self, len: u64) -> io::Result<()> {
        if let Some(kind) = self.fault(Op::Truncate) {
            return Err(injected(Op::Truncate, kind));
        }
        self.inner.truncate_journal(len)?;
        if let Some(v) = &mut self.volume {
            v.journal = v.journal.min(len);
        }
        Ok(())
    }

    fn journal_in_place(&mut self) -> io::Result<bool> {
        if let Some(kind) = self.fault(Op::Check) {
            return Err(injected(Op::Check, kind));
        }
        let in_place = self.inner.journal_in_place()?;
        if let (false, Some(v)) = (in_place, &mut self.volume) {
            // The lost file's room comes back once it is let go of.
            v.journal = 0;
        }
        Ok(in_place)
    }

    fn available_space(&mut self) -> io::Result<Option<u64>> {
        match &self.volume {
            Some(v) => Ok(Some(v.free())),
            None => self.inner.available_space(),
        }
    }

    fn remove_temporaries(&mut self) -> io::Result<Vec<String>> {
        self.inner.remove_temporaries()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::storage::memory::MemStorage;

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

    #[test]
    fn a_small_volume_refuses_what_does_not_fit() {
        let mut s = FaultyStorage::new(MemStorage::new()).with_capacity(10);
        s.write_file_atomic("a", b"1234").unwrap();
        let e = s.write_file_atomic("a", b"1234567").unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::StorageFull, "old and new beside");
        s.append_journal(b"abc\n").unwrap();
        let e = s.append_journal(b"defg\n").unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::StorageFull);
        assert_eq!(s.used(), 10, "the part that fit was written");
        s.truncate_journal(4).unwrap();
        s.set_capacity(20);
        s.append_journal(b"defg\n").unwrap();
        assert_eq!(s.used(), 13);
        s.append_journal(b"hij\n").unwrap();
        let mem = s.into_inner();
        assert_eq!(mem.journal(), b"abc\ndefg\nhij\n");
    }

    #[test]
    fn a_full_fault_says_no_space() {
        let mut s = FaultyStorage::new(MemStorage::new()).fail_at(Op::Append, 1, FaultKind::Full);
        let e = s.append_journal(b"x\n").unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::StorageFull);
        assert_eq!(s.into_inner().journal(), b"");
    }
}
