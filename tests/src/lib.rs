//! Cross-crate tests of `articulated` live in `tests/`.
