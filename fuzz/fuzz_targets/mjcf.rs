//! MJCF import on arbitrary text: a model or an error naming the line, never a panic or a hang.
#![no_main]

use articulated_codegen::mjcf::from_mjcf_str;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = from_mjcf_str(text);
    }
});
