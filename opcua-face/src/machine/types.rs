//! Reading the type model the server holds (OPC UA's own types in the
//! core node manager, the companion NodeSets in the face's): a type's
//! supertypes, and its InstanceDeclarations with their modelling rules, as
//! OPC 10000-3 defines them: the members of a type and of every supertype
//! and interface it has, a subtype's member replacing the one of the same
//! BrowseName.

use std::collections::HashMap;

use crate::stored::stored_value;
use opcua::server::address_space::{AddressSpace, DefaultTypeTree, NodeBase, NodeType, TypeTree};
use opcua::types::{BrowseDirection, NodeId, ObjectId, QualifiedName, ReferenceTypeId, Variant};

/// What an InstanceDeclaration's modelling rule asks of an instance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Rule {
    /// Every instance has it.
    Mandatory,
    /// An instance may have it.
    Optional,
    /// Stands for any number of members of its type (at least one).
    MandatoryPlaceholder,
    /// Stands for any number of members of its type (none too).
    OptionalPlaceholder,
    /// Any other rule (ExposesItsArray), or none: not a member to make.
    Other,
}

impl Rule {
    /// The rule of a HasModellingRule target.
    fn of(target: &NodeId) -> Self {
        let is = |id: ObjectId| *target == id;
        if is(ObjectId::ModellingRule_Mandatory) {
            Rule::Mandatory
        } else if is(ObjectId::ModellingRule_Optional) {
            Rule::Optional
        } else if is(ObjectId::ModellingRule_MandatoryPlaceholder) {
            Rule::MandatoryPlaceholder
        } else if is(ObjectId::ModellingRule_OptionalPlaceholder) {
            Rule::OptionalPlaceholder
        } else {
            Rule::Other
        }
    }
}

/// An InstanceDeclaration: a member of a type.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Decl {
    /// Its BrowseName (the instance's member has the same).
    pub name: QualifiedName,
    /// The declaring node.
    pub node: NodeId,
    /// The reference from its parent (HasComponent, HasProperty, ...).
    pub reference: NodeId,
    /// Its modelling rule.
    pub rule: Rule,
}

/// The type model: the address spaces that hold types, and the server's
/// type tree.
pub(crate) struct Types<'a> {
    spaces: Vec<&'a AddressSpace>,
    tree: &'a DefaultTypeTree,
}

impl<'a> Types<'a> {
    /// The model of `spaces` (looked up in this order) and `tree`.
    pub fn new(spaces: Vec<&'a AddressSpace>, tree: &'a DefaultTypeTree) -> Self {
        Self { spaces, tree }
    }

