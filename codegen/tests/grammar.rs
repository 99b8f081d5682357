//! The chain description grammar: every setting, joint kind, number form, inertia form, trees
//! and their depth-first order, parameters, docs and visibility, through both entry points
//! (`.chain` text and the macro's token path).

use std::f64::consts::PI;
use std::path::Path;

use articulated_codegen::load::{load, parse_chain_str};
use articulated_codegen::lower::lower;
use articulated_codegen::model::{
    Axis, EulerSeq, JointKind, Model, Param, Placement, Value, DEFAULT_GRAVITY,
};
use articulated_codegen::options::{Description, Output, ScalarKind, Visibility};
use articulated_codegen::parse::ChainDef;
use quote::ToTokens;

const B: &str = "body a { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }";
const J: &str = "joint j: revolute(z) { parent: world, child: a }";

/// The description of a `.chain` text, its model checked.
fn describe(src: &str) -> Description {
    let d = parse_chain_str(src, Path::new("t.chain")).unwrap_or_else(|e| panic!("{e}"));
    d.model
        .check()
        .unwrap_or_else(|e| panic!("invalid model: {e}"));
    d
}

fn parse(src: &str) -> Model {
    describe(src).model
}

/// The description of a chain `C` with these items.
fn describe_chain(items: &[&str]) -> Description {
    describe(&format!("chain C {{\n{}\n}}\n", items.join("\n")))
}

fn chain(items: &[&str]) -> Model {
    describe_chain(items).model
}

fn c(x: f64) -> Value {
    Value::Const(x)
}

fn c3(v: [f64; 3]) -> [Value; 3] {
    v.map(Value::Const)
}

fn diag(a: f64, b: f64, d: f64) -> [[Value; 3]; 3] {
    [
        [c(a), c(0.0), c(0.0)],
        [c(0.0), c(b), c(0.0)],
        [c(0.0), c(0.0), c(d)],
    ]
}

/// The kind of the only joint, for a body `a` under `world` with the given kind.
fn kind(k: &str) -> JointKind {
    let m = chain(&[B, &format!("joint j: {k} {{ parent: world, child: a }}")]);
    m.joints[0].kind
}

#[test]
fn hemami_two_link_file() {
    let path = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/two_link.chain"
    ));
    let d = load(path, false).unwrap_or_else(|e| panic!("{e}"));
    let m = &d.model;
    m.check().unwrap();
    assert_eq!(m.name, "TwoLink");
    assert_eq!(d.options.visibility, Visibility::Public);
    assert_eq!(
        d.options.doc,
        vec![
            " Hemami's two-link system: legs on a spherical ankle, trunk on a spherical hip."
                .to_string()
        ]
    );
    assert_eq!(m.gravity, Some(c3([0.0, 0.0, -9.81])));
    assert_eq!(d.options.scalar, ScalarKind::F64);
    assert_eq!(d.options.outputs, Output::DEFAULT.to_vec());
    assert_eq!(
        m.params,
        vec![Param {
            name: "trunk_mass".into(),
            default: 40.0
        }]
    );
    let names: Vec<&str> = m.bodies.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names, ["legs", "trunk"]);
    assert_eq!(m.bodies[0].mass, c(30.0));
    assert_eq!(m.bodies[0].com, c3([0.0, 0.0, 0.45]));
    assert_eq!(m.bodies[0].inertia, diag(2.6, 2.5, 0.25));
    assert_eq!(m.bodies[1].mass, Value::Param(0));
    assert_eq!(m.bodies[1].com, c3([0.0, 0.0, 0.35]));
    assert_eq!(m.bodies[1].inertia, diag(1.6, 1.2, 0.45));
    assert_eq!(m.joints[0].name, "ankle");
    assert_eq!(
        m.joints[0].kind,
        JointKind::SphericalEuler { seq: EulerSeq::XYZ }
    );
    assert_eq!(m.joints[0].parent, None);
    assert_eq!(m.joints[0].placement, Placement::IDENTITY);
    assert_eq!(m.joints[1].name, "hip");
    assert_eq!(m.joints[1].parent, Some(0));
    assert_eq!(m.joints[1].placement.xyz, c3([0.0, 0.0, 0.9]));
    assert_eq!(m.joints[1].placement.rpy, c3([0.0; 3]));
    assert_eq!((m.nq(), m.nv()), (6, 6));
}

