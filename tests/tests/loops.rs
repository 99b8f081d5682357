//! Loop closures (`articulated::constraint::Loop`, `loops: [name: point(a, b) | six_d(a, b)]`)
//! against Pinocchio 4.1's `constraintDynamics` with two-joint constraints
//! (`tests/data/pinocchio_loops/`, values and script committed): the humanoid on its free flyer
//! with its hands holding a rigid bar (a six-dimensional loop) while its left foot stands flat,
//! its hands' origins clasped (a point loop), and each loop alone with Baumgarte terms; the
//! runtime's solve for any set and the generated `constrained_forward_dynamics` of a declared
//! one. And closed forms: a body welded to the world by a six-dimensional loop stays at rest,
//! holding its weight; impacts on the loops keep the momentum and the rows' restitution and lose
//! the energy an impact loses.
//!
//! `cargo test -p articulated-tests --test loops -- --nocapture` prints the errors.

mod common;

use articulated::constraint::{
    self, Baumgarte, ConstraintError, Contact, Kind, Loop, Settings, Solution, System,
};
use articulated::nalgebra::{Matrix3, SVector, Vector3};
use articulated::prelude::*;
use articulated::FramePlacement;
use common::{read_json, rel_err, vec_of};
use serde_json::Value as Json;

/// Forces relative to `m·‖g‖`, accelerations relative to their largest entry.
const TOL: f64 = 1e-9;

/// The rows' capacity: a flat foot and a bar.
const R: usize = 12;

#[derive(Chain)]
#[chain(
    urdf = "../models/humanoid.urdf",
    floating = quaternion,
    outputs = [
        mass_matrix_and_nonlinear_effects,
        frame_placements,
        frame_jacobians_local,
        frame_velocities,
        frame_accelerations
    ],
    frames = [left_foot, left_hand, right_hand]
)]
struct Humanoid;

#[derive(Chain)]
#[chain(
    urdf = "../models/humanoid.urdf",
    floating = quaternion,
    outputs = [],
    contacts = [left_foot: six_d],
    loops = [bar: six_d(left_hand, right_hand)]
)]
struct HumanoidBar;

#[derive(Chain)]
#[chain(
    urdf = "../models/humanoid.urdf",
    floating = quaternion,
    outputs = [],
    loops = [clasp: point(left_hand, right_hand)]
)]
struct HumanoidClasp;

fn data() -> Json {
    read_json("data/pinocchio_loops/pinocchio-loops.json")
}

fn kind(name: &str) -> Kind {
    match name {
        "six_d" => Kind::SixD,
        "point" => Kind::Point,
        other => panic!("kind {other}"),
    }
}

/// The frame `name`'s index in `names`.
fn index(names: &[&str], name: &str) -> usize {
    names
        .iter()
        .position(|n| *n == name)
        .unwrap_or_else(|| panic!("frame {name} not generated"))
}

/// A case's contacts and loops on the frames `names`.
fn constraints_of(case: &Json, names: &[&str]) -> (Vec<Contact>, Vec<Loop>) {
    let contacts = case["contacts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| Contact {
            frame: index(names, c["frame"].as_str().unwrap()),
            kind: kind(c["kind"].as_str().unwrap()),
        })
        .collect();
    let loops = case["loops"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| Loop {
            a: index(names, l["a"].as_str().unwrap()),
            b: index(names, l["b"].as_str().unwrap()),
            kind: kind(l["kind"].as_str().unwrap()),
        })
        .collect();
    (contacts, loops)
}

fn weight(data: &Json, case: &Json) -> f64 {
    data["models"][case["model"].as_str().unwrap()]["mass"]
        .as_f64()
        .unwrap()
        * 9.81
}

/// The state's `(q, v, τ)`.
fn state_of(state: &Json) -> (SVector<f64, 38>, SVector<f64, 37>, SVector<f64, 37>) {
    (
        SVector::from_column_slice(&vec_of(&state["q"])),
        SVector::from_column_slice(&vec_of(&state["v"])),
        SVector::from_column_slice(&vec_of(&state["tau"])),
    )
}

