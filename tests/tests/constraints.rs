//! The runtime's constrained dynamics (`articulated::constraint`) on generated code: against
//! Pinocchio 4.1's `constraintDynamics` (exact: proximal `mu = 0`) and `impulseDynamics`
//! (`tests/data/pinocchio_constraints/`, values and script committed): the humanoid on its free
//! flyer on two flat feet, one foot, a foot and a hand, a hand alone, with Baumgarte terms on
//! six-dimensional and point contacts; the arm with its flange welded or held at a point;
//! impacts with restitution 0 and 0.5. Forces are compared relative to `m·‖g‖`, accelerations
//! and velocities relative to their largest entry; and, independently of Pinocchio, each
//! solution is checked against the equations it solves with the reference's `M` and `nle`.
//!
//! Inverse dynamics with contacts against the forward dynamics that made the motion, and the
//! whole-body Newton and Euler equations (Wieber 2005, eqs. 17–18): the contact wrenches sum to
//! the rate of the centroidal momentum less gravity, the rate the generated
//! `centroidal_momentum_rate` (an independent code path: the bodies' net forces summed).
//!
//! `cargo test -p articulated-tests --test constraints -- --nocapture` prints the
//! worst error of each case.

mod common;

use articulated::constraint::{
    self, Baumgarte, ConstraintError, Contact, Kind, Settings, Solution, System,
};
use articulated::nalgebra::{Matrix3, SMatrix, SVector, Vector3};
use articulated::prelude::*;
use articulated::FramePlacement;
use common::{read_json, rel_err, rows_of, vec_of};
use serde_json::Value as Json;

/// Forces relative to `m·‖g‖`, accelerations relative to their largest entry.
const TOL: f64 = 1e-9;

#[derive(Chain)]
#[chain(
    urdf = "../models/humanoid.urdf",
    floating = quaternion,
    outputs = [
        mass_matrix_and_nonlinear_effects,
        frame_placements,
        frame_jacobians_local,
        frame_velocities,
        frame_accelerations,
        center_of_mass,
        centroidal_momentum_rate
    ],
    frames = [left_foot, right_foot, left_hand, right_hand]
)]
struct Humanoid;

#[derive(Chain)]
#[chain(
    urdf = "../models/arm7.urdf",
    outputs = [
        mass_matrix_and_nonlinear_effects,
        frame_placements,
        frame_jacobians_local,
        frame_velocities,
        frame_accelerations
    ],
    frames = [link7]
)]
struct Arm7;

/// The capacity of the stacked rows: two six-dimensional contacts.
const R: usize = 12;

fn data() -> Json {
    read_json("data/pinocchio_constraints/pinocchio-constraints.json")
}

/// The case's contacts on the chain's frames `names`.
fn contacts(case: &Json, names: &[&str]) -> Vec<Contact> {
    case["contacts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let name = c["frame"].as_str().unwrap();
            let frame = names
                .iter()
                .position(|n| *n == name)
                .unwrap_or_else(|| panic!("frame {name} not generated"));
            let kind = match c["kind"].as_str().unwrap() {
                "six_d" => Kind::SixD,
                "point" => Kind::Point,
                other => panic!("kind {other}"),
            };
            Contact { frame, kind }
        })
        .collect()
}

/// The forces of the case's contacts, concatenated in its order, from a JSON map by frame.
fn forces_of(case: &Json, forces: &Json) -> Vec<f64> {
    case["contacts"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|c| vec_of(&forces[c["frame"].as_str().unwrap()]))
        .collect()
}

/// The reference placements of a Baumgarte state, indexed like `names`.
fn references<const NF: usize>(state: &Json, names: &[&str]) -> [FramePlacement<f64>; NF] {
    core::array::from_fn(|i| {
        let c = &state["contacts"][names[i]]["reference"];
        if c.is_null() {
            return FramePlacement {
                rotation: Matrix3::identity(),
                translation: Vector3::zeros(),
            };
        }
        FramePlacement {
            rotation: Matrix3::from_row_slice(&rows_of(&c["rotation"])),
            translation: Vector3::from_column_slice(&vec_of(&c["translation"])),
        }
    })
}

/// Runs every state of `case` on chain `C`; returns the worst error.
fn check_case<C, const NQ: usize, const NV: usize, const NF: usize>(
    name: &str,
    case: &Json,
    weight: f64,
) -> f64
where
    C: Chain<f64>
        + MassMatrixAndNonlinearEffects<f64, NQ, NV>
        + FramePlacements<f64, NQ, NV, NF>
        + FrameJacobiansLocal<f64, NQ, NV, NF>
        + FrameVelocities<f64, NQ, NV, NF>
        + FrameAccelerations<f64, NQ, NV, NF>,
{
    let names = C::FRAMES;
    let contacts = contacts(case, names);
    let gains = (!case["baumgarte"].is_null()).then(|| Baumgarte {
        kp: case["baumgarte"]["kp"].as_f64().unwrap(),
        kd: case["baumgarte"]["kd"].as_f64().unwrap(),
    });
    let settings = Settings::default();
    let mut worst = 0.0f64;
    for (k, state) in case["states"].as_array().unwrap().iter().enumerate() {
        let q = SVector::<f64, NQ>::from_column_slice(&vec_of(&state["q"]));
        let v = SVector::<f64, NV>::from_column_slice(&vec_of(&state["v"]));
        let tau = SVector::<f64, NV>::from_column_slice(&vec_of(&state["tau"]));
        let refs: [FramePlacement<f64>; NF] = references(state, names);
        let s: Solution<NV, R> = constraint::constrained_forward_dynamics::<C, NQ, NV, NF, R>(
            &q,
            &v,
            &tau,
            &contacts,
            gains.map(|g| (g, &refs)),
            &settings,
        )
        .unwrap_or_else(|e| panic!("{name} state {k}: {e}"));
        let qdd = vec_of(&state["qdd"]);
        let e_qdd = rel_err(s.acceleration.as_slice(), &qdd);
        let theirs = forces_of(case, &state["forces"]);
        let e_f = common::abs_err(&s.forces.as_slice()[..s.rows], &theirs) / weight;
        assert!(
            e_qdd < TOL && e_f < TOL,
            "{name} state {k}: q̈ {e_qdd:.1e}, forces {e_f:.1e} (of m·|g|)\n ours {:?}\n theirs {theirs:?}",
            &s.forces.as_slice()[..s.rows]
        );
        assert!(
            s.residual < 1e-9,
            "{name} state {k}: residual {:e}",
            s.residual
        );
        if gains.is_some() {
            // Our position errors against the ones Pinocchio used.
            let frames = constraint::Frames::<NV, NF>::of::<C, NQ>(&q, &v);
            let system: System<NV, R> = frames.system(&contacts, &[], Some(&refs)).unwrap();
            let theirs: Vec<f64> = case["contacts"]
                .as_array()
                .unwrap()
                .iter()
                .flat_map(|c| vec_of(&state["contacts"][c["frame"].as_str().unwrap()]["error"]))
                .collect();
            let e_e = rel_err(&system.error.as_slice()[..system.rows], &theirs);
            assert!(e_e < TOL, "{name} state {k}: position error {e_e:.1e}");
        }
        worst = worst.max(e_qdd).max(e_f);

        for imp in state["impulses"].as_array().into_iter().flatten() {
            let e = imp["restitution"].as_f64().unwrap();
            let v_minus = SVector::<f64, NV>::from_column_slice(&vec_of(&imp["v_minus"]));
            let s: Solution<NV, R> = constraint::constrained_impulse_dynamics::<C, NQ, NV, NF, R>(
                &q, &v_minus, &contacts, e, &settings,
            )
            .unwrap_or_else(|err| panic!("{name} state {k} impulse e={e}: {err}"));
            let e_v = rel_err(s.acceleration.as_slice(), &vec_of(&imp["v_plus"]));
            let theirs = forces_of(case, &imp["impulses"]);
            let e_p = rel_err(&s.forces.as_slice()[..s.rows], &theirs);
            assert!(
                e_v < TOL && e_p < TOL,
                "{name} state {k} impulse e={e}: v⁺ {e_v:.1e}, impulses {e_p:.1e}"
            );
            worst = worst.max(e_v).max(e_p);
        }
    }
    println!("{name:28} worst {worst:.1e}");
    worst
}

