//! The reference dynamics of URDF models against Pinocchio 4.1, an independent C++ library.
//!
//! Data: `tests/data/pinocchio/pinocchio-values.json` (four shared models, fixed base and, for
//! two, a free base) and `tests/data/pinocchio-arm7.json` (`models/arm7.urdf`, written by
//! `tests/data/make_arm7_reference.py`, with Pinocchio's joint wrenches) and
//! `tests/data/pinocchio-scale.json` (the humanoid and the 50-body chain, from their `.chain`
//! files and URDFs; `tests/data/make_scale_reference.py`). Each URDF is loaded with
//! [`articulated_codegen::load::load_model`] and evaluated with
//! [`articulated::reference::Reference`]; every quantity must agree to 1e-10 relative to its
//! largest entry. `cargo test -p articulated-tests --test pinocchio -- --nocapture` prints the
//! largest relative error per model and quantity.
//!
//! Conventions compared: q, v, a, τ in URDF joint order; `bias` without gravity on both sides;
//! the free base is Wieber's (translation in the world frame, then Euler `zyx`, `v = q̇`), which
//! is Pinocchio's `JointModelComposite(Translation, SphericalZYX)`. Pinocchio's spatial forces are
//! linear first, ours angular first: the wrenches are swapped before comparing.

mod common;

use common::{read_json, rel_err, rows_of, vec_of};
use std::path::{Path, PathBuf};

use articulated::model::Model;
use articulated::reference::{Error, Reference, Wrench};
use articulated_codegen::load::load_model;
use articulated_dynamics::random::Rng;
use serde_json::Value as Json;

const TOL: f64 = 1e-10;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The quantities compared, in print order.
const QUANTITIES: [&str; 6] = [
    "mass_matrix",
    "bias",
    "gravity",
    "tau_out",
    "qdd",
    "joint_wrenches",
];

/// Compares one model (one base) at every state of `case`; returns the largest relative error
/// per quantity (`None` where Pinocchio gave no value).
fn compare(model: &Model, case: &Json, label: &str) -> [Option<f64>; 6] {
    let r = Reference::new(model).unwrap_or_else(|e| panic!("{label}: {e}"));
    assert_eq!(r.nq() as u64, case["nq"].as_u64().unwrap(), "{label}: nq");
    assert_eq!(r.nv() as u64, case["nv"].as_u64().unwrap(), "{label}: nv");
    let mut worst: [Option<f64>; 6] = [None; 6];
    let mut note = |k: usize, e: f64| {
        worst[k] = Some(worst[k].map_or(e, |w: f64| w.max(e)));
    };
    let mut singular = 0;
    for s in case["states"].as_array().unwrap() {
        let (q, v, a, tau) = (
            vec_of(&s["q"]),
            vec_of(&s["v"]),
            vec_of(&s["a"]),
            vec_of(&s["tau"]),
        );
        let m = r.mass_matrix(&q).unwrap();
        let m_theirs = rows_of(&s["mass_matrix"]);
        // Row-major on both sides.
        let m_ours: Vec<f64> = (0..m.nrows())
            .flat_map(|i| (0..m.ncols()).map(move |j| (i, j)))
            .map(|(i, j)| m[(i, j)])
            .collect();
        note(0, rel_err(&m_ours, &m_theirs));
        note(
            1,
            rel_err(r.bias(&q, &v).unwrap().as_slice(), &vec_of(&s["bias"])),
        );
        note(
            2,
            rel_err(r.gravity(&q).unwrap().as_slice(), &vec_of(&s["gravity"])),
        );
        let tau_out = r.inverse_dynamics(&q, &v, &a).unwrap();
        note(3, rel_err(tau_out.as_slice(), &vec_of(&s["tau_out"])));
        let qdd_theirs = vec_of(&s["qdd"]);
        let n = m.nrows();
        let eig = nalgebra::DMatrix::from_row_slice(n, n, &m_theirs).symmetric_eigenvalues();
        let (lo, hi) = eig.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), e| {
            (lo.min(*e), hi.max(e.abs()))
        });
        if lo <= 1e-12 * hi || qdd_theirs.iter().any(|x| x.is_nan()) {
            // M(q) is singular (Pinocchio's own M has a zero eigenvalue): the free base is a
            // massless root body whose motions duplicate a joint below it (two_link_xyz: the
            // ankle's three rotations; arm6_mixed: a rotation about j0's axis). Forward dynamics
            // is undefined; Pinocchio's ABA divides by rounding noise (NaN, or entries ~1e16).
            // We must say so rather than return numbers.
            let res = r.forward_dynamics(&q, &v, &tau);
            assert!(
                matches!(res, Err(Error::Singular(_))),
                "{label}: M(q) is singular (eigenvalues {lo:e} .. {hi:e}), we return {res:?}"
            );
            singular += 1;
        } else {
            let qdd = r.forward_dynamics(&q, &v, &tau).unwrap();
            note(4, rel_err(qdd.as_slice(), &qdd_theirs));
        }
        if let Some(w) = s.get("joint_wrenches") {
            let ours: Vec<f64> = r
                .joint_wrenches(&q, &v, &a)
                .unwrap()
                .iter()
                .flat_map(|w: &Wrench| w.couple.into_iter().chain(w.force))
                .collect();
            // Pinocchio: [f; n] (linear first) → ours: [n; f] (angular first).
            let theirs: Vec<f64> = w
                .as_array()
                .unwrap()
                .iter()
                .flat_map(|f| {
                    let f = vec_of(f);
                    [f[3], f[4], f[5], f[0], f[1], f[2]]
                })
                .collect();
            note(5, rel_err(&ours, &theirs));
        }
    }
    if singular > 0 {
        println!("{label}: M(q) singular at {singular} states, forward dynamics reports it");
    }
    worst
}

