//! The open connections of the C ABI. A C program holds an `addipos *`
//! that is not an address in memory but a token: a slot number and the
//! slot's generation. The library never follows it as a pointer, so a
//! token of a closed connection (or any other value) is answered
//! `ADDIPOS_E_CONNECTION` instead of touching freed memory.

use std::sync::{Arc, RwLock};

use addipos_host::Machine;

/// Bits of a token that hold the slot number plus one.
const SLOT_BITS: u32 = usize::BITS / 2;

/// Most connections open at once.
pub const MAX_OPEN: usize = (1 << SLOT_BITS) - 2;

/// One place of the registry.
#[derive(Debug, Default)]
struct Slot {
    generation: usize,
    machine: Option<Arc<Machine>>,
}

/// The slots, and the free ones.
#[derive(Debug, Default)]
struct Slots {
    slots: Vec<Slot>,
    free: Vec<usize>,
}

static OPEN: RwLock<Slots> = RwLock::new(Slots {
    slots: Vec::new(),
    free: Vec::new(),
});

fn token(slot: usize, generation: usize) -> usize {
    (generation << SLOT_BITS) | (slot + 1)
}

/// Registers an open connection; its token (never 0), or `None` when
/// [`MAX_OPEN`] are open.
pub fn insert(machine: Machine) -> Option<usize> {
    let mut open = OPEN.write().unwrap_or_else(|p| p.into_inner());
    let slot = match open.free.pop() {
        Some(i) => i,
        None if open.slots.len() < MAX_OPEN => {
            open.slots.push(Slot::default());
            open.slots.len() - 1
        }
        None => return None,
    };
    let s = &mut open.slots[slot];
    s.machine = Some(Arc::new(machine));
    Some(token(slot, s.generation))
}

/// The slot a token names, if it is that slot's current token.
fn slot_of(open: &Slots, token: usize) -> Option<usize> {
    let slot = (token & ((1 << SLOT_BITS) - 1)).checked_sub(1)?;
    let s = open.slots.get(slot)?;
    (s.machine.is_some() && token >> SLOT_BITS == s.generation).then_some(slot)
}

/// The connection of a token, if it is open.
pub fn get(token: usize) -> Option<Arc<Machine>> {
    let open = OPEN.read().unwrap_or_else(|p| p.into_inner());
    let slot = slot_of(&open, token)?;
    open.slots[slot].machine.clone()
}

/// Unregisters the connection of a token; it is returned (it goes when
/// the last call still using it ends).
pub fn remove(token: usize) -> Option<Arc<Machine>> {
    let mut open = OPEN.write().unwrap_or_else(|p| p.into_inner());
    let slot = slot_of(&open, token)?;
    let s = &mut open.slots[slot];
    let machine = s.machine.take();
    s.generation = s.generation.wrapping_add(1) & (usize::MAX >> SLOT_BITS);
    open.free.push(slot);
    machine
}

#[cfg(test)]
mod tests {
    use super::*;
    use addipos_host::EmbeddedOptions;

    #[test]
    fn a_closed_token_is_unknown_and_its_slot_comes_back_with_a_new_one() {
        let t = insert(Machine::embedded(EmbeddedOptions::default())).unwrap();
        assert_ne!(t, 0);
        assert!(get(t).is_some());
        assert!(remove(t).is_some());
        assert!(get(t).is_none());
        assert!(remove(t).is_none());
        let again = insert(Machine::embedded(EmbeddedOptions::default())).unwrap();
        assert_ne!(again, t);
        assert!(get(t).is_none());
        assert!(get(again).is_some());
        for junk in [0, 1, usize::MAX, 0xdead_beef] {
            if junk != again {
                assert!(get(junk).is_none(), "{junk:x}");
            }
        }
        remove(again);
    }
}
