//! The reference's frames (`articulated::reference::frames`) against Pinocchio 4.1
//! (`tests/data/pinocchio_frames/pinocchio-frames.json`, written by `make_pinocchio_frames.py`
//! there): `models/arm7.urdf` and `models/tree.urdf` on fixed bases, `models/humanoid.urdf` on a
//! free flyer and on our Euler base, three seeded states each; every URDF link's frame (the
//! bodies, the links the importer merged by fixed joints, a fixed base's root link) and three
//! declared frames per model, placed here as the script placed them in Pinocchio. Compared, to
//! 1e-10 of the largest entry of Pinocchio's value: the placement, the LOCAL velocity, the
//! classical acceleration in LOCAL_WORLD_ALIGNED, the Jacobians and their time variation in
//! LOCAL, WORLD and LOCAL_WORLD_ALIGNED. For the Jacobians, and for their time variations, that
//! is the largest entry over the three reference frames: `J̇_local` of a body on a free or a
//! revolute joint, or of a frame welded to it, is zero up to rounding (its LOCAL columns are
//! constant), and its own largest entry a few ulps. The JSON is in our layout already (angular
//! first, our joint order, our quaternion order): the script converted Pinocchio's.
//!
//! On the Euler base Pinocchio's values come from six single-axis joints: Pinocchio 4.1's
//! composite `Translation + SphericalZYX` base gives the same placements, velocities,
//! accelerations and Jacobians, but a `getFrameJacobianTimeVariation` that is not `dJ/dt` (its
//! `computeJointJacobiansTimeVariation` leaves out the rate of the joint's motion subspace).
//!
//! `cargo test -p articulated-tests --test pinocchio_frames -- --nocapture` prints the worst
//! error of each quantity per model.

mod common;

use std::path::Path;

use articulated::nalgebra::{DMatrix, Matrix3, Rotation3, Vector3};
use articulated::reference::{Reference, ReferenceFrame};
use articulated_codegen::load::load;
use articulated_codegen::urdf::FloatingBase;
use articulated_dynamics::model::{Frame, Model, Placement, Value};
use common::{abs_err, max_abs, read_json, rows_of, vec_of};
use serde_json::Value as Json;

/// Relative to the largest entry of each of Pinocchio's values.
const TOL: f64 = 1e-10;

/// The quantities compared, in print order.
const QUANTITIES: [&str; 10] = [
    "rotation",
    "translation",
    "velocity",
    "acceleration",
    "J local",
    "J world",
    "J lwa",
    "dJ local",
    "dJ world",
    "dJ lwa",
];

fn rpy(r: [f64; 3]) -> Matrix3<f64> {
    // Rz(yaw)·Ry(pitch)·Rx(roll).
    Rotation3::from_euler_angles(r[0], r[1], r[2]).into_inner()
}

fn consts<const N: usize>(x: &[Value; N]) -> [f64; N] {
    x.map(|x| x.as_const().expect("the importer writes constants"))
}

/// A declared frame `{name, link, xyz, rpy}` of the JSON: placed at `(xyz, rpy)` in the link's
/// frame, which is a body's or a frame of the model itself.
fn add_declared(model: &mut Model, d: &Json) {
    let link = d["link"].as_str().unwrap();
    let (parent, p) = model
        .frame(link)
        .unwrap_or_else(|| panic!("no link `{link}`"));
    let (r_link, t_link) = (rpy(consts(&p.rpy)), Vector3::from(consts(&p.xyz)));
    let xyz = Vector3::from_column_slice(&vec_of(&d["xyz"]));
    let r = r_link * rpy(vec_of(&d["rpy"]).try_into().unwrap());
    let t = t_link + r_link * xyz;
    let (roll, pitch, yaw) = Rotation3::from_matrix_unchecked(r).euler_angles();
    model.frames.push(Frame {
        name: d["name"].as_str().unwrap().into(),
        parent,
        placement: Placement {
            xyz: [t[0], t[1], t[2]].map(Value::Const),
            rpy: [roll, pitch, yaw].map(Value::Const),
        },
    });
}

/// Our values of one frame at one state, in [`QUANTITIES`] order (matrices row-major).
fn ours(r: &Reference, q: &[f64], v: &[f64], a: &[f64], f: &str) -> Vec<Vec<f64>> {
    let rows = |m: &DMatrix<f64>| -> Vec<f64> { m.transpose().as_slice().to_vec() };
    let (rot, p) = r.frame_placement(q, f).unwrap();
    let mut out = vec![
        rot.transpose().as_slice().to_vec(),
        p.as_slice().to_vec(),
        r.frame_velocity(q, v, f).unwrap().as_slice().to_vec(),
        r.frame_acceleration(q, v, a, f)
            .unwrap()
            .as_slice()
            .to_vec(),
    ];
    for rf in ReferenceFrame::ALL {
        out.push(rows(&r.frame_jacobian(q, f, rf).unwrap()));
    }
    for rf in ReferenceFrame::ALL {
        out.push(rows(&r.frame_jacobian_time_variation(q, v, f, rf).unwrap()));
    }
    out
}

