//! NC program text: parsed and, when it parses, run by the interpreter on
//! the real emulator. The checks are `fuzz_checks::nc_program`
//! (docs/fuzzing.md).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| fuzz_checks::nc_program(data));
