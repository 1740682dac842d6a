//! The face's node manager as the server sees it: the in-memory manager
//! of its namespace, with two differences.
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
use opcua::server::diagnostics::NamespaceMetadata;
use opcua::server::node_manager::memory::InMemoryNodeManager;
use opcua::server::node_manager::{
    BrowseNode, BrowsePathItem, DynNodeManager, ExternalReferenceRequest, MonitoredItemRef,
    MonitoredItemUpdateRef, NodeManager, NodeManagerBuilder, ReadNode, RegisterNodeItem,
    RequestContext, ServerContext, WriteNode,
};
use opcua::server::CreateMonitoredItem;
use opcua::types::{
    AttributeId, DataValue, ExpandedNodeId, MonitoringMode, NodeId, NumericRange, StatusCode,
    TimestampsToReturn,
};

use tokio_util::sync::DropGuard;

use crate::browse::browse;
use crate::capped::too_large;
use crate::machine::setup;
use crate::manager::ObjectNodes;

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
        match Arc::clone(&built)
            .into_any_arc()
            .downcast::<InMemoryNodeManager<ObjectNodes>>()
        {
            Ok(inner) => Arc::new(Front {
                inner,
                machine: Mutex::new(None),
                largest,
            }),
            // Not the face's manager: nothing to change.
            Err(_) => built,
        }
    }
}

/// The front.
struct Front {
    inner: Arc<InMemoryNodeManager<ObjectNodes>>,
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
impl NodeManager for Front {
    fn owns_node(&self, id: &NodeId) -> bool {
        self.inner.owns_node(id)
    }

    fn name(&self) -> &str {
        self.inner.name()
    }

    fn owns_server_events(&self) -> bool {
        self.inner.owns_server_events()
    }

    fn handle_new_node(&self, parent_id: &ExpandedNodeId) -> bool {
        self.inner.handle_new_node(parent_id)
    }

    fn namespaces_for_user(&self, context: &RequestContext) -> Vec<NamespaceMetadata> {
        self.inner.namespaces_for_user(context)
    }

    /// The manager's own start, then (every type known now) the machine.
    async fn init(&self, type_tree: &mut DefaultTypeTree, context: ServerContext) {
        self.inner.init(type_tree, context.clone()).await;
        let Some((machine, core)) = self.inner.inner().machine() else {
            return;
        };
        let ns = self.inner.inner().ns();
        match setup::start(&self.inner, type_tree, &context, ns, machine, core.clone()) {
            Ok(guard) => {
                *self.machine.lock().unwrap_or_else(|p| p.into_inner()) = Some(guard);
            }
            Err(e) => tracing::error!("OPC UA: the machine is not shown: {e}"),
        }
    }

    async fn resolve_external_references(
        &self,
        context: &RequestContext,
        items: &mut [&mut ExternalReferenceRequest],
    ) {
        self.inner.resolve_external_references(context, items).await;
    }

    async fn read(
        &self,
        context: &RequestContext,
        max_age: f64,
        stamps: TimestampsToReturn,
        nodes: &mut [&mut ReadNode],
    ) -> Result<(), StatusCode> {
        let mut rest: Vec<&mut ReadNode> = Vec::with_capacity(nodes.len());
        {
            let space = self.inner.address_space().read();
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
        self.inner.read(context, max_age, stamps, &mut rest).await
    }

    async fn write(
        &self,
        context: &RequestContext,
        nodes: &mut [&mut WriteNode],
    ) -> Result<(), StatusCode> {
        self.inner.write(context, nodes).await
    }

    async fn browse(
        &self,
        context: &RequestContext,
        nodes: &mut [BrowseNode],
    ) -> Result<(), StatusCode> {
        let space = self.inner.address_space().read();
        let types = context.type_tree.read();
        let (ns, order) = (self.inner.inner().ns(), self.inner.inner().order());
        for node in nodes.iter_mut() {
            if node.node_id().is_null() {
                continue;
            }
            node.set_status(StatusCode::Good);
            browse(&space, &types, ns, order, node);
        }
        Ok(())
    }

    async fn translate_browse_paths_to_node_ids(
        &self,
        context: &RequestContext,
        nodes: &mut [&mut BrowsePathItem],
    ) -> Result<(), StatusCode> {
        self.inner
            .translate_browse_paths_to_node_ids(context, nodes)
            .await
    }

    async fn register_nodes(
        &self,
        context: &RequestContext,
        nodes: &mut [&mut RegisterNodeItem],
    ) -> Result<(), StatusCode> {
        self.inner.register_nodes(context, nodes).await
    }

    async fn unregister_nodes(
        &self,
        context: &RequestContext,
        nodes: &[&NodeId],
    ) -> Result<(), StatusCode> {
        self.inner.unregister_nodes(context, nodes).await
    }

    async fn create_monitored_items(
        &self,
        context: &RequestContext,
        items: &mut [&mut CreateMonitoredItem],
    ) -> Result<(), StatusCode> {
        self.inner.create_monitored_items(context, items).await
    }

    async fn modify_monitored_items(
        &self,
        context: &RequestContext,
        items: &[&MonitoredItemUpdateRef],
    ) {
        self.inner.modify_monitored_items(context, items).await;
    }

    async fn set_monitoring_mode(
        &self,
        context: &RequestContext,
        mode: MonitoringMode,
        items: &[&MonitoredItemRef],
    ) {
        self.inner.set_monitoring_mode(context, mode, items).await;
    }

    async fn delete_monitored_items(&self, context: &RequestContext, items: &[&MonitoredItemRef]) {
        self.inner.delete_monitored_items(context, items).await;
    }
}
