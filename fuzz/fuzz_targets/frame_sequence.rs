//! A client's byte stream of frames served by a connection's session and the shared emulator.
//! The checks are `fuzz_checks::frame_sequence` (docs/fuzzing.md).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| fuzz_checks::frame_sequence(data));
