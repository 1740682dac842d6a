//! Browsing the face's nodes in the order of the table: Device0 before
//! Device4, Group1 before Group32, the objects of a group in the order of
//! the object map. The in-memory address space keeps references in a hash
//! set, so without this a browsing user would see them shuffled.

use std::cmp::Ordering;
use std::collections::{HashMap, VecDeque};

use opcua::server::address_space::{AddressSpace, DefaultTypeTree, ReferenceDirection};
use opcua::server::node_manager::{AddReferenceResult, BrowseNode, ExternalReference};
use opcua::types::{
    BrowseDirection, ExpandedNodeId, NodeClass, NodeId, ReferenceDescription, ReferenceTypeId,
};

/// The references a browse could not hand out at once (its continuation
/// point), in order.
#[derive(Debug, Default)]
pub(crate) struct Rest(VecDeque<ReferenceDescription>);

/// Where each node of the face comes in a browse result.
pub(crate) type Order = HashMap<NodeId, usize>;

/// Browses `node` in `space` (namespace `ns`), its references ordered by
/// `order` (nodes not in it last, by browse name).
pub(crate) fn browse(
    space: &AddressSpace,
    types: &DefaultTypeTree,
    ns: u16,
    order: &Order,
    node: &mut BrowseNode,
) {
    if let Some(mut rest) = node.take_continuation_point::<Rest>() {
        while node.remaining() > 0 {
            let Some(r) = rest.0.pop_front() else { break };
            node.add_unchecked(r);
        }
        if !rest.0.is_empty() {
            node.set_next_continuation_point(rest);
        }
        return;
    }
    let mut found = references(space, types, ns, node);
    found.sort_by(|a, b| {
        let key =
            |r: &ReferenceDescription| order.get(&r.node_id.node_id).copied().unwrap_or(usize::MAX);
        key(a)
            .cmp(&key(b))
            .then_with(|| natural(a.browse_name.name.as_ref(), b.browse_name.name.as_ref()))
    });
    let mut rest = Rest::default();
    for r in found {
        if let AddReferenceResult::Full(r) = node.add(types, r) {
            rest.0.push_back(r);
        }
    }
    if !rest.0.is_empty() {
        node.set_next_continuation_point(Box::new(rest));
    }
}

/// `a` against `b` with their runs of digits compared as numbers: `G1 T2`
/// before `G1 T10` (the tools of the Machine Tools model).
fn natural(a: &str, b: &str) -> Ordering {
    let (mut a, mut b) = (a, b);
    loop {
        match (a.chars().next(), b.chars().next()) {
            (None, None) => return Ordering::Equal,
            (None, Some(_)) => return Ordering::Less,
            (Some(_), None) => return Ordering::Greater,
            (Some(x), Some(y)) if x.is_ascii_digit() && y.is_ascii_digit() => {
                let (na, ra) = digits(a);
                let (nb, rb) = digits(b);
                let by_value = na
                    .trim_start_matches('0')
                    .len()
                    .cmp(&nb.trim_start_matches('0').len())
                    .then_with(|| na.trim_start_matches('0').cmp(nb.trim_start_matches('0')))
                    .then_with(|| na.len().cmp(&nb.len()));
                if by_value != Ordering::Equal {
                    return by_value;
                }
                (a, b) = (ra, rb);
            }
            (Some(x), Some(y)) => {
                if x != y {
                    return x.cmp(&y);
                }
                (a, b) = (&a[x.len_utf8()..], &b[y.len_utf8()..]);
            }
        }
    }
}

/// The leading digits of `s`, and the rest.
fn digits(s: &str) -> (&str, &str) {
    let end = s.find(|c: char| !c.is_ascii_digit()).unwrap_or(s.len());
    s.split_at(end)
}

/// The references of `node` to nodes of `space`; those to nodes of other
/// managers are handed to the server as external references.
fn references(
    space: &AddressSpace,
    types: &DefaultTypeTree,
    ns: u16,
    node: &mut BrowseNode,
) -> Vec<ReferenceDescription> {
    let filter = if node.reference_type_id().is_null() {
        None
    } else {
        node.reference_type_id()
            .as_reference_type_id()
            .ok()
            .map(|t| (t, node.include_subtypes()))
    };
    let source = node.node_id().clone();
    let mut found = Vec::new();
    for r in space.find_references(&source, filter, types, node.browse_direction()) {
        if r.target_node.is_null() {
            continue;
        }
        let Some(target) = space.find_node(r.target_node) else {
            if r.target_node.namespace != ns {
                let external = ExternalReference::new(
                    r.target_node.clone().into(),
                    r.reference_type.clone(),
                    r.direction,
                );
                node.push_external_reference(external);
            }
            continue;
        };
        let target = target.as_node();
        found.push(ReferenceDescription {
            reference_type_id: r.reference_type.clone(),
            is_forward: matches!(r.direction, ReferenceDirection::Forward),
            node_id: ExpandedNodeId::new(target.node_id().clone()),
            browse_name: target.browse_name().clone(),
            display_name: target.display_name().clone(),
            node_class: target.node_class(),
            type_definition: type_definition(space, types, target.node_id(), target.node_class()),
        });
    }
    found
}

/// The type definition of an object or variable (null for other classes).
fn type_definition(
    space: &AddressSpace,
    types: &DefaultTypeTree,
    id: &NodeId,
    class: NodeClass,
) -> ExpandedNodeId {
    if !matches!(class, NodeClass::Object | NodeClass::Variable) {
        return ExpandedNodeId::null();
    }
    space
        .find_references(
            id,
            Some((ReferenceTypeId::HasTypeDefinition, false)),
            types,
            BrowseDirection::Forward,
        )
        .next()
        .map_or_else(ExpandedNodeId::null, |t| {
            ExpandedNodeId::new(t.target_node.clone())
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_in_names_sort_by_value() {
        let mut names = [
            "G1 T10", "G10 T1", "G1 T2", "G2 T1", "G1 T02", "Tools", "G1",
        ];
        names.sort_by(|a, b| natural(a, b));
        assert_eq!(
            names,
            ["G1", "G1 T2", "G1 T02", "G1 T10", "G2 T1", "G10 T1", "Tools"]
        );
        assert_eq!(natural("Axis7", "Axis7"), Ordering::Equal);
        assert_eq!(natural("b", "a1"), Ordering::Greater);
    }
}
