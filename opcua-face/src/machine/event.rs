//! The GeneralModelChangeEvent (OPC 10000-3, 9.32.6) that tells clients
//! which nodes were added or deleted. The library's own generated event
//! holds one change where the standard has an array, and answers a field
//! only when a client names the type that declares it; clients such as
//! asyncua name BaseEventType for every field, `Changes` included. This
//! one answers through its type or any supertype.

use opcua::nodes::{BaseEventType, Event, EventField};
use opcua::types::{
    AttributeId, ByteString, DateTime, LocalizedText, ModelChangeStructureDataType, NodeId,
    NumericRange, ObjectTypeId, QualifiedName, Variant,
};

/// Severity of a model change: low (OPC 10000-5, 6.4.2: 1..200).
const SEVERITY: u16 = 100;

/// A GeneralModelChangeEvent.
#[derive(Debug)]
pub(crate) struct ModelChange {
    base: BaseEventType,
    changes: Vec<ModelChangeStructureDataType>,
}

/// `Verb` bits of a change (OPC 10000-3, 9.32.6).
pub(crate) mod verb {
    /// A node was added.
    pub const NODE_ADDED: u8 = 1;
    /// A node was deleted.
    pub const NODE_DELETED: u8 = 2;
    /// A reference was added.
    pub const REFERENCE_ADDED: u8 = 4;
    /// A reference was deleted.
    pub const REFERENCE_DELETED: u8 = 8;
}

impl ModelChange {
    /// The event of `changes` made below `source` (named `name`); its
    /// EventId is the time and the `serial` number of the event.
    pub fn new(
        source: &NodeId,
        name: &str,
        changes: Vec<ModelChangeStructureDataType>,
        serial: u64,
    ) -> Self {
        let now = DateTime::now();
        let mut id = i64::from(now).to_be_bytes().to_vec();
        id.extend_from_slice(&serial.to_be_bytes());
        let message = format!("{} change(s) below {name}", changes.len());
        let mut base = BaseEventType::new(
            ObjectTypeId::GeneralModelChangeEventType,
            ByteString::from(id),
            LocalizedText::from(message.as_str()),
            now,
        )
        .set_source_node(source.clone())
        .set_source_name(name.into());
        base.severity = SEVERITY;
        Self { base, changes }
    }

    /// The changes.
    #[cfg(test)]
    pub fn changes(&self) -> &[ModelChangeStructureDataType] {
        &self.changes
    }
}

impl EventField for ModelChange {
    fn get_value(
        &self,
        attribute_id: AttributeId,
        index_range: &NumericRange,
        remaining_path: &[QualifiedName],
    ) -> Variant {
        match remaining_path {
            [field] if field.namespace_index == 0 && field.name.as_ref() == "Changes" => {
                self.changes.get_value(attribute_id, index_range, &[])
            }
            _ => self
                .base
                .get_value(attribute_id, index_range, remaining_path),
        }
    }
}

impl Event for ModelChange {
    fn get_field(
        &self,
        type_definition_id: &NodeId,
        attribute_id: AttributeId,
        index_range: &NumericRange,
        browse_path: &[QualifiedName],
    ) -> Variant {
        let types = [
            ObjectTypeId::GeneralModelChangeEventType,
            ObjectTypeId::BaseModelChangeEventType,
            ObjectTypeId::BaseEventType,
        ];
        if types.iter().any(|t| type_definition_id == t) {
            self.get_value(attribute_id, index_range, browse_path)
        } else {
            Variant::Empty
        }
    }

    fn time(&self) -> &DateTime {
        &self.base.time
    }

    fn event_type_id(&self) -> &NodeId {
        &self.base.event_type
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field(e: &ModelChange, ty: ObjectTypeId, name: &str) -> Variant {
        e.get_field(
            &ty.into(),
            AttributeId::Value,
            &NumericRange::None,
            &[QualifiedName::new(0, name)],
        )
    }

    #[test]
    fn changes_and_base_fields_through_any_supertype() {
        let change = ModelChangeStructureDataType {
            affected: NodeId::new(2, "machine/tool/1/5"),
            affected_type: NodeId::new(8, 50u32),
            verb: verb::NODE_ADDED | verb::REFERENCE_ADDED,
        };
        let e = ModelChange::new(&NodeId::new(2, "list"), "Tools", vec![change.clone()], 7);
        for ty in [
            ObjectTypeId::GeneralModelChangeEventType,
            ObjectTypeId::BaseEventType,
        ] {
            let Variant::Array(a) = field(&e, ty, "Changes") else {
                panic!("no Changes through {ty:?}");
            };
            assert_eq!(a.values.len(), 1);
            assert_eq!(field(&e, ty, "SourceName"), Variant::from("Tools"));
        }
        assert_eq!(
            field(&e, ObjectTypeId::ConditionType, "Changes"),
            Variant::Empty
        );
        let event_type: NodeId = ObjectTypeId::GeneralModelChangeEventType.into();
        assert_eq!(
            field(&e, ObjectTypeId::BaseEventType, "EventType"),
            Variant::from(event_type)
        );
        assert_eq!(e.changes(), &[change]);
        let other = ModelChange::new(&NodeId::new(2, "list"), "Tools", vec![], 8);
        assert_ne!(
            field(&e, ObjectTypeId::BaseEventType, "EventId"),
            field(&other, ObjectTypeId::BaseEventType, "EventId")
        );
    }
}