/// The runtime's solve of every case, with its Baumgarte terms where it has them, against
/// Pinocchio's `q̈` and forces; the loops' position errors against Pinocchio's.
#[test]
fn loops_agree_with_pinocchio() {
    let data = data();
    let names = Humanoid::FRAMES;
    // The loops' errors come from their frames, not from references (which only contacts use).
    let unused = [FramePlacement {
        rotation: Matrix3::identity(),
        translation: Vector3::zeros(),
    }; 3];
    for (name, case) in data["cases"].as_object().unwrap() {
        let (contacts, loops) = constraints_of(case, names);
        let gains = (!case["baumgarte"].is_null()).then(|| Baumgarte {
            kp: case["baumgarte"]["kp"].as_f64().unwrap(),
            kd: case["baumgarte"]["kd"].as_f64().unwrap(),
        });
        let weight = weight(&data, case);
        for (k, state) in case["states"].as_array().unwrap().iter().enumerate() {
            let (q, v, tau) = state_of(state);
            let s: Solution<37, R> = constraint::forward_dynamics_of::<Humanoid, 38, 37, 3, R>(
                &q,
                &v,
                &tau,
                &contacts,
                &loops,
                gains.map(|g| (g, &unused)),
                &Settings::default(),
            )
            .unwrap_or_else(|e| panic!("{name} state {k}: {e}"));
            let e_qdd = rel_err(s.acceleration.as_slice(), &vec_of(&state["qdd"]));
            let e_f =
                common::abs_err(&s.forces.as_slice()[..s.rows], &vec_of(&state["forces"])) / weight;
            println!("{name:24} state {k}: q̈ {e_qdd:.1e}, forces {e_f:.1e} (of m·|g|)");
            assert!(
                e_qdd < TOL && e_f < TOL,
                "{name} state {k}: q̈ {e_qdd:.1e}, forces {e_f:.1e} off Pinocchio's"
            );
            assert!(s.residual < 1e-9, "{name} state {k}: {:e}", s.residual);
            if gains.is_some() {
                let frames = constraint::Frames::<37, 3>::of::<Humanoid, 38>(&q, &v);
                let system: System<37, R> = frames.system(&contacts, &loops, None).unwrap();
                let e_e = rel_err(
                    &system.error.as_slice()[..system.rows],
                    &vec_of(&state["error"]),
                );
                assert!(e_e < TOL, "{name} state {k}: position error {e_e:.1e}");
            }
        }
    }
}

/// The generated `constrained_forward_dynamics` of a declared set.
type Generated<const RR: usize> =
    fn(
        &SVector<f64, 38>,
        &SVector<f64, 37>,
        &SVector<f64, 37>,
    ) -> Result<(SVector<f64, 37>, SVector<f64, RR>), ConstraintError>;

/// A declared set's generated solve against Pinocchio's (to [`TOL`]) and the runtime's (1e-11).
fn check_generated<const RR: usize>(case: &str, solve: Generated<RR>) {
    let data = data();
    let c = &data["cases"][case];
    let (contacts, loops) = constraints_of(c, Humanoid::FRAMES);
    let weight = weight(&data, c);
    for (k, state) in c["states"].as_array().unwrap().iter().enumerate() {
        let (q, v, tau) = state_of(state);
        let (qdd, forces) = solve(&q, &v, &tau).unwrap_or_else(|e| panic!("{case} {k}: {e}"));
        let runtime: Solution<37, RR> = constraint::forward_dynamics_of::<Humanoid, 38, 37, 3, RR>(
            &q,
            &v,
            &tau,
            &contacts,
            &loops,
            None,
            &Settings::default(),
        )
        .unwrap();
        common::check_constrained(
            &format!("generated {case} state {k}"),
            (qdd.as_slice(), forces.as_slice()),
            (&vec_of(&state["qdd"]), &vec_of(&state["forces"])),
            (runtime.acceleration.as_slice(), runtime.forces.as_slice()),
            weight,
            TOL,
        );
    }
}

#[test]
fn declared_loops_agree_with_pinocchio_and_the_runtime() {
    assert_eq!(HumanoidBar::LOOPS, [Loop::six_d(1, 2)]);
    assert_eq!(HumanoidBar::CONSTRAINT_ROWS, 12);
    check_generated::<12>("hands_six_d", HumanoidBar::constrained_forward_dynamics);
    assert_eq!(HumanoidClasp::LOOPS, [Loop::point(0, 1)]);
    check_generated::<3>("hands_point", HumanoidClasp::constrained_forward_dynamics);
}

