//! The MJCF front end against MuJoCo 4.0 (`tests/data/mujoco/mujoco-values.json`, written by
//! `make_mujoco_reference.py` there): each model loads here as MuJoCo compiles it, and its `M`
//! (armature included), `qfrc_bias`, `mj_inverse`'s forces and `mj_forward`'s `qacc` (by its
//! residual in MuJoCo's own equations) agree to 1e-10 relative to the largest entry, through
//! the interpreted reference, at three seeded states; so do the sites' world poses and, for each
//! body MuJoCo keeps whole, its mass, centre of mass and inertia tensor in the world, and the
//! joints' springs (`qfrc_spring`). The models:
//! `features/` (every orientation form, default classes, frames, includes, joints at anchors
//! with `ref`, every geom shape's inertia, the compiler's mass rules) and `real/` (the MJCF files
//! PyPI packages ship).
//!
//! MuJoCo's free joint has `qvel = [v (world); ω (body)]` where ours is `[v; ω]` both in the
//! body frame: `v_ours = T·v_mj` with `T = diag(Rᵀ, I)` on each free joint, so `M_mj = Tᵀ·M·T`,
//! forces `τ_mj = Tᵀ·τ`, and accelerations carry the drift of the turning frame,
//! `a_ours = T·a_mj − [ω × v_ours; 0]` (a plain rotation fails as soon as `ω ≠ 0`).
//!
//! `cargo test -p articulated-tests --test mjcf -- --nocapture` prints each model's warnings
//! and worst error.

mod common;

use std::path::Path;

use articulated::prelude::*;
use articulated::reference::Reference;
use articulated_codegen::load::load;
use articulated_codegen::model::JointKind;
use articulated_codegen::urdf::FloatingBase;
use common::{fd_residual, read_json, rel_err, rows_of, vec_of};
use nalgebra::{DMatrix, DVector, Matrix3, Quaternion, SVector, UnitQuaternion, Vector3};

/// Relative to the largest entry of each of MuJoCo's values.
const TOL: f64 = 1e-10;

/// The free joints of a model: `(qpos address, dof address)` of each.
fn free_joints(r: &Reference) -> Vec<(usize, usize)> {
    let (mut iq, mut iv) = (0, 0);
    let mut out = Vec::new();
    for j in &r.model().joints {
        if j.mimic.is_some() {
            continue;
        }
        if matches!(j.kind, JointKind::FreeQuaternion) {
            out.push((iq, iv));
        }
        iq += j.kind.nq();
        iv += j.kind.nv();
    }
    out
}

/// `T` (MuJoCo's velocities to ours) at `qpos`.
fn to_ours(free: &[(usize, usize)], qpos: &[f64], nv: usize) -> DMatrix<f64> {
    let mut t = DMatrix::identity(nv, nv);
    for &(iq, iv) in free {
        let q = UnitQuaternion::from_quaternion(Quaternion::new(
            qpos[iq + 3],
            qpos[iq + 4],
            qpos[iq + 5],
            qpos[iq + 6],
        ));
        let rt: Matrix3<f64> = q.to_rotation_matrix().into_inner().transpose();
        t.view_mut((iv, iv), (3, 3)).copy_from(&rt);
    }
    t
}

/// The drift `[ω × v; 0]` of each free joint at our velocity `v`.
fn drift(free: &[(usize, usize)], v: &DVector<f64>) -> DVector<f64> {
    let mut d = DVector::zeros(v.len());
    for &(_, iv) in free {
        let lin = Vector3::new(v[iv], v[iv + 1], v[iv + 2]);
        let w = Vector3::new(v[iv + 3], v[iv + 4], v[iv + 5]);
        d.rows_mut(iv, 3).copy_from(&w.cross(&lin));
    }
    d
}

/// A function of a state `(q, v, a or τ)`.
type StateFn<'a> = dyn Fn(&[f64], &[f64], &[f64]) -> DVector<f64> + 'a;

/// The dynamics compared: the reference's, or a generated chain's.
struct Dynamics<'a> {
    mass_matrix: &'a (dyn Fn(&[f64]) -> DMatrix<f64> + 'a),
    inverse: &'a StateFn<'a>,
    forward: &'a StateFn<'a>,
}

