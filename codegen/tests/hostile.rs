//! Valid but hostile models (issue 14): the generator finishes in bounded time and memory on
//! each, with code that agrees with the reference, or refuses with a message naming the limit.

use std::path::Path;

use articulated_codegen::generate::{generate, MAX_NV};
use articulated_codegen::load::parse_chain_str;
use articulated_codegen::options::{Description, Output};
use articulated_codegen::sym::Var;
use articulated_codegen::trace::trace;
use articulated_dynamics::model::{Body, Joint};
use articulated_dynamics::random::random_state;
use articulated_dynamics::reference::Reference;

fn chain(text: &str) -> Description {
    parse_chain_str(text, Path::new("hostile.chain")).unwrap_or_else(|e| panic!("{e}"))
}

/// `n` links in series, axes x, y, z in turn.
fn serial(n: usize) -> String {
    let mut s = String::from("chain Serial {\n");
    for i in 0..n {
        s += &format!(
            "body b{i} {{ mass: 1.0, com: [0.0, 0.0, 0.05], inertia: diag(0.01, 0.01, 0.005) }}\n"
        );
    }
    for i in 0..n {
        let parent = if i == 0 {
            "world".to_string()
        } else {
            format!("b{}", i - 1)
        };
        let axis = ["x", "y", "z"][i % 3];
        s += &format!(
            "joint j{i}: revolute({axis}) {{ parent: {parent}, child: b{i}, xyz: [0.0, 0.0, 0.1] }}\n"
        );
    }
    s + "}\n"
}

/// The generator's expression graphs against the reference at three random states: `M` and
/// inverse dynamics.
fn agrees_with_reference(d: &Description) {
    let r = Reference::new(&d.model).unwrap();
    for seed in 0..3 {
        let (q, v, a) = random_state(&d.model, seed);
        let input = |var: Var| match var {
            Var::Q(i) => q[i],
            Var::V(i) => v[i],
            Var::A(i) => a[i],
            _ => 0.0,
        };
        let (m, _) = trace(&d.model, Output::MassMatrix).eval(input);
        let want = r.mass_matrix(&q).unwrap();
        let n = d.model.nv();
        let scale = want.amax().max(1.0);
        for i in 0..n {
            for j in 0..n {
                assert!((m[i * n + j] - want[(i, j)]).abs() < 1e-12 * scale);
            }
        }
        let (tau, _) = trace(&d.model, Output::InverseDynamics).eval(input);
        let want = r.inverse_dynamics(&q, &v, &a).unwrap();
        let scale = want.amax().max(1.0);
        assert!(tau
            .iter()
            .zip(want.iter())
            .all(|(x, y)| (x - y).abs() < 1e-11 * scale));
    }
}

/// Refused by the check stage, at the chain's name, before anything is traced; and by the
/// generator, at the call site, for a model a program built.
#[test]
fn a_deep_chain_past_the_limit_is_refused_naming_it() {
    let text = serial(MAX_NV + 40);
    let Err(e) = parse_chain_str(&text, Path::new("hostile.chain")) else {
        panic!("expected a refusal");
    };
    let [d] = &e.diagnostics[..] else {
        panic!("expected one error: {e}");
    };
    assert_eq!((d.line, d.column), (1, 7), "{e}");
    assert!(
        d.message.contains("200 velocity coordinates")
            && d.message.contains(&format!("limit of {MAX_NV}")),
        "{e}"
    );
    let smaller = chain(&serial(MAX_NV));
    let mut model = smaller.model.clone();
    let extra = model.joints.last().cloned().unwrap();
    let body = model.bodies.last().cloned().unwrap();
    model.joints.push(Joint {
        name: "one_more".into(),
        parent: Some(model.nb() - 1),
        ..extra
    });
    model.bodies.push(Body {
        name: "b_more".into(),
        ..body
    });
    let Err(e) = generate(&model, &smaller.options) else {
        panic!("expected a refusal");
    };
    assert!(e.to_string().contains("161 velocity coordinates"), "{e}");
}

#[test]
fn a_wide_tree_generates_and_agrees() {
    let mut s =
        String::from("chain Wide {\nbody hub { mass: 1.0, inertia: diag(0.1, 0.1, 0.1) }\n");
    for i in 0..100 {
        s += &format!(
            "body leaf{i} {{ mass: 0.1, com: [0.05, 0.0, 0.0], inertia: diag(0.001, 0.001, 0.001) }}\n"
        );
    }
    s += "joint base: revolute(z) { parent: world, child: hub }\n";
    for i in 0..100 {
        s += &format!("joint j{i}: revolute(y) {{ parent: hub, child: leaf{i} }}\n");
    }
    let d = chain(&(s + "}\n"));
    generate(&d.model, &d.options).unwrap_or_else(|e| panic!("{e}"));
    agrees_with_reference(&d);
}

#[test]
fn zero_length_links_and_coincident_joints_generate_and_agree() {
    let d = chain(
        "chain Coincident {
            body a { mass: 1.0, inertia: diag(0.1, 0.1, 0.1) }
            body b { mass: 1.0, inertia: diag(0.1, 0.1, 0.1) }
            body c { mass: 1.0, com: [0.0, 0.0, 0.3], inertia: diag(0.1, 0.1, 0.1) }
            joint j1: revolute(z) { parent: world, child: a }
            joint j2: revolute(z) { parent: a, child: b }
            joint j3: revolute(x) { parent: b, child: c }
        }",
    );
    generate(&d.model, &d.options).unwrap_or_else(|e| panic!("{e}"));
    agrees_with_reference(&d);
}

#[test]
fn numbers_that_overflow_f64_are_refused() {
    let d = chain(
        "chain Edge {
            body a { mass: 1e300, com: [0.0, 0.0, 1e10], inertia: diag(1e300, 1e300, 1e300) }
            joint j1: revolute(y) { parent: world, child: a }
        }",
    );
    let Err(e) = generate(&d.model, &d.options) else {
        panic!("expected a refusal");
    };
    let e = e.to_string();
    assert!(
        e.contains("overflows f64") && e.contains("`mass_matrix`"),
        "{e}"
    );
    // At the other edge, tiny but representable numbers generate.
    let d = chain(
        "chain Tiny {
            body a { mass: 1e-30, com: [0.0, 0.0, 1e-10], inertia: diag(1e-50, 1e-50, 1e-50) }
            joint j1: revolute(y) { parent: world, child: a }
        }",
    );
    generate(&d.model, &d.options).unwrap_or_else(|e| panic!("{e}"));
}

/// A model built by a program rather than a front end is checked before anything is traced: a
/// mimic joint naming a joint that does not exist is refused with its name, not a panic.
#[test]
fn a_program_built_model_is_checked_before_it_is_generated() {
    let mut d = chain(&serial(3));
    d.model.joints[2].mimic = Some(articulated_dynamics::model::Mimic {
        joint: 7,
        multiplier: 1.0,
        offset: 0.0,
    });
    let Err(e) = generate(&d.model, &d.options) else {
        panic!("expected a refusal");
    };
    let e = e.to_string();
    assert!(
        e.contains("the model `Serial` is invalid") && e.contains("joint `j2`"),
        "{e}"
    );
}
