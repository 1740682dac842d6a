//! Tool tables: 1024 entries per compensation group (docs/objects.md
//! device 1, RADIUS/WKZINDEX/WkzLen). An extension keeps its own fields of every
//! entry in the entry itself (`ext`).

/// Number of entries in a tool table (WKZINDEX 0..1023, docs/objects.md
/// device 1).
pub use tc_objects::TOOL_ENTRIES;

/// An index into a tool table (WKZINDEX, 0..=1023).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, PartialOrd, Ord)]
pub struct WkzIndex(u16);

impl WkzIndex {
    /// The index, if `value` lies in 0..=1023.
    pub fn new(value: i32) -> Option<Self> {
        u16::try_from(value)
            .ok()
            .filter(|&v| usize::from(v) < TOOL_ENTRIES)
            .map(WkzIndex)
    }

    /// The index as a number.
    pub const fn get(self) -> usize {
        self.0 as usize
    }
}

/// One tool entry: radius and length default to 0.0; `ext` holds an
/// extension's fields of the same entry (OTC: tool type, wear constant...).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ToolEntry<T = ()> {
    /// Tool radius (RADIUS), interpolation units.
    pub radius: f64,
    /// Tool length (WkzLen), interpolation units.
    pub length: f64,
    /// The extension's fields of this entry.
    pub ext: T,
}

/// The tool table of one compensation group.
#[derive(Debug, Clone, PartialEq)]
pub struct ToolTable<T = ()> {
    entries: Box<[ToolEntry<T>]>,
}

impl<T: Copy + Default> Default for ToolTable<T> {
    fn default() -> Self {
        Self {
            entries: vec![ToolEntry::default(); TOOL_ENTRIES].into_boxed_slice(),
        }
    }
}

impl<T: Copy + Default> ToolTable<T> {
    /// The entry at `index`.
    pub fn entry(&self, index: WkzIndex) -> &ToolEntry<T> {
        // A WkzIndex is below TOOL_ENTRIES, the table's length.
        &self.entries[index.get()]
    }

    /// The entry at `index`, mutable.
    pub fn entry_mut(&mut self, index: WkzIndex) -> &mut ToolEntry<T> {
        &mut self.entries[index.get()]
    }

    /// Every entry, every field back to its default.
    pub fn clear(&mut self) {
        self.entries.fill(ToolEntry::default());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn index_bounds() {
        assert_eq!(WkzIndex::new(0).map(WkzIndex::get), Some(0));
        assert_eq!(WkzIndex::new(1023).map(WkzIndex::get), Some(1023));
        assert_eq!(WkzIndex::new(1024), None);
        assert_eq!(WkzIndex::new(-1), None);
    }

    #[test]
    fn clear_restores_defaults_of_every_field() {
        let mut t = ToolTable::<i32>::default();
        let i = WkzIndex::new(1023).unwrap();
        t.entry_mut(i).radius = 3.0;
        t.entry_mut(i).length = 4.0;
        t.entry_mut(i).ext = 2;
        t.clear();
        assert_eq!(*t.entry(i), ToolEntry::default());
    }
}
