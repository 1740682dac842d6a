//! The emulator: the TC module with the OTC extension on bus 1300, driven
//! by the one request model.

use otc_ext::OtcExtension;
use tc_module::{AxisPos, CycleTime, ExecLeft, Motion, Plan, TcExtension, TcModule, AXES};
use tc_objects::TcObject;
use tc_request::{Reply, Request, SpoolRecord};
use uoi::wire::ProtocolError;
use uoi::{AccessError, ObjectAddress, ObjectBus, Value, ValueType};

/// Device 0 Clean, whose every successful write is counted.
const CLEAN: ObjectAddress = TcObject::Clean.address();

/// The TC module as the emulator runs it.
pub type Tc = TcModule<OtcExtension>;

/// One emulated controller: the TC module with extension `E` (OTC; a
/// test model in tests).
#[derive(Debug, Clone)]
pub struct Emulator<E: TcExtension = OtcExtension> {
    tc: TcModule<E>,
    /// Cleans carried out (see [`Emulator::clean_epoch`]).
    cleans: u64,
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
            cleans: 0,
        }
    }

    /// The same controller with a spooler of `capacity` elements.
    pub fn with_spool_capacity(self, capacity: usize) -> Self {
        Self {
            tc: self.tc.with_spool_capacity(capacity),
            ..self
        }
    }

    /// The TC module.
    pub fn tc(&self) -> &TcModule<E> {
        &self.tc
    }

    /// The TC module, mutable. A write through it bypasses
    /// [`Emulator::write`] and is not counted by
    /// [`clean_epoch`](Self::clean_epoch): object writes go through
    /// [`Emulator::write`] (or [`Emulator::run`]).
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
            Request::FeedAdaption { on, rmin }
                if *rmin >= 0.0 && *rmin <= tc_objects::MAX_COORD =>
            {
                let adaption = tc_module::FeedAdaption {
                    on: *on,
                    rmin: *rmin,
                };
                self.tc.set_feed_adaption(adaption);
                Reply::Ok
            }
            Request::FeedAdaption { .. } => Reply::Access(uoi::AccessError::Range),
            Request::Setup { .. } | Request::SpoolLog { .. } => {
                Reply::Protocol(ProtocolError::UnknownOp)
            }
        }
    }

    /// Reads an object.
    pub fn read(&mut self, addr: ObjectAddress, ty: ValueType) -> Result<Value, AccessError> {
        self.tc.read_checked(addr, ty)
    }

    /// Writes an object: planned, then applied at once. A Clean carried
    /// out (1300/0/1/0 = 1) counts in [`clean_epoch`](Self::clean_epoch).
    pub fn write(&mut self, addr: ObjectAddress, value: Value) -> Result<(), AccessError> {
        let plan = self.plan(addr, value)?;
        self.apply(plan)
    }

    /// Checks a write and says what it would change of the tool data,
    /// changing nothing ([`TcModule::plan_write`]).
    pub fn plan(&self, addr: ObjectAddress, value: Value) -> Result<Plan<E>, AccessError> {
        self.tc.plan_write(addr, value)
    }

    /// Carries out a planned write ([`TcModule::apply`]); a Clean carried
    /// out counts in [`clean_epoch`](Self::clean_epoch).
    pub fn apply(&mut self, plan: Plan<E>) -> Result<(), AccessError> {
        let addr = plan.address();
        self.tc.apply(plan)?;
        if addr == CLEAN {
            self.cleans = self.cleans.wrapping_add(1);
        }
        Ok(())
    }

    /// How many Cleans this emulator has carried out: every write path of
    /// an object ([`Emulator::write`], [`Emulator::run`], the server's
    /// handler and its tool persistence) counts one per Clean that
    /// succeeded. A Clean rejects every TC object, so a host library
    /// voids the handles issued before the count last changed
    /// (docs/host-api.md, "Handles"). A refused Clean changes nothing and
    /// is not counted, nor is a Clean whose tool changes the disk refused
    /// (it is never applied).
    pub fn clean_epoch(&self) -> u64 {
        self.cleans
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::EmulatorService;
    use tc_request::text::parse_request;
    use uoi::tcp::{Handler, Slice};

    fn run(emu: &mut Emulator, text: &str) -> Reply {
        emu.run(&parse_request(text).expect("request"))
    }

    #[test]
    fn every_clean_carried_out_counts_and_a_refused_one_does_not() {
        let mut emu = Emulator::default();
        assert_eq!(emu.clean_epoch(), 0);
        assert_eq!(run(&mut emu, "W 1300/0/1/0 i 1"), Reply::Ok);
        assert_eq!(emu.clean_epoch(), 1);
        assert_eq!(emu.write(CLEAN, Value::I32(1)), Ok(()));
        assert_eq!(emu.clean_epoch(), 2);
        assert_eq!(
            run(&mut emu, "W 1300/0/1/0 i 2"),
            Reply::Access(AccessError::Range)
        );
        assert_eq!(
            run(&mut emu, "W 1300/0/1/0 d 1"),
            Reply::Access(AccessError::TypeMismatch)
        );
        assert_eq!(run(&mut emu, "W 1300/0/12/0 i 1"), Reply::Ok);
        assert_eq!(run(&mut emu, "W 1300/1/1/2 i 1"), Reply::Ok);
        assert_eq!(emu.clean_epoch(), 2);
    }

    #[test]
    fn a_clean_over_the_wire_counts_in_the_shared_emulator() {
        let mut service = EmulatorService::new([0.0; AXES], CycleTime::DEFAULT);
        let clean = parse_request("W 1300/0/1/0 i 1").expect("W").to_wire();
        assert!(matches!(
            service.serve(clean),
            Slice::Done(uoi::wire::Answer::Ok)
        ));
        assert_eq!(service.emulator_mut().clean_epoch(), 1);
    }
}
