use std::hint::black_box;
use tc_module::CycleTime;
use emulator::EmulatorService;
use uoi::tcp::{Handler, Slice};
use uoi::wire::{Answer, Request as WireRequest};
use super::{wire, SLICES};

// The EXEC half of `path_cost` before the typed continuation: a rest
// re-enters `serve` as a wire request.

/// One slice of an `EXEC`'s rest.
#[inline(never)]
fn one_exec_slice(s: &mut EmulatorService, rest: WireRequest) -> Slice {
    s.serve(rest)
}

pub fn exec_slices() {
    let mut s = EmulatorService::new([0.0; 8], CycleTime::DEFAULT);
    for text in [
        "W 1300/1/1/8 i 1",
        "W 1300/3/1/30 i 2",
        "W 1300/3/1/1 i 1",
        "LIN X100000 F6000",
    ] {
        assert!(matches!(s.serve(wire(text)), Slice::Done(Answer::Ok)), "{text}");
    }
    let mut slice = s.serve(wire("EXEC"));
    for _ in 0..SLICES {
        let Slice::More(rest) = slice else {
            panic!("an EXEC of 1,000,000 cycles takes 100 slices");
        };
        slice = one_exec_slice(&mut s, black_box(rest));
    }
}
