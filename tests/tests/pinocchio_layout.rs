//! `articulated::pinocchio`'s conversions against Pinocchio's own states: the Unitree G1 and
//! TIAGo on Pinocchio's free flyer (`[x, y, z, qx, qy, qz, qw]`), TIAGo's and the Kinova arm's
//! continuous joints (`(cos θ, sin θ)`), read from the real robots' URDFs
//! (`tests/data/pinocchio_layout/pinocchio-layout.json`, written by the script beside it with
//! Pinocchio 4.1). Pinocchio's `q`, converted by `Layout::q_from_pinocchio`, must give our
//! reference the joint torques Pinocchio's `rnea` gave (to 1e-10 of the largest), and
//! `q_to_pinocchio` must give Pinocchio's `q` back. Pinocchio's `q` passed unchanged must not
//! (the mistake the conversions are for): on the G1, τ off by far more than rounding.

mod common;

use std::path::Path;

use articulated::interpreted::coordinates_of;
use articulated::pinocchio::Layout;
use articulated::reference::Reference;
use articulated_codegen::load::load;
use articulated_codegen::urdf::FloatingBase;
use common::{read_json, rel_err, vec_of};

const TOL: f64 = 1e-10;

#[test]
fn pinocchio_states_convert_and_give_pinocchio_torques() {
    let json = read_json("data/pinocchio_layout/pinocchio-layout.json");
    let mut checked = 0;
    for (name, m) in json["models"].as_object().unwrap() {
        let path = format!("data/{}", m["urdf"].as_str().unwrap());
        let floating = if m["free_flyer"].as_bool().unwrap() {
            FloatingBase::Quaternion
        } else {
            FloatingBase::Fixed
        };
        let chain = load(Path::new(&path), floating).unwrap_or_else(|e| panic!("{name}: {e}"));
        let model = &chain.model;
        // The same joints in the same order: ours with coordinates, Pinocchio's all.
        let ours: Vec<&str> = model
            .joints
            .iter()
            .filter(|j| j.nv() > 0)
            .map(|j| j.name.as_str())
            .collect();
        let theirs: Vec<&str> = m["joints"]
            .as_array()
            .unwrap()
            .iter()
            .map(|j| j["name"].as_str().unwrap())
            .collect();
        assert_eq!(
            chain.pinocchio_order, theirs,
            "{name}: Pinocchio's joint order"
        );
        let order: Vec<usize> = theirs
            .iter()
            .map(|n| ours.iter().position(|o| o == n).unwrap())
            .collect();
        // Pinocchio's continuous joints are the URDF's, as the importer reports them.
        let mut rub: Vec<&str> = m["joints"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|j| j["kind"].as_str().unwrap().starts_with("JointModelRUB"))
            .map(|j| j["name"].as_str().unwrap())
            .collect();
        let mut continuous_here = chain.continuous.clone();
        continuous_here.sort();
        rub.sort_unstable();
        assert_eq!(continuous_here, rub, "{name}: continuous joints");
        let continuous: Vec<usize> = chain
            .continuous
            .iter()
            .map(|c| {
                let i = model.joints.iter().position(|j| &j.name == c).unwrap();
                model.q_offset(i)
            })
            .collect();
        let coordinates = coordinates_of(model);
        let layout = Layout::new(&coordinates, &continuous)
            .unwrap()
            .with_order(&order)
            .unwrap();
        assert_eq!(layout.nq_pinocchio(), m["nq"].as_u64().unwrap() as usize);
        assert_eq!(layout.nv(), m["nv"].as_u64().unwrap() as usize);
        let reference = Reference::new(model).unwrap();
        for s in m["states"].as_array().unwrap() {
            let (q_pin, v_pin, a_pin) = (vec_of(&s["q"]), vec_of(&s["v"]), vec_of(&s["a"]));
            let tau_pin = vec_of(&s["tau"]);
            let (mut q, mut v, mut a) = (
                vec![0.0; layout.nq()],
                vec![0.0; layout.nv()],
                vec![0.0; layout.nv()],
            );
            layout
                .from_pinocchio(&q_pin, &v_pin, &mut q, &mut v)
                .unwrap();
            layout.v_from_pinocchio(&a_pin, &mut a).unwrap();
            let tau = reference.inverse_dynamics(&q, &v, &a).unwrap();
            let mut tau_in_pinocchio_order = vec![0.0; layout.nv()];
            layout
                .v_to_pinocchio(tau.as_slice(), &mut tau_in_pinocchio_order)
                .unwrap();
            let e = rel_err(&tau_in_pinocchio_order, &tau_pin);
            assert!(e < TOL, "{name}: tau off by {e:.1e}");
            let (mut q_back, mut v_back) = (vec![0.0; q_pin.len()], vec![0.0; v_pin.len()]);
            layout
                .to_pinocchio(&q, &v, &mut q_back, &mut v_back)
                .unwrap();
            assert!(rel_err(&q_back, &q_pin) < 1e-15, "{name}: q back");
            assert_eq!(v_back, v_pin);
            checked += 1;
        }
    }
    assert_eq!(checked, 9);
    // A wrong order fails: TIAGo's joints in the file's order.
    let m = &json["models"]["tiago"];
    let chain = load(
        Path::new(&format!("data/{}", m["urdf"].as_str().unwrap())),
        FloatingBase::Quaternion,
    )
    .unwrap();
    assert_ne!(
        chain.pinocchio_order,
        chain
            .model
            .joints
            .iter()
            .filter(|j| j.nv() > 0)
            .map(|j| j.name.clone())
            .collect::<Vec<_>>()
    );
}

