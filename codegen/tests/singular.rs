//! `trace::singular_everywhere`: the generator's finding that a model's `M(q)` is singular at
//! every configuration, which makes generated forward dynamics, `M⁻¹` and their derivatives
//! refuse every state (`tests/tests/generated_pivots.rs` checks the generated code). Every
//! shipped model is regular (a URDF on a free base where its root has mass); a free base over a massless root body whose rotation duplicates
//! the first joint's is not, with either base, and neither is a joint that moves no mass.

use std::path::Path;

use articulated_codegen::load::load_model;
use articulated_codegen::trace::singular_everywhere;
use articulated_codegen::urdf::{from_urdf_str, FloatingBase};

fn path(rel: &str) -> String {
    format!("{}/../{rel}", env!("CARGO_MANIFEST_DIR"))
}

/// Whether the URDF's first link (the root in the shipped files) has an `<inertial>`.
fn massive_root(p: &Path) -> bool {
    let text = std::fs::read_to_string(p).unwrap();
    let first = &text[text.find("<link").unwrap()..];
    let end = first.find("</link>").unwrap_or(0);
    first[..end].contains("<inertial>") && !first[..first.find('>').unwrap()].ends_with('/')
}

#[test]
fn shipped_models_are_regular() {
    let dir = path("models");
    let mut seen = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let p = entry.unwrap().path();
        let floatings: &[FloatingBase] = match p.extension().and_then(|e| e.to_str()) {
            Some("chain") => &[FloatingBase::Fixed],
            // A URDF root carries its inertial onto a free base; on a fixed one it is the world.
            Some("urdf") if massive_root(&p) => &[
                FloatingBase::Fixed,
                FloatingBase::Euler,
                FloatingBase::Quaternion,
            ],
            Some("urdf") => &[FloatingBase::Fixed],
            _ => continue,
        };
        for &f in floatings {
            let model = load_model(&p, f).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(singular_everywhere(&model), None, "{} ({f:?})", p.display());
            seen += 1;
        }
    }
    assert!(seen >= 20, "only {seen} models");
}

#[test]
fn massless_roots_under_a_free_base_are_singular() {
    for (file, fixed_ok) in [
        ("tests/data/pinocchio/arm6_mixed.urdf", true),
        ("tests/data/pinocchio/two_link_xyz.urdf", true),
        ("models/tree.urdf", true),
    ] {
        let p = path(file);
        let fixed = load_model(Path::new(&p), FloatingBase::Fixed).unwrap();
        assert_eq!(
            singular_everywhere(&fixed).is_none(),
            fixed_ok,
            "{file} fixed"
        );
        for f in [FloatingBase::Euler, FloatingBase::Quaternion] {
            let model = load_model(Path::new(&p), f).unwrap();
            assert!(singular_everywhere(&model).is_some(), "{file} ({f:?})");
        }
    }
}

#[test]
fn a_joint_that_moves_no_mass_is_singular() {
    // `tip` has no inertial: the elbow moves nothing. Give the tip a mass and the model is
    // regular again (the same text otherwise, so that the finding is not a parse artefact).
    let text = |tip: &str| {
        format!(
            r#"<robot name="arm">
  <link name="base"/>
  <link name="upper"><inertial><origin xyz="0 0 -0.5"/><mass value="1.0"/>
    <inertia ixx="0.1" iyy="0.1" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="tip">{tip}</link>
  <joint name="shoulder" type="continuous"><parent link="base"/><child link="upper"/>
    <axis xyz="0 1 0"/></joint>
  <joint name="elbow" type="continuous"><parent link="upper"/><child link="tip"/>
    <origin xyz="0 0 -1"/><axis xyz="0 1 0"/></joint>
</robot>"#
        )
    };
    let model = |tip: &str| {
        from_urdf_str(&text(tip), FloatingBase::Fixed)
            .unwrap_or_else(|e| panic!("{e}"))
            .model
    };
    assert_eq!(singular_everywhere(&model("")), Some(1));
    let massive = model(
        r#"<inertial><origin xyz="0 0 -0.1"/><mass value="0.2"/>
    <inertia ixx="0.001" iyy="0.001" izz="0.0001" ixy="0" ixz="0" iyz="0"/></inertial>"#,
    );
    assert_eq!(singular_everywhere(&massive), None);
}
