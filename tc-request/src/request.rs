//! The one request model of the TC side, and its replies.

use uoi::wire::ProtocolError;
use uoi::{AccessError, ObjectAddress, Value, ValueType};

use crate::axes::AxisPos;
use crate::element::SpoolRecord;
use crate::motion::Motion;

/// A request to the TC module: an object access, a motion command, the
/// executor, or one of the emulator-control ops of conformance replay.
/// The trace parser, the wire codec and the NC front end all produce this.
#[derive(Debug, Clone, PartialEq)]
pub enum Request {
    /// `R addr type`: read an object asking for a type.
    Read(ObjectAddress, ValueType),
    /// `W addr type value`: write an object.
    Write(ObjectAddress, Value),
    /// A motion command.
    Motion(Motion),
    /// `EXEC` (until the spooler is empty) or `EXEC n` (n cycles, at most
    /// [`MAX_EXEC_CYCLES`]).
    Exec(Option<u64>),
    /// `POS`: the executed position.
    Pos,
    /// `QUEUE`: motion waiting: elements in the spooler and plane-null
    /// profiles waiting with the held profile.
    Queue,
    /// `FEED_ADAPT on rmin`: the feed adaptation of corrected arcs of NC
    /// programs (`G10`/`G11`, `#TANGFEED RMIN`, docs/nc.md): from the next
    /// profile on, a corrected arc of programmed radius `R >= rmin` spools
    /// at `F * R'/R`. Not an object of the bus: the TC module's objects and
    /// their answers stay as they are.
    FeedAdaption {
        /// `G11` (true) or `G10` (false).
        on: bool,
        /// The smallest programmed radius adapted, at least 0.
        rmin: f64,
    },
    /// Conformance replay: a fresh emulator in place of the one served.
    Setup {
        /// Initial machine position.
        start: AxisPos,
        /// Interpolation cycle in seconds.
        cycle_s: f64,
        /// Spooler capacity in elements; 0: the server's configured one.
        spool_capacity: u64,
    },
    /// Conformance replay: take the logged spool elements; log from now on
    /// or not.
    SpoolLog {
        /// Logging from now on.
        logging: bool,
    },
}

/// Most cycles one `EXEC n` may ask for: on the wire `u64::MAX` stands for
/// "until the spooler is empty".
pub const MAX_EXEC_CYCLES: u64 = u64::MAX - 1;

/// The answer to a [`Request`].
#[derive(Debug, Clone, PartialEq)]
pub enum Reply {
    /// Done.
    Ok,
    /// A value read.
    Value(Value),
    /// The executed position.
    Pos(AxisPos),
    /// Elements waiting in the spooler.
    Queue(u64),
    /// Logged spool elements (one batch) and whether more wait.
    Spool(Vec<SpoolRecord>, bool),
    /// Refused with an access error.
    Access(AccessError),
    /// Refused by the protocol (a request the server cannot take).
    Protocol(ProtocolError),
}

impl From<Result<(), AccessError>> for Reply {
    fn from(r: Result<(), AccessError>) -> Self {
        match r {
            Ok(()) => Reply::Ok,
            Err(e) => Reply::Access(e),
        }
    }
}

impl From<Result<Value, AccessError>> for Reply {
    fn from(r: Result<Value, AccessError>) -> Self {
        match r {
            Ok(v) => Reply::Value(v),
            Err(e) => Reply::Access(e),
        }
    }
}
