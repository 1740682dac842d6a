//! The `EXEC` half of `path_cost`: a rest is continued as the handler
//! left it (`Handler::proceed`).

use super::{wire, SLICES};
use emulator::{EmulatorService, ExecRest};
use std::hint::black_box;
use tc_module::CycleTime;
use uoi::tcp::{Handler, Slice};
use uoi::wire::Answer;

/// One slice of an `EXEC`'s rest.
#[inline(never)]
fn one_exec_slice(s: &mut EmulatorService, rest: ExecRest) -> Slice<ExecRest> {
    s.proceed(rest)
}

/// An `EXEC` of 1,000,000 cycles with OTC on, [`SLICES`] of its slices
/// measured.
pub fn exec_slices() {
    let mut s = EmulatorService::new([0.0; 8], CycleTime::DEFAULT);
    for text in [
        "W 1300/1/1/8 i 1",
        "W 1300/3/1/30 i 2",
        "W 1300/3/1/1 i 1",
        "LIN X100000 F6000",
    ] {
        assert!(
            matches!(s.serve(wire(text)), Slice::Done(Answer::Ok)),
            "{text}"
        );
    }
    let mut slice = s.serve(wire("EXEC"));
    for _ in 0..SLICES {
        let Slice::More(rest) = slice else {
            panic!("an EXEC of 1,000,000 cycles takes 100 slices");
        };
        slice = one_exec_slice(&mut s, black_box(rest));
    }
}
