//! URDF import: frames, rotated inertials, fixed-joint merging, order, joint kinds and errors,
//! each checked against numbers worked out by hand.

use std::f64::consts::FRAC_PI_2;
use std::path::Path;

use articulated_codegen::load::{load, load_model};
use articulated_codegen::model::{Drive, EulerSeq, JointKind, Model, Value};
use articulated_codegen::options::{Output, Visibility};
use articulated_codegen::urdf::{from_urdf_str, FloatingBase, UrdfError};
use articulated_dynamics::random::Rng;

fn c(v: &Value) -> f64 {
    v.as_const().expect("a constant")
}
fn c3(v: &[Value; 3]) -> [f64; 3] {
    v.map(|x| c(&x))
}
fn c33(m: &[[Value; 3]; 3]) -> [[f64; 3]; 3] {
    m.map(|r| c3(&r))
}

fn close3(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
    a.iter().zip(&b).all(|(x, y)| (x - y).abs() <= tol)
}
fn assert_close33(a: [[f64; 3]; 3], b: [[f64; 3]; 3], tol: f64) {
    for i in 0..3 {
        assert!(close3(a[i], b[i], tol), "\n{a:?}\n!=\n{b:?}");
    }
}

fn robot(body: &str) -> String {
    format!("<?xml version=\"1.0\"?>\n<robot name=\"test_robot\">\n{body}\n</robot>\n")
}

fn inertial(m: f64, xyz: &str, rpy: &str, i: [f64; 6]) -> String {
    format!(
        "<inertial><origin xyz=\"{xyz}\" rpy=\"{rpy}\"/><mass value=\"{m}\"/>\
         <inertia ixx=\"{}\" ixy=\"{}\" ixz=\"{}\" iyy=\"{}\" iyz=\"{}\" izz=\"{}\"/></inertial>",
        i[0], i[1], i[2], i[3], i[4], i[5]
    )
}

/// One link `l1` with the given inertial on a revolute joint about z under a massless base.
fn one_link(inertial: &str) -> Model {
    let xml = robot(&format!(
        "<link name=\"base\"/>\n<link name=\"l1\">{inertial}</link>\n\
         <joint name=\"j1\" type=\"revolute\"><parent link=\"base\"/><child link=\"l1\"/>\
         <axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>"
    ));
    from_urdf_str(&xml, false).expect("valid URDF").model
}

fn err(xml: &str) -> UrdfError {
    match from_urdf_str(xml, false) {
        Ok(_) => panic!("expected an error for\n{xml}"),
        Err(e) => e,
    }
}

#[test]
fn inertials_are_read_not_zeros() {
    // One version of the urdf crate read every inertial as zeros: check ours reads them.
    let m = one_link(&inertial(
        2.5,
        "0.1 -0.2 0.3",
        "0 0 0",
        [0.21, 0.012, -0.013, 0.22, 0.023, 0.33],
    ));
    let b = &m.bodies[0];
    assert_eq!(b.name, "l1");
    assert_eq!(c(&b.mass), 2.5);
    assert_eq!(c3(&b.com), [0.1, -0.2, 0.3]);
    assert_eq!(
        c33(&b.inertia),
        [
            [0.21, 0.012, -0.013],
            [0.012, 0.22, 0.023],
            [-0.013, 0.023, 0.33]
        ]
    );
}

#[test]
fn inertial_rotated_90_degrees_about_z_swaps_ixx_and_iyy() {
    // R = Rz(90°) = [[0,-1,0],[1,0,0],[0,0,1]]. With I = [[a,d,e],[d,b,f],[e,f,c]], by hand:
    // R·I = [[-d,-b,-f],[a,d,e],[e,f,c]], and (R·I)·Rᵀ = [[b,-d,-f],[-d,a,e],[-f,e,c]].
    // A physical tensor (principal moments within the triangle inequality), all entries distinct.
    let (a, b, cc, d, e, f) = (0.2, 0.25, 0.3, 0.01, 0.02, 0.03);
    let m = one_link(&inertial(
        1.0,
        "0 0 0",
        &format!("0 0 {FRAC_PI_2}"),
        [a, d, e, b, f, cc],
    ));
    let expected = [[b, -d, -f], [-d, a, e], [-f, e, cc]];
    assert_close33(c33(&m.bodies[0].inertia), expected, 1e-16);
    // The centre of mass is the inertial origin's xyz, not rotated by its own rpy.
    let m = one_link(&inertial(
        1.0,
        "0.5 0 0",
        &format!("0 0 {FRAC_PI_2}"),
        [a, d, e, b, f, cc],
    ));
    assert_eq!(c3(&m.bodies[0].com), [0.5, 0.0, 0.0]);
}

type M3 = [[f64; 3]; 3];
fn matmul(a: &M3, b: &M3) -> M3 {
    let mut r = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                r[i][j] += a[i][k] * b[k][j];
            }
        }
    }
    r
}
fn tr(a: &M3) -> M3 {
    let mut r = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            r[i][j] = a[j][i];
        }
    }
    r
}
fn rx(t: f64) -> M3 {
    [
        [1.0, 0.0, 0.0],
        [0.0, t.cos(), -t.sin()],
        [0.0, t.sin(), t.cos()],
    ]
}
fn ry(t: f64) -> M3 {
    [
        [t.cos(), 0.0, t.sin()],
        [0.0, 1.0, 0.0],
        [-t.sin(), 0.0, t.cos()],
    ]
}
fn rz(t: f64) -> M3 {
    [
        [t.cos(), -t.sin(), 0.0],
        [t.sin(), t.cos(), 0.0],
        [0.0, 0.0, 1.0],
    ]
}

