//! MJCF import: what is refused (each problem at its line, every problem at once), what is
//! skipped with a warning, and how the front end is chosen. The dynamics themselves are checked
//! against MuJoCo in `tests/tests/mjcf.rs`.

use articulated_codegen::load::{load, load_with, LoadError, LoadOptions};
use articulated_codegen::mjcf::{from_mjcf_str, is_mjcf, MjcfError};
use articulated_codegen::model::JointKind;

fn err(xml: &str) -> MjcfError {
    match from_mjcf_str(xml) {
        Ok(_) => panic!("expected an error for\n{xml}"),
        Err(e) => e,
    }
}

/// `body` inside a model's world body, one element per line from line 3.
fn model(body: &str) -> String {
    format!("<mujoco model=\"t\">\n<worldbody>\n{body}\n</worldbody>\n</mujoco>\n")
}

#[test]
fn each_refusal_names_its_line_and_what_is_wrong() {
    let cases: &[(&str, usize, &str)] = &[
        (
            "<body name=\"a\">\n<joint name=\"j\" axis=\"0 0 0\"/>\n<geom size=\"0.1\"/>\n</body>",
            4,
            "joint `j` of body `a`: the axis is too small",
        ),
        (
            "<body name=\"a\" quat=\"1 0 0 0\" euler=\"0 0 1\">\n<joint/>\n<geom size=\"0.1\"/>\n</body>",
            3,
            "gives its orientation twice: `quat` and `euler`",
        ),
        (
            "<body name=\"a\">\n<joint range=\"0 nan\"/>\n<geom size=\"0.1\"/>\n</body>",
            4,
            "`nan` is not a finite number",
        ),
        (
            "<body name=\"a\">\n<joint class=\"nope\"/>\n<geom size=\"0.1\"/>\n</body>",
            4,
            "the default class `nope` is not defined",
        ),
        (
            "<body name=\"a\">\n<joint/>\n<geom type=\"mesh\" mesh=\"m\"/>\n</body>",
            5,
            "mesh `m`: no `<mesh>` asset has this name",
        ),
        (
            "<body name=\"a\">\n<joint/>\n<geom type=\"capsule\" size=\"0.1\"/>\n</body>",
            5,
            "size 1 must be positive",
        ),
        (
            "<body name=\"a\">\n<joint/>\n<body name=\"b\">\n<freejoint/>\n<geom size=\"1\"/>\n</body>\n</body>",
            5,
            "body `b`: a free joint is supported only as the one joint of a body whose parents are welded",
        ),
        (
            "<body name=\"a\">\n<joint/>\n<inertial pos=\"0 0 0\" mass=\"1\"/>\n</body>",
            5,
            "`<inertial>` needs `diaginertia` or `fullinertia`",
        ),
        (
            "<body name=\"a\">\n<joint/>\n<inertial pos=\"0 0 0\" mass=\"1\" diaginertia=\"1 1 3\"/>\n</body>",
            3,
            "MuJoCo refuses it too",
        ),
        (
            "<body name=\"a\">\n<joint type=\"hinge\" range=\"1 -1\"/>\n<geom size=\"1\"/>\n</body>",
            4,
            "joint `joint0`: its range [1, -1] is empty",
        ),
        (
            "<body name=\"a\">\n<joint/>\n<replicate count=\"3\">\n<body/>\n</replicate>\n</body>",
            5,
            "`<replicate>` is not supported yet",
        ),
        (
            "<body name=\"a\">\n<freejoint align=\"true\"/>\n<geom size=\"1\"/>\n</body>",
            3,
            "a free joint aligned with the inertial frame",
        ),
        (
            "<body name=\"a\">\n<joint type=\"universal\"/>\n<geom size=\"1\"/>\n</body>",
            4,
            "`<joint type=\"universal\">`: expected one of `hinge`, `slide`, `ball`, `free`",
        ),
    ];
    for (body, line, message) in cases {
        let e = err(&model(body));
        assert_eq!(e.line(), Some(*line), "{e}");
        assert!(e.message().contains(message), "`{e}` lacks `{message}`");
        assert!(
            e.to_string().starts_with(&format!("<mjcf>:{line}: ")),
            "{e}"
        );
    }
}

#[test]
fn malformed_xml_and_other_roots_are_refused() {
    let e = err("<mujoco>\n<worldbody>\n<body>\n</worldbody>\n</mujoco>");
    assert!(e.message().starts_with("malformed XML"), "{e}");
    assert_eq!(e.line(), Some(4));
    let e = err("<robot name=\"r\"/>");
    assert!(e.message().contains("`<mujoco>` root"), "{e}");
    assert!(!is_mjcf("<robot name=\"r\"/>") && is_mjcf("<mujoco/>") && !is_mjcf("<mujoco"));
    let e = err("<mujoco>\n<include file=\"other.xml\"/>\n</mujoco>");
    assert!(e.message().contains("given as text"), "{e}");
    assert_eq!(e.line(), Some(2));
}

