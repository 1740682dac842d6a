//! A tool's nodes: a `ToolType` object in the tool list, NodeId
//! `machine/tool/<group>/<number>`, with its mandatory members, its
//! `ControlIdentifier2`, `Name`, `Identifier` and `ToolLife`, and three
//! variables of this server's own: `Radius` and `Length` (AnalogUnitType,
//! mm) and `ToolKind` (MultiStateDiscreteType). `ToolLife` holds
//! `WearRadius`, the radius wear booked on the tool, and while a
//! compensation runs on it `RunningWear`, the wear it has not booked yet.

use opcua::types::{
    LocalizedText, NodeId, QualifiedName, ReferenceTypeId, VariableTypeId, Variant,
};

use super::error::ModelError;
use super::handles::{
    Checked, LifeEntry, NodeTable, RunningVar, ToolVar, RUNNING_ENTRY, WEAR_ENTRY,
};
use super::instance::{named, Root, Template};
use super::model::{mt, Spaces};
use super::types::Types;
use super::units::MILLIMETRE;
use super::view::ToolRecord;

/// `ToolManagement` GroupBased (OPC 40501-1, 12.10): two identifiers, the
/// tool number and the table it is in (docs/decisions.md).
const GROUP_BASED: i32 = 1;
/// `ToolLocked` CapabilityUnavailable: the controller locks no tool, so
/// it has no reason to give.
const NO_REASON: i32 = 0;
/// `ToolLifeIndication` Other: radius wear (the enumeration knows
/// abraded length and diameter, not radius).
const OTHER: i32 = 7;

/// Where a tool's running-wear entry is placed, below the tool.
pub(crate) const LIFE: &str = "ToolLife";
/// The variables of a tool that follow its record.
pub(crate) const LIVE: [ToolVar; 4] = [
    ToolVar::Radius,
    ToolVar::Length,
    ToolVar::ToolKind,
    ToolVar::WearRadius,
];

/// The NodeId string of a tool.
pub(crate) fn base(group: u32, number: u32) -> String {
    format!("machine/tool/{group}/{number}")
}

/// The templates of a tool and of its running-wear entry.
#[derive(Debug, Clone)]
pub(crate) struct ToolTemplates {
    /// A tool (root named by each tool).
    pub tool: Checked<ToolVar>,
    /// `ToolLife/RunningWear`, placed below a tool's `ToolLife`.
    pub running: Checked<RunningVar>,
    /// ToolType.
    pub tool_type: NodeId,
    /// ToolLifeType.
    pub life_type: NodeId,
}

/// Plans the tool templates from the loaded types; `kinds` names the
/// tool kinds.
pub(crate) fn templates(
    types: &Types<'_>,
    at: Spaces,
    kinds: &[String],
) -> Result<ToolTemplates, ModelError> {
    let missing = |owner, member| ModelError::Member { owner, member };
    let list = types.declarations(&at.mt(mt::TOOL_LIST_TYPE));
    let slot = named(&list, "<Tool>").ok_or(missing("ToolListType", "<Tool>"))?;
    let tool_type = at.mt(mt::TOOL_TYPE);
    let life_type = at.mt(mt::TOOL_LIFE_TYPE);
    let root = Root {
        browse_name: QualifiedName::new(at.own, "Tool"),
        reference: slot.reference.clone(),
        type_definition: tool_type.clone(),
        decl: Some(&slot.node),
    };
    let optional = ["ControlIdentifier2", "Name", "Identifier", "ToolLife"];
    let mut tool = Template::plan(types, root, &optional);
    let life = types.members(&tool_type, Some(&slot.node));
    let life_decl = named(&life, LIFE).ok_or(missing("ToolType", LIFE))?;
    let entries = types.children(&life_decl.node);
    let entry = named(&entries, "<ToolLifeEntry>").ok_or(missing("ToolLife", "<ToolLifeEntry>"))?;
    let life_entry = |name: &str| Root {
        browse_name: QualifiedName::new(at.own, name),
        reference: entry.reference.clone(),
        type_definition: life_type.clone(),
        decl: Some(&entry.node),
    };
    tool.add(types, LIFE, life_entry("WearRadius"), &[]);
    add_own(types, at, &mut tool);
    let mut tool = Checked::new(tool)?;
    fixed(&mut tool, kinds);
    let mut running = Template::default();
    running.add(types, "", life_entry("RunningWear"), &[]);
    let mut running = Checked::new(running)?;
    life_fields(&mut running, RUNNING_ENTRY);
    running.template_mut().describe(
        RunningVar::RunningWear.path(),
        "RunningWear",
        "The radius wear of the compensation running on this tool now, mm: booked at its end",
    );
    Ok(ToolTemplates {
        tool,
        running,
        tool_type,
        life_type,
    })
}