#[test]
fn constrained_dynamics_and_impulses_agree_with_pinocchio() {
    let data = data();
    let cases = data["cases"].as_object().unwrap();
    assert_eq!(cases.len(), 8, "cases in the data file");
    for (name, case) in cases {
        let model = case["model"].as_str().unwrap();
        let weight = data["models"][model]["mass"].as_f64().unwrap() * 9.81;
        match model {
            "humanoid_free_flyer" => {
                check_case::<Humanoid, 38, 37, 4>(name, case, weight);
            }
            "arm7" => {
                check_case::<Arm7, 7, 7, 1>(name, case, weight);
            }
            other => panic!("model {other}"),
        }
    }
}

/// The impact's energy balance, a closed form independent of Pinocchio: for restitution `e`,
/// `T⁺ − T⁻ = −½(1 − e²)·(J·v⁻)ᵀ·G⁻¹·(J·v⁻)`, and `J·v⁺ = −e·J·v⁻`.
#[test]
fn impacts_lose_the_energy_the_closed_form_gives() {
    let data = data();
    let case = &data["cases"]["humanoid_feet"];
    let contacts = contacts(case, Humanoid::FRAMES);
    for state in case["states"].as_array().unwrap() {
        let q = SVector::<f64, 38>::from_column_slice(&vec_of(&state["q"]));
        let v = SVector::<f64, 37>::from_column_slice(&vec_of(&state["v"]));
        let (m, _) = Humanoid::mass_matrix_and_nonlinear_effects(&q, &v);
        let frames = constraint::Frames::<37, 4>::of::<Humanoid, 38>(&q, &v);
        let system: System<37, R> = frames.system(&contacts, &[], None).unwrap();
        let j: SMatrix<f64, 12, 37> = system.jacobian;
        let g = j * m.try_inverse().unwrap() * j.transpose();
        let jv = j * v;
        let t_minus = 0.5 * v.dot(&(m * v));
        for e in [0.0, 0.3, 1.0] {
            let s: Solution<37, R> =
                constraint::impulse_dynamics(&m, &v, &system, e, &Settings::default()).unwrap();
            let t_plus = 0.5 * s.acceleration.dot(&(m * s.acceleration));
            let expected = -0.5 * (1.0 - e * e) * jv.dot(&(g.try_inverse().unwrap() * jv));
            let d = (t_plus - t_minus - expected).abs() / t_minus;
            assert!(d < 1e-10, "e = {e}: energy change off by {d:e} of T⁻");
            let bounce = rel_err((j * s.acceleration).as_slice(), (-e * jv).as_slice());
            assert!(bounce < 1e-10, "e = {e}: J·v⁺ off by {bounce:e}");
        }
    }
}

/// Redundant constraints: the same foot twice makes `G` singular. Exactly (`mu = 0`) it is an
/// error naming the second constraint's first row; with a proximal `mu` it converges to forces
/// that hold the constraints (the residual at machine precision) and together equal the single
/// foot's wrench; inconsistent Baumgarte references on the doubled foot never converge.
#[test]
fn redundant_constraints_are_named_or_solved_by_proximal_iterations() {
    let data = data();
    let state = &data["cases"]["humanoid_left_foot"]["states"][0];
    let q = SVector::<f64, 38>::from_column_slice(&vec_of(&state["q"]));
    let v = SVector::<f64, 37>::from_column_slice(&vec_of(&state["v"]));
    let tau = SVector::<f64, 37>::from_column_slice(&vec_of(&state["tau"]));
    let foot = Contact::six_d(0);
    let once: Solution<37, R> = constraint::constrained_forward_dynamics::<Humanoid, 38, 37, 4, R>(
        &q,
        &v,
        &tau,
        &[foot],
        None,
        &Settings::default(),
    )
    .unwrap();
    let twice = [foot, foot];
    let exact = constraint::constrained_forward_dynamics::<Humanoid, 38, 37, 4, R>(
        &q,
        &v,
        &tau,
        &twice,
        None,
        &Settings::default(),
    );
    assert_eq!(
        exact.unwrap_err(),
        ConstraintError::Redundant { contact: 1, row: 0 }
    );

    let proximal = Settings {
        mu: 1e-6,
        max_iterations: 200,
        ..Settings::default()
    };
    let s: Solution<37, R> = constraint::constrained_forward_dynamics::<Humanoid, 38, 37, 4, R>(
        &q, &v, &tau, &twice, None, &proximal,
    )
    .unwrap();
    println!(
        "proximal: {} iterations, residual {:e}",
        s.iterations, s.residual
    );
    assert!(s.residual < 1e-9, "residual {:e}", s.residual);
    assert!(rel_err(s.acceleration.as_slice(), once.acceleration.as_slice()) < 1e-8);
    let sum: Vec<f64> = (0..6).map(|r| s.forces[r] + s.forces[6 + r]).collect();
    assert!(rel_err(&sum, &once.forces.as_slice()[..6]) < 1e-8);
    // The least-norm split: half each (up to the rounding the iterations carry along the
    // null space of `G`, which they do not damp).
    assert!(rel_err(&s.forces.as_slice()[..6], &s.forces.as_slice()[6..12]) < 1e-6);

    // The doubled foot held to two different references cannot hold both.
    let frames = constraint::Frames::<37, 4>::of::<Humanoid, 38>(&q, &v);
    let mut system: System<37, R> = frames.system(&twice, &[], None).unwrap();
    system.error[6] = 0.01;
    let (m, nle) = Humanoid::mass_matrix_and_nonlinear_effects(&q, &v);
    let gains = Some(Baumgarte { kp: 10.0, kd: 0.0 });
    let err = constraint::forward_dynamics(&m, &nle, &tau, &v, &system, gains, &proximal);
    assert!(
        matches!(err, Err(ConstraintError::NotConverged { residual, .. }) if residual > 1e-3),
        "{err:?}"
    );
}