#[test]
fn the_macro_token_path_gives_the_same_model() {
    let path = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/two_link.chain"
    ));
    let from_file = load(path, false).unwrap();
    let tokens = quote::quote! {
        /// Hemami's two-link system: legs on a spherical ankle, trunk on a spherical hip.
        pub chain TwoLink {
            gravity: [0.0, 0.0, -9.81];
            scalar: f64;
            outputs: [mass_matrix, bias, gravity, inverse_dynamics, forward_dynamics];
            param trunk_mass = 40.0;
            body legs { mass: 30.0, com: [0.0, 0.0, 0.45], inertia: diag(2.6, 2.5, 0.25), }
            body trunk { mass: trunk_mass, com: [0.0, 0.0, 0.35], inertia: diag(1.6, 1.2, 0.45) }
            joint ankle: spherical(xyz) { parent: world, child: legs }
            joint hip: spherical(xyz) { parent: legs, child: trunk, xyz: [0.0, 0.0, 0.9], rpy: [0.0, 0.0, 0.0] }
        }
    };
    let def: ChainDef = syn::parse2(tokens).unwrap();
    assert_eq!(lower(&def).unwrap(), from_file);
    // Printing the syntax tree back and reparsing it changes nothing.
    let again: ChainDef = syn::parse2(def.to_token_stream()).unwrap();
    assert_eq!(lower(&again).unwrap(), from_file);
}

// ---- settings ----

#[test]
fn defaults_when_nothing_is_set() {
    let d = describe(&format!("chain C {{ {B} {J} }}"));
    let m = &d.model;
    assert_eq!(m.name, "C");
    assert_eq!(d.options.visibility, Visibility::Private);
    assert!(d.options.doc.is_empty());
    assert_eq!(m.gravity, Some(DEFAULT_GRAVITY));
    assert_eq!(d.options.scalar, ScalarKind::F64);
    assert_eq!(d.options.outputs, Output::DEFAULT.to_vec());
    assert!(m.params.is_empty());
    assert_eq!(m.bodies[0].com, c3([0.0; 3]));
    assert_eq!(m.joints[0].placement, Placement::IDENTITY);
}

#[test]
fn gravity_none_and_custom() {
    assert_eq!(chain(&["gravity: none;", B, J]).gravity, None);
    assert_eq!(
        chain(&["gravity: [0.0, -9.81, 0.0];", B, J]).gravity,
        Some(c3([0.0, -9.81, 0.0]))
    );
    let m = chain(&["param g = 1.62;", "gravity: [0.0, 0.0, g];", B, J]);
    assert_eq!(m.gravity, Some([c(0.0), c(0.0), Value::Param(0)]));
}

#[test]
fn scalars() {
    for (name, kind) in [
        ("f64", ScalarKind::F64),
        ("f32", ScalarKind::F32),
        ("generic", ScalarKind::Generic),
    ] {
        let d = describe_chain(&[&format!("scalar: {name};"), B, J]);
        assert_eq!(d.options.scalar, kind);
    }
}

#[test]
fn outputs_sorted_and_deduplicated() {
    let d = describe_chain(&["outputs: [gravity, mass_matrix, gravity, bias];", B, J]);
    assert_eq!(
        d.options.outputs,
        [Output::MassMatrix, Output::Bias, Output::Gravity]
    );
    let all: Vec<&str> = Output::ALL.iter().rev().map(|(_, n)| *n).collect();
    // The frame outputs compute the frames named: body `a`'s.
    let d = describe_chain(&[
        &format!("outputs: [{}];", all.join(", ")),
        "frames: [a];",
        B,
        J,
    ]);
    let want: Vec<Output> = Output::ALL.iter().map(|(o, _)| *o).collect();
    assert_eq!(d.options.outputs, want);
    assert!(describe_chain(&["outputs: [];", B, J])
        .options
        .outputs
        .is_empty());
}