/// The reference's dynamics.
macro_rules! reference {
    ($r:expr) => {
        Dynamics {
            mass_matrix: &|q| $r.mass_matrix(q).unwrap(),
            inverse: &|q, v, a| $r.inverse_dynamics(q, v, a).unwrap(),
            forward: &|q, v, tau| $r.forward_dynamics(q, v, tau).unwrap(),
        }
    };
}

/// A generated chain's dynamics (`NQ`, `NV` its sizes).
macro_rules! generated {
    ($c:ty, $nq:literal, $nv:literal) => {
        Dynamics {
            mass_matrix: &|q| {
                let m = <$c>::mass_matrix(&SVector::<f64, $nq>::from_column_slice(q));
                DMatrix::from_column_slice($nv, $nv, m.as_slice())
            },
            inverse: &|q, v, a| {
                let tau = <$c>::inverse_dynamics(
                    &SVector::<f64, $nq>::from_column_slice(q),
                    &SVector::<f64, $nv>::from_column_slice(v),
                    &SVector::<f64, $nv>::from_column_slice(a),
                );
                DVector::from_column_slice(tau.as_slice())
            },
            forward: &|q, v, tau| {
                let qdd = <$c>::forward_dynamics(
                    &SVector::<f64, $nq>::from_column_slice(q),
                    &SVector::<f64, $nv>::from_column_slice(v),
                    &SVector::<f64, $nv>::from_column_slice(tau),
                )
                .unwrap();
                DVector::from_column_slice(qdd.as_slice())
            },
        }
    };
}

/// Every error of one state of MuJoCo's (`s`), `(what, relative error)`: `free` are the free
/// joints' addresses.
fn state_errors(
    dynamics: &Dynamics,
    free: &[(usize, usize)],
    s: &serde_json::Value,
) -> Vec<(String, f64)> {
    let q = vec_of(&s["qpos"]);
    let nv = vec_of(&s["qvel"]).len();
    let t = to_ours(free, &q, nv);
    let v = &t * DVector::from_vec(vec_of(&s["qvel"]));
    let d = drift(free, &v);
    let a = &t * DVector::from_vec(vec_of(&s["qacc"])) - &d;
    let m = (dynamics.mass_matrix)(&q);
    let m_mj = t.transpose() * &m * &t;
    let bias_mj = t.transpose() * (dynamics.inverse)(&q, v.as_slice(), (-&d).as_slice());
    let tau_mj = t.transpose() * (dynamics.inverse)(&q, v.as_slice(), a.as_slice());
    let applied = vec_of(&s["tau"]);
    let qdd = (dynamics.forward)(
        &q,
        v.as_slice(),
        (&t * DVector::from_vec(applied.clone())).as_slice(),
    );
    let qdd_mj = t.transpose() * (qdd + &d);
    let theirs_m = DMatrix::from_row_slice(nv, nv, &rows_of(&s["mass_matrix"]));
    let theirs_bias = vec_of(&s["bias"]);
    vec![
        (
            "M".to_string(),
            rel_err(m_mj.transpose().as_slice(), &rows_of(&s["mass_matrix"])),
        ),
        (
            "bias".to_string(),
            rel_err(bias_mj.as_slice(), &theirs_bias),
        ),
        (
            "mj_inverse".to_string(),
            rel_err(tau_mj.as_slice(), &vec_of(&s["tau_inverse"])),
        ),
        (
            "qacc residual".to_string(),
            fd_residual(&theirs_m, &theirs_bias, &applied, qdd_mj.as_slice()),
        ),
    ]
}

