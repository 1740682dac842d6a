//! Reads that could not be answered are refused before they cost memory.
//!
//! A response larger than the server's largest message fails when it is
//! encoded (`BadResponseTooLarge`), but the library builds it first: a
//! Read naming 5,000 times the type dictionary of namespace 0 (318 kB)
//! made the server copy 1.6 GB before refusing it, and a client
//! pipelining such Reads grew it to 2 GB. Here the values a Read asks of
//! a node manager are sized from the address space (each distinct node
//! once) before anything is copied, and a Read whose values add up to more
//! than a response may hold gets `BadResponseTooLarge` for each of them.
//! [`Capped`] puts the core node manager (namespace 0) behind that check;
//! the face's own manager applies it in its `read` (`front.rs`).

use std::collections::HashMap;
use std::sync::Arc;

use crate::stored::stored_value;
use async_trait::async_trait;
use opcua::server::address_space::{AddressSpace, DefaultTypeTree, NodeType};
use opcua::server::diagnostics::NamespaceMetadata;
use opcua::server::node_manager::memory::{CoreNodeManager, InMemoryNodeManagerBuilder};
use opcua::server::node_manager::{
    AddNodeItem, AddReferenceItem, BrowseNode, BrowsePathItem, DeleteNodeItem, DeleteReferenceItem,
    DynNodeManager, ExternalReferenceRequest, HistoryNode, HistoryUpdateNode, MethodCall,
    MonitoredItemRef, MonitoredItemUpdateRef, NodeManager, NodeManagerBuilder, QueryRequest,
    ReadNode, RegisterNodeItem, RequestContext, ServerContext, WriteNode,
};
use opcua::server::CreateMonitoredItem;
use opcua::sync::RwLock;
use opcua::types::{
    AttributeId, ExpandedNodeId, MonitoringMode, NodeId, ReadAnnotationDataDetails,
    ReadAtTimeDetails, ReadEventDetails, ReadProcessedDetails, ReadRawModifiedDetails, StatusCode,
    TimestampsToReturn, Variant,
};

/// Bytes a value is counted at beyond its strings and byte strings (the
/// encoding's own overhead, a number, a structure's fixed fields).
const OVERHEAD: usize = 32;

/// The encoded size of `value`, roughly: its strings, byte strings and
/// elements counted in full, everything else at [`OVERHEAD`].
fn size(value: &Variant) -> usize {
    OVERHEAD
        + match value {
            Variant::ByteString(b) => b.value.as_ref().map_or(0, Vec::len),
            Variant::String(s) => s.value().as_ref().map_or(0, String::len),
            Variant::XmlElement(x) => x.to_string().len(),
            Variant::LocalizedText(t) => {
                t.text.value().as_ref().map_or(0, String::len)
                    + t.locale.value().as_ref().map_or(0, String::len)
            }
            Variant::Array(a) => a.values.iter().map(size).sum(),
            _ => 0,
        }
}

/// Whether the Values `nodes` ask of `space` add up to more than `limit`
/// bytes (each distinct node sized once; attributes other than Value
/// count at [`OVERHEAD`]).
pub(crate) fn too_large(space: &AddressSpace, nodes: &[&mut ReadNode], limit: usize) -> bool {
    let mut sizes: HashMap<&NodeId, usize> = HashMap::new();
    let mut total = 0usize;
    for node in nodes {
        let id = node.node();
        let one = if id.attribute_id != AttributeId::Value {
            OVERHEAD
        } else {
            *sizes
                .entry(&id.node_id)
                .or_insert_with(|| match space.find(&id.node_id) {
                    Some(NodeType::Variable(v)) => stored_value(v).as_ref().map_or(OVERHEAD, size),
                    _ => OVERHEAD,
                })
        };
        total = total.saturating_add(one);
        if total > limit {
            return true;
        }
    }
    false
}

/// Builds the core node manager (namespace 0) behind the size check.
pub(crate) struct CappedCore {
    /// The largest response, bytes.
    pub limit: usize,
}

impl NodeManagerBuilder for CappedCore {
    fn build(self: Box<Self>, context: ServerContext) -> Arc<DynNodeManager> {
        let core = Box::new(InMemoryNodeManagerBuilder::new(
            opcua::server::node_manager::memory::CoreNodeManagerBuilder,
        ))
        .build(context);
        match Arc::clone(&core)
            .into_any_arc()
            .downcast::<CoreNodeManager>()
        {
            Ok(manager) => Arc::new(Capped {
                space: Arc::clone(manager.address_space()),
                inner: core,
                limit: self.limit,
            }),
            Err(_) => core,
        }
    }
}

/// A node manager whose Reads are sized before they are served.
pub(crate) struct Capped {
    inner: Arc<DynNodeManager>,
    space: Arc<RwLock<AddressSpace>>,
    limit: usize,
}

impl Capped {
    /// The address space of the manager inside.
    pub fn address_space(&self) -> &Arc<RwLock<AddressSpace>> {
        &self.space
    }
}

#[async_trait]
impl NodeManager for Capped {
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

    async fn init(&self, type_tree: &mut DefaultTypeTree, context: ServerContext) {
        self.inner.init(type_tree, context).await;
    }