/// A group's name in `outputs:` stands for its outputs (`articulated_codegen::outputs::Group`),
/// beside single outputs; the union is sorted and without duplicates.
#[test]
fn output_groups_expand_to_their_outputs() {
    use Output as O;
    let d = describe_chain(&["outputs: [derivatives, gravity, whole_body];", B, J]);
    assert_eq!(
        d.options.outputs,
        [
            O::Gravity,
            O::CenterOfMass,
            O::CenterOfMassVelocity,
            O::CenterOfMassJacobian,
            O::CentroidalMomentum,
            O::CentroidalMomentumMatrix,
            O::CentroidalMomentumRate,
            O::CentroidalMomentumDrift,
            O::KineticEnergy,
            O::PotentialEnergy,
            O::CoriolisMatrix,
            O::InverseDynamicsDerivatives,
            O::ForwardDynamicsDerivatives,
            O::MassMatrixInverse,
        ]
    );
    let d = describe_chain(&["outputs: [dynamics, mass_matrix, kept];", B, J]);
    assert_eq!(
        d.options.outputs,
        [
            O::MassMatrix,
            O::MassMatrixUpdate,
            O::MassMatrixLower,
            O::Bias,
            O::Gravity,
            O::InverseDynamics,
            O::ForwardDynamics,
            O::NonlinearEffects,
            O::MassMatrixAndNonlinearEffects,
        ]
    );
    // Every output but the serial chains' `joint_wrenches_bottom_up` is in exactly one group.
    let groups = "dynamics, kept, wrenches, whole_body, derivatives, frames";
    let d = describe_chain(&[&format!("outputs: [{groups}];"), "frames: [a];", B, J]);
    let want: Vec<Output> = Output::ALL
        .iter()
        .map(|(o, _)| *o)
        .filter(|&o| o != O::JointWrenchesBottomUp)
        .collect();
    assert_eq!(d.options.outputs, want);
}

// ---- joint kinds ----

#[test]
fn revolute_and_prismatic_axes() {
    for (arg, axis) in [
        ("x", [1.0, 0.0, 0.0]),
        ("y", [0.0, 1.0, 0.0]),
        ("z", [0.0, 0.0, 1.0]),
        ("[0.0, 3.0, 4.0]", [0.0, 0.6, 0.8]),
        ("[-2, 0, 0]", [-1.0, 0.0, 0.0]),
        ("-y", [0.0, -1.0, 0.0]),
    ] {
        assert_eq!(
            kind(&format!("revolute({arg})")),
            JointKind::Revolute { axis },
            "{arg}"
        );
        assert_eq!(
            kind(&format!("prismatic({arg})")),
            JointKind::Prismatic { axis },
            "{arg}"
        );
    }
}

#[test]
fn spherical_every_sequence_and_quaternion() {
    let seqs = [
        "xyz", "xzy", "yxz", "yzx", "zxy", "zyx", "xyx", "xzx", "yxy", "yzy", "zxz", "zyz",
    ];
    for s in seqs {
        let seq = EulerSeq::parse(s).unwrap();
        assert_eq!(
            kind(&format!("spherical({s})")),
            JointKind::SphericalEuler { seq }
        );
        assert_eq!(kind(&format!("free({s})")), JointKind::FreeEuler { seq });
    }
    assert_eq!(
        kind("spherical(xyz)"),
        JointKind::SphericalEuler {
            seq: EulerSeq([Axis::X, Axis::Y, Axis::Z])
        }
    );
    assert_eq!(
        kind("spherical(quaternion)"),
        JointKind::SphericalQuaternion
    );
}

#[test]
fn free_and_fixed() {
    // Wieber's form: `free` is `free(zyx)`.
    assert_eq!(kind("free"), JointKind::FreeEuler { seq: EulerSeq::ZYX });
    assert_eq!(kind("free(quaternion)"), JointKind::FreeQuaternion);
    assert_eq!(kind("fixed"), JointKind::Fixed);
    let m = chain(&[B, "joint j: free(quaternion) { parent: world, child: a }"]);
    assert_eq!((m.nq(), m.nv()), (7, 6));
}

// ---- trees ----

