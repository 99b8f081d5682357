//! Free-floating chains, generated (issue "Free-floating chains", Wieber 2005):
//!
//! - the centre of mass, its velocity and Jacobian, the centroidal momentum and its matrix, the
//!   energies and the Coriolis matrix of the shipped floating models against Pinocchio
//!   (`tests/data/pinocchio-centroidal.json`, written by `tests/data/make_centroidal_reference.py`)
//!   to 1e-10, and against the interpreted reference on random states to 1e-12;
//! - the rate of the centroidal momentum and its drift: the humanoid's against Pinocchio's
//!   `computeCentroidalMomentumTimeVariation` (`tests/data/pinocchio_centroidal_rate/`) to 1e-12,
//!   every floating model's against the reference to 1e-12 and against five-point central
//!   differences of the generated `centroidal_momentum` along the motion to 1e-9, the drift
//!   against the rate at `a = 0` to 1e-12;
//! - Wieber's claims as identities of the generated code: gravity is `−M·[g; 0]` on an Euler free
//!   base (§4), and the six base rows of `M·q̈ + N·q̇` are the Newton and Euler equations of the
//!   whole system, `ḣ_G = Σ` of the bodies' net wrenches about the centre of mass (computed
//!   independently from Wieber's body Jacobians, `reference::jacobian`);
//! - in simulation, with internal couples only, the centre of mass falls with `g` whatever the
//!   couples and the angular momentum about it stays constant (§5).
//!
//! `cargo test -p articulated-tests --test generated_free_floating -- --nocapture` prints the
//! worst errors.

mod common;

use std::path::Path;

use articulated::integrate::{ControlledChain, Dopri5, State};
use articulated::nalgebra::{DVector, Matrix3, SVector, Vector3};
use articulated::prelude::*;
use articulated::reference::{jacobian, Reference};
use articulated_codegen::load::load_model;
use articulated_dynamics::model::Model;
use articulated_dynamics::random::{random_state, Rng};
use common::{
    centroidal_rate_by_differences, centroidal_rate_errors, coriolis_error, read_json, rel_err,
    row_major, rows_of, vec_of, whole_body_errors, WHOLE_BODY_OUTPUTS,
};
use serde_json::Value as Json;

/// Against Pinocchio, relative to the largest entry of its value.
const TOL: f64 = 1e-10;

#[derive(Chain)]
#[chain(
    file = "../models/humanoid.chain",
    outputs = [
        center_of_mass,
        center_of_mass_velocity,
        center_of_mass_jacobian,
        centroidal_momentum,
        centroidal_momentum_matrix,
        centroidal_momentum_rate,
        centroidal_momentum_drift,
        kinetic_energy,
        potential_energy,
        coriolis_matrix
    ]
)]
struct Humanoid;

#[derive(Chain)]
#[chain(
    urdf = "../models/arm7.urdf",
    floating,
    outputs = [
        mass_matrix,
        bias,
        gravity,
        forward_dynamics,
        center_of_mass,
        center_of_mass_velocity,
        center_of_mass_jacobian,
        centroidal_momentum,
        centroidal_momentum_matrix,
        centroidal_momentum_rate,
        centroidal_momentum_drift,
        kinetic_energy,
        potential_energy,
        coriolis_matrix
    ]
)]
struct Arm7Floating;

#[derive(Chain)]
#[chain(
    urdf = "../models/tree.urdf",
    floating,
    outputs = [
        center_of_mass,
        center_of_mass_velocity,
        center_of_mass_jacobian,
        centroidal_momentum,
        centroidal_momentum_matrix,
        centroidal_momentum_rate,
        centroidal_momentum_drift,
        kinetic_energy,
        potential_energy,
        coriolis_matrix
    ]
)]
struct TreeFloating;

#[derive(Chain)]
#[chain(
    file = "fixtures/tumbler.chain",
    outputs = [
        mass_matrix,
        bias,
        forward_dynamics,
        center_of_mass,
        centroidal_momentum
    ]
)]
struct Tumbler;

