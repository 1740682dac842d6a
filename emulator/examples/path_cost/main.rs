//! The instructions of one durable tool write and of one `EXEC` slice on
//! the shared service, for callgrind (docs/performance.md, "Architecture
//! step 3: a tool write and an EXEC slice"):
//!
//! ```text
//! cargo build --release -p emulator --example path_cost
//! valgrind --tool=callgrind --separate-threads=yes target/release/examples/path_cost
//! callgrind_annotate --inclusive=yes callgrind.out.<pid>-01 | grep path_cost::
//! ```
//!
//! `one_tool_write` (run [`WRITES`] times) serves a RADIUS write and, once
//! the tool store's writer has it on disk (outside the function: the
//! writer's thread and the disk are the store's), resumes it.
//! `one_exec_slice` (run [`SLICES`] times) serves one slice of 10,000
//! cycles of an `EXEC` with OTC on.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use emulator::{EmulatorService, ExecRest};
use tc_module::CycleTime;
use tc_request::text::parse_request;
use uoi::tcp::{Handler, Slice};
use uoi::wire::{Answer, Request as WireRequest};

/// RADIUS writes measured.
const WRITES: usize = 200;
/// EXEC slices measured.
const SLICES: usize = 50;

fn wire(text: &str) -> WireRequest {
    parse_request(text).unwrap().to_wire()
}

/// Serves a durable tool write: the part before the disk.
#[inline(never)]
fn one_tool_write(s: &mut EmulatorService, req: WireRequest) -> Slice<ExecRest> {
    s.serve(req)
}

/// The part after the disk.
#[inline(never)]
fn one_tool_write_resumed(s: &mut EmulatorService, token: u64, ok: bool) -> Slice<ExecRest> {
    s.resume(token, ok)
}

fn tool_writes() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = EmulatorService::new([0.0; 8], CycleTime::DEFAULT);
    let _lock = s.open_tools(dir.path(), false).unwrap();
    for i in 0..WRITES {
        let req = wire(&format!("W 1300/1/1/6 d {}", 1.0 + i as f64 / 1000.0));
        let Slice::Wait(w) = one_tool_write(&mut s, req) else {
            panic!("a durable write waits for the disk");
        };
        let ok = w.done.blocking_recv().unwrap_or(false);
        let done = one_tool_write_resumed(&mut s, w.token, ok);
        assert!(matches!(done, Slice::Done(Answer::Ok)));
    }
    s.close_tools();
}

mod exec;
use exec::exec_slices;

fn main() {
    tool_writes();
    exec_slices();
}
