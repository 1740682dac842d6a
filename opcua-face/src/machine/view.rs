//! The machine as the object server tells it: its channel's state, its
//! tools, its identity, and the [`MachineSource`] that looks at the
//! server's handler.

use std::any::Any;
use std::sync::Arc;

/// What the machine's one channel does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChannelState {
    /// Motion is waiting or being executed.
    Running,
    /// A fault stopped it; it may be resumed.
    Interrupted,
    /// Nothing to do.
    Idle,
}

/// One tool of the machine, as its tool table holds it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ToolRecord {
    /// The table (compensation group) that holds it: ControlIdentifier2.
    pub group: u32,
    /// Its number in that table: ControlIdentifier1.
    pub number: u32,
    /// Its radius, mm.
    pub radius: f64,
    /// Its length, mm.
    pub length: f64,
    /// Its kind, an index into [`MachineTool::tool_kinds`].
    pub kind: u32,
    /// The radius wear booked on it, mm.
    pub wear: f64,
    /// The wear of a compensation running on it now (booked when it
    /// stops), mm; `None` while none runs.
    pub running_wear: Option<f64>,
}

impl ToolRecord {
    /// Its name and identifier: `G<group> T<number>`.
    pub fn name(&self) -> String {
        format!("G{} T{}", self.group, self.number)
    }
}

/// The machine at one moment.
#[derive(Debug, Clone, PartialEq)]
pub struct MachineView {
    /// Its channel.
    pub state: ChannelState,
    /// Its tools, each (group, number) once.
    pub tools: Vec<ToolRecord>,
}

/// Looks at the machine: called with the object server's handler, between
/// two of its requests, as often as the face polls (keep it short: every
/// connection waits for it).
pub trait MachineSource: Send + Sync {
    /// The machine now; `None` if `handler` is not the one expected.
    fn look(&self, handler: &mut dyn Any) -> Option<MachineView>;
}

/// What the machine says of itself (its `Identification`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Identity {
    /// `Manufacturer`.
    pub manufacturer: String,
    /// `Model`.
    pub model: String,
    /// `SoftwareRevision`: the build.
    pub software_revision: String,
    /// `SerialNumber`.
    pub serial_number: String,
    /// `ProductInstanceUri`: unique for this machine.
    pub product_instance_uri: String,
}

/// The machine tool the face shows: what its `MachineToolType` instance
/// (OPC 40501-1) is called and says of itself, the tool kinds it names,
/// and the [`MachineSource`] its state and tools come from. Not a client
/// of a machine (the host library's `Machine`): a description handed to
/// the face (docs/decisions.md, decision 500).
#[derive(Clone)]
pub struct MachineTool {
    /// The instance's BrowseName and DisplayName.
    pub name: String,
    /// Its identification.
    pub identity: Identity,
    /// The name of each tool kind ([`ToolRecord::kind`] indexes it).
    pub tool_kinds: Vec<String>,
    /// Where the state and tools come from.
    pub source: Arc<dyn MachineSource>,
}

impl std::fmt::Debug for MachineTool {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MachineTool")
            .field("name", &self.name)
            .field("identity", &self.identity)
            .field("tool_kinds", &self.tool_kinds)
            .finish_non_exhaustive()
    }
}