/// The joints' springs (`−stiffness·(q − rest)` on each revolute and prismatic joint) against
/// MuJoCo's `qfrc_spring`; a ball's or free joint's spring is not represented (a warning says so)
/// and its rows are left out.
fn spring_errors(r: &Reference, s: &serde_json::Value) -> Vec<(String, f64)> {
    let q = vec_of(&s["qpos"]);
    let theirs = vec_of(&s["spring"]);
    let (mut iq, mut iv) = (0, 0);
    let (mut ours, mut kept) = (Vec::new(), Vec::new());
    for j in r.model().joints.iter().filter(|j| j.mimic.is_none()) {
        if j.kind.nq() == 1 {
            ours.push(-j.drive.stiffness * (q[iq] - j.drive.rest));
            kept.push(theirs[iv]);
        }
        iq += j.kind.nq();
        iv += j.kind.nv();
    }
    vec![("springs".to_string(), rel_err(&ours, &kept))]
}

/// The sites' world poses, and the mass, centre of mass and world inertia tensor of each body
/// MuJoCo keeps whole, against MuJoCo's, `(what, relative error)`.
fn frame_errors(r: &Reference, s: &serde_json::Value) -> Vec<(String, f64)> {
    let q = vec_of(&s["qpos"]);
    let rows = |m: &Matrix3<f64>| -> Vec<f64> { m.transpose().as_slice().to_vec() };
    let mut errors = Vec::new();
    for (name, site) in s["sites"].as_object().unwrap() {
        // A site named as a body is that name with `_site` appended.
        let found = [format!("{name}_site"), name.clone()]
            .into_iter()
            .find_map(|n| r.frame_placement(&q, &n).ok());
        let Some((rot, p)) = found else {
            errors.push((format!("site `{name}` missing"), f64::INFINITY));
            continue;
        };
        errors.push((
            format!("site `{name}` position"),
            rel_err(p.as_slice(), &vec_of(&site["pos"])),
        ));
        errors.push((
            format!("site `{name}` axes"),
            rel_err(&rows(&rot), &vec_of(&site["mat"])),
        ));
    }
    for (name, theirs) in s["bodies"].as_object().unwrap() {
        let body = r.model().bodies.iter().find(|b| b.name == *name);
        let (Some(body), Ok((rot, p))) = (body, r.frame_placement(&q, name)) else {
            errors.push((format!("body `{name}` missing"), f64::INFINITY));
            continue;
        };
        let c = |v: &articulated_codegen::model::Value| v.as_const().unwrap();
        let com = p + rot * Vector3::from(body.com.map(|v| c(&v)));
        let inertia = Matrix3::from_fn(|i, j| c(&body.inertia[i][j]));
        let world = rot * inertia * rot.transpose();
        let mass = theirs["mass"].as_f64().unwrap();
        errors.push((
            format!("body `{name}` mass"),
            rel_err(&[c(&body.mass)], &[mass]),
        ));
        errors.push((
            format!("body `{name}` centre of mass"),
            rel_err(com.as_slice(), &vec_of(&theirs["com"])),
        ));
        errors.push((
            format!("body `{name}` inertia"),
            rel_err(&rows(&world), &vec_of(&theirs["inertia"])),
        ));
    }
    errors
}

