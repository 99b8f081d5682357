//! `articulated export --mjcf` end to end: the file it writes loads back (through the MJCF front
//! end) as the same dynamics, `eval` for `eval` at one state; on stdout without `--out`; errors
//! on stderr. (MuJoCo's own values of the exported shipped models are checked in
//! `tests/tests/mjcf.rs`.)

mod common;

use serde_json::Value;

fn numbers(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(a) => a.iter().flat_map(numbers).collect(),
        Value::Number(n) => vec![n.as_f64().unwrap()],
        _ => Vec::new(),
    }
}

#[test]
fn an_exported_model_evaluates_as_the_original() {
    let dir = std::env::temp_dir().join(format!("articulated-export-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cases: [(&str, &[&str], &str); 2] = [
        ("models/two_link.chain", &[], "0.1,-0.2,0.3,0.4,0.5,-0.6"),
        (
            "models/humanoid.urdf",
            &["--floating=quaternion"],
            "0.1,0.2,0.9,0.9,0.1,-0.3,0.3,0.1,-0.2,0.3,0.4,0.5,-0.6,0.1,0.2,0.3,0.4,0.5,0.6,0.7,\
             0.8,-0.1,-0.2,-0.3,-0.4,-0.5,-0.6,-0.7,-0.8,0.05,0.15,0.25,0.35,0.45,0.55,0.65,0.75,0.85",
        ),
    ];
    for (model, flags, q) in cases {
        let out = dir.join("exported.xml");
        let out_s = out.to_str().unwrap();
        let mut args = vec![model, "--mjcf", "--out", out_s];
        args.extend_from_slice(flags);
        let (ok, stdout, stderr) = common::run("export", &args);
        assert!(ok && stdout.is_empty(), "{stderr}");
        let mut original = vec![model, "--q", q];
        original.extend_from_slice(flags);
        let (ok, theirs, stderr) = common::run("eval", &original);
        assert!(ok, "{stderr}");
        let (ok, ours, stderr) = common::run("eval", &[out_s, "--q", q]);
        assert!(ok, "{stderr}");
        let (theirs, ours): (Value, Value) = (
            serde_json::from_str(&theirs).unwrap(),
            serde_json::from_str(&ours).unwrap(),
        );
        for key in ["mass_matrix", "bias", "gravity", "tau", "qdd"] {
            let (a, b) = (numbers(&ours[key]), numbers(&theirs[key]));
            assert_eq!(a.len(), b.len(), "{model} {key}");
            let scale = b.iter().fold(1e-300f64, |m, x| m.max(x.abs()));
            let e = a
                .iter()
                .zip(&b)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
                / scale;
            assert!(e < 1e-12, "{model} {key}: relative error {e:e}");
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn export_prints_mjcf_on_stdout_and_refuses_what_it_cannot_read() {
    let (ok, stdout, stderr) = common::run("export", &["models/double_pendulum.chain", "--mjcf"]);
    assert!(ok, "{stderr}");
    assert!(stdout.starts_with(
        "<!-- Written by the MJCF export of articulated from models/double_pendulum.chain. -->\n<mujoco"
    ));
    let (ok, _, stderr) = common::run("export", &["models/missing.chain", "--mjcf"]);
    assert!(!ok && stderr.contains("missing.chain"), "{stderr}");
    let (ok, _, stderr) = common::run("export", &["models/double_pendulum.chain"]);
    assert!(!ok && stderr.contains("--mjcf"), "{stderr}");
    let (ok, _, stderr) = common::run("export", &["models/payload.chain", "--mjcf"]);
    assert!(
        ok && stderr.contains("note: parameters written at their defaults"),
        "{stderr}"
    );
}
