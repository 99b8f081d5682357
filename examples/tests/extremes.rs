//! The accuracy study's bounds (issue 12), asserted on every row of the extremes table
//! (`articulated_examples::extremes`): generated forward dynamics, `M` and `τ` in `f64` and
//! `f32`, each accuracy choice, against the double-double ground truth.

use articulated_examples::extremes::{rows, Outcome, Row};

const EPS64: f64 = f64::EPSILON;
const EPS32: f64 = f32::EPSILON as f64;

fn describe(r: &Row) -> String {
    format!("{} {} (cond(M) {:.1e}): {r:?}", r.scenario, r.case, r.cond)
}

/// An accepted result is finite: `relative_error` is infinite for a non-finite entry.
fn finite(o: Outcome, r: &Row) {
    if let Outcome::Error(e) = o {
        assert!(e.is_finite(), "non-finite result: {}", describe(r));
    }
}

#[test]
fn nothing_returns_a_non_finite_value() {
    for r in &rows() {
        for o in [
            r.reference,
            r.fastest.forward,
            r.robust.forward,
            r.fastest_f32.forward,
            r.robust_f32.forward,
        ] {
            finite(o, r);
        }
        for m in [r.fastest, r.robust, r.fastest_f32, r.robust_f32] {
            assert!(m.others.is_finite(), "M or τ not finite: {}", describe(r));
        }
    }
}

/// The bound for `accuracy: robust` in `f64`: within 1e-12 of ground truth wherever
/// `cond(M) < 1e8`, and within 10× the reference's own error wherever else the reference solves.
#[test]
fn robust_f64_forward_dynamics_meets_the_bound() {
    for r in &rows() {
        let robust = r.robust.forward;
        if r.cond < 1e8 {
            let e = robust
                .error()
                .unwrap_or_else(|| panic!("refused: {}", describe(r)));
            assert!(e <= 1e-12, "{e:e}: {}", describe(r));
        } else if let Outcome::Error(reference) = r.reference {
            let e = robust
                .error()
                .unwrap_or_else(|| panic!("refused: {}", describe(r)));
            assert!(
                e <= (10.0 * reference).max(64.0 * EPS64),
                "{e:e}: {}",
                describe(r)
            );
        }
    }
}

/// `accuracy: fastest` keeps `LᵀDL` where it is cheaper: its error grows as `ε·cond(M)`, and it
/// still accepts every well-conditioned state.
#[test]
fn fastest_forward_dynamics_errs_within_eps_cond() {
    for r in &rows() {
        for (o, eps) in [(r.fastest.forward, EPS64), (r.fastest_f32.forward, EPS32)] {
            match o {
                Outcome::Error(e) => {
                    assert!(e <= 100.0 * eps * r.cond.max(1.0), "{e:e}: {}", describe(r))
                }
                Outcome::Refused => assert!(r.cond * eps > 1e-4, "refused: {}", describe(r)),
            }
        }
    }
}

/// `f32` with `accuracy: robust`: a few hundred ulps wherever it accepts, and it accepts every
/// state within `f32`'s reach (`cond(M)·ε < 1e-3`) and every leaf-light or slender tip.
#[test]
fn robust_f32_forward_dynamics_stays_accurate() {
    for r in &rows() {
        match r.robust_f32.forward {
            Outcome::Error(e) => assert!(e <= 1e-4, "{e:e}: {}", describe(r)),
            Outcome::Refused => assert!(
                r.cond * EPS32 > 1e-3 && r.scenario.starts_with("gimbal"),
                "refused: {}",
                describe(r)
            ),
        }
    }
}

/// `M` and `τ` are products and sums, no solve: a few ulps everywhere, whatever `cond(M)`.
#[test]
fn mass_matrix_and_inverse_dynamics_keep_their_digits() {
    for r in &rows() {
        for m in [r.fastest, r.robust] {
            assert!(m.others <= 8.0 * EPS64, "{:e}: {}", m.others, describe(r));
        }
        for m in [r.fastest_f32, r.robust_f32] {
            assert!(m.others <= 8.0 * EPS32, "{:e}: {}", m.others, describe(r));
        }
    }
}

/// Singular to `f64`'s precision (`cond(M)·ε > 1`): every `f64` way refuses.
#[test]
fn singular_states_are_refused() {
    let rows = rows();
    let singular: Vec<&Row> = rows.iter().filter(|r| r.cond * EPS64 > 1.0).collect();
    assert!(singular.len() >= 2, "the sweep reaches exact gimbal lock");
    for r in singular {
        assert_eq!(r.robust.forward, Outcome::Refused, "{}", describe(r));
        assert_eq!(r.fastest.forward, Outcome::Refused, "{}", describe(r));
    }
}

/// Quaternion joints pass through the attitudes where the Euler angles lock: `cond(M)` stays
/// that of the bodies, and every way solves to a few ulps of its scalar.
#[test]
fn quaternions_pass_through_gimbal_lock_cleanly() {
    let rows = rows();
    let quaternion: Vec<&Row> = rows
        .iter()
        .filter(|r| r.scenario.contains("quaternions"))
        .collect();
    assert_eq!(quaternion.len(), 9);
    for r in quaternion {
        assert!(r.cond < 1e4, "{}", describe(r));
        for o in [r.fastest.forward, r.robust.forward] {
            let e = o
                .error()
                .unwrap_or_else(|| panic!("refused: {}", describe(r)));
            assert!(e <= 64.0 * EPS64, "{e:e}: {}", describe(r));
        }
        for o in [r.fastest_f32.forward, r.robust_f32.forward] {
            let e = o
                .error()
                .unwrap_or_else(|| panic!("refused: {}", describe(r)));
            assert!(e <= 64.0 * EPS32, "{e:e}: {}", describe(r));
        }
    }
}

/// The cases the issue names are in the table: gimbal lock down to exactly `π/2`, a 1e12 mass
/// ratio (which the `f64` reference refuses and the generated code solves to ground truth's
/// digits), and 1e4 rad/s spin.
#[test]
fn the_named_extremes_are_covered() {
    let rows = rows();
    let find = |scenario: &str, case: &str| {
        rows.iter()
            .find(|r| r.scenario.starts_with(scenario) && r.case == case)
            .unwrap_or_else(|| panic!("no row {scenario} {case}"))
    };
    find("gimbal lock", "δ = 0e0");
    let ratio = find("mass ratio", "1e12");
    for o in [
        ratio.fastest.forward,
        ratio.robust.forward,
        ratio.fastest_f32.forward,
        ratio.robust_f32.forward,
    ] {
        assert!(o.error().is_some(), "refused: {}", describe(ratio));
    }
    assert!(ratio.robust.forward.error().is_some_and(|e| e < 1e-15));
    let spin = find("spin, two-link", "1e4 rad/s");
    for o in [spin.fastest.forward, spin.robust.forward] {
        assert!(o.error().is_some_and(|e| e < 1e-13), "{}", describe(spin));
    }
    for o in [spin.fastest_f32.forward, spin.robust_f32.forward] {
        assert!(o.error().is_some_and(|e| e < 1e-5), "{}", describe(spin));
    }
}
