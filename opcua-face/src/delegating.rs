//! One node manager around another: every `NodeManager` method goes to
//! the manager inside, except the few an [`Overrides`] changes. The core
//! manager behind the size check (`capped.rs`) and the face's own manager
//! as the server sees it (`front.rs`) are both this wrapper, each with
//! its own overrides (docs/decisions.md, decision 501).

use std::sync::Arc;

use async_trait::async_trait;
use opcua::server::address_space::DefaultTypeTree;
use opcua::server::diagnostics::NamespaceMetadata;
use opcua::server::node_manager::{
    AddNodeItem, AddReferenceItem, BrowseNode, BrowsePathItem, DeleteNodeItem, DeleteReferenceItem,
    ExternalReferenceRequest, HistoryNode, HistoryUpdateNode, MethodCall, MonitoredItemRef,
    MonitoredItemUpdateRef, NodeManager, QueryRequest, ReadNode, RegisterNodeItem, RequestContext,
    ServerContext, WriteNode,
};
use opcua::server::CreateMonitoredItem;
use opcua::types::{
    ExpandedNodeId, MonitoringMode, NodeId, ReadAnnotationDataDetails, ReadAtTimeDetails,
    ReadEventDetails, ReadProcessedDetails, ReadRawModifiedDetails, StatusCode, TimestampsToReturn,
};

/// What a [`Delegating`] manager does in place of the manager inside it
/// (`M`). Each method's default is the inner manager's own; an
/// implementation writes only those it changes.
#[async_trait]
pub(crate) trait Overrides<M: NodeManager + Send + Sync + 'static>:
    Send + Sync + 'static
{
    /// Starts the manager (the server calls it once, every type known).
    async fn init(&self, inner: &Arc<M>, type_tree: &mut DefaultTypeTree, context: ServerContext) {
        inner.init(type_tree, context).await;
    }

    /// The Read service.
    async fn read(
        &self,
        inner: &Arc<M>,
        context: &RequestContext,
        max_age: f64,
        stamps: TimestampsToReturn,
        nodes: &mut [&mut ReadNode],
    ) -> Result<(), StatusCode> {
        inner.read(context, max_age, stamps, nodes).await
    }

    /// The Browse service.
    async fn browse(
        &self,
        inner: &Arc<M>,
        context: &RequestContext,
        nodes: &mut [BrowseNode],
    ) -> Result<(), StatusCode> {
        inner.browse(context, nodes).await
    }
}

/// A node manager that hands every call to `inner`, except those its
/// overrides change.
pub(crate) struct Delegating<M, O> {
    inner: Arc<M>,
    overrides: O,
}

impl<M, O> Delegating<M, O> {
    /// `inner` behind `overrides`.
    pub fn new(inner: Arc<M>, overrides: O) -> Self {
        Self { inner, overrides }
    }

    /// The manager inside.
    pub fn inner(&self) -> &Arc<M> {
        &self.inner
    }
}

#[async_trait]
impl<M, O> NodeManager for Delegating<M, O>
where
    M: NodeManager + Send + Sync + 'static,
    O: Overrides<M>,
{
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
        self.overrides.init(&self.inner, type_tree, context).await;
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
        let inner = &self.inner;
        self.overrides
            .read(inner, context, max_age, stamps, nodes)
            .await
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
        self.overrides.browse(&self.inner, context, nodes).await
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