articulated::chain! {
    /// A free body (3 kg, its centre of mass 0.2 m along x from its origin) with a frame
    /// `grip` on it and one, `post`, on the world where the body starts.
    chain Welded {
        gravity: [0.0, 0.0, -9.81];
        outputs: [mass_matrix_and_nonlinear_effects, frame_placements, frame_jacobians_local,
                  frame_velocities, frame_accelerations];
        frames: [grip, post];
        loops: [weld: six_d(grip, post)];
        body block { mass: 3.0, com: [0.2, 0.0, 0.0], inertia: diag(0.02, 0.03, 0.04) }
        joint base: free(quaternion) { parent: world, child: block }
        frame grip { parent: block, xyz: [0.1, -0.05, 0.3], rpy: [0.3, -0.2, 0.5] }
        frame post { parent: world, xyz: [0.0, 0.0, 0.0] }
    }
}

/// A closed form: a free body at rest, welded to the world by a six-dimensional loop, does not
/// move (`q̈ = 0`) and the loop holds its weight: in world axes the force on the body is
/// `−m·g` and its moment about the grip's origin `−(c − p)×(m·g)`; the wrench returned is
/// those in the grip's axes. The same from the generated function; and the loop is the
/// six-dimensional contact on the grip when its other frame is the world's.
#[test]
fn a_body_welded_by_a_loop_holds_its_weight() {
    // A pose away from the post: the loop holds the relative placement it has.
    let axis = Vector3::new(0.3, -0.5, 0.8).normalize() * 0.7;
    let quat = articulated::nalgebra::UnitQuaternion::from_scaled_axis(axis);
    let q = SVector::<f64, 7>::from_column_slice(&[0.4, -0.2, 1.1, quat.w, quat.i, quat.j, quat.k]);
    let v = SVector::<f64, 6>::zeros();
    let tau = SVector::<f64, 6>::zeros();
    let [grip, _] = Welded::frame_placements(&q);
    let (m, g) = (3.0, Vector3::new(0.0, 0.0, -9.81));
    let r = quat.to_rotation_matrix();
    let com = Vector3::new(q[0], q[1], q[2]) + r * Vector3::new(0.2, 0.0, 0.0);
    let f_world = -m * g;
    let n_world = -(com - grip.translation).cross(&(m * g));
    let n = grip.rotation.tr_mul(&n_world);
    let f = grip.rotation.tr_mul(&f_world);
    let expected = [n[0], n[1], n[2], f[0], f[1], f[2]];

    let loops = [Loop::six_d(0, 1)];
    let s: Solution<6, 6> = constraint::forward_dynamics_of::<Welded, 7, 6, 2, 6>(
        &q,
        &v,
        &tau,
        &[],
        &loops,
        None,
        &Settings::default(),
    )
    .unwrap();
    let (qdd, forces) = Welded::constrained_forward_dynamics(&q, &v, &tau).unwrap();
    let contact: Solution<6, 6> = constraint::forward_dynamics_of::<Welded, 7, 6, 2, 6>(
        &q,
        &v,
        &tau,
        &[Contact::six_d(0)],
        &[],
        None,
        &Settings::default(),
    )
    .unwrap();
    for (what, a, w) in [
        ("runtime", s.acceleration, s.forces),
        ("generated", qdd, forces),
        ("contact", contact.acceleration, contact.forces),
    ] {
        let e_w = common::abs_err(w.as_slice(), &expected) / (m * 9.81);
        println!(
            "{what}: |q̈| {:.1e}, wrench off by {e_w:.1e} of m·g",
            a.amax()
        );
        assert!(a.amax() < 1e-12, "{what}: q̈ = {a:?}");
        assert!(e_w < 1e-13, "{what}: {w:?}, expected {expected:?}");
    }

    // The batch twin: each state's own solve, a state with a NaN velocity its error alone.
    let mut vs = [v, v, v];
    vs[1][2] = f64::NAN;
    let mut taus = [tau; 3];
    taus[2][0] = 5.0;
    let mut out = [Ok((SVector::zeros(), SVector::zeros())); 3];
    Welded::constrained_forward_dynamics_batch(&[q; 3], &vs, &taus, &mut out).unwrap();
    for (k, out) in out.iter().enumerate() {
        assert_eq!(
            *out,
            Welded::constrained_forward_dynamics(&q, &vs[k], &taus[k]),
            "{k}"
        );
    }
    assert_eq!(out[1], Err(constraint::ConstraintError::NonFinite));
    assert_ne!(out[0], out[2]);
    let err =
        Welded::constrained_forward_dynamics_batch(&[q; 2], &vs, &[tau; 3], &mut out).unwrap_err();
    assert_eq!((err.argument, err.found, err.expected), ("q", 2, 3));
}

