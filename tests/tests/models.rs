//! Every model shipped in `articulated-models` is written twice, as a `.chain` file and as URDF.
//! The two front ends (our grammar and the URDF importer) share no code, so equal dynamics at
//! random states check both: frames, Euler sequences written as revolute chains, fixed joints
//! merged by the importer and kept by the grammar.

mod common;

use articulated::reference::Reference;
use articulated_codegen::load::load_model;
use articulated_dynamics::random::Rng;
use common::rel_err;
use std::path::Path;

/// `n` numbers uniform in `[-scale, scale)`.
fn uniform(rng: &mut Rng, n: usize, scale: f64) -> Vec<f64> {
    (0..n).map(|_| rng.symmetric(scale)).collect()
}

#[test]
fn chain_and_urdf_files_describe_the_same_dynamics() {
    for files in articulated_models::ALL {
        let Some(urdf) = files.urdf else { continue };
        if files.free_base {
            // The `.chain` file's free base has a quaternion, the URDF's (`floating`) Euler
            // angles: other coordinates. `generated_scale.rs` checks both files against
            // Pinocchio, each in its own coordinates.
            continue;
        }
        let from_chain =
            load_model(Path::new(files.chain), false).unwrap_or_else(|e| panic!("{e}"));
        let from_urdf = load_model(Path::new(urdf), false).unwrap_or_else(|e| panic!("{e}"));
        let (a, b) = (
            Reference::new(&from_chain).unwrap(),
            Reference::new(&from_urdf).unwrap(),
        );
        assert_eq!((a.nq(), a.nv()), (b.nq(), b.nv()), "{}", files.name);
        let mut rng = Rng::new(7);
        let mut worst = 0.0_f64;
        for _ in 0..8 {
            let q = uniform(&mut rng, a.nq(), 3.0);
            let v = uniform(&mut rng, a.nv(), 2.0);
            let acc = uniform(&mut rng, a.nv(), 2.0);
            let checks = [
                (
                    a.mass_matrix(&q).unwrap().as_slice().to_vec(),
                    b.mass_matrix(&q).unwrap().as_slice().to_vec(),
                ),
                (
                    a.bias(&q, &v).unwrap().as_slice().to_vec(),
                    b.bias(&q, &v).unwrap().as_slice().to_vec(),
                ),
                (
                    a.gravity(&q).unwrap().as_slice().to_vec(),
                    b.gravity(&q).unwrap().as_slice().to_vec(),
                ),
                (
                    a.inverse_dynamics(&q, &v, &acc)
                        .unwrap()
                        .as_slice()
                        .to_vec(),
                    b.inverse_dynamics(&q, &v, &acc)
                        .unwrap()
                        .as_slice()
                        .to_vec(),
                ),
            ];
            for (x, y) in &checks {
                let e = rel_err(x, y);
                worst = worst.max(e);
                assert!(
                    e < 1e-12,
                    "{}: .chain and .urdf differ by {e:e}",
                    files.name
                );
            }
        }
        println!(
            "{}: .chain vs .urdf, worst relative difference {worst:.1e}",
            files.name
        );
    }
}
