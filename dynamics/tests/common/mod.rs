//! Helpers shared by the integration tests.
#![allow(dead_code)]

use nalgebra::{DMatrix, DVector};

/// `max |a − b| / max(max |b|, floor)`.
pub fn rel_err_mat(a: &DMatrix<f64>, b: &DMatrix<f64>, floor: f64) -> f64 {
    let scale = b.amax().max(floor);
    (a - b).amax() / scale
}

/// `max |a − b| / max(max |b|, floor)`.
pub fn rel_err_vec(a: &DVector<f64>, b: &DVector<f64>, floor: f64) -> f64 {
    let scale = b.amax().max(floor);
    (a - b).amax() / scale
}
