//! The node manager of the face's namespace: its folders and variables sit
//! in an in-memory address space (names, types, access, ranges), but a
//! variable's value is read from and written to the object table through
//! the object server, and monitored variables are sampled from it.

use std::sync::Arc;
use std::time::Duration;

use async_trait::async_trait;
use opcua::server::address_space::{is_supported_data_encoding, AddressSpace};
use opcua::server::diagnostics::NamespaceMetadata;
use opcua::server::node_manager::memory::InMemoryNodeManagerImpl;
use opcua::server::node_manager::{
    MonitoredItemRef, MonitoredItemUpdateRef, ParsedReadValueId, RequestContext, ServerContext,
    WriteNode,
};
use opcua::server::CreateMonitoredItem;
use opcua::sync::RwLock;
use opcua::types::{
    AttributeId, DataValue, MonitoringMode, NumericRange, StatusCode, TimestampsToReturn,
};

use uoi::tcp::CoreHandle;

use crate::browse::Order;
use crate::machine::view::MachineTool;
use crate::points::{bad, stamped, Points};
use crate::sampler::{Sampler, TICK};

/// The longest sampling interval kept: an item that asks for a longer
/// one is sampled this often.
const SLOWEST: Duration = Duration::from_secs(3600);

/// The URI of the face's namespace.
pub const NAMESPACE: &str = "urn:addipos-tc";

/// A machine to show, the handle to look at it through, and the
/// namespaces (URI, index) of the companion NodeSets loaded for it.
pub(crate) type MachineParts = (MachineTool, CoreHandle, Vec<(String, u16)>);

/// The face's node manager (behind `InMemoryNodeManager`).
pub(crate) struct ObjectNodes {
    ns: u16,
    points: Arc<Points>,
    order: Order,
    sampler: Arc<Sampler>,
    machine: Option<(MachineTool, CoreHandle)>,
    /// The companion NodeSets' namespaces (with a machine).
    companions: Vec<(String, u16)>,
}

impl ObjectNodes {
    /// The node manager of `points` in namespace `ns`, its nodes browsed
    /// in `order`; with the machine to show, the handle to look at it
    /// through and the namespaces of the companion NodeSets loaded.
    pub fn new(ns: u16, points: Points, order: Order, machine: Option<MachineParts>) -> Self {
        let (machine, companions) = match machine {
            Some((m, core, companions)) => (Some((m, core)), companions),
            None => (None, Vec::new()),
        };
        Self {
            ns,
            points: Arc::new(points),
            order,
            sampler: Arc::new(Sampler::new()),
            machine,
            companions,
        }
    }

    /// The namespace index.
    pub fn ns(&self) -> u16 {
        self.ns
    }

    /// The machine shown, and the handle to look at it through.
    pub fn machine(&self) -> Option<&(MachineTool, CoreHandle)> {
        self.machine.as_ref()
    }

    /// Where each node comes in a browse result.
    pub fn order(&self) -> &Order {
        &self.order
    }

    /// The value of one node: a variable of the face from the table, any
    /// other node (a property) from the address space.
    async fn read_one(
        &self,
        context: &RequestContext,
        space: &RwLock<AddressSpace>,
        node: &ParsedReadValueId,
        max_age: f64,
        stamps: TimestampsToReturn,
    ) -> DataValue {
        let Some(point) = self.points.get(&node.node_id) else {
            return space.read().read(context, node, max_age, stamps);
        };
        if node.index_range != NumericRange::None {
            return bad(StatusCode::BadIndexRangeDataMismatch);
        }
        if !is_supported_data_encoding(&node.data_encoding) {
            return bad(StatusCode::BadDataEncodingInvalid);
        }
        stamped(self.points.read(point.source).await, stamps)
    }

    /// Writes one node: only the Value of a variable of the face, without
    /// an index range or a status of its own; timestamps are the server's.
    /// Any other node of the namespace (the machine, the loaded types) is
    /// read-only.
    async fn write_one(&self, space: &RwLock<AddressSpace>, write: &mut WriteNode) {
        let value = write.value();
        let Some(point) = self.points.get(&value.node_id) else {
            let status = if space.read().node_exists(&value.node_id) {
                StatusCode::BadNotWritable
            } else {
                StatusCode::BadNodeIdUnknown
            };
            write.set_status(status);
            return;
        };
        let status = if value.attribute_id != AttributeId::Value {
            StatusCode::BadNotWritable
        } else if value.index_range != NumericRange::None {
            StatusCode::BadIndexRangeDataMismatch
        } else if value.value.status.is_some_and(|s| !s.is_good()) {
            StatusCode::BadWriteNotSupported
        } else {
            let v = value.value.value.clone().unwrap_or_default();
            self.points.write(point.source, &v).await
        };
        write.set_status(status);
    }