fn repo(rel: &str) -> String {
    format!("{}/../{rel}", env!("CARGO_MANIFEST_DIR"))
}

fn tumbler() -> String {
    format!("{}/fixtures/tumbler.chain", env!("CARGO_MANIFEST_DIR"))
}

fn floating(urdf: &str) -> Model {
    load_model(Path::new(&repo(urdf)), true).unwrap_or_else(|e| panic!("{e}"))
}

/// The whole-system quantities at `(q, v)` as Pinocchio's data lists them: centre of mass, its
/// velocity, its Jacobian (rows), the centroidal momentum, its matrix (rows), the kinetic and
/// potential energy, the Coriolis matrix (rows): `common::WHOLE_BODY_OUTPUTS`.
type Quantities = [Vec<f64>; 8];

/// The generated chain's [`Quantities`].
fn generated<C, const NQ: usize, const NV: usize>(q: &[f64], v: &[f64]) -> Quantities
where
    C: WholeBodyOutputs<f64, NQ, NV>,
{
    let (q, v) = (
        SVector::<f64, NQ>::from_column_slice(q),
        SVector::<f64, NV>::from_column_slice(v),
    );
    [
        C::center_of_mass(&q).as_slice().to_vec(),
        C::center_of_mass_velocity(&q, &v).as_slice().to_vec(),
        row_major(C::center_of_mass_jacobian(&q).as_slice(), 3),
        C::centroidal_momentum(&q, &v).as_slice().to_vec(),
        row_major(C::centroidal_momentum_matrix(&q).as_slice(), 6),
        vec![C::kinetic_energy(&q, &v)],
        vec![C::potential_energy(&q)],
        row_major(C::coriolis_matrix(&q, &v).as_slice(), NV),
    ]
}

/// The interpreted reference's [`Quantities`].
fn interpreted(r: &Reference, q: &[f64], v: &[f64]) -> Quantities {
    [
        r.center_of_mass(q).unwrap().as_slice().to_vec(),
        r.center_of_mass_velocity(q, v).unwrap().as_slice().to_vec(),
        row_major(r.center_of_mass_jacobian(q).unwrap().as_slice(), 3),
        r.centroidal_momentum(q, v).unwrap().as_slice().to_vec(),
        row_major(r.centroidal_momentum_matrix(q).unwrap().as_slice(), 6),
        vec![r.kinetic_energy(q, v).unwrap()],
        vec![r.potential_energy(q).unwrap()],
        row_major(r.coriolis_matrix(q, v).unwrap().as_slice(), r.nv()),
    ]
}

/// One configuration of the Pinocchio data against `ours` (the generated chain or the
/// reference); returns the failures. The Coriolis matrix is compared entry by entry: where
/// `v = q̇` (the Euler bases) both are the matrix of the Christoffel symbols (the script stores
/// Pinocchio's from the base built as four joints, its composite joint being wrong, issue 2053);
/// on the free flyer both use the same factorization. The energies are relative to
/// `max(1, |value|)` (joules), the rest to the largest entry of Pinocchio's value.
fn compare(label: &str, data: &Json, ours: impl Fn(&[f64], &[f64]) -> Quantities) -> Vec<String> {
    let mut failures = Vec::new();
    let mut worst = [0.0f64; 8];
    for (k, s) in data["states"].as_array().unwrap().iter().enumerate() {
        let (q, v) = (vec_of(&s["q"]), vec_of(&s["v"]));
        let values = ours(&q, &v);
        for ((w, x), name) in worst.iter_mut().zip(&values).zip(WHOLE_BODY_OUTPUTS) {
            let theirs = match &s[name] {
                Json::Number(n) => vec![n.as_f64().unwrap()],
                j if j[0].is_array() => rows_of(j),
                j => vec_of(j),
            };
            let e = if theirs.len() == 1 {
                (x[0] - theirs[0]).abs() / theirs[0].abs().max(1.0)
            } else {
                rel_err(x, &theirs)
            };
            *w = w.max(e);
            if e.is_nan() || e >= TOL {
                failures.push(format!(
                    "{label} state {k}: {name} differs from Pinocchio by {e:e}"
                ));
            }
        }
    }
    let line: Vec<String> = WHOLE_BODY_OUTPUTS
        .iter()
        .zip(worst)
        .map(|(n, w)| format!("{n} {w:.1e}"))
        .collect();
    println!("{label}: {}", line.join(" | "));
    failures
}

