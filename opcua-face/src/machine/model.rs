//! The machine instance: a `MachineToolType` in the Machinery `Machines`
//! folder with every mandatory node of its type, and beside them the
//! optional ones this server fills (`Identification/Model` and
//! `SoftwareRevision`, `Equipment/Tools` with its `NodeVersion`) and one
//! channel under `Monitoring`. Its NodeIds are strings in the face's
//! namespace: `machine`, then the BrowseName path (`machine/Equipment/Tools`).

use opcua::types::{LocalizedText, NodeId, QualifiedName, ReferenceTypeId, Variant};

use super::error::ModelError;
use super::handles::{Checked, MachineVar, NodeTable};
use super::instance::{named, Root, Template};
use super::types::Types;
use super::units::{range, PERCENT};
use super::view::{ChannelState, MachineTool};

/// The NodeId (string) of the machine.
pub(crate) const MACHINE: &str = "machine";
/// The tool list, below the machine.
pub(crate) const TOOLS: &str = "Equipment/Tools";

/// Numeric identifiers of the OPC 40501-1 nodes used (its NodeIds.csv).
pub(crate) mod mt {
    /// MachineToolType.
    pub const MACHINE_TOOL_TYPE: u32 = 13;
    /// ProductionProgramStateMachineType.
    pub const PROGRAM_STATE_MACHINE: u32 = 15;
    /// ChannelMonitoringType.
    pub const CHANNEL_MONITORING_TYPE: u32 = 16;
    /// MonitoringType.
    pub const MONITORING_TYPE: u32 = 14;
    /// ToolListType.
    pub const TOOL_LIST_TYPE: u32 = 44;
    /// ToolType.
    pub const TOOL_TYPE: u32 = 50;
    /// ToolLifeType.
    pub const TOOL_LIFE_TYPE: u32 = 61;
}

/// The Machinery `Machines` folder (OPC 40001-1 NodeIds.csv).
const MACHINES_FOLDER: u32 = 1001;

/// `ChannelState` values (OPC 40501-1, 12.1).
pub(crate) fn channel_code(state: ChannelState) -> i32 {
    match state {
        ChannelState::Running => 0,
        ChannelState::Interrupted => 1,
        ChannelState::Idle => 2,
    }
}

/// `MachineOperationMode` Automatic: the emulator runs what its host
/// sends.
const AUTOMATIC: i32 = 1;
/// `ChannelMode` Automatic.
const CHANNEL_AUTOMATIC: i32 = 0;
/// The feed override: the emulator runs at the programmed feed.
const FEED_OVERRIDE: f64 = 100.0;

/// The namespace indexes the model lives in.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Spaces {
    /// The face's own (instances).
    pub own: u16,
    /// OPC 40501-1.
    pub mt: u16,
    /// OPC 40001-1.
    pub machinery: u16,
}

impl Spaces {
    /// A node of OPC 40501-1.
    pub fn mt(&self, id: u32) -> NodeId {
        NodeId::new(self.mt, id)
    }

    /// The Machines folder.
    pub fn machines(&self) -> NodeId {
        NodeId::new(self.machinery, MACHINES_FOLDER)
    }
}

impl Spaces {
    /// The NodeId of the machine's variable `v`.
    pub fn machine_var(&self, v: MachineVar) -> NodeId {
        Template::id(self.own, MACHINE, v.path())
    }
}

/// Optional members of the machine the face fills.
const OPTIONAL: [&str; 4] = [
    "Identification/Model",
    "Identification/SoftwareRevision",
    TOOLS,
    "Equipment/Tools/NodeVersion",
];

/// The machine instance with its channel, its values set (the tool list
/// empty; the live values at their start).
pub(crate) fn machine(
    types: &Types<'_>,
    at: Spaces,
    m: &MachineTool,
) -> Result<Template, ModelError> {
    let root = Root {
        browse_name: QualifiedName::new(at.own, m.name.as_str()),
        reference: ReferenceTypeId::Organizes.into(),
        type_definition: at.mt(mt::MACHINE_TOOL_TYPE),
        decl: None,
    };
    let mut t = Template::plan(types, root, &OPTIONAL);
    if t.parts.len() < 2 {
        return Err(ModelError::Type("MachineToolType"));
    }
    add_channel(types, at, &mut t)?;
    let mut t = Checked::<MachineVar>::new(t)?;
    let id = &m.identity;
    let text = |s: &str| Variant::from(LocalizedText::from(s));
    let values: [(MachineVar, Variant); 15] = [
        (MachineVar::Manufacturer, text(&id.manufacturer)),
        (MachineVar::Model, text(&id.model)),
        (
            MachineVar::SoftwareRevision,
            id.software_revision.as_str().into(),
        ),
        (MachineVar::SerialNumber, id.serial_number.as_str().into()),
        (
            MachineVar::ProductInstanceUri,
            id.product_instance_uri.as_str().into(),
        ),
        (MachineVar::OperationMode, AUTOMATIC.into()),
        (MachineVar::ChannelName, "Channel 1".into()),
        (MachineVar::ChannelMode, CHANNEL_AUTOMATIC.into()),
        (
            MachineVar::ChannelState,
            channel_code(ChannelState::Idle).into(),
        ),
        (MachineVar::FeedOverride, FEED_OVERRIDE.into()),
        (MachineVar::FeedOverrideRange, range(0.0, FEED_OVERRIDE)),
        (MachineVar::FeedOverrideUnits, PERCENT.value()),
        (MachineVar::ProgramName, "".into()),
        (MachineVar::ProgramNumberInList, 0u16.into()),
        (MachineVar::NodeVersion, "0".into()),
    ];
    for (v, value) in values {
        t.set(v, value);
    }
    let mut t = t.into_template();
    t.describe(
        TOOLS,
        "Tools",
        "Every tool entry of every tool table that holds data; ControlIdentifier1 is the tool \
         number, ControlIdentifier2 the table (compensation group)",
    );
    Ok(t)
}

/// `Monitoring/Channel1`: a ChannelMonitoringType for the
/// `<MonitoredElement>` placeholder.
fn add_channel(types: &Types<'_>, at: Spaces, t: &mut Template) -> Result<(), ModelError> {
    let decls = types.declarations(&at.mt(mt::MONITORING_TYPE));
    let placeholder = named(&decls, "<MonitoredElement>").ok_or(ModelError::Member {
        owner: "MonitoringType",
        member: "<MonitoredElement>",
    })?;
    let root = Root {
        browse_name: QualifiedName::new(at.own, "Channel1"),
        reference: placeholder.reference.clone(),
        type_definition: at.mt(mt::CHANNEL_MONITORING_TYPE),
        decl: Some(&placeholder.node),
    };
    t.add(types, "Monitoring", root, &[]);
    t.describe(
        "Monitoring/Channel1",
        "Channel1",
        "The emulator's one channel: Active while motion waits or runs, Interrupted while a \
         compensation group is in fault, else Reset",
    );
    Ok(())
}
