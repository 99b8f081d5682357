//! The `chain!{}` macro's entry point on arbitrary token streams: generated code or a
//! `compile_error!` at a span, never a panic or a hang.
#![no_main]

use std::str::FromStr;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    // What the compiler would hand the macro: only text that lexes as Rust tokens.
    if let Ok(tokens) = proc_macro2::TokenStream::from_str(text) {
        let _ = articulated_codegen::expand::chain(tokens);
    }
});