/// Bad input is an error value, never a panic or a NaN.
#[test]
fn bad_input_is_an_error() {
    let q = SVector::<f64, 7>::zeros();
    let v = SVector::<f64, 7>::zeros();
    let mut tau = SVector::<f64, 7>::zeros();
    let settings = Settings::default();
    let run = |tau: &SVector<f64, 7>, contacts: &[Contact]| {
        constraint::constrained_forward_dynamics::<Arm7, 7, 7, 1, 6>(
            &q, &v, tau, contacts, None, &settings,
        )
    };
    assert_eq!(
        run(&tau, &[Contact::six_d(1)]).unwrap_err(),
        ConstraintError::UnknownFrame {
            frame: 1,
            frames: 1
        }
    );
    assert_eq!(
        run(&tau, &[Contact::six_d(0), Contact::point(0)]).unwrap_err(),
        ConstraintError::Capacity {
            needed: 9,
            capacity: 6
        }
    );
    tau[3] = f64::NAN;
    assert_eq!(
        run(&tau, &[Contact::six_d(0)]).unwrap_err(),
        ConstraintError::NonFinite
    );
    let m = SMatrix::<f64, 7, 7>::zeros();
    let system = System::<7, 6>::new();
    assert_eq!(
        constraint::impulse_dynamics(&m, &v, &system, -0.5, &settings).unwrap_err(),
        ConstraintError::NonFinite
    );
    assert_eq!(
        constraint::impulse_dynamics(&m, &v, &system, 0.5, &settings).unwrap_err(),
        ConstraintError::MassMatrix { velocity: 0 }
    );
}

/// A humanoid state of the data file with the base's six joint forces zeroed (nothing actuates
/// a free base).
fn actuated_state(case: &str, k: usize) -> (SVector<f64, 38>, SVector<f64, 37>, SVector<f64, 37>) {
    let data = data();
    let state = &data["cases"][case]["states"][k];
    let q = SVector::<f64, 38>::from_column_slice(&vec_of(&state["q"]));
    let v = SVector::<f64, 37>::from_column_slice(&vec_of(&state["v"]));
    let mut tau = SVector::<f64, 37>::from_column_slice(&vec_of(&state["tau"]));
    tau.fixed_rows_mut::<6>(0).fill(0.0);
    (q, v, tau)
}

/// Inverse dynamics with contacts recovers what forward dynamics was given: on one flat foot
/// the forces are unique, and so are the joints' forces; on two feet the forces it gives are
/// the least-norm ones that produce the same motion (they hold the base's six equations, the
/// joints' forces follow, and they are no larger than the forces forward dynamics found).
#[test]
fn inverse_dynamics_with_contacts_recovers_the_forces() {
    let weight = 82.05 * 9.81;
    let u = constraint::unactuated(Humanoid::COORDINATES);
    assert_eq!(u, 6);
    for (case, contacts) in [
        ("humanoid_left_foot", vec![Contact::six_d(0)]),
        ("humanoid_feet", vec![Contact::six_d(0), Contact::six_d(1)]),
    ] {
        for k in 0..3 {
            let (q, v, tau) = actuated_state(case, k);
            let forward: Solution<37, R> = constraint::constrained_forward_dynamics::<
                Humanoid,
                38,
                37,
                4,
                R,
            >(
                &q, &v, &tau, &contacts, None, &Settings::default()
            )
            .unwrap();
            let frames = constraint::Frames::<37, 4>::of::<Humanoid, 38>(&q, &v);
            let system: System<37, R> = frames.system(&contacts, &[], None).unwrap();
            let (m, nle) = Humanoid::mass_matrix_and_nonlinear_effects(&q, &v);
            let inverse =
                constraint::inverse_dynamics(&m, &nle, &forward.acceleration, &system, u).unwrap();
            assert!(
                inverse.residual < 1e-9 * weight,
                "{case} {k}: {:e}",
                inverse.residual
            );
            let (ours, theirs) = (
                &inverse.forces.as_slice()[..system.rows],
                &forward.forces.as_slice()[..system.rows],
            );
            if contacts.len() == 1 {
                let e = common::abs_err(ours, theirs) / weight;
                assert!(e < 1e-10, "{case} {k}: forces off by {e:.1e} of m·|g|");
                let e = rel_err(inverse.tau.as_slice(), tau.as_slice());
                assert!(e < 1e-10, "{case} {k}: τ off by {e:.1e}");
            } else {
                let norm = |x: &[f64]| x.iter().map(|x| x * x).sum::<f64>().sqrt();
                assert!(
                    norm(ours) <= norm(theirs) * (1.0 + 1e-12),
                    "{case} {k}: not least-norm"
                );
                // The same motion: M·q̈ + nle = τ + Jᵀ·f with the forces it found.
                let lhs = m * forward.acceleration + nle;
                let rhs = inverse.tau + system.jacobian.tr_mul(&inverse.forces);
                let e = rel_err(rhs.as_slice(), lhs.as_slice());
                assert!(e < 1e-12, "{case} {k}: equations of motion off by {e:.1e}");
            }
        }
    }
}

/// Wieber's whole-body Newton and Euler equations (eqs. 17–18): the contact wrenches, moved to
/// the centre of mass in world axes, sum to `ḣ_G − [0; m·g]`, with `ḣ_G` the generated
/// `centroidal_momentum_rate` at the constrained acceleration (the bodies' net forces, a code
/// path apart from the constrained solve's `M` and `nle`), to 1e-10 of `m·‖g‖`; and the
/// zero-moment point of the support has no moment along the ground.
#[test]
fn contact_wrenches_are_the_rate_of_the_centroidal_momentum_less_gravity() {
    let mass = 82.05;
    let weight = mass * 9.81;
    let contacts = [Contact::six_d(0), Contact::six_d(1)];
    for k in 0..3 {
        let (q, v, tau) = actuated_state("humanoid_feet", k);
        let s: Solution<37, R> =
            constraint::constrained_forward_dynamics::<Humanoid, 38, 37, 4, R>(
                &q,
                &v,
                &tau,
                &contacts,
                None,
                &Settings::default(),
            )
            .unwrap();
        let h_dot = Humanoid::centroidal_momentum_rate(&q, &v, &s.acceleration);
        let c = Humanoid::center_of_mass(&q);
        let placements = Humanoid::frame_placements(&q);
        let mut total = [0.0; 6];
        for (i, contact) in contacts.iter().enumerate() {
            let w =
                constraint::wrench_in_world(&placements[contact.frame], &s.force::<6>(6 * i), &c);
            for r in 0..6 {
                total[r] += w[r];
            }
        }
        let mut expected: Vec<f64> = h_dot.iter().copied().collect();
        expected[5] += mass * 9.81;
        let e = common::abs_err(&total, &expected) / weight;
        println!("state {k}: Σ contact wrenches vs ḣ_G − m·g: {e:.1e} of m·|g|");
        assert!(
            e < 1e-10,
            "state {k}: {e:.1e} of m·|g|\n ours {total:?}\n ḣ−mg {expected:?}"
        );

        // The zero-moment point of the support, from the wrenches about the world's origin.
        let origin = SVector::<f64, 3>::zeros();
        let mut about_origin = [0.0; 6];
        for (i, contact) in contacts.iter().enumerate() {
            let local = s.force::<6>(6 * i);
            let w = constraint::wrench_in_world(&placements[contact.frame], &local, &origin);
            for r in 0..6 {
                about_origin[r] += w[r];
            }
        }
        if let Some(zmp) = constraint::center_of_pressure(&about_origin, 0.0) {
            // The tangential moment about the ZMP vanishes: n − p × f has no x, y part.
            let (n, f) = (
                SVector::<f64, 3>::new(about_origin[0], about_origin[1], about_origin[2]),
                SVector::<f64, 3>::new(about_origin[3], about_origin[4], about_origin[5]),
            );
            let moment = n - SVector::<f64, 3>::from(zmp).cross(&f);
            assert!(
                moment[0].abs() + moment[1].abs() < 1e-9 * weight,
                "{moment:?}"
            );
        }
    }
}

