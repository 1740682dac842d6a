//! What the face shows, as the object server hands it over: the bus, its
//! devices, the rows of its object table (with their documentation), and
//! the read-only readings a dashboard watches. Nothing here knows OPC UA.

use std::ops::RangeInclusive;
use std::sync::Arc;

use uoi::wire::{Answer, Request};
use uoi::{Access, AccessError, Meaning, ObjectDesc, Value, ValueRange, ValueType};

use crate::machine::view::MachineTool;

/// The object table of one bus, and the dashboard beside it.
#[derive(Clone)]
pub struct Table {
    /// The BusNumber (a folder `Bus<n>` under Objects).
    pub bus: u16,
    /// Its devices, in the order they are listed.
    pub devices: Vec<Device>,
    /// Its objects.
    pub rows: Vec<Row>,
    /// Read-only values for a dashboard (a folder `Dashboard` in the bus
    /// folder).
    pub readings: Vec<Reading>,
    /// The machine in the OPC UA for Machine Tools model, if it is shown
    /// (then the companion NodeSets are loaded too).
    pub machine: Option<MachineTool>,
}

/// A device of the bus: a folder `Device<n>`.
#[derive(Debug, Clone, PartialEq)]
pub struct Device {
    /// The DeviceNumber.
    pub number: u16,
    /// What the device holds, one line (the folder's description).
    pub title: String,
    /// What an index of it stands for.
    pub index: IndexKind,
}

/// What the index of a device stands for.
#[derive(Debug, Clone, PartialEq)]
pub enum IndexKind {
    /// Each index is an object of its own: the objects sit in the device
    /// folder.
    Object,
    /// Each index is an instance (a group, an axis) of the same set of
    /// objects: a folder `<name><index>` per index.
    Instance {
        /// The folder name before the index: `Group`, `Axis`.
        name: String,
        /// The description of an instance folder; `{}` stands for the
        /// index.
        note: String,
    },
}

/// One row of the object table: an object at each of its indexes and
/// subindexes.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Its name in the object map.
    pub name: String,
    /// What it means to a user.
    pub doc: String,
    /// DeviceNumber.
    pub device: u16,
    /// The indexes it exists under.
    pub index: RangeInclusive<u16>,
    /// The subindexes it occupies.
    pub sub: RangeInclusive<u16>,
    /// Its value type.
    pub ty: ValueType,
    /// Its access right.
    pub access: Access,
    /// Values a write may carry.
    pub range: ValueRange,
}

impl Row {
    /// The row of a module's object table, documented by its key.
    pub fn from_desc<K: Meaning>(desc: &ObjectDesc<K>) -> Self {
        Self {
            name: desc.name.to_string(),
            doc: desc.key.meaning().to_string(),
            device: desc.device,
            index: desc.index.clone(),
            sub: desc.sub.clone(),
            ty: desc.ty,
            access: desc.access,
            range: desc.range,
        }
    }
}

/// Picks a reading's value out of the answer to its request.
pub type Pick = Arc<dyn Fn(&Answer) -> Result<Value, AccessError> + Send + Sync>;

/// A read-only value for a dashboard: asked for with a request of the
/// object server (a read, or an op of its own), picked out of the answer.
#[derive(Clone)]
pub struct Reading {
    /// Its NodeId string, unique (`dashboard/queue`).
    pub id: String,
    /// The folders below `Dashboard` it sits in (`["Group1"]`).
    pub path: Vec<String>,
    /// Its BrowseName and DisplayName.
    pub name: String,
    /// What it shows.
    pub doc: String,
    /// Its value type.
    pub ty: ValueType,
    /// The request that reads it.
    pub request: Request,
    /// Its value in the answer.
    pub pick: Pick,
}

impl std::fmt::Debug for Reading {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Reading")
            .field("id", &self.id)
            .field("name", &self.name)
            .field("request", &self.request)
            .finish_non_exhaustive()
    }
}

/// The value of a plain answer: a value read, or the refusal.
pub fn answer_value(answer: &Answer) -> Result<Value, AccessError> {
    match answer {
        Answer::Value(v) => Ok(*v),
        Answer::Access(e) => Err(*e),
        _ => Err(AccessError::State),
    }
}