#[test]
fn inertial_in_a_general_rotated_frame_is_r_i_rt() {
    let (r, p, y) = (0.3, -0.5, 1.1);
    let i = [
        [0.21, 0.012, -0.013],
        [0.012, 0.25, 0.023],
        [-0.013, 0.023, 0.33],
    ];
    let m = one_link(&inertial(
        3.0,
        "0.01 0.02 0.03",
        &format!("{r} {p} {y}"),
        [i[0][0], i[0][1], i[0][2], i[1][1], i[1][2], i[2][2]],
    ));
    // Independently: R = Rz(y)·Ry(p)·Rx(r) as products of elementary rotations.
    let rot = matmul(&matmul(&rz(y), &ry(p)), &rx(r));
    let expected = matmul(&matmul(&rot, &i), &tr(&rot));
    assert_close33(c33(&m.bodies[0].inertia), expected, 1e-15);
    // Not the transpose convention Rᵀ·I·R (the classic importer bug).
    let wrong = matmul(&matmul(&tr(&rot), &i), &rot);
    let diff: f64 = (0..9)
        .map(|k| (wrong[k / 3][k % 3] - expected[k / 3][k % 3]).abs())
        .sum();
    assert!(diff > 1e-3);
    assert_eq!(c3(&m.bodies[0].com), [0.01, 0.02, 0.03]);
}

#[test]
fn fixed_joint_is_merged_into_its_parent_by_hand() {
    // P: mass 2 at its origin, I = 0.1·E. C on a fixed joint at (1, 0, 0), rotated 90° about z,
    // mass 2 with its centre of mass at (0.2, 0, 0) and I = diag(0.01, 0.02, 0.03) in C.
    // In P: C's com = (1, 0, 0) + Rz(90°)·(0.2, 0, 0) = (1, 0.2, 0), its inertia diag(0.02, 0.01,
    // 0.03). Total: m = 4, com = (0.5, 0.1, 0). Offsets ±(0.5, 0.1, 0), |d|² = 0.26, each
    // m(|d|²E − ddᵀ) = 2·[[0.01, −0.05, 0], [−0.05, 0.25, 0], [0, 0, 0.26]], twice:
    // [[0.04, −0.2, 0], [−0.2, 1.0, 0], [0, 0, 1.04]]. I = [[0.16, −0.2, 0], [−0.2, 1.11, 0],
    // [0, 0, 1.17]].
    let xml = robot(&format!(
        r#"<link name="base"/>
<link name="p">{}</link>
<link name="c">{}</link>
<link name="d">{}</link>
<joint name="jp" type="revolute"><parent link="base"/><child link="p"/><axis xyz="0 1 0"/></joint>
<joint name="weld" type="fixed"><parent link="p"/><child link="c"/><origin xyz="1 0 0" rpy="0 0 {FRAC_PI_2}"/></joint>
<joint name="jd" type="revolute"><parent link="c"/><child link="d"/><origin xyz="0 0 0.5"/><axis xyz="1 0 0"/></joint>"#,
        inertial(2.0, "0 0 0", "0 0 0", [0.1, 0.0, 0.0, 0.1, 0.0, 0.1]),
        inertial(2.0, "0.2 0 0", "0 0 0", [0.01, 0.0, 0.0, 0.02, 0.0, 0.03]),
        inertial(1.0, "0 0 0", "0 0 0", [0.1, 0.0, 0.0, 0.1, 0.0, 0.1]),
    ));
    let m = from_urdf_str(&xml, false).unwrap().model;
    assert_eq!(m.nb(), 2);
    assert_eq!(m.bodies[0].name, "p");
    let p = &m.bodies[0];
    assert!((c(&p.mass) - 4.0).abs() < 1e-15);
    assert!(close3(c3(&p.com), [0.5, 0.1, 0.0], 1e-15));
    assert_close33(
        c33(&p.inertia),
        [[0.16, -0.2, 0.0], [-0.2, 1.11, 0.0], [0.0, 0.0, 1.17]],
        1e-14,
    );
    // The joint below the welded link hangs from `p`, its frame composed: (1, 0, 0) +
    // Rz(90°)·(0, 0, 0.5) = (1, 0, 0.5), rotated 90° about z.
    let jd = &m.joints[1];
    assert_eq!(jd.name, "jd");
    assert_eq!(jd.parent, Some(0));
    assert!(close3(c3(&jd.placement.xyz), [1.0, 0.0, 0.5], 1e-15));
    assert!(close3(c3(&jd.placement.rpy), [0.0, 0.0, FRAC_PI_2], 1e-15));
    assert_eq!(
        jd.kind,
        JointKind::Revolute {
            axis: [1.0, 0.0, 0.0]
        }
    );
}

#[test]
fn joints_in_depth_first_order_children_in_document_order() {
    // Document order of the joints is not depth-first: jb, ja1, ja, jb1.
    let xml = robot(
        r#"<link name="base"/><link name="a"/><link name="b"/><link name="a1"/><link name="b1"/>
<joint name="jb" type="revolute"><parent link="base"/><child link="b"/></joint>
<joint name="ja1" type="revolute"><parent link="a"/><child link="a1"/></joint>
<joint name="ja" type="revolute"><parent link="base"/><child link="a"/></joint>
<joint name="jb1" type="revolute"><parent link="b"/><child link="b1"/></joint>"#,
    );
    let m = from_urdf_str(&xml, false).unwrap().model;
    let names: Vec<&str> = m.joints.iter().map(|j| j.name.as_str()).collect();
    assert_eq!(names, ["jb", "jb1", "ja", "ja1"]);
    let bodies: Vec<&str> = m.bodies.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(bodies, ["b", "b1", "a", "a1"]);
    let parents: Vec<Option<usize>> = m.joints.iter().map(|j| j.parent).collect();
    assert_eq!(parents, [None, Some(0), None, Some(2)]);
    // Links without an inertial are massless.
    assert_eq!(c(&m.bodies[0].mass), 0.0);
    assert_eq!(c33(&m.bodies[0].inertia), [[0.0; 3]; 3]);
    // URDF's default axis is x.
    assert_eq!(
        m.joints[0].kind,
        JointKind::Revolute {
            axis: [1.0, 0.0, 0.0]
        }
    );
}

