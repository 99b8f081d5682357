//! Non-finite inputs to generated code (issue 14): the functions that solve with `M` return an
//! error, never a value; the straight-line ones propagate NaN as documented
//! (`articulated::generated`'s module docs) and stay finite on finite inputs.

use articulated::nalgebra::SVector;
use articulated::prelude::*;

#[derive(Chain)]
#[chain(
    file = "../models/two_link.chain",
    outputs = [mass_matrix, inverse_dynamics, forward_dynamics, mass_matrix_inverse]
)]
struct TwoLink;

#[derive(Chain)]
#[chain(file = "../models/two_link.chain", scalar = f32, accuracy = robust, outputs = [forward_dynamics])]
struct TwoLinkF32;

type V6 = SVector<f64, 6>;

#[test]
fn solving_functions_refuse_non_finite_inputs() {
    let ok = V6::from([0.1, 0.2, -0.1, 0.3, -0.2, 0.1]);
    let bad_values = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, f64::MAX];
    for k in 0..6 {
        for bad in bad_values {
            let mut x = ok;
            x[k] = bad;
            // In q, in v, in τ: an error, or (f64::MAX in τ or v, which a chain can take) a
            // finite value.
            for (q, v, tau) in [(x, ok, ok), (ok, x, ok), (ok, ok, x)] {
                match TwoLink::forward_dynamics(&q, &v, &tau) {
                    Err(_) => {}
                    Ok(qdd) => assert!(
                        qdd.iter().all(|a| a.is_finite()),
                        "q {q} v {v} τ {tau}: {qdd}"
                    ),
                }
            }
            let mut q = ok;
            q[k] = bad;
            // `M⁻¹` does not read the first angle (about the world's x axis, it moves no
            // inertia relative to the others): there a finite value is right; never a NaN.
            match TwoLink::mass_matrix_inverse(&q) {
                Err(_) => {}
                Ok(m) => assert!(
                    (k == 0 || bad.is_finite()) && m.iter().all(|x| x.is_finite()),
                    "q {q}: {m}"
                ),
            }
            if !bad.is_finite() {
                assert!(TwoLink::forward_dynamics(&q, &ok, &ok).is_err(), "q {q}");
            }
        }
    }
    let q32 = SVector::<f32, 6>::from([f32::NAN, 0.0, 0.0, 0.0, 0.0, 0.0]);
    assert!(TwoLinkF32::forward_dynamics(&q32, &SVector::zeros(), &SVector::zeros()).is_err());
}

#[test]
fn straight_line_functions_propagate_nan_and_stay_finite_otherwise() {
    let ok = V6::from([0.1, 0.2, -0.1, 0.3, -0.2, 0.1]);
    let mut q = ok;
    q[1] = f64::NAN;
    assert!(TwoLink::mass_matrix(&q).iter().any(|x| x.is_nan()));
    assert!(TwoLink::inverse_dynamics(&ok, &q, &ok)
        .iter()
        .any(|x| x.is_nan()));
    // Finite and large: finite.
    let big = V6::from_element(1e3);
    assert!(TwoLink::mass_matrix(&big).iter().all(|x| x.is_finite()));
    assert!(TwoLink::inverse_dynamics(&big, &big, &big)
        .iter()
        .all(|x| x.is_finite()));
}