#[derive(Chain)]
#[chain(file = "../models/four_bar.chain")]
struct FourBar;

/// The four-bar's closed configuration at crank angle `theta` (the coupler's far end up): each
/// link's absolute angle θ about y puts its axis along `(cos θ, 0, −sin θ)`; the rocker's pin
/// is where the circles of the coupler about the crank's end and of the rocker about the ground
/// pin meet. Relative joint angles.
fn four_bar_closed(theta: f64) -> SVector<f64, 3> {
    let (a, b, c, d) = (0.2, 0.6, 0.5, 0.6);
    let bx = a * theta.cos();
    let bz = -a * theta.sin();
    let (ux, uz) = (d - bx, -bz);
    let l = (ux * ux + uz * uz).sqrt();
    let (ux, uz) = (ux / l, uz / l);
    let along = (b * b - c * c + l * l) / (2.0 * l);
    let h = (b * b - along * along).sqrt();
    let (mut cx, mut cz) = (bx + along * ux - h * uz, bz + along * uz + h * ux);
    if cz < 0.0 {
        (cx, cz) = (bx + along * ux + h * uz, bz + along * uz - h * ux);
    }
    let angle = |dx: f64, dz: f64| (-dz).atan2(dx);
    let (t1, t2, t3) = (theta, angle(cx - bx, cz - bz), angle(d - cx, -cz));
    SVector::<f64, 3>::new(t1, t2 - t1, t3 - t2)
}

/// A closed loop (issue 34, item 6): the four-bar's loop has three rows but, planar, only two
/// independent (`nv − rank J = 1`, its one degree of freedom; the exact solve names the
/// dependent row); stepped for 10 s under gravity by RK4 with Baumgarte terms and proximal
/// iterations, the loop stays closed to 1e-9 m and the energy, which the loop's force does not
/// change, to 1e-7 of its swing.
#[test]
fn a_four_bar_has_one_degree_of_freedom_and_stays_closed() {
    use articulated::constraint::{ConstrainedChain, Loop};
    use articulated::integrate::{Integrator, Rk4, State};
    let q0 = four_bar_closed(0.3);
    let [tip, ground] = FourBar::frame_placements(&q0);
    let gap = (tip.translation - ground.translation).norm();
    assert!(gap < 1e-12, "the closed configuration is {gap:e} m open");

    let loops = [Loop::point(0, 1)];
    let frames = constraint::Frames::<3, 2>::of::<FourBar, 3>(&q0, &SVector::zeros());
    let system: System<3, 3> = frames.system(&[], &loops, None).unwrap();
    let sv = system.jacobian.singular_values();
    let (hi, lo) = (sv.max(), sv.min());
    let rank = sv.iter().filter(|s| **s > 1e-10 * hi).count();
    assert_eq!(3 - rank, 1, "singular values {sv:?}");
    assert!(lo < 1e-14 * hi, "{sv:?}");
    let (m, nle) = FourBar::mass_matrix_and_nonlinear_effects(&q0, &SVector::zeros());
    let exact = constraint::forward_dynamics(
        &m,
        &nle,
        &SVector::zeros(),
        &SVector::zeros(),
        &system,
        None,
        &Settings::default(),
    );
    assert!(
        matches!(exact, Err(ConstraintError::Redundant { contact: 0, .. })),
        "{exact:?}"
    );

    let settings = Settings {
        mu: 1e-4,
        ..Settings::default()
    };
    let gains = Some(Baumgarte {
        kp: 100.0,
        kd: 20.0,
    });
    let mut chain = ConstrainedChain::<FourBar, _, 3, 3, 2, 3>::new(
        &q0,
        &[],
        &loops,
        gains,
        settings,
        |_, _: &SVector<f64, 3>, _: &SVector<f64, 3>| SVector::zeros(),
    )
    .unwrap();
    let energy = |q: &SVector<f64, 3>, v: &SVector<f64, 3>| {
        FourBar::kinetic_energy(q, v) + FourBar::potential_energy(q)
    };
    let mut state = State::new(0.0, q0, SVector::zeros());
    let e0 = energy(&q0, &state.v);
    let (mut worst_gap, mut worst_energy, mut swing) = (0.0f64, 0.0f64, 0.0f64);
    for step in 1..=10_000 {
        Rk4.advance(
            &mut chain,
            &mut state,
            f64::from(step) * 1e-3,
            step as usize,
        )
        .unwrap();
        let [tip, ground] = FourBar::frame_placements(&state.q);
        worst_gap = worst_gap.max((tip.translation - ground.translation).norm());
        worst_energy = worst_energy.max((energy(&state.q, &state.v) - e0).abs());
        swing = swing.max(FourBar::kinetic_energy(&state.q, &state.v));
    }
    println!(
        "four-bar, 10 s: loop open by at most {worst_gap:.1e} m, energy off by {:.1e} of its \
         swing ({swing:.3} J), crank at {:.3} rad",
        worst_energy / swing,
        state.q[0]
    );
    assert!(worst_gap < 1e-9, "the loop opened by {worst_gap:e} m");
    assert!(
        worst_energy < 1e-7 * swing,
        "energy off by {:e} J",
        worst_energy
    );
    assert!(swing > 0.1, "it hardly moved: {swing} J");
}

articulated::chain! {
    /// A pendulum as a free body (a ball at its centre of mass, 2 kg, 0.003 kg·m² about every
    /// axis) whose rod's end, 0.8 m from the ball, a point loop holds on a pivot in the world.
    chain Bob {
        gravity: [0.0, 0.0, -9.81];
        outputs: [mass_matrix_and_nonlinear_effects, frame_placements, frame_jacobians_local,
                  frame_velocities, frame_accelerations];
        frames: [end, pivot];
        body ball { mass: 2.0, com: [0.0, 0.0, 0.0], inertia: diag(0.003, 0.003, 0.003) }
        joint base: free(quaternion) { parent: world, child: ball }
        frame end { parent: ball, xyz: [0.0, 0.0, 0.8] }
        frame pivot { parent: world, xyz: [0.1, -0.2, 1.0] }
    }
}