#[test]
fn continuous_and_prismatic_axes_normalized_and_model_defaults() {
    let xml = r#"<robot name="my-little_robot2">
<link name="base"/><link name="a"/><link name="b"/>
<joint name="spin" type="continuous"><parent link="base"/><child link="a"/>
  <origin xyz="0.1 0.2 0.3" rpy="0.4 0.5 0.6"/><axis xyz="0 0 2"/></joint>
<joint name="slide" type="prismatic"><parent link="a"/><child link="b"/><axis xyz="3 4 0"/></joint>
</robot>"#;
    let d = from_urdf_str(xml, false).unwrap();
    let m = &d.model;
    assert_eq!(m.name, "MyLittleRobot2");
    assert_eq!(d.options.visibility, Visibility::Public);
    assert_eq!(m.gravity.map(|g| c3(&g)), Some([0.0, 0.0, -9.81]));
    assert_eq!(d.options.outputs, Output::DEFAULT.to_vec());
    assert_eq!((m.nq(), m.nv()), (2, 2));
    assert_eq!(
        m.joints[0].kind,
        JointKind::Revolute {
            axis: [0.0, 0.0, 1.0]
        }
    );
    assert_eq!(c3(&m.joints[0].placement.xyz), [0.1, 0.2, 0.3]);
    assert_eq!(c3(&m.joints[0].placement.rpy), [0.4, 0.5, 0.6]);
    assert_eq!(
        m.joints[1].kind,
        JointKind::Prismatic {
            axis: [0.6, 0.8, 0.0]
        }
    );
    assert_eq!(m.joints[1].parent, Some(0));
}

#[test]
fn floating_base_keeps_the_root_and_comes_first() {
    let xml = robot(&format!(
        r#"<link name="torso">{}</link><link name="arm"/>
<joint name="shoulder" type="revolute"><parent link="torso"/><child link="arm"/><axis xyz="0 1 0"/></joint>"#,
        inertial(7.0, "0 0 0.1", "0 0 0", [1.0, 0.0, 0.0, 2.0, 0.0, 3.0])
    ));
    let fixed = from_urdf_str(&xml, false).unwrap().model;
    assert_eq!(fixed.nb(), 1);
    assert_eq!(fixed.joints[0].parent, None);
    let m = from_urdf_str(&xml, true).unwrap().model;
    assert_eq!(m.nb(), 2);
    assert_eq!((m.nq(), m.nv()), (7, 7));
    assert_eq!(
        m.joints[0].kind,
        JointKind::FreeEuler { seq: EulerSeq::ZYX }
    );
    assert_eq!(m.joints[0].parent, None);
    assert_eq!(c3(&m.joints[0].placement.xyz), [0.0; 3]);
    assert_eq!(c3(&m.joints[0].placement.rpy), [0.0; 3]);
    assert_eq!(m.bodies[0].name, "torso");
    assert_eq!(c(&m.bodies[0].mass), 7.0);
    assert_eq!(c3(&m.bodies[0].com), [0.0, 0.0, 0.1]);
    assert_eq!(m.joints[1].parent, Some(0));
    assert_eq!(m.q_offset(1), 6);

    // A URDF `floating` joint is a free Euler zyx joint too.
    let xml = robot(
        r#"<link name="world"/><link name="box"/>
<joint name="free" type="floating"><parent link="world"/><child link="box"/><origin xyz="0 0 1"/></joint>"#,
    );
    let m = from_urdf_str(&xml, false).unwrap().model;
    assert_eq!(
        m.joints[0].kind,
        JointKind::FreeEuler { seq: EulerSeq::ZYX }
    );
    assert_eq!(c3(&m.joints[0].placement.xyz), [0.0, 0.0, 1.0]);
}

/// A two-link chain with `extra` spliced in; the line numbers below count from `<robot>` = 2.
fn chain_with(extra: &str) -> String {
    robot(&format!(
        "<link name=\"base\"/>\n<link name=\"a\"/>\n\
         <joint name=\"ja\" type=\"revolute\"><parent link=\"base\"/><child link=\"a\"/></joint>\n{extra}"
    ))
}