    /// The node `id`, from whichever space holds it.
    pub fn node(&self, id: &NodeId) -> Option<&'a NodeType> {
        self.spaces.iter().find_map(|s| s.find(id))
    }

    /// The (reference type, target) of `id`'s references of `kind` (and
    /// its subtypes) in `direction`, from every space.
    pub fn references(
        &self,
        id: &NodeId,
        kind: impl Into<NodeId>,
        direction: BrowseDirection,
    ) -> Vec<(NodeId, NodeId)> {
        let kind: NodeId = kind.into();
        let mut out = Vec::new();
        for space in &self.spaces {
            for r in space.find_references(id, Some((kind.clone(), true)), self.tree, direction) {
                let found = (r.reference_type.clone(), r.target_node.clone());
                if !out.contains(&found) {
                    out.push(found);
                }
            }
        }
        out
    }

    /// The first target of `id`'s forward references of `kind`.
    fn target(&self, id: &NodeId, kind: ReferenceTypeId) -> Option<NodeId> {
        self.references(id, kind, BrowseDirection::Forward)
            .into_iter()
            .map(|(_, t)| t)
            .next()
    }

    /// The TypeDefinition of an object or variable.
    pub fn type_definition(&self, id: &NodeId) -> Option<NodeId> {
        self.target(id, ReferenceTypeId::HasTypeDefinition)
    }

    /// The modelling rule of a node (`Other` for none).
    pub fn rule(&self, id: &NodeId) -> Rule {
        self.target(id, ReferenceTypeId::HasModellingRule)
            .map_or(Rule::Other, |r| Rule::of(&r))
    }

    /// Whether `child` is `ancestor` or one of its subtypes.
    pub fn is_subtype(&self, child: &NodeId, ancestor: &NodeId) -> bool {
        self.tree.is_subtype_of(child, ancestor)
    }

    /// `ty` and its supertypes, most derived first.
    pub fn chain(&self, ty: &NodeId) -> Vec<NodeId> {
        let mut chain = vec![ty.clone()];
        let mut at = ty.clone();
        while let Some(up) = self.tree.get_supertype(&at) {
            if chain.contains(up) {
                break;
            }
            chain.push(up.clone());
            at = up.clone();
        }
        chain
    }

    /// The members declared right below `node` (a type, or an
    /// InstanceDeclaration with members of its own), by BrowseName.
    pub fn children(&self, node: &NodeId) -> Vec<Decl> {
        let mut out = Vec::new();
        for (reference, target) in self.references(
            node,
            ReferenceTypeId::HierarchicalReferences,
            BrowseDirection::Forward,
        ) {
            if self.is_subtype(&reference, &ReferenceTypeId::HasSubtype.into()) {
                continue;
            }
            let Some(found) = self.node(&target) else {
                continue;
            };
            out.push(Decl {
                name: found.as_node().browse_name().clone(),
                rule: self.rule(&target),
                node: target,
                reference,
            });
        }
        out
    }

    /// The InstanceDeclarations of type `ty`: its own members, those of
    /// its supertypes and of the interfaces it (or a supertype) has; a
    /// more derived member replaces one of the same BrowseName.
    pub fn declarations(&self, ty: &NodeId) -> Vec<Decl> {
        let mut by_name: HashMap<QualifiedName, Decl> = HashMap::new();
        let mut order: Vec<QualifiedName> = Vec::new();
        for t in self.chain(ty).iter().rev() {
            let interfaces =
                self.references(t, ReferenceTypeId::HasInterface, BrowseDirection::Forward);
            let mut layer: Vec<Decl> = interfaces
                .iter()
                .flat_map(|(_, i)| self.declarations(i))
                .collect();
            layer.extend(self.children(t));
            for d in layer {
                if !by_name.contains_key(&d.name) {
                    order.push(d.name.clone());
                }
                by_name.insert(d.name.clone(), d);
            }
        }
        order
            .into_iter()
            .filter_map(|n| by_name.remove(&n))
            .collect()
    }

    /// The members an instance of `ty` declared by `decl` (if any) gets:
    /// the type's declarations, replaced or extended by those declared
    /// below `decl` itself.
    pub fn members(&self, ty: &NodeId, decl: Option<&NodeId>) -> Vec<Decl> {
        let mut out = self.declarations(ty);
        for own in decl.map(|d| self.children(d)).unwrap_or_default() {
            match out.iter_mut().find(|d| d.name == own.name) {
                Some(d) => *d = own,
                None => out.push(own),
            }
        }
        out
    }

    /// The value a variable of the model holds (its default).
    pub fn value(&self, id: &NodeId) -> Variant {
        match self.node(id) {
            Some(NodeType::Variable(v)) => stored_value(v).unwrap_or_default(),
            _ => Variant::Empty,
        }
    }

    /// The state `name` of state machine type `machine` (or a supertype):
    /// its NodeId and StateNumber.
    pub fn state(&self, machine: &NodeId, name: &str) -> Option<(NodeId, u32)> {
        for t in self.chain(machine) {
            for (_, target) in
                self.references(&t, ReferenceTypeId::HasComponent, BrowseDirection::Forward)
            {
                let Some(NodeType::Object(state)) = self.node(&target) else {
                    continue;
                };
                if state.as_ref().browse_name().name.as_ref() != name {
                    continue;
                }
                let number = self
                    .children(&target)
                    .into_iter()
                    .filter(|d| d.name.name.as_ref() == "StateNumber")
                    .find_map(|d| match self.value(&d.node) {
                        Variant::UInt32(n) => Some(n),
                        _ => None,
                    });
                return Some((target, number.unwrap_or(0)));
            }
        }
        None
    }
}