/// A closed form (issue 34, item 7): a free body held at a point by a loop is a physical
/// pendulum. In the vertical x-z plane at angle θ from the downward vertical (the ball at
/// `pivot + L·(sin θ, 0, −cos θ)`) and rate θ̇, `θ̈ = −m·g·L·sin θ/(I + m·L²)`, the ball's
/// acceleration is `L·θ̈·(cos θ, 0, sin θ) + L·θ̇²·(−sin θ, 0, cos θ)` and the loop's force on
/// the body is `m·a − m·g`.
#[test]
fn a_pendulum_held_by_a_loop_moves_as_the_closed_form() {
    use articulated::constraint::Loop;
    let (mass, inertia, g, length) = (2.0, 0.003, 9.81, 0.8);
    let pivot = Vector3::new(0.1, -0.2, 1.0);
    for (theta, rate) in [(0.6, 1.5), (-1.1, 0.0), (2.0, -3.0)] {
        let (s, c) = f64::sin_cos(theta);
        let p = pivot + Vector3::new(s, 0.0, -c) * length;
        // The body turned by −θ about y puts its rod's end (0, 0, L) on the pivot.
        let (hs, hc) = f64::sin_cos(-theta / 2.0);
        let rotation =
            articulated::nalgebra::Rotation3::from_axis_angle(&Vector3::y_axis(), -theta);
        let mut q = SVector::<f64, 7>::zeros();
        q.fixed_rows_mut::<3>(0).copy_from(&p);
        (q[3], q[5]) = (hc, hs); // [w, x, y, z]: about y
        let velocity = Vector3::new(c, 0.0, s) * (length * rate);
        let omega = Vector3::new(0.0, -rate, 0.0);
        let mut v = SVector::<f64, 6>::zeros();
        v.fixed_rows_mut::<3>(0)
            .copy_from(&(rotation.transpose() * velocity));
        v.fixed_rows_mut::<3>(3).copy_from(&omega);
        let frames = constraint::Frames::<6, 2>::of::<Bob, 7>(&q, &v);
        let gap = (frames.placements[0].translation - pivot).norm();
        assert!(
            gap < 1e-15,
            "θ {theta}: the rod's end is {gap:e} m off the pivot"
        );
        let system: System<6, 3> = frames.system(&[], &[Loop::point(0, 1)], None).unwrap();
        let (m, nle) = Bob::mass_matrix_and_nonlinear_effects(&q, &v);
        let sol = constraint::forward_dynamics(
            &m,
            &nle,
            &SVector::zeros(),
            &v,
            &system,
            None,
            &Settings::default(),
        )
        .unwrap();
        let theta_dd = -mass * g * length * s / (inertia + mass * length * length);
        let a = Vector3::new(c, 0.0, s) * (length * theta_dd)
            + Vector3::new(-s, 0.0, c) * (length * rate * rate);
        let force = (a - Vector3::new(0.0, 0.0, -g)) * mass;
        let ours = Vector3::new(sol.forces[0], sol.forces[1], sol.forces[2]);
        assert!(
            (ours - force).norm() < 1e-12 * mass * g,
            "θ {theta}: force {ours:?} vs {force:?}"
        );
        // v̇ of a free base is the rate of its body-frame velocity: Rᵀ·a − ω × v_body.
        let lin = rotation.transpose() * a - omega.cross(&v.fixed_rows::<3>(0));
        let qdd = sol.acceleration;
        assert!(
            (qdd.fixed_rows::<3>(0) - lin).norm() < 1e-12 * g,
            "θ {theta}: {qdd:?}"
        );
        let spin = Vector3::new(0.0, -theta_dd, 0.0);
        assert!(
            (qdd.fixed_rows::<3>(3) - spin).norm() < 1e-12 * g,
            "θ {theta}: {qdd:?}"
        );
    }
}

/// Random trees of 2 to 30 bodies with every joint kind (`random_model`), random contacts
/// (points and six-dimensional, on random bodies) and random states: the run-time solver
/// (`constraint::dynamic`, the same core as the fixed-size one) on the reference's kinematics
/// against the full KKT system `[M −Jᵀ; J 0]·[q̈; f] = [τ − nle; −γ]` solved by LU, with its
/// rows taken independently from the reference (`J` in LOCAL or the linear rows of
/// LOCAL_WORLD_ALIGNED, `γ` the spatial or classical drift at `q̈ = 0`). Where the rows
/// depend on each other, the solver's `Redundant` is checked against `J`'s singular values.
#[test]
fn the_solver_agrees_with_the_full_kkt_system_on_random_trees() {
    use articulated::constraint::dynamic::{self, FrameKinematics};
    use articulated::nalgebra::{DMatrix, DVector};
    use articulated::reference::frames::ReferenceFrame;
    use articulated::reference::Reference;
    use articulated_dynamics::random::{random_model, random_state, Rng};
    let (mut solved, mut redundant, mut worst) = (0, 0, 0.0f64);
    for (seed, n) in [(1, 2), (2, 3), (4, 5), (6, 8), (9, 12), (13, 20), (17, 30)] {
        let model = random_model(seed, n);
        let r = Reference::new(&model).unwrap();
        let nv = r.nv();
        let mut rng = Rng::new(seed + 1000);
        for state in 0..4 {
            let (q, v, _) = random_state(&model, seed * 10 + state);
            let tau: Vec<f64> = (0..nv).map(|_| rng.symmetric(5.0)).collect();
            // Contacts the tree can hold: on its later bodies (deeper, more joints below
            // them), six-dimensional where there are velocities enough, a second on larger
            // trees.
            let count = if nv >= 9 { 1 + rng.below(2) } else { 1 };
            let contacts: Vec<(String, Kind)> = (0..count)
                .map(|_| {
                    let body = model.bodies[n - 1 - rng.below(n.div_ceil(2))].name.clone();
                    let six = nv >= 6 * count + 2 && rng.unit() < 0.5;
                    (body, if six { Kind::SixD } else { Kind::Point })
                })
                .collect();
            let zero = vec![0.0; nv];
            let mut system = dynamic::System::new(nv);
            let (mut j, mut gamma) = (Vec::new(), Vec::<f64>::new());
            for (name, kind) in &contacts {
                let (rotation, translation) = r.frame_placement(&q, name).unwrap();
                let local = r.frame_jacobian(&q, name, ReferenceFrame::Local).unwrap();
                let frame = FrameKinematics {
                    placement: FramePlacement {
                        rotation,
                        translation,
                    },
                    jacobian: local.clone(),
                    velocity: r.frame_velocity(&q, &v, name).unwrap(),
                    drift: r.frame_acceleration(&q, &v, &zero, name).unwrap(),
                };
                system.push(*kind, &frame, None).unwrap();
                match kind {
                    Kind::SixD => {
                        j.push(local);
                        let drift = r.frame_spatial_acceleration(&q, &v, &zero, name).unwrap();
                        gamma.extend(drift.iter());
                    }
                    Kind::Point => {
                        let lwa = r
                            .frame_jacobian(&q, name, ReferenceFrame::LocalWorldAligned)
                            .unwrap();
                        j.push(lwa.rows(3, 3).into_owned());
                        let drift = r.frame_acceleration(&q, &v, &zero, name).unwrap();
                        gamma.extend(drift.iter().skip(3));
                    }
                }
            }
            let k = gamma.len();
            let mut jac = DMatrix::<f64>::zeros(k, nv);
            let mut row = 0;
            for block in &j {
                jac.rows_mut(row, block.nrows()).copy_from(block);
                row += block.nrows();
            }
            let m = r.mass_matrix(&q).unwrap();
            let nle = r.bias(&q, &v).unwrap() + r.gravity(&q).unwrap();
            let tau = DVector::from_vec(tau);
            let ours = dynamic::forward_dynamics(
                &m,
                &nle,
                &tau,
                &DVector::from_column_slice(&v),
                &system,
                None,
                &Settings::default(),
            );
            let sv = jac.clone().singular_values();
            let full_rank = k <= nv && sv.min() > 1e-7 * sv.max();
            let s = match ours {
                Err(ConstraintError::Redundant { .. }) => {
                    assert!(
                        !full_rank,
                        "seed {seed} state {state}: Redundant, but σ = {sv:?}"
                    );
                    redundant += 1;
                    continue;
                }
                Err(e) => panic!("seed {seed} state {state}: {e}"),
                Ok(s) => s,
            };
            let mut kkt = DMatrix::<f64>::zeros(nv + k, nv + k);
            kkt.view_mut((0, 0), (nv, nv)).copy_from(&m);
            kkt.view_mut((0, nv), (nv, k))
                .copy_from(&(-jac.transpose()));
            kkt.view_mut((nv, 0), (k, nv)).copy_from(&jac);
            let mut rhs = DVector::<f64>::zeros(nv + k);
            rhs.rows_mut(0, nv).copy_from(&(&tau - &nle));
            for (i, g) in gamma.iter().enumerate() {
                rhs[nv + i] = -g;
            }
            let x = kkt.full_piv_lu().solve(&rhs).expect("a regular KKT system");
            let e_qdd = rel_err(s.acceleration.as_slice(), &x.as_slice()[..nv]);
            let e_f = rel_err(s.forces.as_slice(), &x.as_slice()[nv..]);
            assert!(
                e_qdd < 1e-8 && e_f < 1e-8,
                "seed {seed} ({n} bodies) state {state} {contacts:?}: q̈ {e_qdd:.1e}, f {e_f:.1e}"
            );
            worst = worst.max(e_qdd).max(e_f);
            solved += 1;
        }
    }
    println!("random trees: {solved} solved (worst {worst:.1e}), {redundant} redundant");
    assert!(solved >= 15, "{solved} solved, {redundant} redundant");
}