#[test]
fn every_problem_of_a_file_is_reported_at_once() {
    let xml = model(
        "<body name=\"a\">\n<joint axis=\"0 0 0\"/>\n<geom size=\"0.1\"/>\n</body>\n\
         <body name=\"b\">\n<joint class=\"x\"/>\n<geom size=\"0.1\"/>\n</body>",
    );
    let e = err(&xml);
    assert_eq!(e.count(), 2, "{e}");
    let text = e.to_string();
    assert!(
        text.contains("<mjcf>:4: ") && text.contains("<mjcf>:8: "),
        "{text}"
    );
}

#[test]
fn what_is_not_represented_loads_with_a_warning_at_its_line() {
    let xml = "<mujoco>\n<worldbody>\n<body name=\"a\" gravcomp=\"1\">\n\
               <joint name=\"j\" stiffness=\"3\" damping=\"1 2\"/>\n<geom size=\"0.1\"/>\n</body>\n\
               </worldbody>\n<equality>\n<joint joint1=\"j\"/>\n</equality>\n<tendon>\n\
               <fixed name=\"t\"><joint joint=\"j\" coef=\"1\"/></fixed>\n</tendon>\n\
               <actuator>\n<motor joint=\"j\"/>\n<motor joint=\"j\"/>\n</actuator>\n</mujoco>";
    let d = from_mjcf_str(xml).expect("loads");
    let lines: Vec<(Option<usize>, &str)> = d
        .warnings
        .iter()
        .chain(&d.notes)
        .map(|w| (w.line, w.message.as_str()))
        .collect();
    // What is left out by design is a note, not a warning a build would repeat.
    assert!(d
        .notes
        .iter()
        .all(|n| n.message.contains("tendon") || n.message.contains("actuator")));
    assert_eq!(d.notes.len(), 2, "{:?}", d.notes);
    for (line, what) in [
        (3, "`gravcomp` is not represented"),
        (4, "damping beyond the linear term"),
        (4, "damping beyond the linear term"),
        (9, "the joint equality is not applied"),
        (12, "the fixed tendon `t` is skipped"),
        (15, "2 actuators skipped"),
    ] {
        assert!(
            lines
                .iter()
                .any(|(l, m)| *l == Some(line) && m.contains(what)),
            "no warning `{what}` at line {line}: {lines:?}"
        );
    }
    assert_eq!(d.model.joints[0].drive.damping, 1.0);
    assert_eq!(d.model.joints[0].drive.stiffness, 3.0);
}

