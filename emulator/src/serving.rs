//! One slice of a wire request served on an emulator: what the shared
//! service ([`crate::service`]) and a conformance session
//! ([`crate::session`]) both do. Object accesses (READ, WRITE) go straight
//! to the emulator; the TC side's own ops are decoded with `tc-request`,
//! run, and answered with the reply's wire form.

use tc_module::{ExecLeft, TcExtension};
use tc_request::Request;
use uoi::tcp::Slice;
use uoi::wire::{Answer, Request as WireRequest};

use crate::Emulator;

/// An emulator-control op: not the emulator's to serve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Control {
    /// `SETUP`.
    Setup,
    /// `SPOOL_LOG` with its logging flag.
    SpoolLog(bool),
}

/// Serves one slice of `req` on `emu`: object accesses straight, the TC
/// side's own ops decoded by `tc-request` and run; an `EXEC` runs one
/// slice ([`TcModule::exec_slice`](tc_module::TcModule::exec_slice)) and
/// hands back the rest. An emulator-control op is handed back, for the
/// caller to serve.
pub(crate) fn serve_slice<E: TcExtension>(
    emu: &mut Emulator<E>,
    req: WireRequest,
) -> Result<Slice, Control> {
    let answer = match req {
        WireRequest::Read(a, ty) => match emu.read(a, ty) {
            Ok(v) => Answer::Value(v),
            Err(e) => Answer::Access(e),
        },
        WireRequest::Write(a, v) => match emu.write(a, v) {
            Ok(()) => Answer::Ok,
            Err(e) => Answer::Access(e),
        },
        ext => match Request::from_wire(&ext) {
            Ok(Request::Setup { .. }) => return Err(Control::Setup),
            Ok(Request::SpoolLog { logging }) => return Err(Control::SpoolLog(logging)),
            Ok(Request::Exec(cycles)) => match emu.exec_slice(cycles) {
                ExecLeft::Done => Answer::Ok,
                ExecLeft::Rest(rest) => return Ok(Slice::More(Request::Exec(rest).to_wire())),
            },
            Ok(r) => emu.run(&r).to_wire(),
            Err(e) => Answer::Protocol(e),
        },
    };
    Ok(Slice::Done(answer))
}
