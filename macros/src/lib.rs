//! The `chain!` and `#[derive(Chain)]` macros of `articulated`: a shim over
//! `articulated-codegen`, where all the logic lives.
