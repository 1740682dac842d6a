//! The machine as OPC 40501-1 "OPC UA for Machine Tools" models it: one
//! `MachineToolType` instance in the Machinery `Machines` folder, with its
//! identification, a monitored channel, and the tool list with each
//! tool's life. The face knows no TC object: the object server hands it a
//! [`MachineTool`], whose [`MachineSource`] looks at the server's handler
//! (between two requests) and tells the machine's state and tools.
//!
//! * `nodesets`: the OPC Foundation's NodeSets, imported;
//! * `types`: the type model they give (declarations, modelling rules);
//! * `instance`: instances of a type with their mandatory members;
//! * `model`: the machine instance; `tools`: a tool's nodes;
//! * `handles`: the variables of both the face sets, by name, in one
//!   table each, checked against the instances; `error`: why the machine
//!   cannot be shown;
//! * `view`: the machine as its source tells it (state, tools, identity);
//! * `live`: the poll that keeps them up to date, with model-change
//!   events when tools come and go.

pub(crate) mod error;
pub(crate) mod event;
pub(crate) mod handles;
pub(crate) mod instance;
pub(crate) mod live;
pub(crate) mod model;
pub(crate) mod nodesets;
pub(crate) mod setup;
pub(crate) mod tools;
pub(crate) mod types;
pub(crate) mod units;
pub(crate) mod view;

pub use live::{MAX_TOOLS, POLL};
pub use nodesets::{MACHINERY, MACHINE_TOOL};
pub use view::{ChannelState, Identity, MachineSource, MachineTool, MachineView, ToolRecord};
