//! URDF import on arbitrary text, with each base: a model or an error naming the line, never a
//! panic or a hang.
#![no_main]

use articulated_codegen::urdf::{from_urdf_str, FloatingBase};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        for base in [FloatingBase::Fixed, FloatingBase::Quaternion] {
            let _ = from_urdf_str(text, base);
        }
    }
});