fn report(label: &str, worst: &[Option<f64>; 6]) -> Vec<String> {
    let mut line = format!("{label:<28}");
    let mut failures = Vec::new();
    for (q, w) in QUANTITIES.iter().zip(worst) {
        if let Some(e) = w {
            line += &format!(" {q}={e:.1e}");
            // NaN fails too.
            if e.is_nan() || *e > TOL {
                failures.push(format!(
                    "{label}: {q} differs from Pinocchio by {e:e} (relative)"
                ));
            }
        }
    }
    println!("{line}");
    failures
}

#[test]
fn shared_models_match_pinocchio() {
    let data = repo().join("tests/data/pinocchio");
    let json = read_json("data/pinocchio/pinocchio-values.json");
    let mut failures = Vec::new();
    let models = json["models"].as_object().unwrap();
    assert_eq!(models.len(), 4);
    for (name, entry) in models {
        let path = data.join(format!("{name}.urdf"));
        for (base, floating) in [("fixed", false), ("floating", true)] {
            let Some(case) = entry.get(base) else {
                continue;
            };
            let model = load_model(&path, floating).unwrap_or_else(|e| panic!("{e}"));
            let label = format!("{name} ({base})");
            failures.extend(report(&label, &compare(&model, case, &label)));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn arm7_matches_pinocchio_including_joint_wrenches() {
    let json = read_json("data/pinocchio-arm7.json");
    let entry = &json["models"]["arm7"];
    let path = repo().join("models/arm7.urdf");
    let mut failures = Vec::new();
    for (base, floating) in [("fixed", false), ("floating", true)] {
        let model = load_model(&path, floating).unwrap_or_else(|e| panic!("{e}"));
        let label = format!("arm7 ({base})");
        let worst = compare(&model, &entry[base], &label);
        assert!(worst[5].is_some(), "{label}: no joint wrenches compared");
        failures.extend(report(&label, &worst));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The models for scale (`tests/data/pinocchio-scale.json`, written by
/// `tests/data/make_scale_reference.py`): the humanoid's `.chain` file (free base with a
/// quaternion: Pinocchio's free flyer, the quaternion reordered to `[w, x, y, z]`) and its URDF
/// under a free Euler base, and the 50-body chain from both files.
#[test]
fn scale_models_match_pinocchio() {
    let json = read_json("data/pinocchio-scale.json");
    let models = &json["models"];
    let mut failures = Vec::new();
    for (label, file, floating, case) in [
        (
            "humanoid.chain",
            "humanoid.chain",
            false,
            &models["humanoid"]["free_flyer"],
        ),
        (
            "humanoid.urdf (floating)",
            "humanoid.urdf",
            true,
            &models["humanoid"]["floating"],
        ),
        (
            "chain50.chain",
            "chain50.chain",
            false,
            &models["chain50"]["fixed"],
        ),
        (
            "chain50.urdf",
            "chain50.urdf",
            false,
            &models["chain50"]["fixed"],
        ),
    ] {
        let path = repo().join("models").join(file);
        let model = load_model(&path, floating).unwrap_or_else(|e| panic!("{e}"));
        failures.extend(report(label, &compare(&model, case, label)));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// `n` numbers uniform in `[lo, hi)`.
fn uniform(rng: &mut Rng, n: usize, lo: f64, hi: f64) -> Vec<f64> {
    (0..n).map(|_| rng.range(lo, hi)).collect()
}

#[test]
fn arm7_chain_file_and_urdf_describe_the_same_dynamics() {
    let chain =
        load_model(&repo().join("models/arm7.chain"), false).unwrap_or_else(|e| panic!("{e}"));
    let urdf = load_model(&repo().join("models/arm7.urdf"), false).unwrap();
    assert_eq!(chain.name, urdf.name);
    let names = |m: &Model| -> Vec<(String, String)> {
        m.joints
            .iter()
            .zip(&m.bodies)
            .map(|(j, b)| (j.name.clone(), b.name.clone()))
            .collect()
    };
    assert_eq!(names(&chain), names(&urdf));
    let (rc, ru) = (
        Reference::new(&chain).unwrap(),
        Reference::new(&urdf).unwrap(),
    );
    assert_eq!((rc.nq(), rc.nv()), (ru.nq(), ru.nv()));
    let mut rng = Rng::new(0x9E37_79B9_7F4A_7C15);
    let mut worst = [0.0f64; 3];
    for _ in 0..20 {
        let q = uniform(&mut rng, ru.nq(), -3.0, 3.0);
        let v = uniform(&mut rng, ru.nv(), -2.0, 2.0);
        let (mc, mu) = (rc.mass_matrix(&q).unwrap(), ru.mass_matrix(&q).unwrap());
        worst[0] = worst[0].max(rel_err(mc.as_slice(), mu.as_slice()));
        let (bc, bu) = (rc.bias(&q, &v).unwrap(), ru.bias(&q, &v).unwrap());
        worst[1] = worst[1].max(rel_err(bc.as_slice(), bu.as_slice()));
        let (gc, gu) = (rc.gravity(&q).unwrap(), ru.gravity(&q).unwrap());
        worst[2] = worst[2].max(rel_err(gc.as_slice(), gu.as_slice()));
    }
    println!(
        "arm7 .chain vs .urdf: mass_matrix={:.1e} bias={:.1e} gravity={:.1e}",
        worst[0], worst[1], worst[2]
    );
    for (q, e) in ["mass_matrix", "bias", "gravity"].iter().zip(worst) {
        assert!(e <= 1e-12, "arm7 .chain vs .urdf: {q} differs by {e:e}");
    }
}
