//! The bounds of the fuzz checks: how much of an input they read, and
//! what an input may make the emulator do before a check calls it enough.

use tc_module::MAX_COORD;
use uoi::wire::{MAX_FRAME, PREFIX_LEN};

use trace::MAX_LINE_BYTES;

/// Most bytes of an input a check reads: four of the largest frames.
pub const MAX_INPUT: usize = 4 * (PREFIX_LEN + MAX_FRAME);

/// Most bytes of an input [`trace_line`](crate::trace_line) reads: room for a line past the
/// trace reader's limit ([`MAX_LINE_BYTES`]).
pub const MAX_TRACE_INPUT: usize = 2 * MAX_LINE_BYTES;

/// Most bytes of an NC program [`nc_program`](crate::nc_program) reads.
pub const MAX_NC_INPUT: usize = 16 * 1024;

/// Most requests the interpreter may send in one [`nc_program`](crate::nc_program) run;
/// past them every request is refused, which ends the run with an error.
/// A harness bound only: a loop of motion blocks may legitimately run far
/// longer.
pub const NC_REQUEST_BUDGET: u64 = 5_000;

/// Most stepped slices of `EXEC` (each up to `EXEC_SLICE_CYCLES` cycles
/// with OTC on) one [`nc_program`](crate::nc_program) run may take in all; past them an
/// `EXEC` stops where it is. A slow feed over a long path with OTC on
/// would otherwise run for hours of emulated time.
pub const NC_EXEC_SLICES: u32 = 2;

/// Most frames [`frame_sequence`](crate::frame_sequence) serves of one input.
pub const MAX_FRAMES: usize = 512;

/// Most interpolation cycles [`frame_sequence`](crate::frame_sequence) lets one input run, over
/// all its `EXEC` requests; each `EXEC` is cut to what is left. A harness
/// bound only: a legitimate `EXEC` may run far longer, and the fuzzer
/// must not take that for a hang.
pub const EXEC_BUDGET: u64 = 20_000;

/// Largest magnitude of an executed or spooled coordinate: every word,
/// offset and centre a command carries is within [`MAX_COORD`], and a
/// rotation about a centre, an arc about its centre and the tool radius
/// and length move a point by a few such amounts at most.
pub const POS_LIMIT: f64 = 2.0 * MAX_COORD;

/// Most elements [`frame_sequence`](crate::frame_sequence) allows the spooler to hold per frame
/// served (a corrected command spools the corrected element, its
/// transition and the approach or departure).
pub const SPOOLED_PER_FRAME: u64 = 8;
