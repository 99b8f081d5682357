//! Symbolic scalar (being written).
