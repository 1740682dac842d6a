//! The one seam of "something that runs requests": an emulator in this
//! process, or a server over the wire. Trace replay, the NC runner and
//! the host library drive whatever implements it (docs/architecture.md,
//! decision 490).

use crate::element::SpoolRecord;
use crate::request::{Reply, Request};

/// Something that runs requests and reports what they spooled: the
/// emulator (`emulator::Emulator`, which never fails) or a server over
/// the wire (whose connection may).
pub trait Runner {
    /// Why a request could not be carried to the target (a broken
    /// connection); an emulator in the process has none
    /// ([`std::convert::Infallible`]).
    type Error: std::error::Error + 'static;

    /// Carries out one request and answers it; `Err` when it could not be
    /// carried to the target.
    fn run(&mut self, req: &Request) -> Result<Reply, Self::Error>;

    /// The elements spooled since the last call (while the target logs
    /// them).
    fn take_spooled(&mut self) -> Result<Vec<SpoolRecord>, Self::Error>;

    /// The machine axes allocated as X, Y, Z (device 0 AxisNr; to write
    /// and read the `I J K` of spooled arcs).
    fn axis_nr(&mut self) -> Result<[u8; 3], Self::Error>;
}