#[test]
fn errors_name_the_problem_and_the_line() {
    let cases: &[(&str, usize, &str)] = &[
        (
            r#"<joint name="jx" type="revolute"><parent link="a"/><child link="ghost"/></joint>"#,
            6,
            "child link `ghost` is not defined",
        ),
        (
            r#"<joint name="jx" type="revolute"><parent link="nowhere"/><child link="a"/></joint>"#,
            6,
            "parent link `nowhere` is not defined",
        ),
        (
            "<joint name=\"jb\" type=\"revolute\"><parent link=\"base\"/><child link=\"a\"/></joint>",
            6,
            "link `a` has two parents: it is already the child of joint `ja`",
        ),
        ("<link name=\"lonely\"/>", 6, "two root links"),
        (
            "<link name=\"b\"/>\n<link name=\"c\"/>\n\
             <joint name=\"jb\" type=\"revolute\"><parent link=\"c\"/><child link=\"b\"/></joint>\n\
             <joint name=\"jc\" type=\"revolute\"><parent link=\"b\"/><child link=\"c\"/></joint>",
            0,
            "cycle",
        ),
        (
            "<link name=\"b\"><inertial><mass value=\"-1\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link>\n\
             <joint name=\"jb\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/></joint>",
            6,
            "mass of link `b` is -1: expected zero or a positive number",
        ),
        (
            "<link name=\"b\"><inertial><mass value=\"NaN\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link>\n\
             <joint name=\"jb\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/></joint>",
            6,
            "link `b`: its inertial has a non-finite number",
        ),
        (
            "<link name=\"b\"/>\n<joint name=\"jb\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/><origin xyz=\"0 inf 0\"/></joint>",
            7,
            "joint `jb`: its origin or axis has a non-finite number",
        ),
        (
            "<link name=\"b\"/>\n<joint name=\"jb\" type=\"prismatic\"><parent link=\"a\"/><child link=\"b\"/><axis xyz=\"0 0 0\"/></joint>",
            7,
            "joint `jb`: the axis [0.0, 0.0, 0.0] is zero",
        ),
        (
            "<link name=\"b\"/>\n<joint name=\"jb\" type=\"planar\"><parent link=\"a\"/><child link=\"b\"/></joint>",
            7,
            "joint `jb`: planar joints are not supported",
        ),
        (
            "<link name=\"a\"/>",
            6,
            "link `a` is defined twice",
        ),
        (
            r#"<joint name="ja" type="revolute"><parent link="a"/><child link="a"/></joint>"#,
            6,
            "joint `ja` is defined twice",
        ),
    ];
    for (extra, line, msg) in cases {
        let e = err(&chain_with(extra));
        assert!(
            e.message().contains(msg),
            "message `{}` lacks `{msg}`",
            e.message()
        );
        if *line > 0 {
            assert_eq!(e.line(), Some(*line), "{e}");
            assert!(
                e.to_string().starts_with(&format!("<urdf>:{line}: ")),
                "{e}"
            );
        }
    }
    // A second root and a second parent, at once, each at its line.
    let e = err(&chain_with(
        "<link name=\"b\"/>\n<joint name=\"jb\" type=\"revolute\"><parent link=\"base\"/><child link=\"a\"/></joint>",
    ));
    let text = e.to_string();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 2, "{text}");
    assert!(lines[0].starts_with("<urdf>:6: two root links"), "{text}");
    assert!(
        lines[1].starts_with("<urdf>:7: link `a` has two parents"),
        "{text}"
    );
    // A cycle: the line of one of its joints.
    let e = err(&chain_with(
        "<link name=\"b\"/>\n<link name=\"c\"/>\n\
         <joint name=\"jb\" type=\"revolute\"><parent link=\"c\"/><child link=\"b\"/></joint>\n\
         <joint name=\"jc\" type=\"revolute\"><parent link=\"b\"/><child link=\"c\"/></joint>",
    ));
    assert!(matches!(e.line(), Some(8 | 9)), "{e}");
    // Everything a joint of the world: no root at all.
    let e = err(&robot(
        r#"<link name="a"/><link name="b"/>
<joint name="x" type="revolute"><parent link="a"/><child link="b"/></joint>
<joint name="y" type="revolute"><parent link="b"/><child link="a"/></joint>"#,
    ));
    assert!(e.message().contains("cycle"), "{e}");
    // Malformed XML and missing or unreadable elements: urdf-rs gives no line, we find it.
    let e = err("<robot name=\"x\">\n<link name=\"a\">\n</robot>");
    assert!(e.message().starts_with("malformed URDF"), "{e}");
    assert_eq!(e.line(), Some(2), "the unclosed <link>: {e}");
    let e = err("<robot name=\"x\">\n<link name=\"a\"/>\n</joint>\n</robot>");
    assert_eq!(e.line(), Some(3), "the stray </joint>: {e}");
    let e = err(&chain_with(
        "<link name=\"b\"/>\n<joint name=\"jb\" type=\"revolute\"><child link=\"b\"/></joint>",
    ));
    assert!(e.message().contains("missing field `parent`"), "{e}");
    assert_eq!(e.line(), Some(7), "{e}");
    let e = err(&chain_with(
        "<link name=\"b\">\n<inertial><mass value=\"heavy\"/>\n</inertial></link>",
    ));
    assert!(e.message().starts_with("malformed URDF"), "{e}");
    assert_eq!(e.line(), Some(6), "{e}");
    let e = err(&chain_with(
        "<link name=\"b\"/>\n<joint name=\"jb\" type=\"hinge\"><parent link=\"a\"/><child link=\"b\"/></joint>",
    ));
    assert!(e.message().contains("unknown variant `hinge`"), "{e}");
    assert_eq!(e.line(), Some(7), "{e}");
    let e = err("<robot name=\"x\"></robot>");
    assert!(e.message().contains("no links"), "{e}");
}

#[test]
fn file_errors_name_the_file() {
    let e = load(Path::new("/no/such/dir/robot.urdf"), false).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("/no/such/dir/robot.urdf: error: cannot read"),
        "{e}"
    );

    let dir = std::env::temp_dir().join(format!("articulated-urdf-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.urdf");
    std::fs::write(&path, chain_with("<link name=\"b\"/>\n<joint name=\"jb\" type=\"planar\"><parent link=\"a\"/><child link=\"b\"/></joint>")).unwrap();
    let e = load(&path, false).unwrap_err();
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(e.to_string(), format!("{}:7: joint `jb`: planar joints are not supported (write two prismatic joints and a revolute joint through massless links)", path.display()));
}

#[test]
fn fixture_and_shared_models_load() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let data = root.join("../tests/data/pinocchio");
    for (name, nq) in [
        ("double_pendulum", 2),
        ("two_link_xyz", 6),
        ("arm6_mixed", 6),
        ("tree_two_arms", 7),
    ] {
        let m = load_model(&data.join(format!("{name}.urdf")), false).unwrap();
        assert_eq!(m.nq(), nq, "{name}");
        let f = load_model(&data.join(format!("{name}.urdf")), true).unwrap();
        assert_eq!(f.nq(), nq + 6, "{name}");
    }
    let m = load_model(&root.join("tests/fixtures/rotated_tool.urdf"), false).unwrap();
    assert_eq!(m.nb(), 2);
}

#[test]
fn no_panic_on_any_prefix_or_mangling() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/rotated_tool.urdf"),
    )
    .unwrap();
    let mut cuts: Vec<usize> = (0..=text.len())
        .filter(|&k| text.is_char_boundary(k))
        .collect();
    cuts.retain(|k| k.is_multiple_of(3) || *k == text.len());
    for k in cuts {
        let _ = from_urdf_str(&text[..k], false);
        let _ = from_urdf_str(&text[..k], true);
    }
    for (from, to) in [("0.", "1e400 "), ("\"", "'"), ("link", "lnk"), ("1", "-")] {
        let _ = from_urdf_str(&text.replacen(from, to, 1), false);
        let _ = from_urdf_str(&text.replace(from, to), true);
    }
    // Random single-character edits (a fixed seed).
    let chars: Vec<char> = text.chars().collect();
    let alphabet = [
        '<', '>', '/', '"', ' ', 'x', '0', '-', '\n', 'é', '=', '!', '?',
    ];
    let mut rng = Rng::new(0x2545_F491_4F6C_DD1D);
    for _ in 0..3000 {
        let at = rng.below(chars.len());
        let with = alphabet[rng.below(alphabet.len())];
        let mut edited = chars.clone();
        match rng.below(3) {
            0 => edited[at] = with,
            1 => edited.insert(at, with),
            _ => {
                edited.remove(at);
            }
        }
        let edited: String = edited.into_iter().collect();
        let _ = from_urdf_str(&edited, rng.below(2) == 0);
    }
}

