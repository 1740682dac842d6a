//! The handles of one connection: each names one object, was issued in
//! one Clean epoch, and is void once the emulator has carried out a Clean
//! since (the manual: Clean rejects every TC object, so a PCAP program
//! must null its handles).
//!
//! A handle is a `u32`: the connection's tag (bits 24..31, never 0, so 0
//! stays the null handle), a generation (bits 16..23) and a slot number
//! plus one (bits 0..15). The tag tells a handle of another connection
//! (unless the two connections were opened 255 apart); the generation
//! tells a released slot that was given out again (unless it was given
//! out 256 times since).

use std::num::NonZeroU32;

use uoi::{ObjectAddress, ValueType};

use crate::error::{Error, ErrorCode, Result};

/// Most handles one connection holds at once.
pub const MAX_HANDLES: usize = u16::MAX as usize;

/// A handle to one object of one connection (the C ABI's `uoi_handle`;
/// 0 there is the null handle).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Handle(NonZeroU32);

impl Handle {
    /// The handle with this number, if it is not the null handle.
    pub fn from_raw(raw: u32) -> Option<Self> {
        NonZeroU32::new(raw).map(Self)
    }

    /// Its number.
    pub fn raw(self) -> u32 {
        self.0.get()
    }

    fn tag(self) -> u8 {
        (self.raw() >> 24) as u8
    }

    fn generation(self) -> u8 {
        (self.raw() >> 16) as u8
    }

    fn slot(self) -> usize {
        (self.raw() & 0xFFFF) as usize - 1
    }
}

impl std::fmt::Display for Handle {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "0x{:08x}", self.raw())
    }
}

/// The Clean epoch a handle was issued in: the server that issued it
/// (its identity, as `INFO` reports it; 0 for an embedded emulator) and
/// the Cleans it had carried out. A handle is void in any other epoch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Epoch {
    /// The identity of the server.
    pub server: u64,
    /// The Cleans carried out.
    pub cleans: u64,
}

impl From<u64> for Epoch {
    /// The epoch after `cleans` Cleans of an embedded emulator.
    fn from(cleans: u64) -> Self {
        Self { server: 0, cleans }
    }
}

/// What a handle names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Target {
    /// The object.
    pub addr: ObjectAddress,
    /// Its value type.
    pub ty: ValueType,
}

/// One slot of the table.
#[derive(Debug, Clone, Copy)]
struct Slot {
    target: Target,
    /// The Clean epoch it was issued in.
    epoch: Epoch,
    generation: u8,
    live: bool,
}

/// The handles of one connection.
#[derive(Debug)]
pub struct Handles {
    tag: u8,
    slots: Vec<Slot>,
    free: Vec<usize>,
}

impl Handles {
    /// The table of the connection with serial number `serial`.
    pub fn new(serial: u64) -> Self {
        Self {
            // 1..=255: a tag is never 0.
            tag: (serial % 255) as u8 + 1,
            slots: Vec::new(),
            free: Vec::new(),
        }
    }

    /// A new handle to `target`, issued in Clean epoch `epoch`.
    pub fn issue(&mut self, target: Target, epoch: impl Into<Epoch>) -> Result<Handle> {
        let epoch = epoch.into();
        if self.free.is_empty() && self.slots.len() == MAX_HANDLES {
            self.reclaim_stale(epoch);
        }
        let slot = match self.free.pop() {
            Some(i) => i,
            None if self.slots.len() < MAX_HANDLES => {
                self.slots.push(Slot {
                    target,
                    epoch,
                    generation: 0,
                    live: false,
                });
                self.slots.len() - 1
            }
            None => {
                return Err(Error::new(
                    ErrorCode::TooManyHandles,
                    format!(
                        "uoi_init {}: all {MAX_HANDLES} handles of this connection are in use; \
                         release the ones you no longer need with uoi_clean_handle",
                        target.addr
                    ),
                ))
            }
        };
        let s = &mut self.slots[slot];
        *s = Slot {
            target,
            epoch,
            generation: s.generation,
            live: true,
        };
        let raw = (u32::from(self.tag) << 24) | (u32::from(s.generation) << 16) | (slot as u32 + 1);
        Handle::from_raw(raw).ok_or_else(|| Error::new(ErrorCode::Internal, "handle 0 issued"))
    }

    /// Frees the slots of handles issued before Clean epoch `epoch`: they
    /// answer StaleHandle already, and go on doing so (their generation
    /// moves on).
    fn reclaim_stale(&mut self, epoch: Epoch) {
        for (i, s) in self.slots.iter_mut().enumerate() {
            if s.live && s.epoch != epoch {
                s.live = false;
                s.generation = s.generation.wrapping_add(1);
                self.free.push(i);
            }
        }
    }

