//! The server's and the client's frame decoders on any bytes.
//! The checks are `fuzz_checks::frame_decoder` (docs/fuzzing.md).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| fuzz_checks::frame_decoder(data));
