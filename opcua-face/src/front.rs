//! The face's node manager as the server sees it: the in-memory manager
//! of its namespace behind a [`Delegating`] manager, with two differences
//! (and the machine built when the server starts it).
//!
//! * AccessLevel applies to the Value attribute only. The in-memory
//!   manager checks a variable's AccessLevel on every attribute, so a
//!   write-only object (a command such as `Clean`) would answer its
//!   BrowseName, DisplayName and DataType with `BadUserAccessDenied`, and
//!   browsing clients stumble on it. Every other attribute of a variable
//!   is read here without that check.
//! * Browsing lists the nodes in the order of the table (`browse`).

use std::sync::{Arc, Mutex};

use async_trait::async_trait;
use opcua::server::address_space::{
    is_supported_data_encoding, read_node_value, AddressSpace, DefaultTypeTree, NodeType,
};
use opcua::server::node_manager::{
    BrowseNode, DynNodeManager, NodeManager, NodeManagerBuilder, ReadNode, RequestContext,
    ServerContext,
};
use opcua::types::{AttributeId, DataValue, NumericRange, StatusCode, TimestampsToReturn};

use tokio_util::sync::DropGuard;

use crate::browse::browse;
use crate::capped::too_large;
use crate::delegating::{Delegating, Overrides};
use crate::machine::live::Manager;
use crate::machine::setup;

/// Builds the face's in-memory node manager, then the front around it.
pub(crate) struct FrontBuilder<B> {
    /// The in-memory manager's builder.
    pub inner: B,
    /// The largest response, bytes (`capped.rs`).
    pub largest: usize,
}

impl<B: NodeManagerBuilder> NodeManagerBuilder for FrontBuilder<B> {
    fn build(self: Box<Self>, context: ServerContext) -> Arc<DynNodeManager> {
        let largest = self.largest;
        let built = Box::new(self.inner).build(context);
        match Arc::clone(&built).into_any_arc().downcast::<Manager>() {
            Ok(inner) => {
                let front = Front {
                    machine: Mutex::new(None),
                    largest,
                };
                Arc::new(Delegating::new(inner, front))
            }
            // Not the face's manager: nothing to change.
            Err(_) => built,
        }
    }
}

/// What the front changes of the face's manager: its start (the machine
/// is built once every type is known), its reads and its browsing.
struct Front {
    /// Stops the machine's live updates with the face.
    machine: Mutex<Option<DropGuard>>,
    /// The largest response, bytes: a Read asking more is refused before
    /// any value is copied (`capped.rs`).
    largest: usize,
}

/// Whether the read of `node` is an attribute other than the Value of a
/// variable of `space`.
fn is_other_attribute(space: &AddressSpace, node: &ReadNode) -> bool {
    node.node().attribute_id != AttributeId::Value
        && matches!(
            space.find(&node.node().node_id),
            Some(NodeType::Variable(_))
        )
}

/// Reads a variable's attribute other than Value: every check but the
/// access level.
fn read_attribute(
    space: &AddressSpace,
    context: &RequestContext,
    node: &ReadNode,
    max_age: f64,
    stamps: TimestampsToReturn,
) -> DataValue {
    let id = node.node();
    let refused = |status| DataValue {
        status: Some(status),
        ..Default::default()
    };
    if id.index_range != NumericRange::None {
        return refused(StatusCode::BadIndexRangeDataMismatch);
    }
    if !is_supported_data_encoding(&id.data_encoding) {
        return refused(StatusCode::BadDataEncodingInvalid);
    }
    match space.find(&id.node_id) {
        Some(found) => read_node_value(found, context, id, max_age, stamps),
        None => refused(StatusCode::BadNodeIdUnknown),
    }
}

#[async_trait]
impl Overrides<Manager> for Front {
    /// The manager's own start, then (every type known now) the machine.
    async fn init(
        &self,
        inner: &Arc<Manager>,
        type_tree: &mut DefaultTypeTree,
        context: ServerContext,
    ) {
        inner.init(type_tree, context.clone()).await;
        let Some((machine, core)) = inner.inner().machine() else {
            return;
        };
        let ns = inner.inner().ns();
        match setup::start(inner, type_tree, &context, ns, machine, core.clone()) {
            Ok(guard) => {
                *self.machine.lock().unwrap_or_else(|p| p.into_inner()) = Some(guard);
            }
            Err(e) => tracing::error!("OPC UA: the machine is not shown: {e}"),
        }
    }

    async fn read(
        &self,
        inner: &Arc<Manager>,
        context: &RequestContext,
        max_age: f64,
        stamps: TimestampsToReturn,
        nodes: &mut [&mut ReadNode],
    ) -> Result<(), StatusCode> {
        let mut rest: Vec<&mut ReadNode> = Vec::with_capacity(nodes.len());
        {
            let space = inner.address_space().read();
            if too_large(&space, nodes, self.largest) {
                return Err(StatusCode::BadResponseTooLarge);
            }
            for node in nodes.iter_mut() {
                if is_other_attribute(&space, node) {
                    node.set_result(read_attribute(&space, context, node, max_age, stamps));
                } else {
                    rest.push(node);
                }
            }
        }
        if rest.is_empty() {
            return Ok(());
        }
        inner.read(context, max_age, stamps, &mut rest).await
    }

    async fn browse(
        &self,
        inner: &Arc<Manager>,
        context: &RequestContext,
        nodes: &mut [BrowseNode],
    ) -> Result<(), StatusCode> {
        let space = inner.address_space().read();
        let types = context.type_tree.read();
        let (ns, order) = (inner.inner().ns(), inner.inner().order());
        for node in nodes.iter_mut() {
            if node.node_id().is_null() {
                continue;
            }
            node.set_status(StatusCode::Good);
            browse(&space, &types, ns, order, node);
        }
        Ok(())
    }
}
