//! Reference dynamics (to be written).