fn rpy_rot(rpy: [f64; 3]) -> M3 {
    matmul(&matmul(&rz(rpy[2]), &ry(rpy[1])), &rx(rpy[0]))
}

#[test]
fn placements_through_fixed_joints_compose_even_at_gimbal_lock() {
    // base -fixed(A)-> w -revolute(B)-> l: the revolute joint's frame in the world is A·B; the
    // roll-pitch-yaw we store must give that rotation, also where pitch is ±90°.
    let cases: [([f64; 3], [f64; 3]); 5] = [
        ([0.0, FRAC_PI_2, 0.0], [0.3, 0.0, 0.0]),
        ([0.2, -FRAC_PI_2, 0.4], [0.0, 0.0, -0.7]),
        ([0.1, 0.2, 0.3], [-0.4, 0.5, -0.6]),
        ([3.0, FRAC_PI_2 - 3e-8, -3.0], [0.0, 1e-9, 0.0]),
        ([0.0, 0.0, 0.0], [0.0, 0.0, 0.0]),
    ];
    for (a, b) in cases {
        let xml = robot(&format!(
            r#"<link name="base"/><link name="w"/><link name="l"/>
<joint name="weld" type="fixed"><parent link="base"/><child link="w"/><origin xyz="0.1 0.2 0.3" rpy="{} {} {}"/></joint>
<joint name="j" type="revolute"><parent link="w"/><child link="l"/><origin xyz="0.5 -0.5 1" rpy="{} {} {}"/></joint>"#,
            a[0], a[1], a[2], b[0], b[1], b[2]
        ));
        let m = from_urdf_str(&xml, false).unwrap().model;
        assert_eq!(m.nb(), 1);
        assert_eq!(m.joints[0].parent, None);
        let (ra, rb) = (rpy_rot(a), rpy_rot(b));
        let expected = matmul(&ra, &rb);
        assert_close33(rpy_rot(c3(&m.joints[0].placement.rpy)), expected, 1e-15);
        let p = [0.5, -0.5, 1.0];
        let xyz: [f64; 3] =
            [0, 1, 2].map(|i| [0.1, 0.2, 0.3][i] + (0..3).map(|k| ra[i][k] * p[k]).sum::<f64>());
        assert!(close3(c3(&m.joints[0].placement.xyz), xyz, 1e-15));
    }
}

#[test]
fn links_welded_to_the_root_join_the_world_or_the_floating_root() {
    let xml = robot(&format!(
        r#"<link name="world"/><link name="base_link">{}</link><link name="arm">{}</link>
<joint name="to_world" type="fixed"><parent link="world"/><child link="base_link"/><origin xyz="0 0 1"/></joint>
<joint name="shoulder" type="revolute"><parent link="base_link"/><child link="arm"/><origin xyz="0 0 0.5"/><axis xyz="0 1 0"/></joint>"#,
        inertial(3.0, "0 0 0", "0 0 0", [0.1, 0.0, 0.0, 0.1, 0.0, 0.1]),
        inertial(1.0, "0 0 0", "0 0 0", [0.1, 0.0, 0.0, 0.1, 0.0, 0.1]),
    ));
    // Fixed base: base_link is part of the world; the shoulder hangs from the world at z = 1.5.
    let m = from_urdf_str(&xml, false).unwrap().model;
    assert_eq!(m.nb(), 1);
    assert_eq!(m.joints[0].parent, None);
    assert_eq!(c3(&m.joints[0].placement.xyz), [0.0, 0.0, 1.5]);
    // Floating: the free base carries `world` with base_link merged into it (mass 3 at z = 1).
    let m = from_urdf_str(&xml, true).unwrap().model;
    assert_eq!(m.nb(), 2);
    assert_eq!(m.bodies[0].name, "world");
    assert_eq!(c(&m.bodies[0].mass), 3.0);
    assert_eq!(c3(&m.bodies[0].com), [0.0, 0.0, 1.0]);
    assert_close33(
        c33(&m.bodies[0].inertia),
        [[0.1, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, 0.1]],
        1e-16,
    );
    assert_eq!(m.joints[1].parent, Some(0));
    assert_eq!(c3(&m.joints[1].placement.xyz), [0.0, 0.0, 1.5]);
}

/// `floating = quaternion`: the same root under Pinocchio's free flyer (7 positions, 6
/// velocities), and the same dynamics as the Euler base where both are defined (checked in
/// `tests/tests/pinocchio.rs` against Pinocchio's own free flyer).
#[test]
fn a_quaternion_base_is_a_free_flyer() {
    let xml = robot(&format!(
        r#"<link name="torso">{}</link><link name="arm">{}</link>
<joint name="shoulder" type="revolute"><parent link="torso"/><child link="arm"/><axis xyz="0 1 0"/></joint>"#,
        inertial(7.0, "0 0 0.1", "0 0 0", [1.0, 0.0, 0.0, 2.0, 0.0, 3.0]),
        inertial(1.0, "0 0 -0.2", "0 0 0", [0.1, 0.0, 0.0, 0.1, 0.0, 0.05])
    ));
    let m = from_urdf_str(&xml, FloatingBase::Quaternion).unwrap().model;
    assert_eq!(m.joints[0].kind, JointKind::FreeQuaternion);
    assert_eq!((m.nq(), m.nv()), (8, 7));
    assert_eq!(m.bodies[0].name, "torso");
    assert_eq!(FloatingBase::from(true), FloatingBase::Euler);
    assert_eq!(
        FloatingBase::from_name("quaternion"),
        Some(FloatingBase::Quaternion)
    );
    assert_eq!(FloatingBase::from_name("quaternions"), None);
}