    /// A monitored item's sampling interval: the revised one within
    /// [`TICK`] ..= [`SLOWEST`], or the shortest for "the subscription's"
    /// (a negative one).
    fn every(interval_ms: f64) -> Duration {
        if interval_ms > 0.0 {
            Duration::try_from_secs_f64(interval_ms * 1e-3)
                .map_or(SLOWEST, |d| d.clamp(TICK, SLOWEST))
        } else {
            TICK
        }
    }
}

#[async_trait]
impl InMemoryNodeManagerImpl for ObjectNodes {
    async fn init(&self, _space: &mut AddressSpace, context: ServerContext) {
        self.sampler
            .start(Arc::clone(&self.points), context.subscriptions.clone());
    }

    fn name(&self) -> &str {
        "addipos-objects"
    }

    fn namespaces(&self) -> Vec<NamespaceMetadata> {
        let own = NamespaceMetadata {
            is_namespace_subset: Some(false),
            namespace_uri: NAMESPACE.to_owned(),
            namespace_index: self.ns,
            ..Default::default()
        };
        let companions = self
            .companions
            .iter()
            .map(|(uri, index)| NamespaceMetadata {
                namespace_uri: uri.clone(),
                namespace_index: *index,
                ..Default::default()
            });
        std::iter::once(own).chain(companions).collect()
    }

    async fn read_values(
        &self,
        context: &RequestContext,
        space: &RwLock<AddressSpace>,
        nodes: &[&ParsedReadValueId],
        max_age: f64,
        stamps: TimestampsToReturn,
    ) -> Vec<DataValue> {
        let mut values = Vec::with_capacity(nodes.len());
        for node in nodes {
            values.push(self.read_one(context, space, node, max_age, stamps).await);
        }
        values
    }

    async fn create_value_monitored_items(
        &self,
        context: &RequestContext,
        space: &RwLock<AddressSpace>,
        items: &mut [&mut &mut CreateMonitoredItem],
    ) {
        for item in items.iter_mut() {
            let node = item.item_to_monitor().clone();
            let Some(point) = self.points.get(&node.node_id) else {
                let value = space
                    .read()
                    .read(context, &node, 0.0, item.timestamps_to_return());
                item.set_initial_value(value);
                item.set_status(StatusCode::Good);
                continue;
            };
            if !point.access.readable() {
                item.set_status(StatusCode::BadNotReadable);
                continue;
            }
            // Both stamps: the item's own choice applies when it is sent.
            let value = self
                .read_one(context, space, &node, 0.0, TimestampsToReturn::Both)
                .await;
            item.set_initial_value(value.clone());
            item.set_status(StatusCode::Good);
            let wishes = (
                item.monitoring_mode(),
                Self::every(item.sampling_interval()),
            );
            let handle = item.handle();
            self.sampler
                .add(node.node_id, point.source, handle, wishes, value);
        }
    }

    async fn modify_monitored_items(
        &self,
        _context: &RequestContext,
        items: &[&MonitoredItemUpdateRef],
    ) {
        for item in items {
            let every = Self::every(item.update().revised_sampling_interval);
            self.sampler.set_every(item.node_id(), item.handle(), every);
        }
    }

    async fn set_monitoring_mode(
        &self,
        _context: &RequestContext,
        mode: MonitoringMode,
        items: &[&MonitoredItemRef],
    ) {
        for item in items {
            self.sampler.set_mode(item.node_id(), item.handle(), mode);
        }
    }

    async fn delete_monitored_items(&self, _context: &RequestContext, items: &[&MonitoredItemRef]) {
        for item in items {
            self.sampler.remove(item.node_id(), item.handle());
        }
    }

    async fn write(
        &self,
        _context: &RequestContext,
        space: &RwLock<AddressSpace>,
        nodes: &mut [&mut WriteNode],
    ) -> Result<(), StatusCode> {
        for write in nodes.iter_mut() {
            self.write_one(space, write).await;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn any_sampling_interval_a_client_asks_for_is_one_the_sampler_keeps() {
        assert_eq!(ObjectNodes::every(250.0), Duration::from_millis(250));
        assert_eq!(ObjectNodes::every(1.0), TICK);
        assert_eq!(ObjectNodes::every(-1.0), TICK);
        assert_eq!(ObjectNodes::every(f64::NAN), TICK);
        for huge in [1e300, f64::MAX, f64::INFINITY] {
            assert_eq!(ObjectNodes::every(huge), SLOWEST, "{huge}");
        }
    }
}
