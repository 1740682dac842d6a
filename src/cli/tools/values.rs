//! What the `tools` subcommands carry: tool values, and the checked
//! content of a file to import.

use tool_store::{ToolKey, ToolValue};

/// One tool value: group, entry and field, value in the bus unit.
pub type ToolSet = (u8, ToolKey, ToolValue);

/// The checked content of an import file.
#[derive(Debug, Default)]
pub struct Import {
    /// The values to set, in file order.
    pub values: Vec<ToolSet>,
    /// Values (or JSON entries) of groups other than `--group`, left out.
    pub other_groups: usize,
}