/// A mimic joint follows the joint it names: no coordinate of its own, its multiplier and offset
/// (URDF's defaults 1 and 0) kept, its limits and losses dropped, its armature kept.
#[test]
fn a_mimic_joint_follows_the_joint_it_names() {
    let xml = chain_with(
        r#"<link name="b"/>
<joint name="finger2" type="prismatic"><parent link="a"/><child link="b"/><limit lower="0" upper="0.04" effort="5" velocity="1"/><dynamics damping="0.5" armature="0.01"/><mimic joint="ja" multiplier="-0.5" offset="0.1"/></joint>
<link name="c"/>
<joint name="jc" type="revolute"><parent link="b"/><child link="c"/><mimic joint="ja"/></joint>"#,
    );
    let m = from_urdf_str(&xml, false)
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    assert_eq!((m.nb(), m.nq(), m.nv()), (3, 1, 1));
    let f2 = m.joints[1].mimic.expect("finger2 mimics");
    assert_eq!((f2.joint, f2.multiplier, f2.offset), (0, -0.5, 0.1));
    let jc = m.joints[2].mimic.expect("jc mimics");
    assert_eq!((jc.joint, jc.multiplier, jc.offset), (0, 1.0, 0.0));
    assert_eq!(
        m.joints[1].drive,
        Drive {
            armature: 0.01,
            ..Drive::FREE
        }
    );
}

/// What a mimic joint may not follow is an error at its line, naming both joints.
#[test]
fn a_mimic_of_a_fixed_or_mimic_joint_is_an_error_at_its_line() {
    let cases: &[(&str, &str)] = &[
        (
            r#"<joint name="m" type="revolute"><parent link="a"/><child link="b"/><mimic joint="m"/></joint>"#,
            "joint `m` mimics `m`, itself",
        ),
        (
            r#"<joint name="m" type="revolute"><parent link="a"/><child link="b"/><mimic joint="ja" multiplier="nan"/></joint>"#,
            "must be finite",
        ),
    ];
    for (joint, message) in cases {
        let e = err(&chain_with(&format!("<link name=\"b\"/>\n{joint}")));
        assert_eq!(e.line(), Some(7), "{e}");
        assert!(e.message().contains(message), "{e}");
    }
    let fixed_followed = r#"<link name="b"/>
<joint name="weld" type="fixed"><parent link="a"/><child link="b"/></joint>
<link name="c"/>
<joint name="m" type="revolute"><parent link="b"/><child link="c"/><mimic joint="weld"/></joint>"#;
    let e = err(&chain_with(fixed_followed));
    assert_eq!(e.line(), Some(9), "{e}");
    assert!(e.message().contains("mimics `weld`, which is fixed"), "{e}");
    let chained = r#"<link name="b"/>
<joint name="m1" type="revolute"><parent link="a"/><child link="b"/><mimic joint="ja"/></joint>
<link name="c"/>
<joint name="m2" type="revolute"><parent link="b"/><child link="c"/><mimic joint="m1"/></joint>"#;
    let e = err(&chain_with(chained));
    assert_eq!(e.line(), Some(9), "{e}");
    assert!(
        e.message().contains("`m1`, which is a mimic joint itself"),
        "{e}"
    );
}

/// What real files hold and Pinocchio loads: a `<mimic>` on a fixed joint (TALOS's grippers) is
/// ignored, and one that names no joint of the file (Alex's hands) leaves an independent joint
/// with its own limits, each with a warning at the joint's line.
#[test]
fn a_mimic_on_a_fixed_joint_or_of_an_unknown_joint_loads_with_a_warning() {
    let cases: &[(&str, &str, usize)] = &[
        (
            r#"<joint name="m" type="revolute"><parent link="a"/><child link="b"/><limit lower="-1" upper="1" effort="1" velocity="1"/><mimic joint="nobody"/></joint>"#,
            "joint `m` mimics `nobody`, which is not a joint of this robot: it is loaded as an \
             independent joint",
            2,
        ),
        (
            r#"<joint name="m" type="fixed"><parent link="a"/><child link="b"/><mimic joint="ja"/></joint>"#,
            "joint `m` is fixed and mimics `ja`: the `<mimic>` is ignored",
            1,
        ),
    ];
    for (joint, message, nv) in cases {
        let chain = from_urdf_str(&chain_with(&format!("<link name=\"b\"/>\n{joint}")), false)
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(chain.warnings.len(), 1, "{:?}", chain.warnings);
        assert_eq!(chain.warnings[0].line, Some(7));
        assert_eq!(chain.warnings[0].message, *message);
        assert_eq!(chain.model.nv(), *nv);
        assert!(chain.model.joints.iter().all(|j| j.mimic.is_none()));
        if *nv == 2 {
            assert_eq!(chain.model.joints[1].drive.upper, 1.0);
        }
    }
}

/// Every problem of a file is reported at once, each at its line: a user fixes them in one
/// edit, not one run each.
#[test]
fn every_problem_is_reported_at_once() {
    let xml = robot(&format!(
        "<link name=\"base\"/>\n<link name=\"l1\">{}</link>\n\
         <joint name=\"j1\" type=\"revolute\"><parent link=\"base\"/><child link=\"l1\"/></joint>\n\
         <link name=\"l2\">{}</link>\n\
         <joint name=\"j2\" type=\"revolute\"><parent link=\"l1\"/><child link=\"l2\"/><axis xyz=\"0 0 0\"/></joint>",
        inertial(-1.0, "0 0 0", "0 0 0", [0.1, 0.0, 0.0, 0.1, 0.0, 0.1]),
        inertial(1.0, "0 0 0", "0 0 0", [0.1, 0.0, 0.0, 0.1, 0.0, 0.1]),
    ));
    let e = err(&xml);
    assert_eq!(e.count(), 2, "{e}");
    let text = e.to_string();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 2, "{text}");
    assert!(
        lines[0].starts_with("<urdf>:4: ") && lines[0].contains("mass of link `l1` is -1"),
        "{text}"
    );
    assert!(
        lines[1].starts_with("<urdf>:7: ") && lines[1].contains("is zero"),
        "{text}"
    );
}

