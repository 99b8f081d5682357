//! The derivatives of the constrained forward dynamics (`constraint::derivatives`, issue 34,
//! item 8) against central differences of the constrained forward dynamics itself (`q` moved
//! along the configuration's tangent by `control::tangent::retract`), on a fixed arm with its
//! flange welded or held at a point, the same arm on a free base with its flange welded or its
//! flange and forearm held at points, the flange held on the forearm by a point loop or rigidly
//! on the first link by a six-dimensional one (alone, or beside the forearm held at a point), and Hemami's
//! two-link on a free foot (quaternions in the base and the joints) standing on its sole, or held
//! at a point of its trunk.

mod common;

use articulated::constraint::derivatives::{forward_dynamics_derivatives_of, DerivativeOutputs};
use articulated::constraint::{self, Contact, Loop, Settings, Solution};
use articulated::control::tangent::retract;
use articulated::nalgebra::{SMatrix, SVector};
use articulated::{Chain, Coordinates};
use common::max_abs;

macro_rules! chain_with_derivatives {
    ($name:ident, $source:tt = $path:literal, [$($frame:ident),*] $(, $floating:ident)?) => {
        #[derive(Chain)]
        #[chain(
            $source = $path,
            $($floating = quaternion,)?
            outputs = [
                mass_matrix_and_nonlinear_effects,
                frame_placements,
                frame_jacobians_local,
                frame_velocities,
                frame_accelerations,
                inverse_dynamics_derivatives,
                frame_jacobian_time_variations_local,
                frame_jacobian_time_variations_local_world_aligned,
                frame_acceleration_derivatives,
                frame_velocity_derivatives
            ],
            frames = [$($frame),*]
        )]
        struct $name;
    };
}

chain_with_derivatives!(Arm7, urdf = "../models/arm7.urdf", [link7, link4]);
chain_with_derivatives!(
    Arm7Floating,
    urdf = "../models/arm7.urdf",
    [link7, link4, link1],
    floating
);
chain_with_derivatives!(Foot, file = "../models/two_link_foot.chain", [sole, trunk]);
chain_with_derivatives!(Gripper, urdf = "data/gripper_mimic.urdf", [left_tip, thumb]);

/// A chain generated with `forward_dynamics_derivatives` and the constraints given, whose
/// `constrained_forward_dynamics_derivatives` is checked, on the frames of the runtime's chain
/// above, in their order.
macro_rules! declared {
    (
        $name:ident, $source:tt = $path:literal, [$($frame:ident),*],
        $($list:ident = [$($item:tt)*]),+ $(; $floating:ident)?
    ) => {
        #[derive(Chain)]
        #[chain(
            $source = $path,
            $($floating = quaternion,)?
            outputs = [forward_dynamics_derivatives],
            frames = [$($frame),*],
            $($list = [$($item)*]),+
        )]
        struct $name;
    };
}

declared!(Arm7Welded, urdf = "../models/arm7.urdf", [link7], contacts = [link7: six_d]);
declared!(Arm7AtPoint, urdf = "../models/arm7.urdf", [link7], contacts = [link7: point]);
declared!(
    Arm7Held,
    urdf = "../models/arm7.urdf",
    [link7, link4, link1],
    contacts = [link4: point],
    loops = [hold: six_d(link7, link1)];
    floating
);
declared!(
    Arm7Rod,
    urdf = "../models/arm7.urdf",
    [link7, link4, link1],
    loops = [rod: point(link7, link4)];
    floating
);
declared!(
    FootStanding,
    file = "../models/two_link_foot.chain",
    [sole, trunk],
    contacts = [sole: six_d]
);
declared!(
    GripperHeld,
    urdf = "data/gripper_mimic.urdf",
    [left_tip, thumb],
    contacts = [left_tip: point]
);

/// A state: `q` from the neutral configuration moved by `δ` (deterministic, away from
/// singularities), `v` and `τ` alike.
fn state<C: Chain<f64>, const NQ: usize, const NV: usize>(
    seed: f64,
) -> (SVector<f64, NQ>, SVector<f64, NV>, SVector<f64, NV>) {
    // Identity quaternions, zero elsewhere.
    let mut neutral = Vec::with_capacity(NQ);
    for c in C::COORDINATES {
        match c {
            Coordinates::Vector(n) => neutral.extend(vec![0.0; *n]),
            Coordinates::Quaternion => neutral.extend([1.0, 0.0, 0.0, 0.0]),
            Coordinates::FreeQuaternion => neutral.extend([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]),
        }
    }
    let delta: Vec<f64> = (0..NV)
        .map(|i| 0.3 * ((i as f64) * 1.3 + seed).sin())
        .collect();
    let mut q = vec![0.0; NQ];
    assert!(retract(C::COORDINATES, &neutral, &delta, &mut q));
    let v = SVector::from_fn(|i, _| 0.6 * ((i as f64) * 0.7 + 2.0 * seed).cos());
    let tau = SVector::from_fn(|i, _| 2.0 * ((i as f64) * 1.9 + 3.0 * seed).sin());
    (SVector::from_column_slice(&q), v, tau)
}