/// Pinocchio's, in the same order.
fn theirs(p: &Json) -> Vec<Vec<f64>> {
    let mut out = vec![
        rows_of(&p["rotation"]),
        vec_of(&p["translation"]),
        vec_of(&p["velocity"]),
        vec_of(&p["acceleration"]),
    ];
    for key in ["jacobian", "jacobian_time_variation"] {
        for rf in ReferenceFrame::ALL {
            out.push(rows_of(&p[key][rf.name()]));
        }
    }
    out
}

/// What quantity `k`'s error is relative to: its largest entry, for a Jacobian or a time
/// variation the largest over the three reference frames (1 where that is 0: a frame on the
/// world).
fn scale(largest: &[f64], k: usize) -> f64 {
    let family = match k {
        4..=6 => &largest[4..7],
        7..=9 => &largest[7..10],
        _ => &largest[k..=k],
    };
    let s = family.iter().fold(0.0f64, |s, x| s.max(*x));
    if s > 0.0 {
        s
    } else {
        1.0
    }
}

#[test]
fn frames_agree_with_pinocchio() {
    let json = read_json("data/pinocchio_frames/pinocchio-frames.json");
    let mut failures = Vec::new();
    let mut compared = 0;
    for (name, m) in json["models"].as_object().unwrap() {
        let floating = match m["floating"].as_str().unwrap() {
            "fixed" => FloatingBase::Fixed,
            "quaternion" => FloatingBase::Quaternion,
            "euler" => FloatingBase::Euler,
            other => panic!("{name}: base `{other}`"),
        };
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("..")
            .join(m["urdf"].as_str().unwrap());
        let mut model = load(&path, floating)
            .unwrap_or_else(|e| panic!("{name}: {e}"))
            .model;
        let joints: Vec<&str> = model
            .joints
            .iter()
            .filter(|j| j.nv() > 0)
            .map(|j| j.name.as_str())
            .collect();
        let expected: Vec<&str> = m["joints"]
            .as_array()
            .unwrap()
            .iter()
            .map(|j| j.as_str().unwrap())
            .collect();
        assert_eq!(joints, expected, "{name}: joint order");
        assert_eq!(model.nq(), m["nq"].as_u64().unwrap() as usize, "{name}: nq");
        assert_eq!(model.nv(), m["nv"].as_u64().unwrap() as usize, "{name}: nv");
        for d in m["declared"].as_array().unwrap() {
            add_declared(&mut model, d);
        }
        // Every URDF link is a frame of the model, and nothing else is.
        let frames: Vec<&str> = m["frames"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f.as_str().unwrap())
            .collect();
        let mut ours_sorted: Vec<&str> = model.frame_names().collect();
        let mut theirs_sorted = frames.clone();
        ours_sorted.sort_unstable();
        theirs_sorted.sort_unstable();
        assert_eq!(ours_sorted, theirs_sorted, "{name}: frames");

        let r = Reference::new(&model).unwrap();
        let mut worst = [0.0f64; QUANTITIES.len()];
        for s in m["states"].as_array().unwrap() {
            let (q, v, a) = (vec_of(&s["q"]), vec_of(&s["v"]), vec_of(&s["a"]));
            for f in &frames {
                let (x, y) = (ours(&r, &q, &v, &a, f), theirs(&s["frames"][*f]));
                let scales: Vec<f64> = y.iter().map(|y| max_abs(y)).collect();
                for (k, (x, y)) in x.iter().zip(&y).enumerate() {
                    let e = abs_err(x, y) / scale(&scales, k);
                    // A NaN error fails too.
                    worst[k] = if e.is_nan() {
                        f64::INFINITY
                    } else {
                        worst[k].max(e)
                    };
                    if e.is_nan() || e > TOL {
                        failures.push(format!("{name}, {f}: {} off by {e:.1e}", QUANTITIES[k]));
                    }
                }
                compared += 1;
            }
        }
        let line: Vec<String> = QUANTITIES
            .iter()
            .zip(worst)
            .map(|(q, e)| format!("{q}={e:.1e}"))
            .collect();
        println!("{name:<20} {} frames: {}", frames.len(), line.join(" "));
        if let Some(e) = m.get("composite_time_variation_error") {
            println!(
                "{name:<20} (Pinocchio's composite Euler base: dJ off by {:.2} of the largest)",
                e.as_f64().unwrap()
            );
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // 3 states × (11 + 12 + 37 + 37) frames.
    assert_eq!(compared, 3 * (11 + 12 + 37 + 37));
}