/// The check stage's problems (a cycle, a mimic of a mimic joint) come with the walk's (a
/// negative mass), at once, in line order, each at the line of the link or joint it is about.
#[test]
fn the_check_stages_problems_come_with_the_others_at_once() {
    let xml = chain_with(&format!(
        "<link name=\"b\">{}</link>\n\
         <joint name=\"jb\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/></joint>\n\
         <link name=\"c\"/>\n\
         <joint name=\"m1\" type=\"revolute\"><parent link=\"b\"/><child link=\"c\"/><mimic joint=\"ja\"/></joint>\n\
         <link name=\"d\"/>\n\
         <joint name=\"m2\" type=\"revolute\"><parent link=\"c\"/><child link=\"d\"/><mimic joint=\"m1\"/></joint>\n\
         <link name=\"x\"/>\n\
         <link name=\"y\"/>\n\
         <joint name=\"xy\" type=\"revolute\"><parent link=\"x\"/><child link=\"y\"/></joint>\n\
         <joint name=\"yx\" type=\"revolute\"><parent link=\"y\"/><child link=\"x\"/></joint>",
        inertial(-1.0, "0 0 0", "0 0 0", [0.1, 0.0, 0.0, 0.1, 0.0, 0.1]),
    ));
    let e = err(&xml);
    let text = e.to_string();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines,
        [
            "<urdf>:6: mass of link `b` is -1: expected zero or a positive number",
            "<urdf>:11: joint `m2` mimics `m1`, which is a mimic joint itself: mimic the joint \
             that one follows, with the multipliers and offsets composed",
            "<urdf>:14: joints form a cycle `y` → `x` → `y`: none of these links is reachable \
             from a root link; expected a tree hanging from a root link",
        ]
    );
}

/// A joint's `<dynamics>` and `<limit>` become its drive, with the non-standard `armature`;
/// absent limits are no limits (urdf-rs reads them as 0).
#[test]
fn dynamics_and_limits_are_read_into_the_drive() {
    let xml = chain_with(
        r#"<link name="b"/>
<joint name="jb" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 1 0"/>
<limit lower="-1.5" upper="2.5" effort="40" velocity="3"/><dynamics damping="0.7" friction="0.2" armature="0.03"/></joint>
<link name="c"/>
<joint name="jc" type="continuous"><parent link="b"/><child link="c"/><limit effort="5" velocity="0"/></joint>"#,
    );
    let m = from_urdf_str(&xml, false)
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    let drive = |name: &str| m.joints.iter().find(|j| j.name == name).unwrap().drive;
    assert_eq!(drive("ja"), Drive::FREE);
    assert_eq!(
        drive("jb"),
        Drive {
            armature: 0.03,
            damping: 0.7,
            friction: 0.2,
            lower: -1.5,
            upper: 2.5,
            velocity: 3.0,
            effort: 40.0,
            ..Drive::FREE
        }
    );
    assert_eq!(
        drive("jc"),
        Drive {
            effort: 5.0,
            ..Drive::FREE
        }
    );
}

/// A drive that cannot be is refused at its joint's line, saying what is wrong.
#[test]
fn a_bad_drive_is_refused_at_its_line() {
    let cases = [
        (
            r#"<dynamics damping="-1"/>"#,
            "joint `jb`: damping must be finite and >= 0, found -1",
        ),
        (
            r#"<limit lower="1" upper="-1" effort="1" velocity="1"/>"#,
            "joint `jb`: limits must satisfy lower <= upper, found [1, -1]",
        ),
        (
            r#"<dynamics armature="heavy"/>"#,
            "joint `jb`: `<dynamics armature=\"heavy\">` is not a number",
        ),
    ];
    for (element, message) in cases {
        let e = err(&chain_with(&format!(
            "<link name=\"b\"/>\n<joint name=\"jb\" type=\"revolute\"><parent link=\"a\"/>\
             <child link=\"b\"/>{element}</joint>"
        )));
        assert_eq!(e.line(), Some(7), "{e}");
        assert_eq!(e.message(), message);
    }
}

/// What the dynamics never reads does not stop an import: a `<mesh>` without `filename` (as
/// iCub's description has), an unknown element inside `<visual>`; and the lines of later errors
/// stay the file's.
#[test]
fn visual_and_collision_elements_are_never_read() {
    let geometry = r#"<visual><geometry><mesh scale="1 1 1"/></geometry><material name="m"/></visual>
<collision><geometry><mesh/></geometry><whatever/></collision>"#;
    let xml = robot(&format!(
        "<link name=\"base\"/>\n<link name=\"a\">{}\n{geometry}\n</link>\n\
         <joint name=\"ja\" type=\"revolute\"><parent link=\"base\"/><child link=\"a\"/></joint>",
        inertial(1.0, "0 0 0", "0 0 0", [0.1, 0.0, 0.0, 0.1, 0.0, 0.1])
    ));
    let m = from_urdf_str(&xml, false)
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    assert_eq!(m.nb(), 1);
    assert_eq!(c(&m.bodies[0].mass), 1.0);
    let bad = xml.replace(
        "<parent link=\"base\"/><child link=\"a\"/>",
        "<parent link=\"base\"/><child link=\"ghost\"/>",
    );
    assert_eq!(err(&bad).line(), Some(8));
}

