//! The emulator: an object server with the TC module on bus 1300, plus the
//! motion side (commands, executor, spool log) that traces drive.

use otc_ext::OtcExtension;
use tc_module::{AxisPos, Motion, SpoolElement, TcModule};
use uoi::{AccessError, ObjectAddress, ObjectServer, Value, ValueType};

/// One emulated controller.
pub struct Emulator {
    server: ObjectServer,
}

impl Default for Emulator {
    fn default() -> Self {
        Self::new([0.0; tc_module::AXES], tc_module::executor::DEFAULT_CYCLE_S)
    }
}

impl Emulator {
    /// A controller whose machine stands at `start`, with an interpolation
    /// cycle of `cycle_s` seconds.
    pub fn new(start: AxisPos, cycle_s: f64) -> Self {
        let mut server = ObjectServer::new();
        // A fresh server has no bus yet, so registering cannot collide.
        let tc = TcModule::new(start, cycle_s).with_extension(Box::new(OtcExtension::default()));
        let _ = server.register(tc);
        Self { server }
    }

    /// The TC module.
    pub fn tc(&self) -> &TcModule {
        self.server
            .module::<TcModule>()
            .expect("the TC module is registered in Emulator::new")
    }

    /// The TC module, mutable.
    pub fn tc_mut(&mut self) -> &mut TcModule {
        self.server
            .module_mut::<TcModule>()
            .expect("the TC module is registered in Emulator::new")
    }

    /// Reads an object.
    pub fn read(&mut self, addr: ObjectAddress, ty: ValueType) -> Result<Value, AccessError> {
        self.server.read(addr, ty)
    }

    /// Writes an object.
    pub fn write(&mut self, addr: ObjectAddress, value: Value) -> Result<(), AccessError> {
        self.server.write(addr, value)
    }

    /// Executes a motion command.
    pub fn command(&mut self, m: &Motion) -> Result<(), AccessError> {
        self.tc_mut().command(m)
    }

    /// Runs the executor `cycles` cycles, or until the spooler is empty.
    pub fn exec(&mut self, cycles: Option<u64>) {
        self.tc_mut().exec(cycles)
    }

    /// The executed position.
    pub fn position(&self) -> AxisPos {
        *self.tc().position()
    }

    /// Elements waiting in the spooler.
    pub fn queue_len(&self) -> usize {
        self.tc().queue_len()
    }

    /// Keeps every spooled element in a log (for trace replay).
    pub fn set_spool_log(&mut self, on: bool) {
        self.tc_mut().spooler_mut().set_logging(on)
    }

    /// Takes the elements spooled since the last call.
    pub fn take_spool_log(&mut self) -> Vec<SpoolElement> {
        self.tc_mut().spooler_mut().take_log()
    }
}