#[test]
fn the_importer_predicts_pinocchios_joint_order_on_every_real_robot() {
    // Pinocchio's URDF parser takes a link's child joints by name: on most files that is not
    // the document's order (TIAGo's wheels come first in its file, last in Pinocchio).
    let json = read_json("data/pinocchio_layout/pinocchio-layout.json");
    let (mut compared, mut reordered) = (0, 0);
    for (file, o) in json["orders"].as_object().unwrap() {
        let path = format!("data/real_robots/urdf/{file}");
        let chain = load(Path::new(&path), FloatingBase::Fixed).unwrap();
        let ours = &chain.pinocchio_order;
        // Where Pinocchio refused the mimic joints (`mimic=True`), they have coordinates
        // there: compare the others.
        let theirs: Vec<&str> = o["joints"]
            .as_array()
            .unwrap()
            .iter()
            .map(|j| j.as_str().unwrap())
            .filter(|j| ours.iter().any(|o| o == j))
            .collect();
        assert_eq!(ours, &theirs, "{file}");
        let document: Vec<&str> = chain
            .model
            .joints
            .iter()
            .filter(|j| j.nv() > 0)
            .map(|j| j.name.as_str())
            .collect();
        assert_eq!(document.len(), ours.len(), "{file}");
        reordered += usize::from(document != theirs);
        compared += 1;
    }
    println!("{compared} robots, {reordered} where Pinocchio's joint order is not the file's");
    assert_eq!(compared, 65);
    assert!(reordered > 10, "{reordered}");
}

#[test]
fn pinocchio_q_unconverted_gives_wrong_torques() {
    // The G1 has no continuous joint: Pinocchio's q has our length, and nothing but the
    // quaternion's order tells it apart.
    let json = read_json("data/pinocchio_layout/pinocchio-layout.json");
    let m = &json["models"]["g1"];
    let model = load(
        Path::new(&format!("data/{}", m["urdf"].as_str().unwrap())),
        FloatingBase::Quaternion,
    )
    .unwrap()
    .model;
    let reference = Reference::new(&model).unwrap();
    let s = &m["states"][0];
    let (q_pin, v, a) = (vec_of(&s["q"]), vec_of(&s["v"]), vec_of(&s["a"]));
    let tau = reference.inverse_dynamics(&q_pin, &v, &a).unwrap();
    let e = rel_err(tau.as_slice(), &vec_of(&s["tau"]));
    println!("G1, Pinocchio's q unconverted: tau off by {e:.2} of its largest entry");
    assert!(e > 1e-2, "{e}");
}

#[test]
fn bad_layouts_and_sizes_are_errors() {
    use articulated::Coordinates::{FreeQuaternion, Quaternion, Vector};
    let coords = [FreeQuaternion, Vector(1), Quaternion, Vector(3)];
    // q[7] is the revolute joint's; q[8] a quaternion's, q[12] an Euler joint's.
    assert!(Layout::new(&coords, &[7]).is_ok());
    for bad in [[8], [12], [3], [20]] {
        let e = Layout::new(&coords, &bad).unwrap_err();
        assert!(e.to_string().contains("not the coordinate"), "{e}");
    }
    assert!(Layout::new(&coords, &[7, 7]).is_err());
    let layout = Layout::new(&coords, &[7]).unwrap();
    assert_eq!(
        (layout.nq(), layout.nq_pinocchio(), layout.nv()),
        (15, 16, 13)
    );
    let q = [0.0; 15];
    let mut short = [9.0; 15];
    assert!(layout.q_to_pinocchio(&q, &mut short).is_err());
    assert_eq!(short, [9.0; 15], "nothing written");
    let mut out = [0.0; 16];
    assert!(layout.q_to_pinocchio(&q[..14], &mut out).is_err());
    let (mut qo, mut vo) = ([0.0; 16], [0.0; 12]);
    assert!(layout
        .to_pinocchio(&q, &[0.0; 13], &mut qo, &mut vo)
        .is_err());
    // The spherical joint's quaternion [w, x, y, z] is Pinocchio's [x, y, z, w].
    let mut q = [0.0; 15];
    q[8..12].copy_from_slice(&[0.5, 0.1, 0.2, 0.3]);
    layout.q_to_pinocchio(&q, &mut out).unwrap();
    assert_eq!(&out[9..13], &[0.1, 0.2, 0.3, 0.5]);
}