articulated::chain! {
    /// A 10 kg block on a free base standing on four corner points.
    chain Block {
        gravity: [0.0, 0.0, -9.81];
        outputs: [mass_matrix_and_nonlinear_effects, frame_placements, frame_jacobians_local,
                  frame_velocities, frame_accelerations];
        frames: [front_left, front_right, back_left, back_right];
        body block { mass: 10.0, com: [0.0, 0.0, 0.05], inertia: diag(0.05, 0.1, 0.12) }
        joint base: free(quaternion) { parent: world, child: block }
        frame front_left { parent: block, xyz: [0.2, 0.1, 0.0] }
        frame front_right { parent: block, xyz: [0.2, -0.1, 0.0] }
        frame back_left { parent: block, xyz: [-0.2, 0.1, 0.0] }
        frame back_right { parent: block, xyz: [-0.2, -0.1, 0.0] }
    }
}

#[derive(Chain)]
#[chain(file = "../models/two_link_foot.chain")]
struct Standing;

/// The optimal contact forces (issue 34, item 4): a block standing on four corners shares its
/// weight as the least-norm forces do, and accelerating sideways at 0.5 g it needs friction:
/// infeasible at μ = 0.3, within the cones at μ = 0.8; Hemami's two-link on its foot, whose one
/// flat contact determines the wrench, gets that wrench back where its centre of pressure is on
/// the sole, and no forces where the motion would push it past the toes.
#[test]
fn optimal_contact_forces_respect_friction_and_soles() {
    use articulated::constraint::optimal::{contact_forces, Limits, OptimalError, Sole};
    // The block, at rest, its corners on the ground.
    let mut q = SVector::<f64, 7>::zeros();
    q[3] = 1.0;
    let v = SVector::<f64, 6>::zeros();
    let corners: Vec<Contact> = (0..4).map(Contact::point).collect();
    let frames = constraint::Frames::<6, 4>::of::<Block, 7>(&q, &v);
    let system: System<6, 12> = frames.system(&corners, &[], None).unwrap();
    let (m, nle) = Block::mass_matrix_and_nonlinear_effects(&q, &v);
    let limits = |mu: f64| {
        vec![
            Limits {
                friction: mu,
                sole: None
            };
            4
        ]
    };
    let still = SVector::<f64, 6>::zeros();
    let least = constraint::inverse_dynamics(&m, &nle, &still, &system, 6).unwrap();
    let best = contact_forces(&m, &nle, &still, &system, &corners, &limits(0.5), 6, 1.0).unwrap();
    let e = common::abs_err(best.forces.as_slice(), least.forces.as_slice()) / (10.0 * 9.81);
    assert!(
        e < 1e-6,
        "at rest: {e:e} of the weight\n{:?}\n{:?}",
        best.forces,
        least.forces
    );
    for r in (2..12).step_by(3) {
        assert!(
            (best.forces[r] - 10.0 * 9.81 / 4.0).abs() < 1e-5,
            "{:?}",
            best.forces
        );
    }
    // Sideways at 0.5 g (the base's linear acceleration is in its frame, here the world's).
    let mut sideways = SVector::<f64, 6>::zeros();
    sideways[1] = 0.5 * 9.81;
    let slips = contact_forces(&m, &nle, &sideways, &system, &corners, &limits(0.3), 6, 1.0);
    assert_eq!(slips.unwrap_err(), OptimalError::Infeasible { contacts: 4 });
    let grips =
        contact_forces(&m, &nle, &sideways, &system, &corners, &limits(0.8), 6, 1.0).unwrap();
    assert!(grips.residual < 1e-6 * 10.0 * 9.81, "{}", grips.residual);
    for c in 0..4 {
        let f = &grips.forces.as_slice()[3 * c..3 * c + 3];
        assert!(
            f[0].hypot(f[1]) <= 0.8 * f[2] * (1.0 + 1e-6),
            "corner {c}: {f:?}"
        );
    }

    // Hemami's two-link on its foot: one flat contact, its wrench determined by the motion.
    let mut q = SVector::<f64, 13>::zeros();
    q[3] = 1.0;
    q[8] = 0.05;
    let v = SVector::<f64, 12>::zeros();
    let sole = [Contact::six_d(0)];
    let frames = constraint::Frames::<12, 1>::of::<Standing, 13>(&q, &v);
    let system: System<12, 6> = frames.system(&sole, &[], None).unwrap();
    let (m, nle) = Standing::mass_matrix_and_nonlinear_effects(&q, &v);
    let limits = [Limits {
        friction: 0.8,
        sole: Some(Sole {
            x: [-0.07, 0.19],
            y: [-0.12, 0.12],
        }),
    }];
    let cop = |w: &SVector<f64, 6>| -w[1] / w[5];
    for (ankle, expect_feasible) in [(0.0, true), (-0.8, true), (3.0, false)] {
        let mut qdd = SVector::<f64, 12>::zeros();
        qdd[7] = ankle; // ankle pitch acceleration
        let unique = constraint::inverse_dynamics(&m, &nle, &qdd, &system, 6).unwrap();
        let x = cop(&unique.forces);
        assert_eq!(
            (-0.07..=0.19).contains(&x),
            expect_feasible,
            "ankle {ankle}: CoP {x}"
        );
        let best = contact_forces(&m, &nle, &qdd, &system, &sole, &limits, 6, 1e-3);
        if expect_feasible {
            let best = best.unwrap();
            let e = common::abs_err(best.forces.as_slice(), unique.forces.as_slice());
            assert!(e < 1e-6 * 75.1 * 9.81, "ankle {ankle}: {e:e}");
        } else {
            assert_eq!(best.unwrap_err(), OptimalError::Infeasible { contacts: 1 });
        }
    }
}