    /// The slot of `h`, if `h` is one of this connection's live handles.
    fn slot_of(&self, h: Handle, call: &str) -> Result<usize> {
        let foreign = || {
            Error::new(
                ErrorCode::BadHandle,
                format!("{call}: handle {h} was not issued by this connection"),
            )
        };
        if h.tag() != self.tag {
            return Err(foreign());
        }
        let slot = self.slots.get(h.slot()).ok_or_else(foreign)?;
        if !slot.live || slot.generation != h.generation() {
            return Err(Error::new(
                ErrorCode::StaleHandle,
                format!(
                    "{call}: handle {h} was released (uoi_clean_handle, or voided by a Clean \
                     and its place given out again): initialise the object again with uoi_init"
                ),
            ));
        }
        Ok(h.slot())
    }

    /// What `h` names and the Clean epoch it was issued in, if it is one
    /// of this connection's live handles.
    pub fn lookup(&self, h: Handle, call: &str) -> Result<(Target, Epoch)> {
        let slot = self.slots[self.slot_of(h, call)?];
        Ok((slot.target, slot.epoch))
    }

    /// What `h` names, if it is live and was issued in Clean epoch
    /// `epoch` (the emulator's count now).
    #[cfg(test)]
    pub fn resolve(&self, h: Handle, epoch: impl Into<Epoch>, call: &str) -> Result<Target> {
        let (target, issued) = self.lookup(h, call)?;
        if issued != epoch.into() {
            return Err(Self::voided(h, target, call));
        }
        Ok(target)
    }

    /// The error of handle `h` to `target`, voided by a Clean.
    pub fn voided(h: Handle, target: Target, call: &str) -> Error {
        Error::new(
            ErrorCode::StaleHandle,
            format!(
                "{call}: handle {h} ({}) was initialised before a Clean ({} = 1), or by a \
                     server that has restarted since: Clean rejects every TC object, so every \
                     handle issued before it is void; initialise the object again with uoi_init",
                target.addr,
                tc_objects::TcObject::Clean.address()
            ),
        )
    }

    /// Releases `h`; its slot may be given out again.
    pub fn release(&mut self, h: Handle) -> Result<()> {
        let i = self.slot_of(h, "uoi_clean_handle")?;
        let s = &mut self.slots[i];
        s.live = false;
        s.generation = s.generation.wrapping_add(1);
        self.free.push(i);
        Ok(())
    }

    /// Handles live now (void ones included until released).
    #[cfg(test)]
    pub fn live(&self) -> usize {
        self.slots.iter().filter(|s| s.live).count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn radius() -> Target {
        Target {
            addr: tc_objects::TcObject::Radius.of(1),
            ty: ValueType::F64,
        }
    }

    #[test]
    fn a_clean_voids_the_handles_issued_before_it() {
        let mut t = Handles::new(1);
        let h = t.issue(radius(), 0).unwrap();
        assert_eq!(t.resolve(h, 0, "read").unwrap(), radius());
        let e = t.resolve(h, 1, "read").unwrap_err();
        assert_eq!(e.code(), ErrorCode::StaleHandle);
        assert!(e.message().contains("Clean"), "{e}");
        assert!(e.message().contains("uoi_init"), "{e}");
        let fresh = t.issue(radius(), 1).unwrap();
        assert_ne!(fresh, h);
        assert!(t.resolve(fresh, 1, "read").is_ok());
    }

    #[test]
    fn handles_of_another_connection_and_released_ones_are_refused() {
        let mut a = Handles::new(1);
        let mut b = Handles::new(2);
        let ha = a.issue(radius(), 0).unwrap();
        let hb = b.issue(radius(), 0).unwrap();
        assert_eq!(
            a.resolve(hb, 0, "r").unwrap_err().code(),
            ErrorCode::BadHandle
        );
        assert_eq!(
            b.resolve(ha, 0, "r").unwrap_err().code(),
            ErrorCode::BadHandle
        );
        let never = Handle::from_raw(ha.raw() + 7).unwrap();
        assert_eq!(
            a.resolve(never, 0, "r").unwrap_err().code(),
            ErrorCode::BadHandle
        );
        a.release(ha).unwrap();
        assert_eq!(
            a.resolve(ha, 0, "r").unwrap_err().code(),
            ErrorCode::StaleHandle
        );
        assert_eq!(a.release(ha).unwrap_err().code(), ErrorCode::StaleHandle);
        let again = a.issue(radius(), 0).unwrap();
        assert_ne!(again, ha, "the slot comes back with a new generation");
        assert!(a.resolve(again, 0, "r").is_ok());
        assert_eq!(a.live(), 1);
    }

    #[test]
    fn the_table_is_bounded_and_gives_void_handles_places_back() {
        let mut t = Handles::new(7);
        for _ in 0..MAX_HANDLES {
            t.issue(radius(), 0).unwrap();
        }
        let full = t.issue(radius(), 0).unwrap_err();
        assert_eq!(full.code(), ErrorCode::TooManyHandles);
        // After a Clean every old handle is void: their places come back.
        let h = t.issue(radius(), 1).unwrap();
        assert!(t.resolve(h, 1, "r").is_ok());
        assert_eq!(t.live(), 1);
    }
}
