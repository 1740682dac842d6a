//! Tool tables: 1024 entries per compensation group (uoi-map.md device 1,
//! RADIUS/WKZINDEX/WkzLen).

/// Number of entries in a tool table.
pub const TOOL_ENTRIES: usize = 1024;

/// An index into a tool table (WKZINDEX, 0..=1023).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, PartialOrd, Ord)]
pub struct WkzIndex(u16);

impl WkzIndex {
    /// The index, if `value` lies in 0..=1023.
    pub fn new(value: i32) -> Option<Self> {
        u16::try_from(value)
            .ok()
            .filter(|&v| (v as usize) < TOOL_ENTRIES)
            .map(WkzIndex)
    }

    /// The index as a number.
    pub const fn get(self) -> usize {
        self.0 as usize
    }
}

/// One tool entry: every field defaults to 0.0.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ToolEntry {
    /// Tool radius (RADIUS), interpolation units.
    pub radius: f64,
    /// Tool length (WkzLen), interpolation units.
    pub length: f64,
}

/// The tool table of one compensation group.
#[derive(Debug, Clone, PartialEq)]
pub struct ToolTable {
    entries: Box<[ToolEntry; TOOL_ENTRIES]>,
}

impl Default for ToolTable {
    fn default() -> Self {
        Self {
            entries: Box::new([ToolEntry::default(); TOOL_ENTRIES]),
        }
    }
}

impl ToolTable {
    /// The entry at `index`.
    pub fn entry(&self, index: WkzIndex) -> &ToolEntry {
        &self.entries[index.get()]
    }

    /// The entry at `index`, mutable.
    pub fn entry_mut(&mut self, index: WkzIndex) -> &mut ToolEntry {
        &mut self.entries[index.get()]
    }

    /// Every entry back to its default.
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
    fn clear_restores_defaults() {
        let mut t = ToolTable::default();
        let i = WkzIndex::new(1023).unwrap();
        t.entry_mut(i).radius = 3.0;
        t.entry_mut(i).length = 4.0;
        t.clear();
        assert_eq!(*t.entry(i), ToolEntry::default());
    }
}
