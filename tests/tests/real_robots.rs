//! Every URDF of the PyPI package `example-robot-data` 6.0.0 that Pinocchio 4.1 loads (68 of 69;
//! verbatim copies in `tests/data/real_robots/urdf/`, but for Alex's three, whose licence forbids
//! commercial use: see the data's README) loads here too, and agrees with
//! Pinocchio's values (`tests/data/real_robots/pinocchio-real-robots.json`, written by
//! `make_real_robots.py` there): `M`, `nonLinearEffects`, gravity and `rnea` at one seeded state,
//! on a fixed base and on our Euler free base, to 1e-10 relative to the largest entry, through
//! the interpreted reference. These are the files a new user tries first (ANYmal, Go1, B1, HyQ,
//! TIAGo, iCub, PR2, Allegro, Romeo, TALOS…): placeholder and non-physical inertias, rounding
//! noise written as a tensor, `<mimic>` on fixed joints and of joints that do not exist, empty
//! `<texture/>` elements, models where nothing moves.
//!
//! Where Pinocchio's own model differs from the file's physics it is said and skipped: Romeo's
//! and `talos_full_v2`'s `<mimic>` joints are coupled here but independent in Pinocchio (whose
//! `mimic=True` refuses them), so only their sizes are compared.
//!
//! `cargo test -p articulated-tests --test real_robots -- --nocapture` prints each robot's
//! warnings and worst error.

mod common;

use std::path::Path;

use articulated::reference::Reference;
use articulated_codegen::load::load;
use articulated_codegen::urdf::FloatingBase;
use common::{read_json, rel_err, rows_of, vec_of};

/// Relative to the largest entry of each of Pinocchio's values.
const TOL: f64 = 1e-10;

#[test]
fn every_robot_pinocchio_loads_loads_and_agrees() {
    let json = read_json("data/real_robots/pinocchio-real-robots.json");
    let models = json["models"].as_object().unwrap();
    let (mut loaded, mut compared) = (0, 0);
    let mut failures = Vec::new();
    for (name, m) in models {
        if !m["loads"].as_bool().unwrap() {
            continue;
        }
        let path = format!("data/real_robots/{}", m["urdf"].as_str().unwrap());
        if name.starts_with("alex_description/") {
            // Not copied: their licence forbids commercial use (the data README says so).
            assert!(!Path::new(&path).exists(), "{path} is here now: test it");
            continue;
        }
        // Pinocchio's mimic joints have coordinates where it could not couple them.
        let coupled_here = m["mimic_joints"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|j| {
                m["joints"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .any(|k| k["name"] == j["joint"])
            })
            .count();
        let same_physics = m["uses_mimic"].as_bool().unwrap() || coupled_here == 0;
        for (base, floating) in [
            ("fixed", FloatingBase::Fixed),
            ("floating", FloatingBase::Euler),
        ] {
            let label = format!("{name} ({base})");
            let p = &m[base];
            let chain = match load(Path::new(&path), floating) {
                Ok(chain) => chain,
                Err(e) => {
                    failures.push(format!("{label}: does not load:\n{e}"));
                    continue;
                }
            };
            loaded += 1;
            for w in &chain.warnings {
                println!("{}", w.display_in(Path::new(&path)));
            }
            let model = chain.model;
            let nv = p["nv"].as_u64().unwrap() as usize;
            let expected_nv = if same_physics { nv } else { nv - coupled_here };
            if model.nv() != expected_nv {
                failures.push(format!("{label}: nv {} against {expected_nv}", model.nv()));
                continue;
            }
            if !same_physics {
                continue;
            }
            let r = match Reference::new(&model) {
                Ok(r) => r,
                Err(e) => {
                    failures.push(format!("{label}: the reference refuses it: {e}"));
                    continue;
                }
            };
            let (q, v, a) = (vec_of(&p["q"]), vec_of(&p["v"]), vec_of(&p["a"]));
            let mm = r.mass_matrix(&q).unwrap();
            let m_ours: Vec<f64> = (0..nv)
                .flat_map(|i| (0..nv).map(move |j| (i, j)))
                .map(|ij| mm[ij])
                .collect();
            let g = r.gravity(&q).unwrap();
            let nle: Vec<f64> = (r.bias(&q, &v).unwrap() + &g).iter().copied().collect();
            let tau: Vec<f64> = r
                .inverse_dynamics(&q, &v, &a)
                .unwrap()
                .iter()
                .copied()
                .collect();
            let errors = [
                ("M", rel_err(&m_ours, &rows_of(&p["mass_matrix"]))),
                ("nle", rel_err(&nle, &vec_of(&p["nonlinear_effects"]))),
                ("gravity", rel_err(g.as_slice(), &vec_of(&p["gravity"]))),
                ("tau", rel_err(&tau, &vec_of(&p["tau_out"]))),
            ];
            let worst = errors.iter().fold(0.0f64, |a, e| a.max(e.1));
            println!("{label}: nv {nv}, worst error {worst:.1e}");
            compared += 1;
            for (what, e) in errors {
                // A NaN error fails too.
                if e.is_nan() || e > TOL {
                    failures.push(format!("{label}: {what} off by {e:.1e}"));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert_eq!(
        loaded, 130,
        "65 robots (68 less Alex's three), fixed and floating"
    );
    assert!(compared >= 124, "only {compared} compared");
}