/// The generated chains and the reference against Pinocchio on the four floating
/// configurations. The humanoid on the Euler base is the same tree as on the free flyer with
/// another base: only the reference is compared there (generating it again would add a minute to
/// every build for a base that the arm and the tree already check in generated code).
#[test]
fn floating_models_match_pinocchio() {
    let json = read_json("data/pinocchio-centroidal.json");
    let models = &json["models"];
    let humanoid = load_model(Path::new(&repo("models/humanoid.chain")), false).unwrap();
    let configurations = [
        (
            "humanoid (free flyer)",
            &models["humanoid"]["free_flyer"],
            humanoid,
        ),
        (
            "humanoid (floating)",
            &models["humanoid"]["floating"],
            floating("models/humanoid.urdf"),
        ),
        (
            "arm7 (floating)",
            &models["arm7"]["floating"],
            floating("models/arm7.urdf"),
        ),
        (
            "tree (floating)",
            &models["tree"]["floating"],
            floating("models/tree.urdf"),
        ),
    ];
    let mut failures = Vec::new();
    for (label, data, model) in &configurations {
        assert_eq!(data["nv"].as_u64(), Some(model.nv() as u64), "{label}");
        let r = Reference::new(model).unwrap();
        failures.extend(compare(&format!("{label}, reference"), data, |q, v| {
            interpreted(&r, q, v)
        }));
    }
    let [(_, humanoid, _), _, (_, arm7, _), (_, tree, _)] = &configurations;
    failures.extend(compare(
        "humanoid (free flyer), generated",
        humanoid,
        generated::<Humanoid, 38, 37>,
    ));
    failures.extend(compare(
        "arm7 (floating), generated",
        arm7,
        generated::<Arm7Floating, 13, 13>,
    ));
    failures.extend(compare(
        "tree (floating), generated",
        tree,
        generated::<TreeFloating, 13, 13>,
    ));
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The humanoid's rate of the centroidal momentum and its drift, generated and interpreted,
/// against Pinocchio 4.1's `computeCentroidalMomentumTimeVariation` (`data.dhg`, linear first:
/// swapped by the script) on its free flyer, to 1e-12 of the largest entry
/// (`tests/data/pinocchio_centroidal_rate/`, script and values).
#[test]
fn humanoid_centroidal_momentum_rate_matches_pinocchio() {
    let json = read_json("data/pinocchio_centroidal_rate/pinocchio-centroidal-rate.json");
    let data = &json["models"]["humanoid_free_flyer"];
    let model = load_model(Path::new(&repo("models/humanoid.chain")), false).unwrap();
    assert_eq!(data["nv"].as_u64(), Some(model.nv() as u64));
    let r = Reference::new(&model).unwrap();
    let mut worst = [0.0f64; 5];
    for (k, s) in data["states"].as_array().unwrap().iter().enumerate() {
        let (q, v, a) = (vec_of(&s["q"]), vec_of(&s["v"]), vec_of(&s["a"]));
        let (rate, drift, h) = (
            vec_of(&s["centroidal_momentum_rate"]),
            vec_of(&s["centroidal_momentum_drift"]),
            vec_of(&s["centroidal_momentum"]),
        );
        let (qs, vs, as_) = (
            SVector::<f64, 38>::from_column_slice(&q),
            SVector::<f64, 37>::from_column_slice(&v),
            SVector::<f64, 37>::from_column_slice(&a),
        );
        let e = [
            rel_err(
                Humanoid::centroidal_momentum_rate(&qs, &vs, &as_).as_slice(),
                &rate,
            ),
            rel_err(
                Humanoid::centroidal_momentum_drift(&qs, &vs).as_slice(),
                &drift,
            ),
            rel_err(
                r.centroidal_momentum_rate(&q, &v, &a).unwrap().as_slice(),
                &rate,
            ),
            rel_err(
                r.centroidal_momentum_drift(&q, &v).unwrap().as_slice(),
                &drift,
            ),
            // The layout's check: the momentum itself, as `floating_models_match_pinocchio`.
            rel_err(Humanoid::centroidal_momentum(&qs, &vs).as_slice(), &h),
        ];
        for (w, e) in worst.iter_mut().zip(e) {
            *w = w.max(e);
        }
        assert!(e.iter().all(|&e| e < 1e-12), "state {k}: {e:?}");
    }
    println!(
        "humanoid (free flyer) vs Pinocchio: rate {:.1e}, drift {:.1e} generated; {:.1e}, {:.1e} \
         interpreted; h_G {:.1e}",
        worst[0], worst[1], worst[2], worst[3], worst[4]
    );
}

/// The generated outputs of every floating model against the reference at random states.
#[test]
fn floating_models_match_the_reference() {
    fn check<C, const NQ: usize, const NV: usize>(label: &str, model: &Model)
    where
        C: WholeBodyOutputs<f64, NQ, NV>,
    {
        let r = Reference::new(model).unwrap();
        let mut worst = [0.0f64; 8];
        for seed in 0..16 {
            let (q, v, _) = random_state(model, seed);
            let e = whole_body_errors::<C, NQ, NV>(&r, &q, &v);
            let n = coriolis_error::<C, NQ, NV>(&r, &q, &v);
            for (w, e) in worst.iter_mut().zip(e.into_iter().chain([n])) {
                *w = w.max(e);
            }
        }
        for (name, e) in WHOLE_BODY_OUTPUTS.iter().zip(worst) {
            assert!(e < 1e-12, "{label}: {name} off by {e:e}");
        }
        // The rate of the centroidal momentum and its drift against the reference, the rate
        // against differences of the generated `h_G` along the motion, the drift against the
        // rate at `a = 0`.
        let mut rate = [0.0f64; 4];
        for seed in 0..16 {
            let (q, v, a) = random_state(model, seed);
            let e = centroidal_rate_errors::<C, NQ, NV>(&r, &q, &v, &a);
            let d = centroidal_rate_by_differences::<C, NQ, NV>(&q, &v, &a, 1e-3);
            for (w, e) in rate.iter_mut().zip(e.into_iter().chain(d)) {
                *w = w.max(e);
            }
        }
        println!(
            "{label}: centroidal_momentum_rate, _drift vs reference {:.1e}, {:.1e}; rate vs \
             differences of h_G {:.1e}; drift vs rate at a = 0 {:.1e}",
            rate[0], rate[1], rate[2], rate[3]
        );
        let [reference, drift_reference, differences, drift] = rate;
        assert!(
            reference < 1e-12 && drift_reference < 1e-12,
            "{label}: {rate:?}"
        );
        assert!(differences < 1e-9, "{label}: {rate:?}");
        assert!(drift < 1e-12, "{label}: {rate:?}");
    }
    check::<Humanoid, 38, 37>(
        "humanoid",
        &load_model(Path::new(&repo("models/humanoid.chain")), false).unwrap(),
    );
    check::<Arm7Floating, 13, 13>("arm7 (floating)", &floating("models/arm7.urdf"));
    check::<TreeFloating, 13, 13>("tree (floating)", &floating("models/tree.urdf"));
}

/// Wieber 2005, §4: with the Euler free base (translation in the world frame, first), gravity's
/// generalized force is `𝓕_g = M(q)·[g; 0]`, so the generated `gravity = −M·[g; 0]`, exactly.
#[test]
fn gravity_is_minus_m_g_on_the_euler_base() {
    let model = floating("models/arm7.urdf");
    let mut worst = 0.0f64;
    for seed in 0..64 {
        let (q, _, _) = random_state(&model, seed);
        let q = SVector::<f64, 13>::from_column_slice(&q);
        let mut g = SVector::<f64, 13>::zeros();
        g[2] = -9.81;
        let want = -(Arm7Floating::mass_matrix(&q) * g);
        let e = rel_err(Arm7Floating::gravity(&q).as_slice(), want.as_slice());
        worst = worst.max(e);
    }
    println!("gravity = −M·[g; 0]: worst relative error {worst:.1e}");
    assert!(worst < 1e-12, "{worst:e}");
}

/// `ḣ_G = [Σ (x_k − x_G) × f_k + R_k·(I_k·ω̇_k + ω_k × I_k·ω_k); Σ f_k]` with `f_k = m_k·ẍ_k`:
/// the rate of the centroidal momentum from each body's own motion, by Wieber's body Jacobians
/// and their rates (`ẍ_k = J_t·a + J̇_t·v`, `ω̇_k = J_R·a + J̇_R·v`), sharing nothing with the
/// generated code.
fn centroidal_rate(model: &Model, q: &[f64], v: &[f64], a: &[f64]) -> (Vector3<f64>, Vector3<f64>) {
    let bodies = jacobian::body_jacobians(model, &[], q, v).unwrap();
    let (vv, aa) = (DVector::from_column_slice(v), DVector::from_column_slice(a));
    let mass: f64 = bodies.iter().map(|b| b.mass).sum();
    let com = bodies.iter().map(|b| b.com * b.mass).sum::<Vector3<f64>>() / mass;
    let (mut moment, mut force) = (Vector3::zeros(), Vector3::zeros());
    for b in &bodies {
        let acc = &b.jt * &aa + &b.jt_dot * &vv;
        let f = Vector3::new(acc[0], acc[1], acc[2]) * b.mass;
        let w = &b.jr * &vv;
        let w = Vector3::new(w[0], w[1], w[2]);
        let dw = &b.jr * &aa + &b.jr_dot * &vv;
        let dw = Vector3::new(dw[0], dw[1], dw[2]);
        let n_c: Vector3<f64> = b.rotation * (b.inertia * dw + w.cross(&(b.inertia * w)));
        moment += (b.com - com).cross(&f) + n_c;
        force += f;
    }
    (moment, force)
}

/// Wieber 2005, §4: the six base rows of `M·q̈ + N·q̇` are the Newton and Euler equations of the
/// whole system. On the Euler base (`[x; θ]`, zyx, `v = q̇`) the rows of `x` are the total
/// external force in the world frame and those of `θ` the moment about the base origin `x`
/// projected on the three rotation axes, `Eᵀ·n_x` with the axes `E = [e_z, R_z·e_y, R_z·R_y·e_x]`;
/// so `n_G = n_x + (x − x_G) × f` must be `k̇_G` and `f` must be `ṗ`.
#[test]
fn base_rows_are_the_newton_and_euler_equations_euler_base() {
    let model = floating("models/arm7.urdf");
    let mut worst = 0.0f64;
    for seed in 0..32 {
        let (q, v, a) = random_state(&model, seed);
        let (qs, vs, as_) = (
            SVector::<f64, 13>::from_column_slice(&q),
            SVector::<f64, 13>::from_column_slice(&v),
            SVector::<f64, 13>::from_column_slice(&a),
        );
        let tau = Arm7Floating::mass_matrix(&qs) * as_ + Arm7Floating::bias(&qs, &vs);
        let f = Vector3::new(tau[0], tau[1], tau[2]);
        let (rz, ry) = (
            Matrix3::from(articulated::nalgebra::Rotation3::from_axis_angle(
                &Vector3::z_axis(),
                q[3],
            )),
            Matrix3::from(articulated::nalgebra::Rotation3::from_axis_angle(
                &Vector3::y_axis(),
                q[4],
            )),
        );
        let axes =
            Matrix3::from_columns(&[Vector3::z(), rz * Vector3::y(), rz * ry * Vector3::x()]);
        let n_x = axes.transpose().try_inverse().unwrap() * Vector3::new(tau[3], tau[4], tau[5]);
        let x = Vector3::new(q[0], q[1], q[2]);
        let com = Arm7Floating::center_of_mass(&qs);
        let n_g = n_x + (x - com).cross(&f);
        let (k_dot, p_dot) = centroidal_rate(&model, &q, &v, &a);
        let want: Vec<f64> = k_dot.iter().chain(p_dot.iter()).copied().collect();
        let got: Vec<f64> = n_g.iter().chain(f.iter()).copied().collect();
        worst = worst.max(rel_err(&got, &want));
    }
    println!("Euler base: base rows vs Σ body wrenches about G: worst relative error {worst:.1e}");
    assert!(worst < 1e-10, "{worst:e}");
}

/// The same on the quaternion base (`v = [v; ω]` in the base frame): the base rows are the
/// external force and moment about the base origin in the base frame, `[f_b; n_b]`; in the world
/// `f = R·f_b`, `n_G = R·n_b + (x − x_G) × f`.
#[test]
fn base_rows_are_the_newton_and_euler_equations_quaternion_base() {
    let model = load_model(Path::new(&tumbler()), false).unwrap();
    let mut worst = 0.0f64;
    for seed in 0..32 {
        let (q, v, a) = random_state(&model, seed);
        let (qs, vs, as_) = (
            SVector::<f64, 12>::from_column_slice(&q),
            SVector::<f64, 10>::from_column_slice(&v),
            SVector::<f64, 10>::from_column_slice(&a),
        );
        let tau = Tumbler::mass_matrix(&qs) * as_ + Tumbler::bias(&qs, &vs);
        let rot = articulated::nalgebra::UnitQuaternion::from_quaternion(
            articulated::nalgebra::Quaternion::new(q[3], q[4], q[5], q[6]),
        )
        .to_rotation_matrix()
        .into_inner();
        let f = rot * Vector3::new(tau[0], tau[1], tau[2]);
        let n_o = rot * Vector3::new(tau[3], tau[4], tau[5]);
        let x = Vector3::new(q[0], q[1], q[2]);
        let com = Tumbler::center_of_mass(&qs);
        let n_g = n_o + (x - com).cross(&f);
        let (k_dot, p_dot) = centroidal_rate(&model, &q, &v, &a);
        let want: Vec<f64> = k_dot.iter().chain(p_dot.iter()).copied().collect();
        let got: Vec<f64> = n_g.iter().chain(f.iter()).copied().collect();
        worst = worst.max(rel_err(&got, &want));
    }
    println!(
        "quaternion base: base rows vs Σ body wrenches about G: worst relative error {worst:.1e}"
    );
    assert!(worst < 1e-10, "{worst:e}");
}

/// Wieber 2005, §5: under internal couples only (zero on the base's six coordinates), whatever
/// they are, the centre of mass falls with `g` (`x_G(t) = x_G0 + ẋ_G0·t + ½·g·t²`) and the
/// angular momentum about it stays constant; the total energy changes by exactly the couples'
/// work, so it is not checked here. Simulated with the generated forward dynamics and DOPRI5
/// (tolerance 1e-11); the bounds are integration tolerances.
fn falls_with_g<C, const NQ: usize, const NV: usize>(label: &str, model: &Model, seed: u64)
where
    C: ForwardDynamics<f64, NQ, NV> + CenterOfMass<f64, NQ, NV> + CentroidalMomentum<f64, NQ, NV>,
{
    let (q0, v0, _) = random_state(model, seed);
    let mut rng = Rng::new(seed);
    // Internal couples: a sinusoid of random amplitude and phase on every joint coordinate.
    let amp: Vec<f64> = (0..NV)
        .map(|k| if k < 6 { 0.0 } else { rng.symmetric(2.0) })
        .collect();
    let phase: Vec<f64> = (0..NV).map(|_| rng.symmetric(3.0)).collect();
    let couples = move |t: f64, _q: &SVector<f64, NQ>, _v: &SVector<f64, NV>| {
        SVector::<f64, NV>::from_fn(|k, _| amp[k] * (3.0 * t + phase[k]).sin())
    };
    let mut system = ControlledChain::<f64, C, _>::new(couples);
    let mut integrator = Dopri5::new(1e-11, 1e-12);
    let start = State::new(
        0.0,
        SVector::from_column_slice(&q0),
        SVector::from_column_slice(&v0),
    );
    let (x0, h0) = (
        C::center_of_mass(&start.q),
        C::centroidal_momentum(&start.q, &start.v),
    );
    let xdot0 = h0.fixed_rows::<3>(3) / mass_of(model);
    let g = Vector3::new(0.0, 0.0, -9.81);
    let (mut com_err, mut k_err) = (0.0f64, 0.0f64);
    let k_scale = h0.fixed_rows::<3>(0).norm() + (h0.fixed_rows::<3>(3).norm() * 1.0);
    let sim = articulated::simulate::Simulation::new(0.0, 1.0, 0.05);
    sim.run(
        &mut system,
        &mut integrator,
        start,
        |s| {
            let t = s.t;
            let want = x0 + xdot0 * t + g * (0.5 * t * t);
            com_err = com_err.max((C::center_of_mass(&s.q) - want).amax());
            let h = C::centroidal_momentum(&s.q, &s.v);
            k_err = k_err.max((h.fixed_rows::<3>(0) - h0.fixed_rows::<3>(0)).amax());
            Ok(())
        },
        |_, _| {},
    )
    .unwrap_or_else(|e| panic!("{label}: {e}"));
    println!("{label}: centre of mass off its parabola by {com_err:.1e} m, angular momentum drift {:.1e} (relative)", k_err / k_scale);
    assert!(
        com_err < 1e-8,
        "{label}: the centre of mass leaves its parabola by {com_err:e} m"
    );
    assert!(
        k_err < 1e-8 * k_scale,
        "{label}: k_G drifts by {k_err:e} (scale {k_scale:e})"
    );
}

fn mass_of(model: &Model) -> f64 {
    Reference::new(model)
        .unwrap()
        .tree()
        .nodes
        .iter()
        .map(|n| n.inertia.m)
        .sum()
}

#[test]
fn internal_couples_leave_the_centroidal_motion_alone() {
    falls_with_g::<Arm7Floating, 13, 13>("arm7 (Euler base)", &floating("models/arm7.urdf"), 3);
    falls_with_g::<Tumbler, 12, 10>(
        "tumbler (quaternion base)",
        &load_model(Path::new(&tumbler()), false).unwrap(),
        5,
    );
}

/// The simulation test can fail: a couple on the base (an external force) moves the centre of
/// mass off its parabola.
#[test]
fn an_external_force_moves_the_centre_of_mass() {
    let model = load_model(Path::new(&tumbler()), false).unwrap();
    let (q0, v0, _) = random_state(&model, 1);
    let push = |_t: f64, _q: &SVector<f64, 12>, _v: &SVector<f64, 10>| {
        let mut tau = SVector::<f64, 10>::zeros();
        tau[0] = 1.0;
        tau
    };
    let mut system = ControlledChain::<f64, Tumbler, _>::new(push);
    let mut integrator = Dopri5::new(1e-11, 1e-12);
    let start = State::new(
        0.0,
        SVector::from_column_slice(&q0),
        SVector::from_column_slice(&v0),
    );
    let x0 = Tumbler::center_of_mass(&start.q);
    let xdot0 =
        Tumbler::centroidal_momentum(&start.q, &start.v).fixed_rows::<3>(3) / mass_of(&model);
    let end = articulated::simulate::Simulation::new(0.0, 1.0, 0.05)
        .run(&mut system, &mut integrator, start, |_| Ok(()), |_, _| {})
        .unwrap();
    let want = x0 + xdot0 + Vector3::new(0.0, 0.0, -9.81 * 0.5);
    assert!((Tumbler::center_of_mass(&end.q) - want).amax() > 1e-3);
}
