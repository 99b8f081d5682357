//! The `.chain` grammar and its lowering on arbitrary text: a description or a list of
//! line-numbered errors, never a panic or a hang.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = articulated_codegen::load::parse_chain_str(text, std::path::Path::new("fuzz.chain"));
    }
});
