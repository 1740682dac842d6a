//! The object map of bus 1300 as the module dispatches it: the TC
//! module's own rows (devices 0 to 2, from the vocabulary crate
//! `tc-objects`, docs/objects.md), to which an extension appends its rows
//! (OTC: devices 3 and 4). The dispatcher in `uoi` enforces address, type,
//! access and range from it before the module sees a value.

use std::ops::RangeInclusive;

use uoi::{Meaning, ObjectDesc};

use crate::extension::TcExtension;

use tc_objects::{TcObject, GROUPS, TC_OBJECTS};

/// The key of a row of the whole bus-1300 map.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TcKey<K> {
    /// One of the TC module's own objects.
    Tc(TcObject),
    /// An extension's object indexed by compensation group.
    Group(K),
    /// An extension's other object.
    Ext(K),
}

/// The whole map: the TC rows, then the extension's group rows (their
/// index range is always [`GROUPS`], whatever the row says), then its
/// other rows.
pub fn object_table<E: TcExtension>() -> Vec<ObjectDesc<TcKey<E::Key>>> {
    let own = TC_OBJECTS.iter().map(|r| r.with_key(TcKey::Tc(r.key)));
    let group = E::GROUP_OBJECTS.iter().map(|r| {
        let mut row = r.with_key(TcKey::Group(r.key));
        row.index = GROUPS;
        row
    });
    let other = E::OBJECTS.iter().map(|r| r.with_key(TcKey::Ext(r.key)));
    own.chain(group).chain(other).collect()
}

impl<K: Meaning> Meaning for TcKey<K> {
    fn meaning(&self) -> &'static str {
        match self {
            TcKey::Tc(o) => o.meaning(),
            TcKey::Group(k) | TcKey::Ext(k) => k.meaning(),
        }
    }
}

/// Whether two inclusive ranges share a value.
fn meet(x: &RangeInclusive<u16>, y: &RangeInclusive<u16>) -> bool {
    x.start() <= y.end() && y.start() <= x.end()
}

/// Pairs of rows of `table` that answer for the same address (an
/// extension row shadowed by a TC row, say), by name.
pub fn overlapping_rows<K>(table: &[ObjectDesc<K>]) -> Vec<(&'static str, &'static str)> {
    let mut out = Vec::new();
    for (i, a) in table.iter().enumerate() {
        for b in &table[i + 1..] {
            if a.device == b.device && meet(&a.index, &b.index) && meet(&a.sub, &b.sub) {
                out.push((a.name, b.name));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::extension::NoExtension;

    #[test]
    fn tc_rows_do_not_overlap() {
        assert_eq!(overlapping_rows(&object_table::<NoExtension>()), vec![]);
    }
}
