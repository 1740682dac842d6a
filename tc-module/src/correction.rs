//! The correction engine: the one-profile buffer (trc-geometry.md).

/// The one-profile buffer of a group. Empty means the next profile is an
/// approach.
#[derive(Debug, Clone, Default)]
pub struct Buffer {
    held: Option<()>,
}

impl Buffer {
    /// Whether a profile is held (STATUS bit ProfMarked).
    pub fn is_marked(&self) -> bool {
        self.held.is_some()
    }
}