#[test]
fn every_mjcf_model_mujoco_loads_loads_and_agrees() {
    let json = read_json("data/mujoco/mujoco-values.json");
    let mut failures = Vec::new();
    let mut compared = 0;
    for (file, m) in json["models"].as_object().unwrap() {
        if !m["loads"].as_bool().unwrap() {
            continue;
        }
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("data/mujoco")
            .join(file);
        let chain = match load(&path, FloatingBase::Fixed) {
            Ok(c) => c,
            Err(e) => {
                failures.push(format!("{file}: does not load:\n{e}"));
                continue;
            }
        };
        for w in &chain.warnings {
            println!("{}", w.display_in(&path));
        }
        let r = Reference::new(&chain.model).unwrap();
        let (nq, nv) = (m["nq"].as_u64().unwrap(), m["nv"].as_u64().unwrap());
        if (r.nq() as u64, r.nv() as u64) != (nq, nv) {
            failures.push(format!(
                "{file}: nq, nv = {}, {} against MuJoCo's {nq}, {nv}",
                r.nq(),
                r.nv()
            ));
            continue;
        }
        let mut worst = 0.0f64;
        for s in m["states"].as_array().unwrap() {
            let free = free_joints(&r);
            let errors = state_errors(&reference!(r), &free, s);
            let others = frame_errors(&r, s).into_iter().chain(spring_errors(&r, s));
            for (what, e) in errors.into_iter().chain(others) {
                worst = worst.max(e);
                if e.is_nan() || e > TOL {
                    failures.push(format!("{file}: {what} off by {e:.1e}"));
                }
            }
        }
        compared += 1;
        println!("{file}: nv {nv}, worst error {worst:.1e}");
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert_eq!(
        compared, 58,
        "8 feature models, 15 exported and 35 real ones"
    );
}

/// Every model file beside the values has values (a file added without rerunning the script
/// would otherwise go untested); included files (no `<worldbody>`) are not models.
#[test]
fn every_mjcf_file_has_mujoco_values() {
    let json = read_json("data/mujoco/mujoco-values.json");
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/mujoco");
    let mut stack = vec![
        root.join("features"),
        root.join("exported"),
        root.join("real"),
    ];
    let mut missing = Vec::new();
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "xml")
                && std::fs::read_to_string(&path)
                    .unwrap()
                    .contains("<worldbody")
            {
                let rel = path
                    .strip_prefix(&root)
                    .unwrap()
                    .to_str()
                    .unwrap()
                    .replace('\\', "/");
                if json["models"].get(&rel).is_none() {
                    missing.push(rel);
                }
            }
        }
    }
    assert!(
        missing.is_empty(),
        "no MuJoCo values for {missing:?}: rerun make_mujoco_reference.py"
    );
}

/// Joints at anchors, `ref`, a ball, a free body, from MJCF (`features/joints.xml`).
#[derive(Chain)]
#[chain(mjcf = "data/mujoco/features/joints.xml", outputs = [mass_matrix, inverse_dynamics, forward_dynamics])]
struct Joints;

/// Gymnasium's ant: a free torso, eight hinges in bodies placed by `fromto` geoms.
#[derive(Chain)]
#[chain(mjcf = "data/mujoco/real/gymnasium/ant.xml", outputs = [mass_matrix, inverse_dynamics, forward_dynamics])]
struct GymAnt;

