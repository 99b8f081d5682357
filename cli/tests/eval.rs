//! `articulated eval` end to end: the binary's JSON against Pinocchio's values (an independent
//! library), and its error paths.

mod common;

use common::repo;
use std::path::Path;

use articulated_dynamics::random::Rng;
use serde_json::Value;

/// Runs `articulated eval`; (exit success, stdout, stderr).
fn eval(args: &[&str]) -> (bool, String, String) {
    common::run("eval", args)
}

fn csv(v: &Value) -> String {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| format!("{:e}", x.as_f64().unwrap()))
        .collect::<Vec<_>>()
        .join(",")
}

fn flat(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(items) => items.iter().flat_map(flat).collect(),
        Value::Number(n) => vec![n.as_f64().unwrap()],
        _ => panic!("not numeric: {v}"),
    }
}

/// Largest difference between `ours` and `theirs`, relative to the largest entry of `theirs`.
fn rel_err(ours: &Value, theirs: &Value) -> f64 {
    let (a, b) = (flat(ours), flat(theirs));
    assert_eq!(a.len(), b.len(), "shapes differ: {ours} vs {theirs}");
    let scale = b.iter().fold(1e-300_f64, |m, x| m.max(x.abs()));
    a.iter()
        .zip(&b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

/// Runs `eval` on every state Pinocchio recorded for `urdf` and compares each output to 1e-10.
fn agree_with_pinocchio(urdf: &str, data: &str, model: &str, base: &str) {
    let text = std::fs::read_to_string(repo().join(data)).expect("reference data present");
    // Python's json.dump writes NaN as a bare `NaN`, which is not JSON: read it as null.
    let json: Value = serde_json::from_str(&text.replace("NaN", "null")).unwrap();
    let entry = &json["models"][model][base];
    let floating = base == "floating";
    let mut worst = [0.0_f64; 5];
    let mut singular = 0;
    for state in entry["states"].as_array().unwrap() {
        let (q, v, a, tau) = (
            csv(&state["q"]),
            csv(&state["v"]),
            csv(&state["a"]),
            csv(&state["tau"]),
        );
        let mut args = vec![urdf, "--q", &q, "--v", &v, "--a", &a, "--tau", &tau];
        if floating {
            args.push("--floating");
        }
        let (ok, stdout, stderr) = eval(&args);
        if state["qdd"].as_array().unwrap().iter().any(Value::is_null) {
            // Pinocchio's q̈ is NaN: M(q) is singular there (a massless root whose free-base
            // rotations repeat the joints below it). We must refuse, not print noise.
            assert!(
                !ok,
                "{model}/{base}: M is singular, yet eval printed {stdout}"
            );
            assert!(stderr.contains("singular"), "{stderr}");
            singular += 1;
            continue;
        }
        assert!(ok, "eval failed: {stderr}");
        let ours: Value = serde_json::from_str(&stdout).unwrap();
        assert_eq!(ours["nq"], entry["nq"]);
        assert_eq!(ours["nv"], entry["nv"]);
        let pairs = [
            ("mass_matrix", "mass_matrix"),
            ("bias", "bias"),
            ("gravity", "gravity"),
            ("tau", "tau_out"),
            ("qdd", "qdd"),
        ];
        for (k, (ours_key, theirs_key)) in pairs.iter().enumerate() {
            let e = rel_err(&ours[ours_key], &state[theirs_key]);
            worst[k] = worst[k].max(e);
            assert!(e < 1e-10, "{model}/{base} {ours_key}: relative error {e:e}");
        }
    }
    println!("{model}/{base}: {singular} states with a singular M refused; worst relative error M {:.1e} bias {:.1e} gravity {:.1e} tau {:.1e} qdd {:.1e}",
        worst[0], worst[1], worst[2], worst[3], worst[4]);
}

#[test]
fn arm7_urdf_agrees_with_pinocchio() {
    agree_with_pinocchio(
        "models/arm7.urdf",
        "tests/data/pinocchio-arm7.json",
        "arm7",
        "fixed",
    );
    agree_with_pinocchio(
        "models/arm7.urdf",
        "tests/data/pinocchio-arm7.json",
        "arm7",
        "floating",
    );
}

#[test]
fn two_spherical_joints_urdf_agrees_with_pinocchio() {
    let data = "tests/data/pinocchio/pinocchio-values.json";
    let urdf = "tests/data/pinocchio/two_link_xyz.urdf";
    agree_with_pinocchio(urdf, data, "two_link_xyz", "fixed");
    agree_with_pinocchio(urdf, data, "two_link_xyz", "floating");
}

/// The drives read from URDF are printed as read (the file's numbers), and the armature is in
/// `M`: its diagonal exceeds that of the same arm without rotors by exactly the armature.
#[test]
fn drives_are_printed_and_armature_is_in_the_mass_matrix() {
    let q = "0.3,-0.4,0.5,1.1,-0.2,0.7,0.1";
    let (ok, with, stderr) = eval(&["tests/data/arm7_armature.urdf", "--q", q]);
    assert!(ok, "{stderr}");
    let (ok, without, stderr) = eval(&["models/arm7.urdf", "--q", q]);
    assert!(ok, "{stderr}");
    let (with, without): (Value, Value) = (
        serde_json::from_str(&with).unwrap(),
        serde_json::from_str(&without).unwrap(),
    );
    let drives = with["drives"].as_array().unwrap();
    assert_eq!(drives.len(), 7);
    assert_eq!(drives[0]["joint"], "j1");
    assert_eq!(drives[0]["armature"], 0.4);
    assert_eq!(drives[6]["armature"], 0.05);
    assert_eq!(
        (&drives[3]["damping"], &drives[3]["friction"]),
        (&0.5.into(), &0.1.into())
    );
    assert_eq!(
        (&drives[3]["lower"], &drives[3]["effort"]),
        (&(-2.96).into(), &176.0.into())
    );
    // The plain arm: limits only, no rotor.
    let plain = without["drives"].as_array().unwrap();
    assert!(plain
        .iter()
        .all(|d| d["armature"] == 0.0 && d["velocity"] == 1.7));
    let armature = [0.40, 0.40, 0.25, 0.25, 0.12, 0.08, 0.05];
    let (m, m0) = (flat(&with["mass_matrix"]), flat(&without["mass_matrix"]));
    for r in 0..7 {
        for c in 0..7 {
            let extra = if r == c { armature[r] } else { 0.0 };
            let d = m[r * 7 + c] - m0[r * 7 + c];
            assert!((d - extra).abs() < 1e-14, "M[{r}][{c}]: {d} vs {extra}");
        }
    }
}

#[test]
fn defaults_are_neutral_and_zero() {
    let (ok, stdout, stderr) = eval(&["models/double_pendulum.chain"]);
    assert!(ok, "{stderr}");
    let out: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(out["nq"], 2);
    assert_eq!(out["nv"], 2);
    // Hanging straight down at rest: no gravity torque, no bias, no motion.
    for key in ["bias", "gravity", "tau", "qdd"] {
        assert!(
            flat(&out[key]).iter().all(|x| x.abs() < 1e-12),
            "{key}: {}",
            out[key]
        );
    }
    // M(0) in closed form: m1 c1² + I1 + m2 (l1 + c2)² + I2 (both about y).
    let m00 = 1.0 * 0.25 + 0.02 + 0.7 * 1.35 * 1.35 + 0.01;
    assert!((flat(&out["mass_matrix"])[0] - m00).abs() < 1e-12);
}

#[test]
fn unreadable_file_is_an_error() {
    let (ok, _, stderr) = eval(&["models/no_such_model.chain"]);
    assert!(!ok);
    assert!(stderr.contains("no_such_model.chain"), "{stderr}");
    assert!(stderr.contains("cannot read"), "{stderr}");
}

#[test]
fn unknown_extension_is_an_error() {
    let (ok, _, stderr) = eval(&["README.md"]);
    assert!(!ok);
    assert!(
        stderr.contains("expected a `.chain`, `.urdf` or `.xml` (URDF or MJCF) file"),
        "{stderr}"
    );
}

#[test]
fn parse_error_names_line_and_column() {
    let dir = std::env::temp_dir().join(format!("articulated-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.chain");
    std::fs::write(
        &path,
        "chain Bad {\n    body b { mass: 1.0, inertia: diag(1.0, 1.0, 1.0) }\n    joint j: revolute(y) { parent: world, child: nobody }\n}\n",
    )
    .unwrap();
    let (ok, _, stderr) = eval(&[path.to_str().unwrap()]);
    assert!(!ok);
    // `nobody` is on line 3, column 50 (1-based).
    let expected = format!("{}:3:50:", path.display());
    assert!(
        stderr.contains(&expected),
        "expected `{expected}` in: {stderr}"
    );
    assert!(stderr.contains("nobody"), "{stderr}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn wrong_length_is_an_error() {
    let (ok, _, stderr) = eval(&["models/two_link.chain", "--q", "0.1,0.2"]);
    assert!(!ok);
    assert!(
        stderr.contains("--q has 2 values, but the model needs 6"),
        "{stderr}"
    );
}

#[test]
fn non_finite_value_is_an_error() {
    for bad in ["nan", "inf", "-inf"] {
        let q = format!("0,0,{bad},0,0,0");
        let (ok, _, stderr) = eval(&["models/two_link.chain", "--q", &q]);
        assert!(!ok, "{bad} accepted");
        assert!(
            stderr.contains("--q[2]") && stderr.contains("finite"),
            "{stderr}"
        );
    }
    let (ok, _, stderr) = eval(&["models/two_link.chain", "--v", "0,0,zero,0,0,0"]);
    assert!(!ok);
    assert!(
        stderr.contains("--v[2] = `zero` is not a number"),
        "{stderr}"
    );
}

#[test]
fn floating_on_a_chain_file_is_an_error() {
    let (ok, _, stderr) = eval(&["models/two_link.chain", "--floating"]);
    assert!(!ok);
    assert!(stderr.contains("free base"), "{stderr}");
}

#[test]
fn every_shipped_model_evaluates() {
    for m in articulated_models::ALL {
        for path in std::iter::once(m.chain).chain(m.urdf) {
            let (ok, stdout, stderr) = eval(&[path]);
            assert!(ok, "{path}: {stderr}");
            let out: Value = serde_json::from_str(&stdout).unwrap();
            assert!(flat(&out["qdd"]).iter().all(|x| x.is_finite()), "{path}");
        }
    }
}

/// `count` numbers in `[-scale, scale)` from a seeded stream, as `--x` text.
fn pseudo_random(rng: &mut Rng, count: usize, scale: f64) -> String {
    (0..count)
        .map(|_| format!("{:e}", rng.symmetric(scale)))
        .collect::<Vec<_>>()
        .join(",")
}

/// `q` (as `--q` text) with each quaternion of `model` divided by its norm: the states of
/// a configuration space where quaternions are unit.
fn unit_quaternions(model: &articulated_dynamics::model::Model, q: &str) -> String {
    use articulated_dynamics::model::JointKind;
    let mut q: Vec<f64> = q.split(',').map(|x| x.parse().unwrap()).collect();
    let mut at = 0;
    for j in &model.joints {
        let w = match j.kind {
            JointKind::SphericalQuaternion => Some(at),
            JointKind::FreeQuaternion => Some(at + 3),
            _ => None,
        };
        if let Some(w) = w {
            let n = q[w..w + 4].iter().map(|x| x * x).sum::<f64>().sqrt();
            q[w..w + 4].iter_mut().for_each(|x| *x /= n);
        }
        at += j.nq();
    }
    q.iter()
        .map(|x| format!("{x:e}"))
        .collect::<Vec<_>>()
        .join(",")
}

/// Every shipped model (`.chain` and `.urdf`, and the URDF under a free base) at the neutral
/// configuration and at three seeded states: for each, the `eval` arguments.
fn shipped_states() -> Vec<Vec<String>> {
    let mut rng = Rng::new(2005);
    let mut all = Vec::new();
    for m in articulated_models::ALL {
        let mut files: Vec<(&str, bool)> = vec![(m.chain, false)];
        if let Some(urdf) = m.urdf {
            files.push((urdf, false));
            files.push((urdf, true));
        }
        for (path, floating) in files {
            let model = articulated_codegen::load::load_model(Path::new(path), floating)
                .unwrap_or_else(|e| panic!("{e}"));
            let (nq, nv) = (model.nq(), model.nv());
            let mut base = vec![path.to_string()];
            if floating {
                base.push("--floating".to_string());
            }
            all.push(base.clone());
            for _ in 0..3 {
                let mut args = base.clone();
                for (flag, n, scale) in [("--q", nq, 1.0), ("--v", nv, 2.0), ("--a", nv, 3.0)] {
                    args.push(flag.to_string());
                    let mut x = pseudo_random(&mut rng, n, scale);
                    if flag == "--q" {
                        x = unit_quaternions(&model, &x);
                    }
                    args.push(x);
                }
                args.push("--tau".to_string());
                args.push(pseudo_random(&mut rng, nv, 10.0));
                all.push(args);
            }
        }
    }
    all
}

/// Runs both engines on `args`: (reference, symbolic), each (success, stdout, stderr).
type Run = (bool, String, String);
fn both_engines(args: &[String]) -> (Run, Run) {
    let mut args: Vec<&str> = args.iter().map(String::as_str).collect();
    let by_ref = eval(&args);
    args.extend(["--engine", "symbolic"]);
    (by_ref, eval(&args))
}

/// The generator's expression graphs (`--engine symbolic`) against the reference on every
/// shipped model and state where the reference's M(q) is regular: every output to 1e-12
/// relative (q̈ to `2e-16·cond(M)` where that is larger). This checks the generator's graphs
/// without compiling them. (States where the reference finds M(q) singular are the next test's.)
#[test]
fn symbolic_engine_agrees_with_the_reference() {
    let mut compared = 0;
    for args in shipped_states() {
        let what = args.join(" ");
        let ((ref_ok, by_ref, ref_err), (sym_ok, by_sym, sym_err)) = both_engines(&args);
        if !ref_ok {
            assert!(ref_err.contains("singular"), "{what}: {ref_err}");
            continue;
        }
        assert!(sym_ok, "{what}: {sym_err}");
        let (r, s): (Value, Value) = (
            serde_json::from_str(&by_ref).unwrap(),
            serde_json::from_str(&by_sym).unwrap(),
        );
        assert_eq!(r["nq"], s["nq"], "{what}");
        assert_eq!(r["nv"], s["nv"], "{what}");
        for key in [
            "mass_matrix",
            "bias",
            "gravity",
            "tau",
            "qdd",
            "center_of_mass",
            "center_of_mass_velocity",
            "centroidal_momentum",
            "centroidal_momentum_rate",
            "kinetic_energy",
            "potential_energy",
            "coriolis_matrix",
        ] {
            let e = rel_err(&s[key], &r[key]);
            // q̈ solves with M: its rounding grows with M's condition number (a light foot
            // under a heavy body: 7e4), every other output is straight-line arithmetic.
            let tol = match (key, r["mass_matrix_condition"].as_f64()) {
                ("qdd", Some(cond)) => 1e-12f64.max(2e-16 * cond),
                _ => 1e-12,
            };
            assert!(e <= tol, "{what}: {key} differs by {e:e} relative");
        }
        compared += 1;
    }
    println!("{compared} states compared");
    assert!(compared >= 40, "only {compared} states compared");
}

/// Where the reference finds M(q) singular, the generated forward dynamics must refuse too.
///
/// Regression: on `double_pendulum.urdf --floating` (a massless URDF root under the free base,
/// so M(q) is singular everywhere) the generated CRBA + LᵀDL used to let a pivot of rounding
/// size pass its test (it was compared with its own unreduced `M_kk` only) and returned
/// q̈ ≈ 1e16. Every pivot is now also compared with the trace of M.
#[test]
fn symbolic_engine_refuses_where_the_reference_does() {
    let mut missed = Vec::new();
    for args in shipped_states() {
        let ((ref_ok, _, _), (sym_ok, by_sym, _)) = both_engines(&args);
        if !ref_ok && sym_ok {
            let qdd = serde_json::from_str::<Value>(&by_sym).unwrap()["qdd"].clone();
            missed.push(format!("{}: qdd {qdd}", args.join(" ")));
        }
    }
    assert!(missed.is_empty(), "{}", missed.join("\n"));
}

#[test]
fn symbolic_engine_refuses_a_singular_mass_matrix() {
    // Gimbal lock: the ankle's `xyz` angles with the pitch at π/2 put the first and last axes
    // on one line, so M(q) is singular. Both engines refuse and name the joint.
    let args = [
        "models/inverted_pendulum.chain",
        "--q",
        "0,1.5707963267948966,0",
    ];
    let (ok, stdout, ref_err) = eval(&args);
    assert!(!ok, "the reference printed {stdout}");
    assert!(
        ref_err.contains("the mass matrix is singular here: at joint `ankle`"),
        "{ref_err}"
    );
    let mut symbolic = args.to_vec();
    symbolic.extend(["--engine", "symbolic"]);
    let (ok, stdout, stderr) = eval(&symbolic);
    assert!(!ok, "printed {stdout}");
    assert!(
        stderr.contains("the mass matrix is singular here: at joint `ankle`"),
        "{stderr}"
    );
}

/// At exact gimbal lock forward dynamics cannot be computed, but everything else can: `eval`
/// prints it all, with `qdd` as an error object naming the pivot, reports the failure on stderr
/// and exits with failure, for both engines. `M` printed is singular to working precision
/// (its condition number, printed too, past 1e16), and gravity is the reference's.
#[test]
fn a_singular_state_prints_what_it_can_and_fails() {
    let q = format!("0.2,{},-0.3,0.1,0.4,0.2", std::f64::consts::FRAC_PI_2);
    for engine in ["reference", "symbolic"] {
        let (ok, stdout, stderr) = eval(&["models/two_link.chain", "--q", &q, "--engine", engine]);
        assert!(!ok, "{engine}: {stdout}");
        assert!(
            stderr.contains("`qdd`") && stderr.contains("pivot"),
            "{stderr}"
        );
        let out: Value = serde_json::from_str(&stdout).unwrap_or_else(|e| panic!("{e}: {stdout}"));
        let message = out["qdd"]["error"]
            .as_str()
            .unwrap_or_else(|| panic!("{stdout}"));
        assert!(message.contains("singular"), "{message}");
        assert!(
            out["mass_matrix_condition"]
                .as_f64()
                .is_some_and(|c| c > 1e16),
            "{stdout}"
        );
        let m = flat(&out["mass_matrix"]);
        assert_eq!(m.len(), 36);
        // At the lock the ankle's first and third axes coincide: rows 0 and 2 of M agree.
        for k in 0..6 {
            assert!((m[k] - m[12 + k]).abs() < 1e-12, "{stdout}");
        }
        let g = flat(&out["gravity"]);
        let reference = articulated_dynamics::reference::Reference::new(
            &articulated_codegen::load::load_model(&repo().join("models/two_link.chain"), false)
                .unwrap(),
        )
        .unwrap()
        .gravity(
            &q.split(',')
                .map(|x| x.parse().unwrap())
                .collect::<Vec<f64>>(),
        )
        .unwrap();
        for (a, b) in g.iter().zip(reference.iter()) {
            assert!((a - b).abs() < 1e-10, "{stdout}");
        }
    }
}

/// `--floating=quaternion` puts Pinocchio's free flyer under a URDF root: 7 more positions and 6
/// more velocities, and at rest the same joint gravity as the Euler base; a base of another name
/// is an error.
#[test]
fn a_quaternion_floating_base() {
    let (ok, stdout, stderr) = eval(&["models/arm7.urdf", "--floating=quaternion"]);
    assert!(ok, "{stderr}");
    let flyer: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(
        (flyer["nq"].as_u64(), flyer["nv"].as_u64()),
        (Some(14), Some(13))
    );
    let (ok, stdout, stderr) = eval(&["models/arm7.urdf", "--floating"]);
    assert!(ok, "{stderr}");
    let euler: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(
        (euler["nq"].as_u64(), euler["nv"].as_u64()),
        (Some(13), Some(13))
    );
    let (gf, ge) = (flat(&flyer["gravity"]), flat(&euler["gravity"]));
    for k in 6..13 {
        assert!(
            (gf[k] - ge[k]).abs() < 1e-12 * (1.0 + ge[k].abs()),
            "{gf:?} vs {ge:?}"
        );
    }
    let (ok, _, stderr) = eval(&["models/arm7.urdf", "--floating=quat"]);
    assert!(
        !ok && stderr.contains("expected `euler` or `quaternion`"),
        "{stderr}"
    );
}

/// A URDF with mimic joints: the couplings are printed, both engines agree, and the kinetic
/// energy is the independent tree's at the coupled state (`q_tree = G·q + o`, `v_tree = G·v`).
#[test]
fn mimic_joints_are_printed_and_couple_the_tree() {
    let (q, v) = ("0.1,0.2,0.3,0.02,0.4", "1,-1,0.5,0.1,2");
    // Tree order: shoulder, elbow, wrist, finger_left, left_tip = −0.5·elbow + 0.3,
    // finger_right = finger_left, right_knuckle, thumb = 12·finger_left − 0.2.
    let (q_tree, v_tree) = (
        "0.1,0.2,0.3,0.02,0.2,0.02,0.4,0.04",
        "1,-1,0.5,0.1,0.5,0.1,2,1.2",
    );
    let file = "tests/data/gripper_mimic.urdf";
    let mut outputs = Vec::new();
    for engine in ["reference", "symbolic"] {
        let (ok, out, stderr) = eval(&[file, "--q", q, "--v", v, "--engine", engine]);
        assert!(ok, "{stderr}");
        outputs.push(serde_json::from_str::<Value>(&out).unwrap());
    }
    let mimic = outputs[0]["mimic"].as_array().unwrap();
    assert_eq!(mimic.len(), 3);
    assert_eq!(
        (&mimic[0]["joint"], &mimic[0]["follows"]),
        (&"left_tip".into(), &"elbow".into())
    );
    assert_eq!(
        (&mimic[2]["multiplier"], &mimic[2]["offset"]),
        (&12.0.into(), &(-0.2).into())
    );
    assert_eq!(outputs[0]["nv"], 5);
    for key in ["mass_matrix", "tau", "qdd", "kinetic_energy"] {
        let e = rel_err(&outputs[1][key], &outputs[0][key]);
        assert!(e < 1e-12, "{key}: symbolic vs reference {e:e}");
    }
    let independent = "tests/data/gripper_independent.urdf";
    let (ok, tree, stderr) = eval(&[independent, "--q", q_tree, "--v", v_tree]);
    assert!(ok, "{stderr}");
    let tree: Value = serde_json::from_str(&tree).unwrap();
    let e = rel_err(&outputs[0]["kinetic_energy"], &tree["kinetic_energy"]);
    assert!(e < 1e-14, "kinetic energy vs the independent tree: {e:e}");
}

/// A real robot file whose inertias no rigid body has (Romeo's shoulder and elbow break the
/// triangle inequality) loads with a warning per body on stderr, at its line; `--strict`
/// refuses it with the same lines as errors; `--balance-inertia` evens them out silently.
#[test]
fn warnings_reach_stderr_and_strict_refuses_them() {
    let romeo = "tests/data/real_robots/urdf/romeo_description/urdf/romeo_small.urdf";
    let (ok, stdout, stderr) = eval(&[romeo]);
    assert!(ok, "{stderr}");
    assert!(serde_json::from_str::<Value>(&stdout).is_ok());
    let warnings: Vec<&str> = stderr
        .lines()
        .filter(|l| l.contains(": warning: "))
        .collect();
    assert_eq!(warnings.len(), 2, "{stderr}");
    let warned =
        |line: usize, link: &str| format!("{romeo}:{line}: warning: inertia of link `{link}`");
    assert!(
        warnings[0].starts_with(&warned(547, "RShoulderYawLink")),
        "{stderr}"
    );
    assert!(
        warnings[1].starts_with(&warned(585, "RElbowYawLink")),
        "{stderr}"
    );
    let (ok, stdout, stderr) = eval(&[romeo, "--strict"]);
    assert!(!ok && stdout.is_empty(), "{stdout}");
    assert_eq!(
        stderr.matches(": error: inertia of link `").count(),
        2,
        "{stderr}"
    );
    let (ok, _, stderr) = eval(&[romeo, "--balance-inertia"]);
    assert!(ok, "{stderr}");
    assert!(!stderr.contains("warning"), "{stderr}");
}

/// A model where nothing moves (a quadrotor's links all fixed, on a fixed base) evaluates to
/// empty results, not an error.
#[test]
fn a_model_where_nothing_moves_evaluates_to_empty_results() {
    let quadrotor = "tests/data/real_robots/urdf/hector_description/robots/quadrotor_base.urdf";
    let (ok, stdout, stderr) = eval(&[quadrotor]);
    assert!(ok, "{stderr}");
    let v: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!((v["nq"].as_u64(), v["nv"].as_u64()), (Some(0), Some(0)));
    for key in [
        "mass_matrix",
        "bias",
        "gravity",
        "tau",
        "qdd",
        "coriolis_matrix",
    ] {
        assert_eq!(v[key], Value::Array(Vec::new()), "{key}");
    }
    assert_eq!(v["center_of_mass"], Value::Null);
    assert_eq!(v["kinetic_energy"].as_f64(), Some(0.0));
}

/// `eval` names every entry of `q` and `v` (issue 31): the joint and, for a joint of several
/// coordinates, its component, in the order of the vectors; mimic joints have none.
#[test]
fn coordinates_are_named() {
    let names = |args: &[&str]| {
        let (ok, stdout, stderr) = eval(args);
        assert!(ok, "{stderr}");
        let v: Value = serde_json::from_str(&stdout).unwrap();
        let list = |k: &str| -> Vec<String> {
            v["coordinates"][k]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_str().unwrap().to_string())
                .collect()
        };
        let (q, vv) = (list("q"), list("v"));
        assert_eq!(q.len() as u64, v["nq"].as_u64().unwrap());
        assert_eq!(vv.len() as u64, v["nv"].as_u64().unwrap());
        (q, vv)
    };
    // Two spherical joints in Euler angles `xyz`: the angles in their sequence.
    let (q, v) = names(&["models/two_link.chain"]);
    assert_eq!(
        q,
        ["ankle.rx", "ankle.ry", "ankle.rz", "hip.rx", "hip.ry", "hip.rz"]
    );
    assert_eq!(v, q);
    // A quaternion free base under a URDF: scalar first in q, linear then angular in v.
    let (q, v) = names(&["models/arm7.urdf", "--floating=quaternion"]);
    let base_q = [
        "root_joint.x",
        "root_joint.y",
        "root_joint.z",
        "root_joint.qw",
    ];
    assert_eq!(q[..4], base_q);
    assert_eq!(q[7], "j1");
    assert_eq!(
        v[..6],
        [
            "root_joint.vx",
            "root_joint.vy",
            "root_joint.vz",
            "root_joint.wx",
            "root_joint.wy",
            "root_joint.wz"
        ]
    );
    assert_eq!(v[6], "j1");
    // Mimic joints take no coordinate.
    let (q, _) = names(&["tests/data/gripper_mimic.urdf"]);
    assert_eq!(
        q,
        ["shoulder", "elbow", "wrist", "finger_left", "right_knuckle"]
    );
}

/// `--q-order pinocchio`: Pinocchio's own states of TIAGo on a free flyer (its quaternion
/// `[qx, qy, qz, qw]`, its continuous wheels as `(cos θ, sin θ)`, its joints in the order of
/// their names: the wheels last where the file has them first) go in as Pinocchio wrote them,
/// and `tau` comes out as Pinocchio's `rnea` gave it, entry by entry; the names say the
/// layout. Without the option the same numbers are refused (the lengths differ).
#[test]
fn pinocchio_layout_in_and_out() {
    let text =
        std::fs::read_to_string(repo().join("tests/data/pinocchio_layout/pinocchio-layout.json"))
            .unwrap();
    let json: Value = serde_json::from_str(&text).unwrap();
    let m = &json["models"]["tiago"];
    let urdf = repo().join("tests/data").join(m["urdf"].as_str().unwrap());
    let urdf = urdf.to_str().unwrap();
    for s in m["states"].as_array().unwrap() {
        let (q, v, a) = (csv(&s["q"]), csv(&s["v"]), csv(&s["a"]));
        let args = [
            urdf,
            "--floating=quaternion",
            "--q-order",
            "pinocchio",
            "--q",
            &q,
            "--v",
            &v,
            "--a",
            &a,
        ];
        let (ok, stdout, stderr) = eval(&args);
        assert!(ok, "{stderr}");
        let out: Value = serde_json::from_str(&stdout).unwrap();
        let e = rel_err(&out["tau"], &s["tau"]);
        assert!(e < 1e-10, "tau off by {e:.1e}");
        assert_eq!(out["nq"], m["nq"]);
        let names = &out["coordinates"]["q"];
        assert_eq!(names[3], "root_joint.qx");
        assert_eq!(names[6], "root_joint.qw");
        let last: Vec<&str> = names.as_array().unwrap()[53..]
            .iter()
            .map(|x| x.as_str().unwrap())
            .collect();
        assert_eq!(
            last,
            [
                "wheel_left_joint.cos",
                "wheel_left_joint.sin",
                "wheel_right_joint.cos",
                "wheel_right_joint.sin"
            ]
        );
        let (ok, _, stderr) = eval(
            &args[..2]
                .iter()
                .chain(&args[4..])
                .copied()
                .collect::<Vec<_>>(),
        );
        assert!(!ok && stderr.contains("--q has 57 values"), "{stderr}");
    }
}

/// `--frames`: every frame of every shipped model (each body, each URDF link merged into its
/// body), by both engines: the generator's graphs (`trace::frames`) against the reference
/// (itself checked against Pinocchio), placements, velocities, accelerations, Jacobians and
/// their time variations, to 1e-12 of each value's largest entry (or absolutely, below 1).
#[test]
fn frames_by_both_engines_agree() {
    let mut compared = 0;
    for args in shipped_states()
        .into_iter()
        .step_by(4)
        .chain(shipped_states().into_iter().skip(1).step_by(4))
    {
        let floating = args.iter().any(|a| a == "--floating");
        let model = articulated_codegen::load::load_model(Path::new(&args[0]), floating).unwrap();
        let frames: Vec<&str> = model.frame_names().collect();
        let mut args = args.clone();
        args.push("--frames".into());
        args.push(frames.join(","));
        let ((ref_ok, by_ref, ref_err), (sym_ok, by_sym, sym_err)) = both_engines(&args);
        let what = &args[0];
        if !ref_ok && ref_err.contains("singular") {
            continue;
        }
        assert!(ref_ok && sym_ok, "{what}: {ref_err} {sym_err}");
        let (r, s): (Value, Value) = (
            serde_json::from_str(&by_ref).unwrap(),
            serde_json::from_str(&by_sym).unwrap(),
        );
        for name in &frames {
            let (a, b) = (&r["frames"][*name], &s["frames"][*name]);
            let per_frame = ["jacobian", "jacobian_time_variation"]
                .into_iter()
                .flat_map(|k| {
                    ["local", "world", "local_world_aligned"]
                        .map(|f| (format!("{k} {f}"), &b[k][f], &a[k][f]))
                });
            let quantities = ["rotation", "translation", "velocity", "acceleration"]
                .map(|k| (k.to_string(), &b[k], &a[k]))
                .into_iter()
                .chain(per_frame);
            for (key, ours, theirs) in quantities {
                let (x, y) = (flat(ours), flat(theirs));
                assert_eq!(x.len(), y.len(), "{what} `{name}` {key}");
                let scale = y.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                let e = x
                    .iter()
                    .zip(&y)
                    .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()))
                    / scale;
                assert!(e < 1e-12, "{what} frame `{name}` {key}: off by {e:.1e}");
            }
            compared += 1;
        }
    }
    assert!(compared > 100, "{compared}");
}

/// `--contacts` (and `--restitution`) against Pinocchio 4.1's `constraintDynamics` and
/// `impulseDynamics` (`tests/data/pinocchio_constraints/`): the humanoid on its free flyer on
/// two flat feet, one foot, a foot and a hand, a hand alone, and the arm with its flange welded
/// or held at a point, by both engines; `q̈` relative to its largest entry, forces and
/// impulses relative to `m·‖g‖` and to their largest entry.
#[test]
fn contacts_agree_with_pinocchio_by_both_engines() {
    let path = repo().join("tests/data/pinocchio_constraints/pinocchio-constraints.json");
    let json: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let mut compared = 0;
    for (name, case) in json["cases"].as_object().unwrap() {
        if !case["baumgarte"].is_null() {
            continue; // eval's reference is the current placement: e = 0.
        }
        let model = case["model"].as_str().unwrap();
        let entry = &json["models"][model];
        let weight = entry["mass"].as_f64().unwrap() * 9.81;
        let contacts: Vec<String> = case["contacts"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| {
                format!(
                    "{}:{}",
                    c["frame"].as_str().unwrap(),
                    c["kind"].as_str().unwrap()
                )
            })
            .collect();
        let frames: Vec<&str> = case["contacts"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c["frame"].as_str().unwrap())
            .collect();
        let urdf = repo().join(entry["urdf"].as_str().unwrap());
        for (k, state) in case["states"].as_array().unwrap().iter().enumerate() {
            let impulse = state["impulses"]
                .as_array()
                .and_then(|i| i.iter().find(|i| i["restitution"] == 0.5));
            let mut args: Vec<String> = vec![
                urdf.to_str().unwrap().into(),
                "--q".into(),
                csv(&state["q"]),
                "--v".into(),
                csv(&state["v"]),
                "--tau".into(),
                csv(&state["tau"]),
                "--contacts".into(),
                contacts.join(","),
            ];
            if entry["floating"] == "quaternion" {
                args.push("--floating=quaternion".into());
            }
            if impulse.is_some() {
                args.extend(["--restitution".into(), "0.5".into()]);
            }
            // The symbolic engine traces the whole humanoid: its first state only.
            let engines: &[&str] = if k == 0 {
                &["reference", "symbolic"]
            } else {
                &["reference"]
            };
            for engine in engines {
                let mut args: Vec<&str> = args.iter().map(String::as_str).collect();
                args.extend(["--engine", engine]);
                let (ok, out, err) = eval(&args);
                assert!(ok, "{name} state {k} {engine}: {err}");
                let ours: Value = serde_json::from_str(&out).unwrap();
                let c = &ours["constrained"];
                let e_qdd = rel_err(&c["qdd"], &state["qdd"]);
                let mut e_f = 0.0f64;
                for f in &frames {
                    let (a, b) = (flat(&c["forces"][f]), flat(&state["forces"][f]));
                    assert_eq!(a.len(), b.len());
                    e_f = a
                        .iter()
                        .zip(&b)
                        .fold(e_f, |m, (x, y)| m.max((x - y).abs() / weight));
                }
                assert!(
                    e_qdd < 1e-9 && e_f < 1e-9,
                    "{name} state {k} {engine}: q̈ {e_qdd:.1e}, forces {e_f:.1e}"
                );
                assert!(c["residual"].as_f64().unwrap() < 1e-9, "{name}: {c}");
                if let Some(i) = impulse {
                    let ours = &ours["impulse"];
                    let e_v = rel_err(&ours["v_plus"], &i["v_plus"]);
                    let e_p = frames
                        .iter()
                        .map(|f| rel_err(&ours["impulses"][f], &i["impulses"][f]))
                        .fold(0.0f64, f64::max);
                    assert!(
                        e_v < 1e-9 && e_p < 1e-9,
                        "{name} state {k} {engine}: v⁺ {e_v:.1e}, impulses {e_p:.1e}"
                    );
                }
                compared += 1;
            }
        }
    }
    assert_eq!(compared, 24);
}

/// `--contacts` refuses a bad list, an unknown frame, a bad restitution or gains at the
/// argument; redundant contacts name the contact.
#[test]
fn bad_contacts_are_errors() {
    let arm = repo().join("models/arm7.chain");
    let arm = arm.to_str().unwrap();
    for (args, expected) in [
        (vec!["--contacts", "link7:plane"], "expected FRAME:KIND"),
        (vec!["--contacts", "link7"], "expected FRAME:KIND"),
        (vec!["--contacts", "hand:point"], "hand"),
        (
            vec!["--contacts", "link7:point", "--restitution", "-1"],
            "--restitution",
        ),
        (
            vec!["--contacts", "link7:point", "--baumgarte", "1"],
            "baumgarte",
        ),
        (
            vec!["--contacts", "link7:six_d,link7:point"],
            "row 0 of the contact on `link7` depends on the rows before it",
        ),
    ] {
        // Away from the upright arm, where the flange's Jacobian loses rank.
        let mut all = vec![arm, "--q", "0.1,0.5,0.3,-0.8,0.5,0.6,0.7"];
        all.extend(&args);
        let (ok, out, err) = eval(&all);
        assert!(!ok, "{args:?}: {out}");
        assert!(err.contains(expected), "{args:?}: {err}");
    }
}
