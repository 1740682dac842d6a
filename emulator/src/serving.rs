//! One slice of a wire request served on an emulator: what the shared
//! service ([`crate::service`]) and a conformance session
//! ([`crate::session`]) both do. Object accesses (READ, WRITE) go straight
//! to the emulator; the TC side's own ops are decoded with `tc-request`,
//! run, and answered with the reply's wire form. A long `EXEC` leaves its
//! rest typed ([`ExecRest`]), continued by [`proceed_slice`].

use tc_module::{ExecLeft, TcExtension};
use tc_request::Request;
use uoi::tcp::Slice;
use uoi::wire::{Answer, Request as WireRequest};

use crate::Emulator;

/// The rest of an `EXEC` served in slices, as the handler keeps it
/// between two slices ([`uoi::tcp::Handler::Rest`]): the cycles left, or
/// `None` to run until the spooler is empty. Resumed as it is
/// ([`proceed_slice`]), never encoded and decoded again.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ExecRest(pub Option<u64>);

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
) -> Result<Slice<ExecRest>, Control> {
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
            Ok(Request::Exec(cycles)) => return Ok(proceed_slice(emu, ExecRest(cycles))),
            Ok(r) => emu.run(&r).to_wire(),
            Err(e) => Answer::Protocol(e),
        },
    };
    Ok(Slice::Done(answer))
}

/// The next slice of an `EXEC` from its rest: `Ok` once it is complete,
/// else the rest again.
pub(crate) fn proceed_slice<E: TcExtension>(
    emu: &mut Emulator<E>,
    rest: ExecRest,
) -> Slice<ExecRest> {
    match emu.exec_slice(rest.0) {
        ExecLeft::Done => Slice::Done(Answer::Ok),
        ExecLeft::Rest(left) => Slice::More(ExecRest(left)),
    }
}
