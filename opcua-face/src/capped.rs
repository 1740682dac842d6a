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
//! [`Capped`] puts the core node manager (namespace 0) behind that check
//! (a [`Delegating`] manager); the face's own manager applies it in its
//! `read` (`front.rs`).

use std::collections::HashMap;
use std::sync::Arc;

use async_trait::async_trait;
use opcua::server::address_space::{AddressSpace, NodeType};
use opcua::server::node_manager::memory::{CoreNodeManager, InMemoryNodeManagerBuilder};
use opcua::server::node_manager::{
    DynNodeManager, NodeManager, NodeManagerBuilder, ReadNode, RequestContext, ServerContext,
};
use opcua::types::{AttributeId, NodeId, StatusCode, TimestampsToReturn, Variant};

use crate::delegating::{Delegating, Overrides};
use crate::stored::stored_value;

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
            Ok(manager) => Arc::new(Capped::new(manager, SizeCheck { limit: self.limit })),
            Err(_) => core,
        }
    }
}

/// The core node manager, its Reads sized before they are served.
pub(crate) type Capped = Delegating<CoreNodeManager, SizeCheck>;

/// What [`Capped`] changes: a Read is sized first.
pub(crate) struct SizeCheck {
    /// The largest response, bytes.
    limit: usize,
}

#[async_trait]
impl Overrides<CoreNodeManager> for SizeCheck {
    /// The check, then the manager's own read.
    async fn read(
        &self,
        inner: &Arc<CoreNodeManager>,
        context: &RequestContext,
        max_age: f64,
        stamps: TimestampsToReturn,
        nodes: &mut [&mut ReadNode],
    ) -> Result<(), StatusCode> {
        if too_large(&inner.address_space().read(), nodes, self.limit) {
            return Err(StatusCode::BadResponseTooLarge);
        }
        inner.read(context, max_age, stamps, nodes).await
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