/// The variables of this server's own below a tool: `Radius`, `Length`
/// (AnalogUnitType) and `ToolKind` (MultiStateDiscreteType).
fn add_own(types: &Types<'_>, at: Spaces, tool: &mut Template) {
    let own = [
        ("Radius", VariableTypeId::AnalogUnitType),
        ("Length", VariableTypeId::AnalogUnitType),
        ("ToolKind", VariableTypeId::MultiStateDiscreteType),
    ];
    for (name, ty) in own {
        let root = Root {
            browse_name: QualifiedName::new(at.own, name),
            reference: ReferenceTypeId::HasComponent.into(),
            type_definition: ty.into(),
            decl: None,
        };
        tool.add(types, "", root, &[]);
    }
}

/// The values every tool has alike, and the descriptions.
fn fixed(t: &mut Checked<ToolVar>, kinds: &[String]) {
    t.set(ToolVar::ControlIdentifierInterpretation, GROUP_BASED);
    t.set(ToolVar::Locked, false);
    t.set(ToolVar::ReasonForLocking, NO_REASON);
    t.set(ToolVar::RadiusUnits, MILLIMETRE.value());
    t.set(ToolVar::LengthUnits, MILLIMETRE.value());
    let names: Vec<LocalizedText> = kinds
        .iter()
        .map(|k| LocalizedText::from(k.as_str()))
        .collect();
    t.set(ToolVar::ToolKindNames, names);
    life_fields(t, WEAR_ENTRY);
    let t = t.template_mut();
    t.describe(ToolVar::Radius.path(), "Radius", "The tool's radius, mm");
    t.describe(ToolVar::Length.path(), "Length", "The tool's length, mm");
    t.describe(
        ToolVar::ToolKind.path(),
        "ToolKind",
        "The kind of tool (EnumStrings name each value)",
    );
    t.describe(
        ToolVar::WearRadius.path(),
        "WearRadius",
        "The radius wear booked on this tool while it is the table's current tool, mm (the \
         radius is already smaller by it)",
    );
}

/// The properties of a tool life `entry`: mm, counting up; its value 0.
fn life_fields<V: NodeTable>(t: &mut Checked<V>, entry: LifeEntry<V>) {
    let [value, units, indication, counting] = entry;
    t.set(units, MILLIMETRE.value());
    t.set(indication, OTHER);
    t.set(counting, true);
    t.set(value, 0.0);
}

/// The value of a tool's live variable `v` (`None`: not one of
/// [`LIVE`]).
pub(crate) fn value(r: &ToolRecord, v: ToolVar) -> Option<Variant> {
    match v {
        ToolVar::Radius => Some(r.radius.into()),
        ToolVar::Length => Some(r.length.into()),
        ToolVar::ToolKind => Some(r.kind.into()),
        ToolVar::WearRadius => Some(r.wear.into()),
        _ => None,
    }
}

/// The template of tool `r`: its names, identifiers and values.
pub(crate) fn of(t: &ToolTemplates, r: &ToolRecord, own: u16) -> Template {
    let mut tool = t.tool.clone();
    let name = r.name();
    if let Some(root) = tool.template_mut().get_mut("") {
        root.browse_name = QualifiedName::new(own, name.as_str());
        root.display_name = name.as_str().into();
        root.description = Some(
            format!("Tool {} of tool table {}", r.number, r.group)
                .as_str()
                .into(),
        );
    }
    tool.set(ToolVar::ControlIdentifier1, r.number);
    tool.set(ToolVar::ControlIdentifier2, r.group);
    tool.set(ToolVar::Name, name.as_str());
    tool.set(ToolVar::Identifier, name.as_str());
    for v in LIVE {
        if let Some(value) = value(r, v) {
            tool.set(v, value);
        }
    }
    tool.into_template()
}
