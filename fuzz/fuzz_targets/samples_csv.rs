//! The CSV reader of `articulated invert` (sampled trajectories) on arbitrary text and widths:
//! samples or an error naming the line, never a panic or a hang.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&width, rest)) = data.split_first() else {
        return;
    };
    if let Ok(text) = std::str::from_utf8(rest) {
        let _ = articulated::samples::Samples::parse_csv(text, usize::from(width % 16));
    }
});