#[test]
fn an_xml_file_goes_to_the_front_end_its_root_names() {
    let dir = std::env::temp_dir().join(format!("articulated-mjcf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mjcf = dir.join("m.xml");
    std::fs::write(
        &mjcf,
        "<mujoco>\n<worldbody>\n<body><joint type=\"ball\"/><geom size=\"1\"/></body>\n\
         </worldbody>\n</mujoco>",
    )
    .unwrap();
    let urdf = dir.join("u.xml");
    std::fs::write(
        &urdf,
        "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"><inertial><mass value=\"1\"/>\
         <inertia ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>\
         <joint name=\"j\" type=\"continuous\"><parent link=\"a\"/><child link=\"b\"/></joint></robot>",
    )
    .unwrap();
    let m = load(&mjcf, false).unwrap().model;
    assert_eq!(m.joints[0].kind, JointKind::SphericalQuaternion);
    let u = load(&urdf, false).unwrap().model;
    assert!(matches!(u.joints[0].kind, JointKind::Revolute { .. }));
    // A free base is the file's own in MJCF.
    assert!(matches!(
        load(&mjcf, true),
        Err(LoadError::FloatingChain(_))
    ));
    // An include is read from the file's directory; a problem there is at its line.
    std::fs::write(
        dir.join("inc.xml"),
        "<mujoco>\n<default>\n<joint axis=\"0 0 0\"/>\n</default>\n</mujoco>",
    )
    .unwrap();
    let main = dir.join("main.xml");
    std::fs::write(
        &main,
        "<mujoco>\n<include file=\"inc.xml\"/>\n<worldbody>\n<body><joint/><geom size=\"1\"/></body>\n</worldbody>\n</mujoco>",
    )
    .unwrap();
    let e = load(&main, false).unwrap_err().to_string();
    assert!(e.starts_with(&format!("{}:4: ", main.display())), "{e}");
    std::fs::write(
        &main,
        "<mujoco>\n<include file=\"missing.xml\"/>\n</mujoco>",
    )
    .unwrap();
    let e = load(&main, false).unwrap_err().to_string();
    assert!(
        e.contains(":2: cannot read the included file `missing.xml`"),
        "{e}"
    );
    // An inertia no rigid body has is refused, as MuJoCo does, unless balanced on request.
    let odd = dir.join("odd.xml");
    std::fs::write(
        &odd,
        "<mujoco>\n<worldbody>\n<body><joint/>\n<inertial pos=\"0 0 0\" mass=\"1\" diaginertia=\"1 1 3\"/>\n</body>\n</worldbody>\n</mujoco>",
    )
    .unwrap();
    assert!(load(&odd, false).is_err());
    let options = LoadOptions {
        balance_inertia: true,
        ..LoadOptions::default()
    };
    let balanced = load_with(&odd, options).unwrap().model;
    let i = balanced.bodies[0]
        .inertia
        .map(|row| row.map(|v| v.as_const().unwrap()));
    assert!(
        (i[0][0] - 5.0 / 3.0).abs() < 1e-12 && (i[2][2] - 5.0 / 3.0).abs() < 1e-12,
        "{i:?}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_builder_generates_from_mjcf_with_its_warnings() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/mujoco/features/equality.xml");
    let builder = articulated_codegen::Builder::new().mjcf(&path);
    let source = builder.to_source().unwrap();
    assert!(
        source.contains("pub struct Equality"),
        "{}",
        &source[..200.min(source.len())]
    );
    assert_eq!(builder.warnings().unwrap().len(), 3, "one per equality");
    let coupled = articulated_codegen::Builder::new()
        .mjcf(&path)
        .mimic_equalities();
    let warnings = coupled.warnings().unwrap();
    assert!(
        warnings.len() == 2 && warnings[1].contains("not linear"),
        "{warnings:?}"
    );
}

#[test]
fn a_mesh_given_by_its_vertices_and_faces_weighs_its_volume() {
    // The unit cube, outward triangles, 1000 kg/m³: 1000 kg, 1000/6 kg·m² about its centre.
    let xml = "<mujoco>\n<asset>\n<mesh name=\"cube\" vertex=\"0 0 0 1 0 0 0 1 0 1 1 0 0 0 1 1 0 1 0 1 1 1 1 1\" \
               face=\"0 2 3 0 3 1 4 5 7 4 7 6 0 1 5 0 5 4 2 6 7 2 7 3 0 4 6 0 6 2 1 3 7 1 7 5\"/>\n\
               <mesh name=\"hull\" vertex=\"0 0 0 1 0 0 0 1 0 0 0 1\"/>\n</asset>\n<worldbody>\n\
               <body><joint/><geom type=\"mesh\" mesh=\"cube\"/></body>\n</worldbody>\n</mujoco>";
    let body = &from_mjcf_str(xml).unwrap().model.bodies[0];
    let c = |v: &articulated_codegen::model::Value| v.as_const().unwrap();
    assert!((c(&body.mass) - 1000.0).abs() < 1e-9);
    assert!(body.com.iter().all(|x| (c(x) - 0.5).abs() < 1e-12));
    assert!((c(&body.inertia[0][0]) - 1000.0 / 6.0).abs() < 1e-9);
    // A mesh without faces is its convex hull, which is not computed yet.
    let e = err(&xml.replace("mesh=\"cube\"", "mesh=\"hull\""));
    assert!(e.message().contains("convex hull"), "{e}");
}

/// Real models spoiled at random (an attribute's value replaced by a hostile one, an element cut
/// out, the text cut short): each loads or is refused, never a panic, and a refusal names a line.
#[test]
fn spoiled_real_models_are_refused_never_a_panic() {
    use articulated_dynamics::random::Rng;
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/mujoco");
    let files = [
        "real/gymnasium/humanoid.xml",
        "real/gymnasium/ant.xml",
        "features/joints.xml",
        "features/orientations.xml",
    ];
    let hostile = [
        "nan", "-1", "0", "1e308", "-1e308", "0 0 0 0", "", "x", "1 2", "inf", "0 0 0",
    ];
    let mut rng = Rng::new(0x4D4A_4346);
    let mut refused = 0;
    for file in files {
        let text = std::fs::read_to_string(dir.join(file)).unwrap();
        let quotes: Vec<usize> = text.match_indices("=\"").map(|(i, _)| i + 2).collect();
        for _ in 0..150 {
            let spoiled = match rng.below(3) {
                0 => {
                    let start = quotes[rng.below(quotes.len())];
                    let end = start + text[start..].find('"').unwrap();
                    format!(
                        "{}{}{}",
                        &text[..start],
                        hostile[rng.below(hostile.len())],
                        &text[end..]
                    )
                }
                1 => {
                    // A line cut out: an element, or half of one.
                    let lines: Vec<usize> = text.match_indices('\n').map(|(i, _)| i).collect();
                    let k = rng.below(lines.len() - 1);
                    format!("{}{}", &text[..lines[k]], &text[lines[k + 1]..])
                }
                _ => {
                    let mut cut = rng.below(text.len());
                    while !text.is_char_boundary(cut) {
                        cut -= 1;
                    }
                    text[..cut].to_string()
                }
            };
            let outcome = std::panic::catch_unwind(|| from_mjcf_str(&spoiled));
            match outcome {
                Err(_) => panic!("{file}: a panic on\n{spoiled}"),
                Ok(Err(e)) => {
                    refused += 1;
                    assert!(!e.message().is_empty(), "{file}: an empty error");
                }
                Ok(Ok(_)) => {}
            }
        }
    }
    assert!(
        refused > 100,
        "only {refused} of 600 spoiled models refused"
    );
}
