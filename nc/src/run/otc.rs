//! `#OTC`: options and switching written to the OTC objects (device 3),
//! and the OTC error bits read back after switching.

use tc_objects::{OtcMode as Mode, ProcType};
use uoi::{Value, ValueType};

use super::eval::eval;
use super::objects;
use super::{Interpreter, RunErrorKind};
use crate::model::{OtcCommand, OtcKind, OtcMode, OtcOption};

/// A whole number as an `i` value.
pub(super) fn whole(v: f64, what: &'static str) -> Result<i32, RunErrorKind> {
    if v.fract() == 0.0 && v >= f64::from(i32::MIN) && v <= f64::from(i32::MAX) {
        // Checked to be a whole number in range.
        Ok(v as i32)
    } else {
        Err(RunErrorKind::NotWhole { what, value: v })
    }
}

impl Interpreter<'_> {
    /// Carries out one `#OTC` command. Switching acts where the program
    /// stands on the path: the motion programmed before it is run first
    /// (`EXEC`), so the wear is counted from ON to OFF along the path.
    pub(super) fn otc(&mut self, cmd: &OtcCommand) -> Result<(), RunErrorKind> {
        if cmd.switch.is_some() {
            self.send(&tc_request::Request::Exec(None))?;
        }
        if cmd.switch == Some(false) {
            self.write(objects::OTC_ON, Value::I32(0))?;
            self.check_otc_error()?;
        }
        for option in &cmd.options {
            self.otc_option(option)?;
        }
        if cmd.switch == Some(true) {
            self.write(objects::OTC_ON, Value::I32(1))?;
            self.check_otc_error()?;
        }
        Ok(())
    }

    fn otc_option(&mut self, option: &OtcOption) -> Result<(), RunErrorKind> {
        let (addr, value) = match option {
            OtcOption::Kind(k) => (
                objects::OTC_PROC_TYPE,
                Value::I32(
                    match k {
                        OtcKind::Radius => ProcType::Radius,
                        OtcKind::Length => ProcType::Length,
                        OtcKind::ToolDir => ProcType::ToolDir,
                        OtcKind::SurfNormDir => ProcType::SurfNormDir,
                    }
                    .code(),
                ),
            ),
            OtcOption::Mode(m) => (
                objects::OTC_MODE,
                Value::I32(
                    match m {
                        OtcMode::Disc => Mode::Disc,
                        OtcMode::Cont => Mode::Cont,
                        OtcMode::Auto => Mode::Auto,
                    }
                    .code(),
                ),
            ),
            OtcOption::WearConst(e) => (objects::OTC_WEAR_CONST, Value::F64(eval(e, self)?)),
            OtcOption::WearConstTool => (objects::OTC_WEAR_CONST_TOOL, Value::I32(1)),
            OtcOption::AccWeight(e) => {
                let w = whole(eval(e, self)?, "ACC_WEIGHT")?;
                (objects::OTC_ACC_WEIGHT, Value::I32(w))
            }
        };
        self.write(addr, value)?;
        self.check_otc_error()
    }

    /// Reads OtcError; each bit newly set is a fault of this block.
    fn check_otc_error(&mut self) -> Result<(), RunErrorKind> {
        let bits = whole(
            self.read_object(objects::OTC_ERROR, ValueType::I32)?,
            "OtcError",
        )?;
        let new = bits & !self.otc_seen;
        self.otc_seen = bits;
        for (bit, name) in objects::OTC_ERROR_BITS {
            if new & bit != 0 {
                let fault = self.error(RunErrorKind::Otc { bit, name });
                self.report.fault(fault);
            }
        }
        Ok(())
    }
}