/// Every derivative against central differences (step `h`), each matrix to `tol` of its
/// largest entry (1 at least); returns the worst.
fn check<C, const NQ: usize, const NV: usize, const NF: usize, const R: usize>(
    label: &str,
    contacts: &[Contact],
    loops: &[Loop],
    seed: f64,
) -> f64
where
    C: DerivativeOutputs<NQ, NV, NF> + Chain<f64>,
{
    let (q, v, tau) = state::<C, NQ, NV>(seed);
    let d = forward_dynamics_derivatives_of::<C, NQ, NV, NF, R>(&q, &v, &tau, contacts, loops)
        .unwrap_or_else(|e| panic!("{label}: {e}"));
    let solve = |q: &SVector<f64, NQ>, v: &SVector<f64, NV>, tau: &SVector<f64, NV>| {
        let s: Solution<NV, R> = constraint::forward_dynamics_of::<C, NQ, NV, NF, R>(
            q,
            v,
            tau,
            contacts,
            loops,
            None,
            &Settings::default(),
        )
        .unwrap();
        (s.acceleration, s.forces)
    };
    let h = 1e-6;
    let mut fd_q = (
        SMatrix::<f64, NV, NV>::zeros(),
        SMatrix::<f64, R, NV>::zeros(),
    );
    let mut fd_v = fd_q;
    let mut fd_tau = fd_q;
    for k in 0..NV {
        let moved = |s: f64| {
            let mut delta = [0.0; NV];
            delta[k] = s * h;
            let mut out = [0.0; NQ];
            assert!(retract(C::COORDINATES, q.as_slice(), &delta, &mut out));
            SVector::<f64, NQ>::from(out)
        };
        let e = SVector::<f64, NV>::from_fn(|i, _| if i == k { h } else { 0.0 });
        let central =
            |plus: (SVector<f64, NV>, SVector<f64, R>),
             minus: (SVector<f64, NV>, SVector<f64, R>),
             into: &mut (SMatrix<f64, NV, NV>, SMatrix<f64, R, NV>)| {
                into.0.set_column(k, &((plus.0 - minus.0) / (2.0 * h)));
                into.1.set_column(k, &((plus.1 - minus.1) / (2.0 * h)));
            };
        central(
            solve(&moved(1.0), &v, &tau),
            solve(&moved(-1.0), &v, &tau),
            &mut fd_q,
        );
        central(
            solve(&q, &(v + e), &tau),
            solve(&q, &(v - e), &tau),
            &mut fd_v,
        );
        central(
            solve(&q, &v, &(tau + e)),
            solve(&q, &v, &(tau - e)),
            &mut fd_tau,
        );
    }
    let err = |ours: &[f64], theirs: &[f64]| {
        let scale = max_abs(theirs).max(1.0);
        ours.iter()
            .zip(theirs)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
            / scale
    };
    let pairs = [
        ("∂q̈/∂q", err(d.dqdd_dq.as_slice(), fd_q.0.as_slice())),
        ("∂q̈/∂v", err(d.dqdd_dv.as_slice(), fd_v.0.as_slice())),
        ("∂q̈/∂τ", err(d.dqdd_dtau.as_slice(), fd_tau.0.as_slice())),
        ("∂f/∂q", err(d.dforces_dq.as_slice(), fd_q.1.as_slice())),
        ("∂f/∂v", err(d.dforces_dv.as_slice(), fd_v.1.as_slice())),
        ("∂f/∂τ", err(d.dforces_dtau.as_slice(), fd_tau.1.as_slice())),
    ];
    println!(
        "{label}: {}",
        pairs
            .iter()
            .map(|(n, e)| format!("{n} {e:.1e}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let worst = pairs.iter().fold(0.0f64, |m, p| m.max(p.1));
    assert!(worst < 1e-6, "{label}: {pairs:?}");
    worst
}

#[test]
fn derivatives_match_central_differences() {
    for seed in [0.0, 1.0] {
        check::<Arm7, 7, 7, 2, 6>("arm7, flange welded", &[Contact::six_d(0)], &[], seed);
        check::<Arm7, 7, 7, 2, 6>("arm7, flange at a point", &[Contact::point(0)], &[], seed);
        check::<Arm7Floating, 14, 13, 3, 12>(
            "arm7 on a free base, flange welded",
            &[Contact::six_d(0)],
            &[],
            seed,
        );
        check::<Arm7Floating, 14, 13, 3, 12>(
            "arm7 on a free base, flange and forearm at points",
            &[Contact::point(0), Contact::point(1)],
            &[],
            seed,
        );
        check::<Arm7Floating, 14, 13, 3, 12>(
            "arm7 on a free base, flange held on the forearm by a loop",
            &[],
            &[Loop::point(0, 1)],
            seed,
        );
        check::<Arm7Floating, 14, 13, 3, 12>(
            "arm7 on a free base, flange held rigidly on the first link by a loop",
            &[],
            &[Loop::six_d(0, 2)],
            seed,
        );
        check::<Arm7Floating, 14, 13, 3, 12>(
            "arm7 on a free base, forearm at a point, flange held rigidly on the first link",
            &[Contact::point(1)],
            &[Loop::six_d(0, 2)],
            seed,
        );
        check::<Foot, 13, 12, 2, 9>(
            "two-link on its foot, sole flat",
            &[Contact::six_d(0)],
            &[],
            seed,
        );
        check::<Foot, 13, 12, 2, 9>(
            "two-link on its foot, trunk at a point",
            &[Contact::point(1)],
            &[],
            seed,
        );
    }
}

/// The worst of the six derivatives of `ours` against `theirs`, each matrix relative to its
/// largest entry (1 at least), and `q̈` and the forces alike.
fn worst_of<const NV: usize, const R: usize>(
    ours: &constraint::derivatives::Derivatives<NV, R>,
    theirs: &constraint::derivatives::Derivatives<NV, R>,
) -> f64 {
    let err = |a: &[f64], b: &[f64]| common::abs_err(a, b) / max_abs(b).max(1.0);
    let (o, t) = (&ours.solution, &theirs.solution);
    [
        err(o.acceleration.as_slice(), t.acceleration.as_slice()),
        err(o.forces.as_slice(), t.forces.as_slice()),
        err(ours.dqdd_dq.as_slice(), theirs.dqdd_dq.as_slice()),
        err(ours.dqdd_dv.as_slice(), theirs.dqdd_dv.as_slice()),
        err(ours.dqdd_dtau.as_slice(), theirs.dqdd_dtau.as_slice()),
        err(ours.dforces_dq.as_slice(), theirs.dforces_dq.as_slice()),
        err(ours.dforces_dv.as_slice(), theirs.dforces_dv.as_slice()),
        err(ours.dforces_dtau.as_slice(), theirs.dforces_dtau.as_slice()),
    ]
    .into_iter()
    .fold(0.0, f64::max)
}

/// The generated derivatives of declared constraints against the runtime's for the same
/// constraints on the same frames (a different computation: the runtime's from
/// `inverse_dynamics_derivatives` and the frames' derivative outputs, checked against central
/// differences above), on the arm fixed and on a free base, Hemami's two-link on its foot
/// (quaternions) and the gripper whose fingers mimic each other; each to 1e-10. The solutions'
/// residuals are at rounding.
#[test]
fn generated_derivatives_match_the_runtime() {
    macro_rules! case {
        ($label:literal, $gen:ty, $run:ty, $nq:literal, $nv:literal, $nf:literal, $r:literal) => {
            for seed in [0.0, 1.0, 2.0] {
                let (q, v, tau) = state::<$gen, $nq, $nv>(seed);
                let ours = <$gen>::constrained_forward_dynamics_derivatives(&q, &v, &tau)
                    .unwrap_or_else(|e| panic!("{}: {e}", $label));
                let theirs = forward_dynamics_derivatives_of::<$run, $nq, $nv, $nf, $r>(
                    &q,
                    &v,
                    &tau,
                    <$gen>::CONTACTS,
                    <$gen>::LOOPS,
                )
                .unwrap();
                let e = worst_of(&ours, &theirs);
                println!("{} (seed {seed}): {e:.1e}", $label);
                assert!(e < 1e-10, "{}: {e:.1e}", $label);
                assert!(ours.solution.residual < 1e-10, "{}", $label);
            }
        };
    }
    case!("arm7, flange welded", Arm7Welded, Arm7, 7, 7, 2, 6);
    case!("arm7, flange at a point", Arm7AtPoint, Arm7, 7, 7, 2, 3);
    case!(
        "arm7 on a free base, held",
        Arm7Held,
        Arm7Floating,
        14,
        13,
        3,
        9
    );
    case!(
        "arm7 on a free base, rod",
        Arm7Rod,
        Arm7Floating,
        14,
        13,
        3,
        3
    );
    case!("two-link on its foot", FootStanding, Foot, 13, 12, 2, 6);
    case!(
        "gripper, a fingertip held",
        GripperHeld,
        Gripper,
        5,
        5,
        2,
        3
    );
}

/// Against Pinocchio 4.1's `computeConstraintDynamicsDerivatives`
/// (`tests/data/pinocchio_constraints/`, the arm's cases: flange welded, flange at a point), each
/// matrix to 1e-9 of its largest entry.
#[test]
fn derivatives_agree_with_pinocchio() {
    let data = common::read_json("data/pinocchio_constraints/pinocchio-constraints.json");
    let mut worst = 0.0f64;
    for (case, contact) in [
        ("arm7_welded", Contact::six_d(0)),
        ("arm7_point", Contact::point(0)),
    ] {
        for (k, state) in data["cases"][case]["states"]
            .as_array()
            .unwrap()
            .iter()
            .enumerate()
        {
            let vec =
                |key: &str| SVector::<f64, 7>::from_column_slice(&common::vec_of(&state[key]));
            let (q, v, tau) = (vec("q"), vec("v"), vec("tau"));
            let runtime =
                forward_dynamics_derivatives_of::<Arm7, 7, 7, 2, 6>(&q, &v, &tau, &[contact], &[])
                    .unwrap();
            // The generated function's rows are the contact's alone: pad to the runtime's 6.
            let generated = if case == "arm7_welded" {
                Arm7Welded::constrained_forward_dynamics_derivatives(&q, &v, &tau).unwrap()
            } else {
                let g =
                    Arm7AtPoint::constrained_forward_dynamics_derivatives(&q, &v, &tau).unwrap();
                let pad = |m: &SMatrix<f64, 3, 7>| {
                    SMatrix::<f64, 6, 7>::from_fn(|r, c| if r < 3 { m[(r, c)] } else { 0.0 })
                };
                constraint::derivatives::Derivatives {
                    solution: Solution {
                        acceleration: g.solution.acceleration,
                        forces: SVector::from_fn(
                            |r, _| if r < 3 { g.solution.forces[r] } else { 0.0 },
                        ),
                        rows: 3,
                        residual: g.solution.residual,
                        iterations: 1,
                    },
                    dqdd_dq: g.dqdd_dq,
                    dqdd_dv: g.dqdd_dv,
                    dqdd_dtau: g.dqdd_dtau,
                    dforces_dq: pad(&g.dforces_dq),
                    dforces_dv: pad(&g.dforces_dv),
                    dforces_dtau: pad(&g.dforces_dtau),
                }
            };
            let theirs = &state["derivatives"];
            for (who, d) in [("runtime", &runtime), ("generated", &generated)] {
                let rows = d.solution.rows;
                // Ours are column-major; the forces' rows past `rows` are zero.
                let forces = |m: &SMatrix<f64, 6, 7>| -> Vec<f64> {
                    (0..rows)
                        .flat_map(|r| (0..7).map(move |c| (r, c)))
                        .map(|(r, c)| m[(r, c)])
                        .collect()
                };
                let square = |m: &SMatrix<f64, 7, 7>| m.transpose().as_slice().to_vec();
                for (name, ours) in [
                    ("dqdd_dq", square(&d.dqdd_dq)),
                    ("dqdd_dv", square(&d.dqdd_dv)),
                    ("dqdd_dtau", square(&d.dqdd_dtau)),
                    ("dforces_dq", forces(&d.dforces_dq)),
                    ("dforces_dv", forces(&d.dforces_dv)),
                    ("dforces_dtau", forces(&d.dforces_dtau)),
                ] {
                    let pin = common::rows_of(&theirs[name]);
                    let e = common::abs_err(&ours, &pin) / max_abs(&pin).max(1.0);
                    assert!(e < 1e-9, "{who}, {case} state {k}: {name} off by {e:.1e}");
                    worst = worst.max(e);
                }
            }
        }
    }
    println!("worst against Pinocchio: {worst:.1e}");
}

declared!(
    LegsStanding,
    file = "data/legs.chain",
    [left_foot, right_foot],
    contacts = [left_foot: six_d, right_foot: six_d]
);

/// The humanoid's legs on their free quaternion base standing on both soles: their traced
/// derivatives would be more operations than the generator emits as one function, so they are
/// composed (`codegen/src/generate/constrained_composed.rs`: the solve, `M⁻¹`, the residuals'
/// derivatives, then the solve's linear map and its products at run time). Against central
/// differences of the chain's own `constrained_forward_dynamics` (the traced solve, which
/// shares no code with the products), each matrix to 1e-6 of its largest entry, at three
/// states; the residual of the solution at rounding.
#[test]
fn composed_derivatives_match_central_differences() {
    const NQ: usize = LegsStanding::NQ;
    const NV: usize = LegsStanding::NV;
    const R: usize = LegsStanding::CONSTRAINT_ROWS;
    // The generated function's docs say it is composed: its helper is what this test reaches.
    assert!(LegsStanding::CONSTRAINED_FORWARD_DYNAMICS_DERIVATIVES_OPS.total() > 20_000);
    let mut worst = 0.0f64;
    for seed in [0.0, 1.0, 2.0] {
        let (q, v, tau) = state::<LegsStanding, NQ, NV>(seed);
        let d = LegsStanding::constrained_forward_dynamics_derivatives(&q, &v, &tau).unwrap();
        assert!(d.solution.residual < 1e-10, "{}", d.solution.residual);
        let solve = |q: &SVector<f64, NQ>, v: &SVector<f64, NV>, tau: &SVector<f64, NV>| {
            LegsStanding::constrained_forward_dynamics(q, v, tau).unwrap()
        };
        let (qdd, forces) = solve(&q, &v, &tau);
        let scale = max_abs(qdd.as_slice()).max(1.0);
        assert!(
            common::abs_err(d.solution.acceleration.as_slice(), qdd.as_slice()) < 1e-12 * scale
        );
        let h = 1e-6;
        let mut fd = [(
            SMatrix::<f64, NV, NV>::zeros(),
            SMatrix::<f64, R, NV>::zeros(),
        ); 3];
        for k in 0..NV {
            let moved = |s: f64| {
                let mut delta = [0.0; NV];
                delta[k] = s * h;
                let mut out = [0.0; NQ];
                assert!(retract(
                    LegsStanding::COORDINATES,
                    q.as_slice(),
                    &delta,
                    &mut out
                ));
                SVector::<f64, NQ>::from(out)
            };
            let e = SVector::<f64, NV>::from_fn(|i, _| if i == k { h } else { 0.0 });
            let pairs = [
                (solve(&moved(1.0), &v, &tau), solve(&moved(-1.0), &v, &tau)),
                (solve(&q, &(v + e), &tau), solve(&q, &(v - e), &tau)),
                (solve(&q, &v, &(tau + e)), solve(&q, &v, &(tau - e))),
            ];
            for (into, (plus, minus)) in fd.iter_mut().zip(pairs) {
                into.0.set_column(k, &((plus.0 - minus.0) / (2.0 * h)));
                into.1.set_column(k, &((plus.1 - minus.1) / (2.0 * h)));
            }
        }
        let err =
            |ours: &[f64], theirs: &[f64]| common::abs_err(ours, theirs) / max_abs(theirs).max(1.0);
        let [(q_a, q_f), (v_a, v_f), (t_a, t_f)] = &fd;
        for (name, e) in [
            ("∂q̈/∂q", err(d.dqdd_dq.as_slice(), q_a.as_slice())),
            ("∂q̈/∂v", err(d.dqdd_dv.as_slice(), v_a.as_slice())),
            ("∂q̈/∂τ", err(d.dqdd_dtau.as_slice(), t_a.as_slice())),
            ("∂f/∂q", err(d.dforces_dq.as_slice(), q_f.as_slice())),
            ("∂f/∂v", err(d.dforces_dv.as_slice(), v_f.as_slice())),
            ("∂f/∂τ", err(d.dforces_dtau.as_slice(), t_f.as_slice())),
        ] {
            println!("legs standing (seed {seed}): {name} {e:.1e}");
            worst = worst.max(e);
        }
        let _ = forces;
    }
    assert!(worst < 1e-6, "{worst:.1e}");
}
