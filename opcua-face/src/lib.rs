//! # opcua-face — an OPC UA face of a UOI object table
//!
//! Serves the objects of one bus to OPC UA clients (UaExpert, SCADA, PLC
//! gateways) beside the UOI protocol: browse them as `Objects/Bus<n>/
//! Device<d>/...`, read and write them, and watch them with
//! subscriptions. The [`Table`] says what there is (the object server's
//! own table and documentation); a [`CoreHandle`](uoi::tcp::CoreHandle)
//! is the one way to the values: every read and write is served by the
//! handler the UOI connections share, so no value is kept in a node and
//! a write through either face is seen by the other at once.
//!
//! * [`layout`]: what the object server hands over;
//! * `space`: the folders and variables planned from it (NodeIds
//!   `ns=<urn:addipos-tc>;s=1300/1/2/6`), and `nodes`: them as OPC UA
//!   nodes;
//! * `points`: a variable's value through the object server; [`status`]:
//!   a refusal as an OPC UA status;
//! * `manager`: the node manager of the namespace; `front`: it as the
//!   server sees it, AccessLevel applied to the Value attribute only and
//!   `browse` in the order of the table; `capped`: the core manager's
//!   Reads sized first; both are a `delegating` manager, which hands the
//!   one inside every call but those it changes; `sampler`: the
//!   monitored variables sampled from the table;
//! * `security`: who gets in; `pki`: the certificate store; `face`: the
//!   server, bound and run;
//! * [`machine`]: the machine in the OPC UA for Machine Tools model
//!   (OPC 40501-1), its tool list kept up to date from a
//!   [`MachineSource`].

mod browse;
mod capped;
mod delegating;
mod face;
mod front;
mod guard;
pub mod layout;
pub mod machine;
mod manager;
mod nodes;
mod pki;
mod points;
mod publishing;
mod sampler;
mod security;
mod space;
pub mod status;
mod stored;

pub use face::{Face, FaceConfig, APPLICATION_NAME, APPLICATION_URI};
pub use layout::{answer_value, Device, IndexKind, Pick, Reading, Row, Table};
pub use machine::{
    ChannelState, Identity, MachineSource, MachineTool, MachineView, ToolRecord, MACHINERY,
    MACHINE_TOOL,
};
pub use manager::NAMESPACE;
pub use pki::{CertSubject, OWN_CERT, OWN_KEY, RENEW_DAYS};
pub use sampler::TICK as FASTEST_SAMPLING;
