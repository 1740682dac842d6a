//! The emulator: the TC module with the OTC extension on bus 1300, driven
//! by the one request model.

use otc_ext::OtcExtension;
use tc_module::{AxisPos, CycleTime, ExecLeft, Motion, TcExtension, TcModule, AXES};
use tc_request::{Reply, Request, SpoolRecord};
use uoi::wire::ProtocolError;
use uoi::{AccessError, ObjectAddress, ObjectBus, Value, ValueType};

/// The TC module as the emulator runs it.
pub type Tc = TcModule<OtcExtension>;

/// One emulated controller: the TC module with extension `E` (OTC; a
/// test model in tests).
#[derive(Debug, Clone)]
pub struct Emulator<E: TcExtension = OtcExtension> {
    tc: TcModule<E>,
}

impl Default for Emulator {
    fn default() -> Self {
        Self::new([0.0; AXES], CycleTime::DEFAULT)
    }
}

impl Emulator {
    /// A controller whose machine stands at `start`, with interpolation
    /// cycle `cycle`.
    pub fn new(start: AxisPos, cycle: CycleTime) -> Self {
        Self::with_extension(start, cycle, OtcExtension::default())
    }
}

impl<E: TcExtension> Emulator<E> {
    /// A controller with extension `ext`.
    pub fn with_extension(start: AxisPos, cycle: CycleTime, ext: E) -> Self {
        Self {
            tc: TcModule::new(start, cycle, ext),
        }
    }

    /// The same controller with a spooler of `capacity` elements.
    pub fn with_spool_capacity(self, capacity: usize) -> Self {
        Self {
            tc: self.tc.with_spool_capacity(capacity),
        }
    }

    /// The TC module.
    pub fn tc(&self) -> &TcModule<E> {
        &self.tc
    }

    /// The TC module, mutable.
    pub fn tc_mut(&mut self) -> &mut TcModule<E> {
        &mut self.tc
    }

    /// Carries out a request of a controller (everything but the
    /// emulator-control ops `SETUP` and `SPOOL_LOG`, which the server's
    /// handler serves; they are answered `UnknownOp` here).
    pub fn run(&mut self, req: &Request) -> Reply {
        match req {
            Request::Read(addr, ty) => self.read(*addr, *ty).into(),
            Request::Write(addr, v) => self.write(*addr, *v).into(),
            Request::Motion(m) => self.command(m).into(),
            Request::Exec(n) => {
                self.exec(*n);
                Reply::Ok
            }
            Request::Pos => Reply::Pos(self.position()),
            // A queue length always fits u64.
            Request::Queue => Reply::Queue(self.queue_len() as u64),
            Request::Setup { .. } | Request::SpoolLog { .. } => {
                Reply::Protocol(ProtocolError::UnknownOp)
            }
        }
    }

    /// Reads an object.
    pub fn read(&mut self, addr: ObjectAddress, ty: ValueType) -> Result<Value, AccessError> {
        self.tc.read_checked(addr, ty)
    }

    /// Writes an object.
    pub fn write(&mut self, addr: ObjectAddress, value: Value) -> Result<(), AccessError> {
        self.tc.write_checked(addr, value)
    }

    /// Executes a motion command.
    pub fn command(&mut self, m: &Motion) -> Result<(), AccessError> {
        self.tc.command(m)
    }

    /// Runs the executor `cycles` cycles, or until the spooler is empty.
    pub fn exec(&mut self, cycles: Option<u64>) {
        self.tc.exec(cycles)
    }

    /// One slice of `EXEC cycles` (see [`TcModule::exec_slice`]).
    pub fn exec_slice(&mut self, cycles: Option<u64>) -> ExecLeft {
        self.tc.exec_slice(cycles)
    }

    /// The executed position.
    pub fn position(&self) -> AxisPos {
        self.tc.position()
    }

    /// Motion waiting (`QUEUE`).
    pub fn queue_len(&self) -> usize {
        self.tc.queue_len()
    }

    /// Keeps every spooled element in a log (for trace replay).
    pub fn set_spool_log(&mut self, on: bool) {
        self.tc.spooler_mut().set_logging(on)
    }

    /// Takes the elements spooled since the last call, as reported.
    pub fn take_spool_log(&mut self) -> Vec<SpoolRecord> {
        let log = self.tc.spooler_mut().take_log();
        log.iter().map(|e| e.record()).collect()
    }
}
