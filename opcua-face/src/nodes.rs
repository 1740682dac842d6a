//! The planned folders and variables as nodes of the OPC UA address
//! space: folders organise, a variable carries its data type, access level
//! and, where its writable range is one interval, an `EURange` property
//! (the variable is then an `AnalogItemType`). No variable holds a value.

use std::collections::HashMap;

use opcua::server::address_space::{AccessLevel, AddressSpace, ObjectBuilder, VariableBuilder};
use opcua::types::{
    DataTypeId, ExtensionObject, LocalizedText, NodeId, ObjectId, QualifiedName, Range,
    VariableTypeId, Variant,
};
use uoi::Access;

use crate::points::{data_type, Point};
use crate::sampler::TICK;
use crate::space::{Parent, Plan, Var};

/// Puts the nodes of `plan` into `space` (namespace `ns`); gives the
/// variables by NodeId.
pub(crate) fn insert(space: &mut AddressSpace, ns: u16, plan: &Plan) -> HashMap<NodeId, Point> {
    for folder in &plan.folders {
        let parent = match &folder.parent {
            Parent::Objects => ObjectId::ObjectsFolder.into(),
            Parent::Folder(id) => NodeId::new(ns, id.as_str()),
        };
        ObjectBuilder::new(
            &NodeId::new(ns, folder.id.as_str()),
            QualifiedName::new(ns, folder.name.as_str()),
            folder.name.as_str(),
        )
        .is_folder()
        .description(LocalizedText::from(folder.doc.as_str()))
        .organized_by(parent)
        .insert(space);
    }
    plan.vars
        .iter()
        .map(|var| {
            let id = NodeId::new(ns, var.id.as_str());
            insert_var(space, ns, &id, var);
            let point = Point {
                source: var.source,
                access: var.access,
            };
            (id, point)
        })
        .collect()
}

/// The access level of an access right.
pub(crate) fn access_level(access: Access) -> AccessLevel {
    match access {
        Access::ReadOnly => AccessLevel::CURRENT_READ,
        Access::WriteOnly => AccessLevel::CURRENT_WRITE,
        Access::ReadWrite => AccessLevel::CURRENT_READ | AccessLevel::CURRENT_WRITE,
    }
}

/// One variable, and its `EURange` where it has one.
fn insert_var(space: &mut AddressSpace, ns: u16, id: &NodeId, var: &Var) {
    let level = access_level(var.access);
    let kind = if var.range.is_some() {
        VariableTypeId::AnalogItemType
    } else {
        VariableTypeId::BaseDataVariableType
    };
    VariableBuilder::new(
        id,
        QualifiedName::new(ns, var.name.as_str()),
        var.name.as_str(),
    )
    .description(LocalizedText::from(var.doc.as_str()))
    .data_type(data_type(var.ty))
    .value_rank(-1)
    .access_level(level)
    .user_access_level(level)
    .minimum_sampling_interval(TICK.as_secs_f64() * 1e3)
    .has_type_definition(kind)
    .organized_by(NodeId::new(ns, var.parent.as_str()))
    .insert(space);
    if let Some((low, high)) = var.range {
        let range = ExtensionObject::from_message(Range { low, high });
        VariableBuilder::new(
            &NodeId::new(ns, format!("{}/EURange", var.id).as_str()),
            QualifiedName::new(0, "EURange"),
            "EURange",
        )
        .description(LocalizedText::from("Values a write may carry"))
        .data_type(DataTypeId::Range)
        .value_rank(-1)
        .value(Variant::from(range))
        .access_level(AccessLevel::CURRENT_READ)
        .user_access_level(AccessLevel::CURRENT_READ)
        .has_type_definition(VariableTypeId::PropertyType)
        .property_of(id.clone())
        .insert(space);
    }
}
