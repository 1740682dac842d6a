//! The face's variables and the one way to their values: every read and
//! write goes to the object server through its [`CoreHandle`], so the
//! table stays the only place a value is kept.

use std::collections::HashMap;

use opcua::types::{
    DataTypeId, DataValue, DateTime, NodeId, StatusCode, TimestampsToReturn, Variant,
};
use uoi::tcp::CoreHandle;
use uoi::wire::{Answer, Request};
use uoi::{Access, Value, ValueType};

use crate::layout::Reading;
use crate::space::Source;
use crate::status::{access_status, protocol_status};

/// What the face knows of one variable.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Point {
    /// Where its value comes from.
    pub source: Source,
    /// Its access right.
    pub access: Access,
}

/// The variables of the face and the object server behind them.
pub(crate) struct Points {
    map: HashMap<NodeId, Point>,
    readings: Vec<Reading>,
    core: CoreHandle,
}

impl Points {
    /// The points of `map`, read through `core`.
    pub fn new(map: HashMap<NodeId, Point>, readings: Vec<Reading>, core: CoreHandle) -> Self {
        Self {
            map,
            readings,
            core,
        }
    }

    /// The variable `id`, if it is one of the face's.
    pub fn get(&self, id: &NodeId) -> Option<Point> {
        self.map.get(id).copied()
    }

    /// The value of `source`, now.
    pub async fn read(&self, source: Source) -> Result<Variant, StatusCode> {
        let value = match source {
            Source::Object(addr, ty) => {
                let answer = self.core.call(Request::Read(addr, ty)).await;
                served(&answer)?;
                crate::layout::answer_value(&answer)
            }
            Source::Reading(i) => {
                let reading = self.readings.get(i).ok_or(StatusCode::BadNodeIdUnknown)?;
                let answer = self.core.call(reading.request.clone()).await;
                served(&answer)?;
                (reading.pick)(&answer)
            }
        };
        value.map(to_variant).map_err(access_status)
    }

    /// Writes `value` to `source`: `Good`, or why the table refused it.
    pub async fn write(&self, source: Source, value: &Variant) -> StatusCode {
        let Source::Object(addr, _) = source else {
            return StatusCode::BadNotWritable;
        };
        let value = match from_variant(value) {
            Ok(v) => v,
            Err(status) => return status,
        };
        match self.core.call(Request::Write(addr, value)).await {
            Answer::Ok => StatusCode::Good,
            Answer::Access(e) => access_status(e),
            Answer::Protocol(e) => protocol_status(e),
            Answer::Value(_) | Answer::Ext(_) => StatusCode::BadInternalError,
        }
    }

    /// A sample of `source` as subscriptions see it (stamped now, or the
    /// refusal's status).
    pub async fn sample(&self, source: Source) -> DataValue {
        stamped(self.read(source).await, TimestampsToReturn::Both)
    }
}

/// Whether the object server served the request at all.
fn served(answer: &Answer) -> Result<(), StatusCode> {
    match answer {
        Answer::Protocol(e) => Err(protocol_status(*e)),
        _ => Ok(()),
    }
}

/// The OPC UA value of an object's value.
pub(crate) fn to_variant(value: Value) -> Variant {
    match value {
        Value::I32(v) => Variant::Int32(v),
        Value::F64(v) => Variant::Double(v),
    }
}

/// The object value an OPC UA client writes: Int32 or Double; any other
/// type (none included) is not one an object holds.
pub(crate) fn from_variant(value: &Variant) -> Result<Value, StatusCode> {
    match value {
        Variant::Int32(v) => Ok(Value::I32(*v)),
        Variant::Double(v) => Ok(Value::F64(*v)),
        _ => Err(StatusCode::BadTypeMismatch),
    }
}

/// The OPC UA data type of a value type.
pub(crate) fn data_type(ty: ValueType) -> DataTypeId {
    match ty {
        ValueType::I32 => DataTypeId::Int32,
        ValueType::F64 => DataTypeId::Double,
    }
}

/// A read's result with the timestamps the client asked for (both stamps
/// are the moment of the read: the table is the source).
pub(crate) fn stamped(
    result: Result<Variant, StatusCode>,
    stamps: TimestampsToReturn,
) -> DataValue {
    match result {
        Ok(value) => {
            let now = DateTime::now();
            let source = matches!(
                stamps,
                TimestampsToReturn::Source | TimestampsToReturn::Both
            );
            let server = matches!(
                stamps,
                TimestampsToReturn::Server | TimestampsToReturn::Both
            );
            DataValue {
                value: Some(value),
                status: Some(StatusCode::Good),
                source_timestamp: source.then_some(now),
                server_timestamp: server.then_some(now),
                ..Default::default()
            }
        }
        Err(status) => bad(status),
    }
}

/// A result that is only a bad status.
pub(crate) fn bad(status: StatusCode) -> DataValue {
    DataValue {
        status: Some(status),
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_int32_and_double_are_object_values() {
        assert_eq!(from_variant(&Variant::Int32(-3)), Ok(Value::I32(-3)));
        assert_eq!(from_variant(&Variant::Double(2.5)), Ok(Value::F64(2.5)));
        for other in [
            Variant::Empty,
            Variant::Float(2.5),
            Variant::Int64(3),
            Variant::Boolean(true),
            Variant::from("3"),
        ] {
            assert_eq!(
                from_variant(&other),
                Err(StatusCode::BadTypeMismatch),
                "{other:?}"
            );
        }
        assert_eq!(to_variant(Value::F64(1.5)), Variant::Double(1.5));
    }

    #[test]
    fn stamps_as_asked() {
        let v = stamped(Ok(Variant::Int32(1)), TimestampsToReturn::Neither);
        assert!(v.source_timestamp.is_none() && v.server_timestamp.is_none());
        let v = stamped(Ok(Variant::Int32(1)), TimestampsToReturn::Source);
        assert!(v.source_timestamp.is_some() && v.server_timestamp.is_none());
        let v = stamped(Err(StatusCode::BadNotReadable), TimestampsToReturn::Both);
        assert_eq!(v.status, Some(StatusCode::BadNotReadable));
        assert!(v.value.is_none());
    }
}