/// A leg on a free base whose description declares its contact (issue 34, item 1): the sole
/// held flat, six rows; in the scalar given.
macro_rules! walker {
    ($(#[$doc:meta])* $name:ident, $scalar:ident) => {
        articulated::chain! {
            $(#[$doc])*
            chain $name {
                scalar: $scalar;
                contacts: [sole: six_d];
                outputs: [mass_matrix];
                body pelvis { mass: 10.0, com: [0.0, 0.0, 0.05], inertia: diag(0.15, 0.1, 0.12) }
                body thigh { mass: 4.0, com: [0.0, 0.0, -0.2], inertia: diag(0.06, 0.06, 0.01) }
                body shank { mass: 2.5, com: [0.0, 0.0, -0.2], inertia: diag(0.04, 0.04, 0.006) }
                body foot { mass: 1.0, com: [0.05, 0.0, -0.03], inertia: diag(0.002, 0.005, 0.005) }
                joint base: free(quaternion) { parent: world, child: pelvis }
                joint hip: spherical(zxy) { parent: pelvis, child: thigh, xyz: [0.0, 0.1, -0.05] }
                joint knee: revolute(y) { parent: thigh, child: shank, xyz: [0.0, 0.0, -0.4] }
                joint ankle: spherical(zyx) { parent: shank, child: foot, xyz: [0.0, 0.0, -0.4] }
                frame sole { parent: foot, xyz: [0.05, 0.0, -0.06], rpy: [0.0, 0.1, 0.0] }
            }
        }
    };
}

walker!(
    /// The leg in `f64`.
    Walker,
    f64
);
walker!(
    /// The leg in `f32`.
    WalkerF32,
    f32
);
walker!(
    /// The leg generic in its scalar.
    WalkerGeneric,
    generic
);

/// A state of [`Walker`] away from its neutral configuration: a turned base, bent joints,
/// every velocity nonzero, torques on the joints.
fn walker_state(k: usize) -> (SVector<f64, 14>, SVector<f64, 13>, SVector<f64, 13>) {
    let s = k as f64;
    let quat = [0.9 + 0.01 * s, 0.1, -0.2 + 0.05 * s, 0.3];
    let norm = quat.iter().map(|x| x * x).sum::<f64>().sqrt();
    let mut q = SVector::<f64, 14>::zeros();
    q.fixed_rows_mut::<3>(0)
        .copy_from_slice(&[0.1, -0.2 + s * 0.1, 0.9]);
    for (i, x) in quat.iter().enumerate() {
        q[3 + i] = x / norm;
    }
    for i in 7..14 {
        q[i] = 0.3 * ((i as f64) * 1.7 + s).sin();
    }
    let v = SVector::<f64, 13>::from_fn(|i, _| 0.5 * ((i as f64) * 0.9 + 2.0 * s).cos());
    let tau = SVector::<f64, 13>::from_fn(|i, _| {
        if i < 6 {
            0.0
        } else {
            3.0 - (i as f64) * 0.7 + s
        }
    });
    (q, v, tau)
}

/// A description's declared contact gives the generated `constrained_forward_dynamics` (issue
/// 34, item 1): its frame joins `FRAMES`, its outputs are generated, and at any state it gives
/// the runtime's `constraint::constrained_forward_dynamics` on the same contact, `q̈` and the
/// wrench, to 1e-12; the solution holds the equations of motion and the constraint.
#[test]
fn a_declared_contact_gives_the_runtime_constrained_dynamics() {
    assert_eq!(<Walker as Chain<f64>>::FRAMES, ["sole"]);
    assert_eq!(Walker::CONTACTS, [Contact::six_d(0)]);
    assert!(Walker::LOOPS.is_empty());
    assert_eq!(Walker::CONSTRAINT_ROWS, 6);
    for k in 0..4 {
        let (q, v, tau) = walker_state(k);
        let (qdd, forces) = Walker::constrained_forward_dynamics(&q, &v, &tau).unwrap();
        let runtime: Solution<13, 6> =
            constraint::constrained_forward_dynamics::<Walker, 14, 13, 1, 6>(
                &q,
                &v,
                &tau,
                &[Contact::six_d(0)],
                None,
                &Settings::default(),
            )
            .unwrap();
        let e_qdd = rel_err(qdd.as_slice(), runtime.acceleration.as_slice());
        let e_f = rel_err(forces.as_slice(), runtime.forces.as_slice());
        assert!(
            e_qdd < 1e-12 && e_f < 1e-12,
            "state {k}: q̈ {e_qdd:e}, forces {e_f:e}"
        );
        // M·q̈ + nle = τ + Jᵀ·f and J·q̈ + γ = 0.
        let frames = constraint::Frames::<13, 1>::of::<Walker, 14>(&q, &v);
        let system: System<13, 6> = frames.system(Walker::CONTACTS, &[], None).unwrap();
        let (m, nle) = Walker::mass_matrix_and_nonlinear_effects(&q, &v);
        let e_motion = rel_err(
            (m * qdd + nle).as_slice(),
            (tau + system.jacobian.tr_mul(&forces)).as_slice(),
        );
        let held = system.jacobian * qdd + system.drift;
        assert!(
            e_motion < 1e-12,
            "state {k}: equations of motion off by {e_motion:e}"
        );
        assert!(
            held.amax() < 1e-9,
            "state {k}: constraint off by {:e}",
            held.amax()
        );
        assert!(forces.amax() > 1.0, "state {k}: no force carried");
    }
}

#[derive(Chain)]
#[chain(file = "../models/four_bar.chain", loops = [closure: point(tip, ground)])]
struct ClosedFourBar;

/// A loop declared in `#[chain(…)]` on the four-bar (issue 34, item 1): its frames are the
/// file's `frames`, three rows; the loop is planar, its three rows hold only two independent
/// ones, and the exact solve of the generated `constrained_forward_dynamics` says so, naming
/// the loop (constraint 0).
#[test]
fn a_declared_planar_loop_is_redundant() {
    use articulated::constraint::Loop;
    assert_eq!(<ClosedFourBar as Chain<f64>>::FRAMES, ["tip", "ground"]);
    assert!(ClosedFourBar::CONTACTS.is_empty());
    assert_eq!(ClosedFourBar::LOOPS, [Loop::point(0, 1)]);
    assert_eq!(ClosedFourBar::CONSTRAINT_ROWS, 3);
    for theta in [0.3, 1.2, -2.0] {
        let q = four_bar_closed(theta);
        let result = ClosedFourBar::constrained_forward_dynamics(
            &q,
            &SVector::from([0.4, -0.2, 0.1]),
            &SVector::zeros(),
        );
        assert!(
            matches!(result, Err(ConstraintError::Redundant { contact: 0, .. })),
            "θ = {theta}: {result:?}"
        );
    }
}

#[derive(Chain)]
#[chain(
    urdf = "../models/humanoid.urdf",
    floating = quaternion,
    outputs = [],
    contacts = [left_foot: six_d, right_foot: six_d]
)]
struct HumanoidFeet;

#[derive(Chain)]
#[chain(
    urdf = "../models/humanoid.urdf",
    floating = quaternion,
    outputs = [],
    contacts = [left_foot: six_d, right_hand: point]
)]
struct HumanoidFootAndHand;