/// A link's inertia follows the `.chain` rules: no negative principal moment, the triangle
/// inequality; zero (a frame, a point mass) and the edge of the inequality are accepted.
#[test]
fn inertias_that_no_body_has_load_with_a_warning_at_the_link() {
    let link = |i: [f64; 6]| {
        robot(&format!(
            "<link name=\"base\"/>\n<link name=\"l1\">{}</link>\n\
             <joint name=\"j1\" type=\"revolute\"><parent link=\"base\"/><child link=\"l1\"/></joint>",
            inertial(1.0, "0 0 0", "0 0 0", i)
        ))
    };
    let warning = |i: [f64; 6]| {
        let chain = from_urdf_str(&link(i), false).unwrap_or_else(|e| panic!("{i:?}: {e}"));
        assert_eq!(chain.warnings.len(), 1, "{i:?}: {:?}", chain.warnings);
        assert_eq!(chain.warnings[0].line, Some(4));
        // Loaded as written.
        assert_eq!(chain.model.bodies[0].inertia[0][0], Value::Const(i[0]));
        chain.warnings[0].message.clone()
    };
    let w = warning([1.0, 0.0, 0.0, 1.0, 0.0, -0.5]);
    assert!(
        w.contains("inertia of link `l1` is not positive semi-definite"),
        "{w}"
    );
    let w = warning([0.1, 0.0, 0.0, 0.1, 0.0, 0.5]);
    assert!(w.contains("triangle inequality"), "{w}");
    // Off-diagonal terms large enough to make it indefinite.
    let w = warning([0.1, 0.2, 0.0, 0.1, 0.0, 0.1]);
    assert!(w.contains("not positive semi-definite"), "{w}");
    for ok in [
        [0.0; 6],
        [0.5, 0.0, 0.0, 0.5, 0.0, 1.0],
        [0.2, 0.01, 0.0, 0.3, 0.0, 0.4],
    ] {
        let chain = from_urdf_str(&link(ok), false).unwrap_or_else(|e| panic!("{ok:?}: {e}"));
        assert!(chain.warnings.is_empty(), "{ok:?}: {:?}", chain.warnings);
    }
}

/// Each moving body is judged once the links welded to it are merged into it: a camera whose
/// tensor breaks the triangle inequality, welded to a base whose inertia is fine, is fine
/// (ANYmal C, TIAGo's antenna); rounding noise written as a tensor (iCub's ankle: zero but for
/// an off-diagonal 1.4e-20, eigenvalues ±1.4e-20) is rounding next to the model's largest
/// moment and passes silently, while the same shape at the scale of the model warns.
#[test]
fn inertias_are_judged_on_merged_bodies_against_the_models_scale() {
    let two = |camera: [f64; 6], noise: [f64; 6]| {
        robot(&format!(
            "<link name=\"base\"/>\n<link name=\"l1\">{}</link>\n\
             <joint name=\"j1\" type=\"revolute\"><parent link=\"base\"/><child link=\"l1\"/></joint>\n\
             <link name=\"camera\">{}</link>\n\
             <joint name=\"weld\" type=\"fixed\"><parent link=\"l1\"/><child link=\"camera\"/><origin xyz=\"0.1 0 0\"/></joint>\n\
             <link name=\"l2\">{}</link>\n\
             <joint name=\"j2\" type=\"revolute\"><parent link=\"l1\"/><child link=\"l2\"/></joint>",
            inertial(1.0, "0 0 0", "0 0 0", [0.1, 0.0, 0.0, 0.1, 0.0, 0.1]),
            inertial(0.05, "0 0 0", "0 0 0", camera),
            inertial(0.5, "0 0 0", "0 0 0", noise),
        ))
    };
    let odd_camera = [0.001, 0.0, 0.0, 0.001, 0.0, 0.005];
    let noise = [0.0, 1.4e-20, 0.0, 0.0, 0.0, 0.0];
    let chain = from_urdf_str(&two(odd_camera, noise), false).unwrap_or_else(|e| panic!("{e}"));
    assert!(chain.warnings.is_empty(), "{:?}", chain.warnings);
    // The same noise at the model's scale is no rounding.
    let chain = from_urdf_str(&two(odd_camera, [0.0, 0.01, 0.0, 0.0, 0.0, 0.0]), false).unwrap();
    assert_eq!(chain.warnings.len(), 1, "{:?}", chain.warnings);
    assert_eq!(chain.warnings[0].line, Some(8));
    assert!(chain.warnings[0].message.contains("link `l2`"));
    // A camera heavy enough to dominate its body still warns, naming both links.
    let heavy = [0.5, 0.0, 0.0, 0.5, 0.0, 5.0];
    let chain = from_urdf_str(&two(heavy, noise), false).unwrap();
    assert_eq!(chain.warnings.len(), 1, "{:?}", chain.warnings);
    assert_eq!(chain.warnings[0].line, Some(4));
    assert!(
        chain.warnings[0]
            .message
            .contains("inertia of link `l1` (with `camera` welded to it) breaks the triangle"),
        "{}",
        chain.warnings[0].message
    );
}

/// The `Builder` hands the loader's warnings to cargo (`Builder::warnings`, printed as
/// `cargo:warning=` by `write`), refuses them with `strict()`, and `balance_inertia()` gives a
/// body whose principal moments break the triangle inequality their mean about every axis
/// (MuJoCo's `balanceinertia`).
#[test]
fn builder_warnings_strict_and_balance() {
    use articulated_codegen::load::{load_with, LoadError, LoadOptions};
    use articulated_codegen::Builder;
    let path = format!(
        "{}/../macros/tests/ui/fixtures/odd_inertia.urdf",
        env!("CARGO_MANIFEST_DIR")
    );
    let warnings = Builder::new().urdf(&path, false).warnings().unwrap();
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    assert!(warnings[0].ends_with(
        "odd_inertia.urdf:4: warning: inertia of link `arm` (with `tool` welded to it) breaks \
         the triangle inequality: principal moments 0.01 + 0.01 < 0.05; expected each moment to \
         be at most the sum of the other two"
    ));
    let strict = Builder::new().urdf(&path, false).strict().to_source();
    assert!(
        matches!(&strict, Err(articulated_codegen::build::BuildError::Load(LoadError::Strict { warnings, .. })) if warnings.len() == 2),
        "{strict:?}"
    );
    let warnings = Builder::new()
        .urdf(&path, false)
        .balance_inertia()
        .warnings()
        .unwrap();
    assert_eq!(warnings.len(), 1, "only the mimic's: {warnings:?}");
    let options = LoadOptions {
        balance_inertia: true,
        ..LoadOptions::default()
    };
    let model = load_with(Path::new(&path), options).unwrap().model;
    let mean = (0.01 + 0.01 + 0.05) / 3.0;
    let i = model.bodies[0].inertia;
    for (r, row) in i.iter().enumerate() {
        for (c, x) in row.iter().enumerate() {
            let expected = if r == c { mean } else { 0.0 };
            assert!(
                matches!(x, Value::Const(v) if (v - expected).abs() < 1e-15),
                "{i:?}"
            );
        }
    }
}
