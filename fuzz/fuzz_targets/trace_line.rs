//! The trace reader and the request parser on any bytes.
//! The checks are `fuzz_checks::trace_line` (docs/fuzzing.md).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| fuzz_checks::trace_line(data));