#[derive(Chain)]
#[chain(urdf = "../models/arm7.urdf", outputs = [], contacts = [link7: six_d])]
struct Arm7Welded;

/// A generated `constrained_forward_dynamics`.
type Generated<const NQ: usize, const NV: usize, const R: usize> =
    fn(
        &SVector<f64, NQ>,
        &SVector<f64, NV>,
        &SVector<f64, NV>,
    ) -> Result<(SVector<f64, NV>, SVector<f64, R>), ConstraintError>;

/// The generated `constrained_forward_dynamics` of a declared set (issue 34, item 1) on every
/// state of the Pinocchio case without Baumgarte terms that holds the same contacts: `q̈` and the
/// forces against Pinocchio's (to [`TOL`], the forces of `m·‖g‖`) and against the runtime's
/// solution from the chain's other outputs (to 1e-11): the two ways, a solve traced for the set
/// and one assembled at run time for any subset, checked against each other.
fn check_generated<C, const NQ: usize, const NV: usize, const NF: usize, const RR: usize>(
    case: &str,
    solve: Generated<NQ, NV, RR>,
    contacts: &[Contact],
) where
    C: Chain<f64>
        + MassMatrixAndNonlinearEffects<f64, NQ, NV>
        + FramePlacements<f64, NQ, NV, NF>
        + FrameJacobiansLocal<f64, NQ, NV, NF>
        + FrameVelocities<f64, NQ, NV, NF>
        + FrameAccelerations<f64, NQ, NV, NF>,
{
    let data = data();
    let c = &data["cases"][case];
    assert!(c["baumgarte"].is_null());
    let weight = data["models"][c["model"].as_str().unwrap()]["mass"]
        .as_f64()
        .unwrap()
        * 9.81;
    for (k, state) in c["states"].as_array().unwrap().iter().enumerate() {
        let q = SVector::<f64, NQ>::from_column_slice(&vec_of(&state["q"]));
        let v = SVector::<f64, NV>::from_column_slice(&vec_of(&state["v"]));
        let tau = SVector::<f64, NV>::from_column_slice(&vec_of(&state["tau"]));
        let (qdd, forces) = solve(&q, &v, &tau).unwrap_or_else(|e| panic!("{case} {k}: {e}"));
        let runtime: Solution<NV, RR> =
            constraint::constrained_forward_dynamics::<C, NQ, NV, NF, RR>(
                &q,
                &v,
                &tau,
                contacts,
                None,
                &Settings::default(),
            )
            .unwrap();
        common::check_constrained(
            &format!("{case} state {k}"),
            (qdd.as_slice(), forces.as_slice()),
            (&vec_of(&state["qdd"]), &forces_of(c, &state["forces"])),
            (runtime.acceleration.as_slice(), runtime.forces.as_slice()),
            weight,
            TOL,
        );
    }
}

#[test]
fn generated_constrained_dynamics_agree_with_pinocchio_and_the_runtime() {
    check_generated::<HumanoidFeet, 38, 37, 2, 12>(
        "humanoid_feet",
        HumanoidFeet::constrained_forward_dynamics,
        HumanoidFeet::CONTACTS,
    );
    check_generated::<HumanoidFootAndHand, 38, 37, 2, 9>(
        "humanoid_foot_and_hand",
        HumanoidFootAndHand::constrained_forward_dynamics,
        HumanoidFootAndHand::CONTACTS,
    );
    check_generated::<Arm7Welded, 7, 7, 1, 6>(
        "arm7_welded",
        Arm7Welded::constrained_forward_dynamics,
        Arm7Welded::CONTACTS,
    );
}

/// The generated function's errors: a non-finite input is `NonFinite` before anything is
/// computed, as the runtime's (a redundancy: `a_declared_planar_loop_is_redundant`).
#[test]
fn generated_constrained_dynamics_refuse_what_the_runtime_refuses() {
    let data = data();
    let state = &data["cases"]["humanoid_feet"]["states"][0];
    let q = SVector::<f64, 38>::from_column_slice(&vec_of(&state["q"]));
    let v = SVector::<f64, 37>::from_column_slice(&vec_of(&state["v"]));
    let tau = SVector::<f64, 37>::from_column_slice(&vec_of(&state["tau"]));
    let mut bad = v;
    bad[7] = f64::NAN;
    assert_eq!(
        HumanoidFeet::constrained_forward_dynamics(&q, &bad, &tau).unwrap_err(),
        ConstraintError::NonFinite
    );
    let mut far = q;
    far[0] = f64::INFINITY;
    assert_eq!(
        HumanoidFeet::constrained_forward_dynamics(&far, &v, &tau).unwrap_err(),
        ConstraintError::NonFinite
    );
    let (q7, v7) = (
        SVector::<f64, 7>::repeat(0.3),
        SVector::<f64, 7>::repeat(0.1),
    );
    assert!(Arm7Welded::constrained_forward_dynamics(&q7, &v7, &v7).is_ok());
    assert!(matches!(
        Arm7Welded::constrained_forward_dynamics(&q7, &v7, &SVector::repeat(f64::NAN)),
        Err(ConstraintError::NonFinite)
    ));
}

/// The declared contact's function in `f32` and generic in the scalar (issue 34: "f32 and
/// generic where the solver allows"): generic at `T = f64` gives the `f64` chain's values to
/// 1e-12, `f32` to 1e-4 of the largest entry, at the states of
/// `a_declared_contact_gives_the_runtime_constrained_dynamics`.
#[test]
fn a_declared_contact_solves_in_f32_and_generic_scalars() {
    for k in 0..4 {
        let (q, v, tau) = walker_state(k);
        let (qdd, forces) = Walker::constrained_forward_dynamics(&q, &v, &tau).unwrap();
        let (g_qdd, g_forces) = WalkerGeneric::constrained_forward_dynamics(&q, &v, &tau).unwrap();
        let e_generic = rel_err(g_qdd.as_slice(), qdd.as_slice())
            .max(rel_err(g_forces.as_slice(), forces.as_slice()));
        let (s_qdd, s_forces) = WalkerF32::constrained_forward_dynamics(
            &q.map(|x| x as f32),
            &v.map(|x| x as f32),
            &tau.map(|x| x as f32),
        )
        .unwrap();
        let wide = |x: &[f32]| x.iter().map(|&x| f64::from(x)).collect::<Vec<_>>();
        let e_f32 = rel_err(&wide(s_qdd.as_slice()), qdd.as_slice())
            .max(rel_err(&wide(s_forces.as_slice()), forces.as_slice()));
        println!("state {k}: generic {e_generic:.1e}, f32 {e_f32:.1e}");
        assert!(e_generic < 1e-12, "state {k}: generic off by {e_generic:e}");
        assert!(e_f32 < 1e-4, "state {k}: f32 off by {e_f32:e}");
    }
    let mut bad = walker_state(0).1.map(|x| x as f32);
    bad[3] = f32::NAN;
    let (q, _, tau) = walker_state(0);
    assert_eq!(
        WalkerF32::constrained_forward_dynamics(&q.map(|x| x as f32), &bad, &tau.map(|x| x as f32))
            .unwrap_err(),
        ConstraintError::NonFinite
    );
}
