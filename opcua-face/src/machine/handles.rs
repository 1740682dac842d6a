//! The variables of the machine and of a tool whose values the face sets,
//! by name: one table each of names and browse paths ([`MachineVar`],
//! [`ToolVar`], [`RunningVar`]). An instance planned from the NodeSets is
//! checked once against its table ([`Checked::new`]), so a value set
//! through a name cannot miss its node; a test checks the tables against
//! the built-in NodeSets (docs/decisions.md, decision 503).

use std::marker::PhantomData;

use opcua::types::Variant;

use super::error::ModelError;
use super::instance::{Kind, Template};

/// A table of variables: each name once, with its browse path below the
/// instance's root (BrowseNames joined by `/`).
pub(crate) trait NodeTable: Copy + 'static {
    /// What the instance is (in an error).
    const INSTANCE: &'static str;
    /// Every variable of the table.
    const ALL: &'static [Self];
    /// The browse path of this one.
    fn path(self) -> &'static str;
}

/// One table: the enum of names, its browse paths, and [`NodeTable`].
macro_rules! node_table {
    (
        $(#[$doc:meta])* $name:ident in $instance:literal {
            $($(#[$vdoc:meta])* $var:ident => $path:literal,)*
        }
    ) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub(crate) enum $name {
            $($(#[$vdoc])* $var,)*
        }

        impl NodeTable for $name {
            const INSTANCE: &'static str = $instance;
            const ALL: &'static [Self] = &[$($name::$var,)*];
            fn path(self) -> &'static str {
                match self {
                    $($name::$var => $path,)*
                }
            }
        }
    };
}

node_table! {
    /// A variable of the machine (a `MachineToolType` instance) the face
    /// sets.
    MachineVar in "machine" {
        /// `Identification/Manufacturer`.
        Manufacturer => "Identification/Manufacturer",
        /// `Identification/Model`.
        Model => "Identification/Model",
        /// `Identification/SoftwareRevision`.
        SoftwareRevision => "Identification/SoftwareRevision",
        /// `Identification/SerialNumber`.
        SerialNumber => "Identification/SerialNumber",
        /// `Identification/ProductInstanceUri`.
        ProductInstanceUri => "Identification/ProductInstanceUri",
        /// The machine's operation mode.
        OperationMode => "Monitoring/MachineTool/OperationMode",
        /// The channel's name.
        ChannelName => "Monitoring/Channel1/Name",
        /// The channel's mode.
        ChannelMode => "Monitoring/Channel1/ChannelMode",
        /// The channel's state.
        ChannelState => "Monitoring/Channel1/ChannelState",
        /// The feed override, %.
        FeedOverride => "Monitoring/Channel1/FeedOverride",
        /// Its range.
        FeedOverrideRange => "Monitoring/Channel1/FeedOverride/EURange",
        /// Its unit.
        FeedOverrideUnits => "Monitoring/Channel1/FeedOverride/EngineeringUnits",
        /// The active program's name.
        ProgramName => "Production/ActiveProgram/Name",
        /// Its number in the list.
        ProgramNumberInList => "Production/ActiveProgram/NumberInList",
        /// The state of the active program.
        ProgramState => "Production/ActiveProgram/State/CurrentState",
        /// That state's NodeId.
        ProgramStateId => "Production/ActiveProgram/State/CurrentState/Id",
        /// That state's number.
        ProgramStateNumber => "Production/ActiveProgram/State/CurrentState/Number",
        /// The tool list's NodeVersion.
        NodeVersion => "Equipment/Tools/NodeVersion",
    }
}

node_table! {
    /// A variable of a tool (a `ToolType` instance in the tool list) the
    /// face sets.
    ToolVar in "tool" {
        /// The tool number.
        ControlIdentifier1 => "ControlIdentifier1",
        /// The tool table (compensation group).
        ControlIdentifier2 => "ControlIdentifier2",
        /// How the two identifiers are read.
        ControlIdentifierInterpretation => "ControlIdentifierInterpretation",
        /// Its name.
        Name => "Name",
        /// Its identifier.
        Identifier => "Identifier",
        /// Whether it is locked.
        Locked => "Locked",
        /// Why it is locked.
        ReasonForLocking => "Locked/ReasonForLocking",
        /// Its radius, mm.
        Radius => "Radius",
        /// The radius's unit.
        RadiusUnits => "Radius/EngineeringUnits",
        /// Its length, mm.
        Length => "Length",
        /// The length's unit.
        LengthUnits => "Length/EngineeringUnits",
        /// Its kind.
        ToolKind => "ToolKind",
        /// The names of the kinds.
        ToolKindNames => "ToolKind/EnumStrings",
        /// The radius wear booked on it, mm.
        WearRadius => "ToolLife/WearRadius",
        /// The booked wear's unit.
        WearUnits => "ToolLife/WearRadius/EngineeringUnits",
        /// What the booked wear indicates.
        WearIndication => "ToolLife/WearRadius/Indication",
        /// Whether the booked wear counts up.
        WearCountingUp => "ToolLife/WearRadius/IsCountingUp",
    }
}

node_table! {
    /// A variable of a tool's running-wear entry (placed below its
    /// `ToolLife` while a compensation runs on it).
    RunningVar in "running-wear entry" {
        /// The wear of the compensation running now, mm.
        RunningWear => "RunningWear",
        /// Its unit.
        Units => "RunningWear/EngineeringUnits",
        /// What it indicates.
        Indication => "RunningWear/Indication",
        /// Whether it counts up.
        CountingUp => "RunningWear/IsCountingUp",
    }
}

/// A tool life entry's variables in one table: the value, its unit, what
/// it indicates, whether it counts up.
pub(crate) type LifeEntry<V> = [V; 4];

/// The booked wear's entry.
pub(crate) const WEAR_ENTRY: LifeEntry<ToolVar> = [
    ToolVar::WearRadius,
    ToolVar::WearUnits,
    ToolVar::WearIndication,
    ToolVar::WearCountingUp,
];

/// The running wear's entry.
pub(crate) const RUNNING_ENTRY: LifeEntry<RunningVar> = [
    RunningVar::RunningWear,
    RunningVar::Units,
    RunningVar::Indication,
    RunningVar::CountingUp,
];

/// A template that holds every variable of table `V`: values are set by
/// name, and cannot miss.
#[derive(Debug, Clone)]
pub(crate) struct Checked<V> {
    template: Template,
    table: PhantomData<V>,
}

impl<V: NodeTable> Checked<V> {
    /// `template`, if it holds every variable of `V`; else the first one
    /// missing.
    pub fn new(template: Template) -> Result<Self, ModelError> {
        for &v in V::ALL {
            let is_variable = template
                .parts
                .iter()
                .find(|p| p.path == v.path())
                .is_some_and(|p| matches!(p.kind, Kind::Variable { .. }));
            if !is_variable {
                return Err(ModelError::Variable {
                    instance: V::INSTANCE,
                    path: v.path(),
                });
            }
        }
        Ok(Self {
            template,
            table: PhantomData,
        })
    }

    /// Sets the value of variable `v`.
    pub fn set(&mut self, v: V, value: impl Into<Variant>) {
        // Every variable of the table is there (checked by `new`).
        let _ = self.template.set(v.path(), value);
    }

    /// The template.
    pub fn template(&self) -> &Template {
        &self.template
    }

    /// The template, the values set.
    pub fn into_template(self) -> Template {
        self.template
    }

    /// The template, to change what is not a value of the table (names,
    /// descriptions).
    pub fn template_mut(&mut self) -> &mut Template {
        &mut self.template
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use std::any::Any;
    use std::collections::HashSet;
    use std::sync::Arc;

    use opcua::server::address_space::{AddressSpace, CoreNamespace, DefaultTypeTree};

    use super::*;
    use crate::machine::model::{self, Spaces};
    use crate::machine::nodesets::{self, MACHINERY, MACHINE_TOOL};
    use crate::machine::tools;
    use crate::machine::types::Types;
    use crate::machine::view::{Identity, MachineSource, MachineTool, MachineView};

    /// A source that never sees a machine (the model needs none).
    struct Nothing;

    impl MachineSource for Nothing {
        fn look(&self, _handler: &mut dyn Any) -> Option<MachineView> {
            None
        }
    }

    fn machine_tool() -> MachineTool {
        MachineTool {
            name: "Test".into(),
            identity: Identity {
                manufacturer: "m".into(),
                model: "m".into(),
                software_revision: "1".into(),
                serial_number: "1".into(),
                product_instance_uri: "urn:test".into(),
            },
            tool_kinds: vec!["mill".into()],
            source: Arc::new(Nothing),
        }
    }

    fn unique_paths<V: NodeTable>() -> bool {
        let paths: HashSet<&str> = V::ALL.iter().map(|v| v.path()).collect();
        paths.len() == V::ALL.len()
    }

    #[test]
    fn every_table_names_each_path_once() {
        assert!(unique_paths::<MachineVar>());
        assert!(unique_paths::<ToolVar>());
        assert!(unique_paths::<RunningVar>());
    }

    /// The built-in NodeSets and OPC UA's own types, loaded as the server
    /// loads them (the face's namespace first).
    #[test]
    fn every_variable_of_the_tables_is_in_the_instances_the_nodesets_give() {
        let mut tree = DefaultTypeTree::new();
        let own_ns = tree
            .namespaces_mut()
            .add_namespace(crate::manager::NAMESPACE);
        let mut core = AddressSpace::new();
        core.add_namespace("http://opcfoundation.org/UA/", 0);
        core.import_node_set(&CoreNamespace, tree.namespaces_mut());
        let mut own = AddressSpace::new();
        own.add_namespace(crate::manager::NAMESPACE, own_ns);
        nodesets::import(&mut own, tree.namespaces_mut()).unwrap();
        core.load_into_type_tree(&mut tree);
        own.load_into_type_tree(&mut tree);
        let index = |uri| tree.namespaces().get_index(uri).unwrap();
        let at = Spaces {
            own: own_ns,
            mt: index(MACHINE_TOOL),
            machinery: index(MACHINERY),
        };
        let types = Types::new(vec![&own, &core], &tree);
        let machine = model::machine(&types, at, &machine_tool()).unwrap();
        assert!(Checked::<MachineVar>::new(machine).is_ok());
        let kinds = ["mill".to_string()];
        let t = tools::templates(&types, at, &kinds).unwrap();
        assert!(Checked::<ToolVar>::new(t.tool.into_template()).is_ok());
        assert!(Checked::<RunningVar>::new(t.running.into_template()).is_ok());
    }

    #[test]
    fn a_template_without_a_variable_of_the_table_is_refused() {
        let e = Checked::<RunningVar>::new(Template::default()).unwrap_err();
        assert_eq!(
            e.to_string(),
            "the running-wear entry has no variable RunningWear"
        );
    }
}
