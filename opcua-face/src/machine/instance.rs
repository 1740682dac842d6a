//! Instances of the model's types: an object or variable of a type with
//! every Mandatory member (recursively: each member an instance of its own
//! type), the Optional members asked for by path, the attributes copied
//! from the InstanceDeclarations. Planned once as a [`Template`] with
//! relative paths, then placed (NodeIds from a base) as often as needed:
//! a tool is placed whenever one appears.

use crate::stored::stored_value;
use opcua::server::address_space::{
    AccessLevel, AddressSpace, EventNotifier, NodeType, ObjectBuilder, ReferenceDirection,
    VariableBuilder,
};
use opcua::types::{
    DataTypeId, LocalizedText, NodeClass, NodeId, QualifiedName, ReferenceTypeId, Variant,
};

use super::types::{Decl, Rule, Types};

/// What an object or variable of a template is.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Kind {
    /// An object.
    Object,
    /// A variable: its data type, value rank, array dimensions and value.
    Variable {
        data_type: NodeId,
        value_rank: i32,
        dims: Option<Vec<u32>>,
        value: Variant,
    },
}

/// One node of a template.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Part {
    /// Its path below the template's root, BrowseName names joined by `/`
    /// (empty for the root).
    pub path: String,
    /// Its parent's path (`None`: the root, whose parent is outside).
    pub parent: Option<String>,
    /// The reference from the parent.
    pub reference: NodeId,
    pub browse_name: QualifiedName,
    pub display_name: LocalizedText,
    pub description: Option<LocalizedText>,
    pub type_definition: NodeId,
    pub kind: Kind,
}

/// The nodes of one instance, parents first.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Template {
    pub parts: Vec<Part>,
}

/// The root of an instance: what it is called, its type, and the
/// declaration (a placeholder) it instantiates, if any.
pub(crate) struct Root<'n> {
    pub browse_name: QualifiedName,
    pub reference: NodeId,
    pub type_definition: NodeId,
    pub decl: Option<&'n NodeId>,
}

/// Data types a value may narrow (a variable declared `Number` holds a
/// Double): abstract ones.
const ABSTRACT_TYPES: [DataTypeId; 4] = [
    DataTypeId::BaseDataType,
    DataTypeId::Number,
    DataTypeId::Integer,
    DataTypeId::UInteger,
];

/// `path` joined with a member's name (either may be empty).
fn join(path: &str, name: &str) -> String {
    match (path.is_empty(), name.is_empty()) {
        (true, _) => name.to_owned(),
        (false, true) => path.to_owned(),
        (false, false) => format!("{path}/{name}"),
    }
}

impl Template {
    /// The instance of `root`'s type with its Mandatory members and the
    /// Optional ones `optional` names (paths below the root).
    pub fn plan(types: &Types<'_>, root: Root<'_>, optional: &[&str]) -> Self {
        let mut t = Template::default();
        let source = root.decl.cloned().unwrap_or(root.type_definition.clone());
        let part = t.part(
            types,
            "",
            None,
            &root.browse_name,
            &root.reference,
            &source,
            &root.type_definition,
        );
        t.parts.push(part);
        t.members(types, "", &root.type_definition, root.decl, optional);
        t
    }

    /// Adds the members of the node at `path` (of type `ty`, declared by
    /// `decl`), each with its own members.
    fn members(
        &mut self,
        types: &Types<'_>,
        path: &str,
        ty: &NodeId,
        decl: Option<&NodeId>,
        optional: &[&str],
    ) {
        for d in types.members(ty, decl) {
            let child = join(path, d.name.name.as_ref());
            let wanted = match d.rule {
                Rule::Mandatory => true,
                Rule::Optional => optional.contains(&child.as_str()),
                _ => false,
            };
            if !wanted {
                continue;
            }
            let Some(td) = types.type_definition(&d.node) else {
                continue;
            };
            let part = self.part(
                types,
                &child,
                Some(path),
                &d.name,
                &d.reference,
                &d.node,
                &td,
            );
            self.parts.push(part);
            self.members(types, &child, &td, Some(&d.node), optional);
        }
    }

    /// Adds an instance of another type below the node at `path` (a
    /// placeholder's member, or one of the server's own).
    pub fn add(&mut self, types: &Types<'_>, path: &str, root: Root<'_>, optional: &[&str]) {
        let child = join(path, root.browse_name.name.as_ref());
        let source = root.decl.cloned().unwrap_or(root.type_definition.clone());
        let part = self.part(
            types,
            &child,
            Some(path),
            &root.browse_name,
            &root.reference,
            &source,
            &root.type_definition,
        );
        self.parts.push(part);
        let full: Vec<String> = optional.iter().map(|o| join(&child, o)).collect();
        let full: Vec<&str> = full.iter().map(String::as_str).collect();
        self.members(types, &child, &root.type_definition, root.decl, &full);
    }