#[test]
fn depth_first_order_children_in_declaration_order() {
    // world ─ jc → c
    //       └ ja → a ─ jb → b ─ je → e
    //                └ jd → d
    // Declared out of order; bodies declared alphabetically.
    let body = |n: &str| format!("body {n} {{ mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }}");
    let (a, b, c_, d, e) = (body("a"), body("b"), body("c"), body("d"), body("e"));
    let m = chain(&[
        &a,
        &b,
        &c_,
        &d,
        &e,
        "joint jb: revolute(x) { parent: a, child: b }",
        "joint jc: revolute(y) { parent: world, child: c }",
        "joint jd: revolute(z) { parent: a, child: d }",
        "joint ja: revolute(x) { parent: world, child: a }",
        "joint je: fixed { parent: b, child: e }",
    ]);
    let bodies: Vec<&str> = m.bodies.iter().map(|b| b.name.as_str()).collect();
    let joints: Vec<&str> = m.joints.iter().map(|j| j.name.as_str()).collect();
    let parents: Vec<Option<usize>> = m.joints.iter().map(|j| j.parent).collect();
    assert_eq!(bodies, ["c", "a", "b", "e", "d"]);
    assert_eq!(joints, ["jc", "ja", "jb", "je", "jd"]);
    assert_eq!(parents, [None, None, Some(1), Some(2), Some(1)]);
    assert_eq!(m.nq(), 4);
}

#[test]
fn items_in_any_order() {
    let d = describe_chain(&[
        J,
        "joint k: revolute(x) { parent: a, child: b }",
        "body b { mass: m, inertia: diag(1.0, 1.0, 1.0) }",
        "outputs: [bias];",
        B,
        "param m = 2.0;",
    ]);
    let m = &d.model;
    assert_eq!(m.bodies[1].mass, Value::Param(0));
    assert_eq!(d.options.outputs, [Output::Bias]);
    assert_eq!(m.joints[1].parent, Some(0));
}

#[test]
fn massless_bodies_fixed_to_the_world() {
    // `base` and `plate` do not move: they may be massless (zero inertia too); `arm` moves.
    let m = chain(&[
        "body base { mass: 0.0, inertia: diag(0.0, 0.0, 0.0) }",
        "body plate { mass: 0, inertia: [[0, 0, 0], [0, 0, 0], [0, 0, 0]] }",
        "body arm { mass: 1.0, inertia: diag(0.1, 0.1, 0.01) }",
        "joint weld: fixed { parent: world, child: base }",
        "joint bolt: fixed { parent: base, child: plate }",
        "joint shoulder: revolute(y) { parent: plate, child: arm }",
    ]);
    assert_eq!(m.bodies[0].mass, c(0.0));
    assert_eq!(m.nq(), 1);
}

// ---- numbers and parameters ----

#[test]
fn constant_folding() {
    let m = chain(&[
        B,
        "joint j: revolute(z) { parent: world, child: a, \
         xyz: [1 - 2 - 3, -(1.0 + 2.0) * 3.0, 2 * 3 - 4 / 8], \
         rpy: [pi, pi / 2.0, -pi / 4 * 2] }",
    ]);
    let p = m.joints[0].placement;
    assert_eq!(p.xyz, c3([-4.0, -9.0, 5.5]));
    assert_eq!(p.rpy, c3([PI, PI / 2.0, -PI / 2.0]));
    let m = chain(&[
        "body a { mass: 1_000, com: [1e-3, 2.5E2, 0x10], inertia: diag((1), ((2.0)), -(-3)) }",
        J,
    ]);
    assert_eq!(m.bodies[0].mass, c(1000.0));
    assert_eq!(m.bodies[0].com, c3([1e-3, 250.0, 16.0]));
    assert_eq!(m.bodies[0].inertia, diag(1.0, 2.0, 3.0));
}