/// Impacts on loops (`constraint::impulse_dynamics_of`): at each loop case's states without
/// gains (the bar beside the flat left foot, the clasp), for restitutions 0, ½ and 1, the
/// closed forms an impact keeps: `J·v⁺ = −e·J·v⁻` on every row, the momentum
/// `M·(v⁺ − v⁻) = Jᵀ·p`, and the energy lost `½(1 − e²)·(J·v⁻)ᵀ·G⁻¹·(J·v⁻)` with `G = J·M⁻¹·Jᵀ`
/// formed here by nalgebra's LU (none when `e = 1`). Not against Pinocchio: its 4.1
/// `impulseDynamics` leaves `J·v⁺ ≠ 0` at `e = 0` on two-joint constraints, by its own
/// `getConstraintsJacobian` too (5.96 against `|J·v⁻|` 5.38 on the bar's first state).
#[test]
fn loop_impacts_keep_momentum_and_lose_the_energy_they_should() {
    let data = data();
    let names = Humanoid::FRAMES;
    for (name, case) in data["cases"].as_object().unwrap() {
        if !case["baumgarte"].is_null() {
            continue;
        }
        let (contacts, loops) = constraints_of(case, names);
        for (k, state) in case["states"].as_array().unwrap().iter().enumerate() {
            let (q, v, _) = state_of(state);
            let frames = constraint::Frames::<37, 3>::of::<Humanoid, 38>(&q, &v);
            let system: System<37, R> = frames.system(&contacts, &loops, None).unwrap();
            let rows = system.rows;
            let j = system.jacobian.rows(0, rows).into_owned();
            let (m, _) = Humanoid::mass_matrix_and_nonlinear_effects(&q, &v);
            let minv = m.lu().try_inverse().unwrap();
            let g = &j * minv * j.transpose();
            let jv = &j * v;
            for e in [0.0, 0.5, 1.0] {
                let s: Solution<37, R> = constraint::impulse_dynamics_of::<Humanoid, 38, 37, 3, R>(
                    &q,
                    &v,
                    &contacts,
                    &loops,
                    e,
                    &Settings::default(),
                )
                .unwrap_or_else(|err| panic!("{name} state {k}: {err}"));
                let (v_plus, p) = (s.acceleration, s.forces.rows(0, rows).into_owned());
                let scale = jv.amax().max(1.0);
                let e_rows = (&j * v_plus + e * &jv).amax() / scale;
                let momentum = m * (v_plus - v);
                let e_momentum = (momentum - j.transpose() * &p).amax() / momentum.amax().max(1.0);
                let lost = 0.5 * v_plus.dot(&(m * v_plus)) - 0.5 * v.dot(&(m * v));
                let predicted = -0.5 * (1.0 - e * e) * jv.dot(&g.clone().lu().solve(&jv).unwrap());
                let e_energy = (lost - predicted).abs() / (0.5 * v.dot(&(m * v))).max(1.0);
                println!(
                    "{name:12} state {k}, e = {e}: rows {e_rows:.1e}, momentum {e_momentum:.1e}, \
                     energy {e_energy:.1e} (lost {lost:.3})"
                );
                assert!(
                    e_rows < 1e-10,
                    "{name} state {k}, e = {e}: J·v⁺ {e_rows:.1e}"
                );
                assert!(
                    e_momentum < 1e-9,
                    "{name} state {k}, e = {e}: {e_momentum:.1e}"
                );
                assert!(e_energy < 1e-9, "{name} state {k}, e = {e}: {e_energy:.1e}");
            }
        }
    }
}
