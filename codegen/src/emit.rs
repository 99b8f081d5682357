//! Emission of straight-line Rust (being written).