/// The code generated from MJCF agrees with MuJoCo as the reference does.
#[test]
fn generated_from_mjcf_agrees_with_mujoco() {
    let json = read_json("data/mujoco/mujoco-values.json");
    let cases = [
        ("features/joints.xml", generated!(Joints, 17, 15)),
        ("real/gymnasium/ant.xml", generated!(GymAnt, 15, 14)),
    ];
    let mut failures = Vec::new();
    for (file, dynamics) in &cases {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("data/mujoco")
            .join(file);
        let r = Reference::new(&load(&path, FloatingBase::Fixed).unwrap().model).unwrap();
        let free = free_joints(&r);
        for s in json["models"][file]["states"].as_array().unwrap() {
            for (what, e) in state_errors(dynamics, &free, s) {
                if e.is_nan() || e > TOL {
                    failures.push(format!("{file} (generated): {what} off by {e:.1e}"));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The shipped models written by `articulated export --mjcf` (`data/mujoco/exported/`, each
/// file's first line naming its source and base): each file is what the exporter writes today, and the
/// original model (`.chain` or URDF, through the reference) agrees with MuJoCo's values of the
/// exported file, so MuJoCo runs the same bodies and joints.
#[test]
fn shipped_models_exported_to_mjcf_agree_with_mujoco() {
    let json = read_json("data/mujoco/mujoco-values.json");
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/mujoco/exported");
    let workspace = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut failures = Vec::new();
    let mut compared = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap();
        let (header, body) = text.split_once('\n').unwrap();
        let source = header
            .strip_prefix("<!-- Written by the MJCF export of articulated from ")
            .and_then(|c| c.strip_suffix(". -->"))
            .unwrap_or_else(|| panic!("{}: no source on its first line", path.display()));
        let (source, floating) = match source.split_once(", with ") {
            None => (source, FloatingBase::Fixed),
            Some((s, "an Euler free base")) => (s, FloatingBase::Euler),
            Some((s, "a quaternion free base")) => (s, FloatingBase::Quaternion),
            Some((_, other)) => panic!("{other}"),
        };
        let command = format!("articulated export --mjcf {source}");
        let source = workspace.join(source);
        let model = load(&source, floating).unwrap().model;
        let exported = articulated_codegen::mjcf::to_mjcf(&model).unwrap();
        let file = format!("exported/{}", path.file_name().unwrap().to_str().unwrap());
        if exported.text != body {
            failures.push(format!(
                "{file} is not what `articulated {command}` writes now: rerun it"
            ));
        }
        let r = Reference::new(&model).unwrap();
        let free = free_joints(&r);
        for s in json["models"][&file]["states"].as_array().unwrap() {
            for (what, e) in state_errors(&reference!(r), &free, s) {
                if e.is_nan() || e > TOL {
                    failures.push(format!("{file} (from {command}): {what} off by {e:.1e}"));
                }
            }
        }
        compared += 1;
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert_eq!(compared, 15);
}

/// `mimic_equalities` (`features/equality.xml`): `b − ref_b = 0.1 − 0.5·(a − ref_a)` becomes the
/// mimic joint `b = −0.5·a + (0.1 + ref_b + 0.5·ref_a)` and `c` is locked at `ref_c + 0.2`, so
/// with `G = ∂q_full/∂q` (constant) the coupled model's `M` is `Gᵀ·M_full(q_full)·G` and its `τ`
/// is `Gᵀ·τ_full(q_full, G·v, G·a)`, with `M_full` and `τ_full` those of the model that keeps
/// every coordinate (which agrees with MuJoCo above). The quadratic equality stays one, with a
/// warning.
#[test]
fn joint_equalities_become_exact_mimic_joints_and_locks_on_request() {
    use articulated_codegen::load::{load_with, LoadOptions};
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/mujoco/features/equality.xml");
    let full = Reference::new(&load(&path, FloatingBase::Fixed).unwrap().model).unwrap();
    let options = LoadOptions {
        mimic_equalities: true,
        ..LoadOptions::default()
    };
    let chain = load_with(&path, options).unwrap();
    assert!(
        chain
            .warnings
            .iter()
            .any(|w| w.message.contains("equality on `e` is not linear")),
        "{:?}",
        chain.warnings
    );
    let coupled = Reference::new(&chain.model).unwrap();
    assert_eq!((coupled.nq(), coupled.nv()), (3, 3), "a, d, e");
    let (ref_a, ref_b, ref_c) = (10f64.to_radians(), 20f64.to_radians(), -15f64.to_radians());
    let mut g = DMatrix::zeros(5, 3);
    g[(0, 0)] = 1.0;
    g[(1, 0)] = -0.5;
    g[(3, 1)] = 1.0;
    g[(4, 2)] = 1.0;
    for (q, v, a) in [
        ([0.3, 0.05, -0.4], [0.7, -0.2, 0.5], [-1.0, 0.4, 2.0]),
        ([-1.1, -0.02, 1.0], [-0.3, 0.6, -0.8], [0.5, -1.5, 0.2]),
    ] {
        let b = -0.5 * q[0] + (0.1 + ref_b + 0.5 * ref_a);
        let q_full = [q[0], b, ref_c + 0.2, q[1], q[2]];
        let m_full = full.mass_matrix(&q_full).unwrap();
        let expected_m = g.transpose() * &m_full * &g;
        let m = coupled.mass_matrix(&q).unwrap();
        assert!(
            rel_err(m.as_slice(), expected_m.as_slice()) < 1e-13,
            "{m} against {expected_m}"
        );
        let (vf, af) = (
            &g * DVector::from_row_slice(&v),
            &g * DVector::from_row_slice(&a),
        );
        let expected_tau = g.transpose()
            * full
                .inverse_dynamics(&q_full, vf.as_slice(), af.as_slice())
                .unwrap();
        let tau = coupled.inverse_dynamics(&q, &v, &a).unwrap();
        assert!(
            rel_err(tau.as_slice(), expected_tau.as_slice()) < 1e-13,
            "{tau} against {expected_tau}"
        );
    }
}