#[test]
fn parameters_wherever_a_number_stands() {
    let m = chain(&[
        "param mass = 2.0;",
        "param l = 0.5;",
        "param ixx = 0.1;",
        "param ixy = 0.01;",
        "param q0 = 0.3;",
        "body a { mass: mass, com: [0.0, 0.0, l], \
         inertia: [[ixx, ixy, 0.0], [ixy, 0.1, 0.0], [0.0, 0.0, 0.1]] }",
        "body b { mass: 1.0, inertia: diag(ixx, ixx, ixx) }",
        J,
        "joint k: revolute(x) { parent: a, child: b, xyz: [l, 0.0, 0.0], rpy: [q0, 0.0, 0.0] }",
    ]);
    let names: Vec<&str> = m.params.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["mass", "l", "ixx", "ixy", "q0"]);
    assert_eq!(m.param_defaults(), [2.0, 0.5, 0.1, 0.01, 0.3]);
    let p = Value::Param;
    assert_eq!(m.bodies[0].mass, p(0));
    assert_eq!(m.bodies[0].com, [c(0.0), c(0.0), p(1)]);
    assert_eq!(m.bodies[0].inertia[0], [p(2), p(3), c(0.0)]);
    assert_eq!(m.bodies[0].inertia[1], [p(3), c(0.1), c(0.0)]);
    assert_eq!(m.bodies[1].inertia, {
        let mut i = diag(0.0, 0.0, 0.0);
        (0..3).for_each(|k| i[k][k] = p(2));
        i
    });
    assert_eq!(m.joints[1].placement.xyz, [p(1), c(0.0), c(0.0)]);
    assert_eq!(m.joints[1].placement.rpy, [p(4), c(0.0), c(0.0)]);
}

#[test]
fn parameter_defaults_fold() {
    let m = chain(&["param half_pi = pi / 2;", B, J]);
    assert_eq!(m.param_defaults(), [PI / 2.0]);
}

// ---- inertia ----

#[test]
fn inertia_forms() {
    let m = chain(&["body a { mass: 1.0, inertia: diag(2.6, 2.5, 0.25) }", J]);
    assert_eq!(m.bodies[0].inertia, diag(2.6, 2.5, 0.25));
    let m = chain(&[
        "body a { mass: 1.0, inertia: [[2.0, -0.5, 0.1], [-0.5, 2.0, 0.2], [0.1, 0.2, 3.0]] }",
        J,
    ]);
    assert_eq!(
        m.bodies[0].inertia,
        [
            [c(2.0), c(-0.5), c(0.1)],
            [c(-0.5), c(2.0), c(0.2)],
            [c(0.1), c(0.2), c(3.0)],
        ]
    );
    // A thin plate: Izz = Ixx + Iyy exactly, on the edge of the triangle inequality.
    chain(&["body a { mass: 1.0, inertia: diag(0.1, 0.2, 0.3) }", J]);
}

// ---- docs, visibility, punctuation ----

#[test]
fn docs_and_visibility() {
    let d = describe(&format!(
        "/// First line.\n///\n/// Third, after a blank.\n#[doc = \"attribute form\"]\n\
         pub(crate) chain V {{ {B} {J} }}"
    ));
    assert_eq!(
        d.options.doc,
        [
            " First line.",
            "",
            " Third, after a blank.",
            "attribute form"
        ]
    );
    assert_eq!(d.options.visibility.to_string(), "pub(crate)");
    for vis in ["", "pub", "pub(super)", "pub(in crate::robots)"] {
        let d = describe(&format!("{vis} chain V {{ {B} {J} }}"));
        assert_eq!(d.options.visibility.to_string(), vis);
    }
}

#[test]
fn doc_comments_on_items_are_accepted() {
    let d = describe_chain(&[
        "/// Standard gravity.",
        "gravity: [0.0, 0.0, -9.81];",
        "/// The payload.",
        "param m = 1.0;",
        "/// The only body.",
        "body a { mass: m, inertia: diag(1.0, 1.0, 1.0) }",
        "/** The only joint. */",
        J,
    ]);
    assert!(d.options.doc.is_empty());
    assert_eq!(d.model.nb(), 1);
}

#[test]
fn optional_punctuation_and_comments() {
    let m = parse(
        "chain P {
            // line comment
            body a { mass: 1.0, inertia: diag(1.0, 1.0, 1.0), };
            /* block comment */
            joint j: revolute(z) { parent: world, child: a, };
            body b { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }
            joint k: revolute(z) { parent: a, child: b }
        };",
    );
    assert_eq!(m.nb(), 2);
}