    /// One part copied from `source` (a declaration, or the type itself).
    #[allow(clippy::too_many_arguments)]
    fn part(
        &self,
        types: &Types<'_>,
        path: &str,
        parent: Option<&str>,
        name: &QualifiedName,
        reference: &NodeId,
        source: &NodeId,
        type_definition: &NodeId,
    ) -> Part {
        let node = types.node(source);
        let kind = match node {
            Some(NodeType::Variable(v)) => Kind::Variable {
                data_type: v.data_type(),
                value_rank: v.value_rank(),
                dims: v.array_dimensions(),
                value: stored_value(v).unwrap_or_default(),
            },
            Some(NodeType::VariableType(v)) => Kind::Variable {
                data_type: v.data_type().clone(),
                value_rank: v.value_rank(),
                dims: v.array_dimensions(),
                value: v.value().and_then(|d| d.value.clone()).unwrap_or_default(),
            },
            _ => Kind::Object,
        };
        let from_decl =
            node.filter(|n| matches!(n.node_class(), NodeClass::Object | NodeClass::Variable));
        Part {
            path: path.to_owned(),
            parent: parent.map(str::to_owned),
            reference: reference.clone(),
            browse_name: name.clone(),
            display_name: from_decl
                .map(|n| n.as_node().display_name().clone())
                .unwrap_or_else(|| name.name.as_ref().into()),
            description: from_decl.and_then(|n| n.as_node().description().cloned()),
            type_definition: type_definition.clone(),
            kind,
        }
    }

    /// The part at `path`.
    pub fn get_mut(&mut self, path: &str) -> Option<&mut Part> {
        self.parts.iter_mut().find(|p| p.path == path)
    }

    /// Sets the value of the variable at `path` (an abstract data type
    /// narrowed to the value's); `false` if there is none.
    pub fn set(&mut self, path: &str, value: impl Into<Variant>) -> bool {
        let value: Variant = value.into();
        let Some(Part {
            kind:
                Kind::Variable {
                    data_type,
                    value: v,
                    ..
                },
            ..
        }) = self.get_mut(path)
        else {
            return false;
        };
        if ABSTRACT_TYPES.iter().any(|t| *data_type == *t) {
            if let Some(t) = value.data_type() {
                *data_type = t.node_id;
            }
        }
        *v = value;
        true
    }

    /// Sets the display name and description of the node at `path`.
    pub fn describe(&mut self, path: &str, display: &str, description: &str) {
        if let Some(p) = self.get_mut(path) {
            p.display_name = display.into();
            p.description = Some(description.into());
        }
    }

    /// The NodeId of the node at `path` when placed at `base`.
    pub fn id(ns: u16, base: &str, path: &str) -> NodeId {
        NodeId::new(ns, join(base, path).as_str())
    }

    /// Puts the instance into `space` (namespace `ns`), its root at
    /// NodeId `base` below `parent`; read-only variables. Gives the
    /// NodeIds made (a part the library finds invalid is left out).
    pub fn place(
        &self,
        space: &mut AddressSpace,
        ns: u16,
        base: &str,
        parent: &NodeId,
    ) -> Vec<NodeId> {
        let mut made = Vec::with_capacity(self.parts.len());
        for p in &self.parts {
            let id = Self::id(ns, base, &p.path);
            let up = match &p.parent {
                Some(path) => Self::id(ns, base, path),
                None => parent.clone(),
            };
            let Some(node) = p.node(&id) else {
                continue;
            };
            let type_of: NodeId = ReferenceTypeId::HasTypeDefinition.into();
            let refs = [
                (&up, &p.reference, ReferenceDirection::Inverse),
                (&p.type_definition, &type_of, ReferenceDirection::Forward),
            ];
            if space.insert(node, Some(&refs[..])) {
                made.push(id);
            }
        }
        made
    }
}

impl Part {
    /// The node of this part with NodeId `id` (`None` if invalid).
    fn node(&self, id: &NodeId) -> Option<NodeType> {
        let description = self.description.clone().unwrap_or_default();
        match &self.kind {
            Kind::Object => {
                let b = ObjectBuilder::new(id, self.browse_name.clone(), self.display_name.clone())
                    .description(description)
                    .event_notifier(EventNotifier::empty());
                b.is_valid().then(|| b.build().into())
            }
            Kind::Variable {
                data_type,
                value_rank,
                dims,
                value,
            } => {
                let mut b =
                    VariableBuilder::new(id, self.browse_name.clone(), self.display_name.clone())
                        .description(description)
                        .data_type(data_type.clone())
                        .value_rank(*value_rank)
                        .value(value.clone())
                        .access_level(AccessLevel::CURRENT_READ)
                        .user_access_level(AccessLevel::CURRENT_READ);
                if let Some(d) = dims {
                    b = b.array_dimensions(d);
                }
                b.is_valid().then(|| b.build().into())
            }
        }
    }
}

/// The declaration among `decls` named `name`.
pub(crate) fn named<'d>(decls: &'d [Decl], name: &str) -> Option<&'d Decl> {
    decls.iter().find(|d| d.name.name.as_ref() == name)
}