    async fn resolve_external_references(
        &self,
        context: &RequestContext,
        items: &mut [&mut ExternalReferenceRequest],
    ) {
        self.inner.resolve_external_references(context, items).await;
    }

    /// The check, then the manager's own read.
    async fn read(
        &self,
        context: &RequestContext,
        max_age: f64,
        stamps: TimestampsToReturn,
        nodes: &mut [&mut ReadNode],
    ) -> Result<(), StatusCode> {
        if too_large(&self.space.read(), nodes, self.limit) {
            return Err(StatusCode::BadResponseTooLarge);
        }
        self.inner.read(context, max_age, stamps, nodes).await
    }

    async fn history_read_raw_modified(
        &self,
        context: &RequestContext,
        details: &ReadRawModifiedDetails,
        nodes: &mut [&mut HistoryNode],
        stamps: TimestampsToReturn,
    ) -> Result<(), StatusCode> {
        self.inner
            .history_read_raw_modified(context, details, nodes, stamps)
            .await
    }

    async fn history_read_processed(
        &self,
        context: &RequestContext,
        details: &ReadProcessedDetails,
        nodes: &mut [&mut HistoryNode],
        stamps: TimestampsToReturn,
    ) -> Result<(), StatusCode> {
        self.inner
            .history_read_processed(context, details, nodes, stamps)
            .await
    }

    async fn history_read_at_time(
        &self,
        context: &RequestContext,
        details: &ReadAtTimeDetails,
        nodes: &mut [&mut HistoryNode],
        stamps: TimestampsToReturn,
    ) -> Result<(), StatusCode> {
        self.inner
            .history_read_at_time(context, details, nodes, stamps)
            .await
    }

    async fn history_read_events(
        &self,
        context: &RequestContext,
        details: &ReadEventDetails,
        nodes: &mut [&mut HistoryNode],
        stamps: TimestampsToReturn,
    ) -> Result<(), StatusCode> {
        self.inner
            .history_read_events(context, details, nodes, stamps)
            .await
    }

    async fn history_read_annotations(
        &self,
        context: &RequestContext,
        details: &ReadAnnotationDataDetails,
        nodes: &mut [&mut HistoryNode],
        stamps: TimestampsToReturn,
    ) -> Result<(), StatusCode> {
        self.inner
            .history_read_annotations(context, details, nodes, stamps)
            .await
    }

    async fn write(
        &self,
        context: &RequestContext,
        nodes: &mut [&mut WriteNode],
    ) -> Result<(), StatusCode> {
        self.inner.write(context, nodes).await
    }

    async fn history_update(
        &self,
        context: &RequestContext,
        nodes: &mut [&mut HistoryUpdateNode],
    ) -> Result<(), StatusCode> {
        self.inner.history_update(context, nodes).await
    }

    async fn browse(
        &self,
        context: &RequestContext,
        nodes: &mut [BrowseNode],
    ) -> Result<(), StatusCode> {
        self.inner.browse(context, nodes).await
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

    async fn query(
        &self,
        context: &RequestContext,
        request: &mut QueryRequest,
    ) -> Result<(), StatusCode> {
        self.inner.query(context, request).await
    }

    async fn call(
        &self,
        context: &RequestContext,
        methods: &mut [&mut MethodCall],
    ) -> Result<(), StatusCode> {
        self.inner.call(context, methods).await
    }

    async fn add_nodes(
        &self,
        context: &RequestContext,
        nodes: &mut [&mut AddNodeItem],
    ) -> Result<(), StatusCode> {
        self.inner.add_nodes(context, nodes).await
    }

    async fn add_references(
        &self,
        context: &RequestContext,
        references: &mut [&mut AddReferenceItem],
    ) -> Result<(), StatusCode> {
        self.inner.add_references(context, references).await
    }

    async fn delete_nodes(
        &self,
        context: &RequestContext,
        nodes: &mut [&mut DeleteNodeItem],
    ) -> Result<(), StatusCode> {
        self.inner.delete_nodes(context, nodes).await
    }

    async fn delete_node_references(
        &self,
        context: &RequestContext,
        to_delete: &[&DeleteNodeItem],
    ) {
        self.inner.delete_node_references(context, to_delete).await;
    }

    async fn delete_references(
        &self,
        context: &RequestContext,
        references: &mut [&mut DeleteReferenceItem],
    ) -> Result<(), StatusCode> {
        self.inner.delete_references(context, references).await
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use opcua::types::{ByteString, LocalizedText};

    #[test]
    fn strings_and_byte_strings_count_in_full() {
        let big = Variant::from(ByteString::from(vec![0u8; 1000]));
        assert_eq!(size(&big), OVERHEAD + 1000);
        assert_eq!(size(&Variant::from("abc")), OVERHEAD + 3);
        assert_eq!(
            size(&Variant::from(LocalizedText::new("en", "ab"))),
            OVERHEAD + 4
        );
        let array = Variant::from(vec![LocalizedText::from("ab"), LocalizedText::from("cd")]);
        assert_eq!(size(&array), OVERHEAD + 2 * (OVERHEAD + 2));
        assert_eq!(size(&Variant::from(1.5)), OVERHEAD);
    }
}
