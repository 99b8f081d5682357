//! Runnable examples of `articulated` live in `examples/`.
