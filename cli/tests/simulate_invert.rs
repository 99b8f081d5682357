//! `articulated simulate` and `articulated invert`, end to end through the binary: the trajectory
//! file's form, its physics (energy kept by RK4, checked with the reference), the couples
//! recovered from it (zero for a chain left to itself), the sidecars naming every column, a
//! plot, every bad input giving a message, a non-zero exit and no file, a fault in a run
//! keeping the states before it, and the note on limits left without `--drives`.

mod common;

use std::path::{Path, PathBuf};

use articulated::reference::Reference;
use articulated_codegen::load::load_model;
use common::{repo, run};

/// A fresh directory for one test's files.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("articulated-cli-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The rows of a CSV file as numbers, after its header.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

/// A JSON file.
fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// A sidecar's columns as `[header, name, unit]`.
fn columns(sidecar: &serde_json::Value) -> Vec<[String; 3]> {
    sidecar["columns"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| ["header", "name", "unit"].map(|k| c[k].as_str().unwrap().to_string()))
        .collect()
}

#[test]
fn simulate_writes_the_trajectory_and_rk4_keeps_the_energy() {
    let dir = scratch("simulate");
    let (out, plot) = (dir.join("swing.csv"), dir.join("swing.svg"));
    // The two-link hanging down (roll π) and swinging: no gimbal lock on the way.
    let (ok, stdout, stderr) = run(
        "simulate",
        &[
            "models/two_link.chain",
            "--t-end",
            "2",
            "--dt",
            "0.001",
            "--integrator",
            "rk4",
            "--q0",
            "3.0,0.2,0,0,-0.3,0",
            "--v0",
            "0,0,0.5,0,0,0",
            "--out",
            out.to_str().unwrap(),
            "--plot",
            plot.to_str().unwrap(),
        ],
    );
    assert!(ok, "{stderr}");
    assert!(stdout.contains("2001 states"), "{stdout}");
    let (header, rows) = read_csv(&out);
    let want: Vec<String> = std::iter::once("t".to_string())
        .chain((0..6).map(|i| format!("q{i}")))
        .chain((0..6).map(|i| format!("v{i}")))
        .collect();
    assert_eq!(header, want);
    assert_eq!(
        rows.len(),
        2001,
        "one row per step, the initial state included"
    );
    assert_eq!(rows[0][1..7], [3.0, 0.2, 0.0, 0.0, -0.3, 0.0]);
    assert!((rows[2000][0] - 2.0).abs() < 1e-12);
    // Energy, by the reference, kept to RK4's accuracy at this step.
    let model = load_model(&repo().join("models/two_link.chain"), false).unwrap();
    let r = Reference::new(&model).unwrap();
    let energy = |row: &[f64]| {
        r.kinetic_energy(&row[1..7], &row[7..13]).unwrap() + r.potential_energy(&row[1..7]).unwrap()
    };
    let (e0, swing) = (
        energy(&rows[0]),
        r.kinetic_energy(&rows[0][1..7], &[0.0, 0.0, 0.5, 0.0, 0.0, 0.0])
            .unwrap(),
    );
    let drift = rows
        .iter()
        .map(|row| (energy(row) - e0).abs())
        .fold(0.0, f64::max);
    assert!(
        drift < 1e-6 * (e0.abs() + swing),
        "energy drifts by {drift:e} J"
    );
    let svg = std::fs::read_to_string(&plot).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("energy"));
    // Issue 31: titled by the chain's name, not by the path; curves labelled by joint.
    assert!(svg.contains("TwoLink: angles") && svg.contains("TwoLink: energy"));
    assert!(!svg.contains(dir.to_str().unwrap()));
    assert!(
        svg.contains("\nhip.ry\n</text>"),
        "a legend names the coordinates"
    );
    // The sidecar names every column, as written out here from the description's joints
    // (`ankle` and `hip`, Euler angles `xyz`).
    let sidecar = read_json(&dir.join("swing.csv.json"));
    assert_eq!(sidecar["model"]["file"], "models/two_link.chain");
    assert_eq!(sidecar["model"]["name"], "TwoLink");
    let angles = [
        "ankle.rx", "ankle.ry", "ankle.rz", "hip.rx", "hip.ry", "hip.rz",
    ];
    let column = |header: String, name: &str, unit: &str| [header, name.into(), unit.into()];
    let mut want = vec![column("t".into(), "time", "s")];
    for (i, a) in angles.iter().enumerate() {
        want.push(column(format!("q{i}"), a, "rad"));
    }
    for (i, a) in angles.iter().enumerate() {
        want.push(column(format!("v{i}"), a, "rad/s"));
    }
    assert_eq!(columns(&sidecar), want);
    assert_eq!(sidecar["integrator"], "rk4");
    assert_eq!(sidecar["dt"], 0.001);
    assert_eq!(sidecar["rows"], 2001);
    assert_eq!(sidecar["t_last"], 2.0);
    assert_eq!(
        sidecar["outcome"],
        serde_json::json!({"status": "completed"})
    );
    // Files as any other the user makes (0o666 less the umask), not owner-only.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        let normal = dir.join("normal");
        std::fs::write(&normal, "x").unwrap();
        for p in [&out, &plot, &dir.join("swing.csv.json")] {
            assert_eq!(mode(p), mode(&normal), "{}", p.display());
        }
    }

    // The couples behind a motion without forces are zero, to the differentiation's accuracy
    // (against the couples gravity alone would need: m·g·l ≈ 400 N·m).
    let couples = dir.join("couples.csv");
    let (ok, stdout, stderr) = run(
        "invert",
        &[
            "models/two_link.chain",
            out.to_str().unwrap(),
            "--out",
            couples.to_str().unwrap(),
        ],
    );
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("couples at 1991 of 2001 samples"),
        "{stdout}"
    );
    let (header, rows) = read_csv(&couples);
    assert_eq!(header[0], "t");
    assert_eq!(
        header[1..],
        ["tau0", "tau1", "tau2", "tau3", "tau4", "tau5"]
    );
    // Its sidecar: the couples on the same coordinates, in N·m.
    let sidecar = read_json(&dir.join("couples.csv.json"));
    let mut want = vec![column("t".into(), "time", "s")];
    for (i, a) in angles.iter().enumerate() {
        want.push(column(format!("tau{i}"), a, "N·m"));
    }
    assert_eq!(columns(&sidecar), want);
    assert_eq!(sidecar["rows"], 1991);
    assert_eq!(sidecar["trajectory"], out.to_str().unwrap());
    let worst = rows
        .iter()
        .flat_map(|r| r[1..].to_vec())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(
        worst < 1e-3,
        "couples of an unforced motion up to {worst:e} N·m"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `--drives`: a damped pendulum released against its stop loses energy as `∫ d·v² dt` says
/// (checked step by step on the written trajectory) and stays at its stop; without the flag it
/// keeps its energy and swings through.
#[test]
fn simulate_with_drives_damps_and_stops() {
    let dir = scratch("drives");
    let chain = dir.join("pendulum.chain");
    std::fs::write(
        &chain,
        "chain Pendulum {\n\
         body bob { mass: 1.0, com: [0.0, 0.0, -1.0], inertia: diag(0.01, 0.01, 0.01) }\n\
         joint pivot: revolute(y) { parent: world, child: bob, damping: 0.2, lower: -0.5, upper: 0.5 }\n\
         }\n",
    )
    .unwrap();
    let model = load_model(&chain, false).unwrap();
    let r = Reference::new(&model).unwrap();
    let energy = |row: &[f64]| {
        r.kinetic_energy(&row[1..2], &row[2..3]).unwrap() + r.potential_energy(&row[1..2]).unwrap()
    };
    let simulate = |drives: bool, out: &Path| {
        let mut args = vec![
            chain.to_str().unwrap(),
            "--t-end",
            "3",
            "--dt",
            "0.0005",
            "--q0",
            "0.4",
            "--v0",
            "2.0",
            "--out",
            out.to_str().unwrap(),
        ];
        if drives {
            args.push("--drives");
        }
        let (ok, _, stderr) = run("simulate", &args);
        assert!(ok, "{stderr}");
        read_csv(out).1
    };
    let free = simulate(false, &dir.join("free.csv"));
    let e0 = energy(&free[0]);
    assert!(free.iter().all(|row| (energy(row) - e0).abs() < 1e-6));
    assert!(
        free.iter().any(|row| row[1] > 0.6),
        "without stops it swings past 0.5 rad"
    );

    let held = simulate(true, &dir.join("held.csv"));
    // Never deeper into the stop than the kinetic energy it can have there allows against
    // 1e4 N·m/rad: at most the initial one plus gravity's work over the full drop, 2·m·g·l.
    let kinetic = r.kinetic_energy(&[0.4], &[2.0]).unwrap() + 2.0 * 9.81;
    let deepest = held.iter().map(|row| row[1]).fold(f64::MIN, f64::max);
    assert!(
        deepest > 0.5 && deepest < 0.5 + (2.0 * kinetic / 1e4).sqrt(),
        "{deepest}"
    );
    // Inside the range only the damper works: the energy lost over each step is d·v²·dt.
    for pair in held.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        if a[1].abs() < 0.5 && b[1].abs() < 0.5 {
            let lost = energy(a) - energy(b);
            let damper = 0.2 * 0.5 * (a[2] * a[2] + b[2] * b[2]) * (b[0] - a[0]);
            assert!(
                (lost - damper).abs() < 1e-6,
                "{lost:e} vs {damper:e} at t = {}",
                a[0]
            );
        }
    }
    assert!(energy(held.last().unwrap()) < e0 - 0.5);
    std::fs::remove_dir_all(&dir).ok();
}

/// Runs a command that must fail; its stderr, after checking that `out` was not written.
fn fails(subcommand: &str, args: &[&str], out: &Path) -> String {
    let (ok, stdout, stderr) = run(subcommand, args);
    assert!(!ok, "succeeded: {stdout}");
    assert!(!out.exists(), "{} was written", out.display());
    stderr
}

#[test]
fn bad_input_is_an_error_and_leaves_no_file() {
    let dir = scratch("errors");
    let out = dir.join("out.csv");
    let o = out.to_str().unwrap();
    let write = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_owned()
    };
    let pendulum = "models/double_pendulum.chain";

    // invert: a field that is not a number names its line and column.
    let csv = write("nan.csv", "t,q0,q1\n0,0,0\n0.1,x,0\n");
    let e = fails("invert", &[pendulum, &csv, "--out", o], &out);
    assert!(e.contains("line 3") && e.contains("q0"), "{e}");
    // A row with the wrong number of fields.
    let csv = write("fields.csv", "t,q0,q1\n0,0,0\n0.1,0\n");
    let e = fails("invert", &[pendulum, &csv, "--out", o], &out);
    assert!(e.contains("line 3"), "{e}");
    // A non-finite sample.
    let csv = write("inf.csv", "t,q0,q1\n0,0,0\n0.1,inf,0\n");
    let e = fails("invert", &[pendulum, &csv, "--out", o], &out);
    assert!(e.contains("line 3"), "{e}");
    // Too short for the differentiation window (11 samples by default).
    let text: String = std::iter::once("t,q0,q1\n".to_string())
        .chain((0..5).map(|k| format!("{},0,0\n", k as f64 * 0.1)))
        .collect();
    let csv = write("short.csv", &text);
    let e = fails("invert", &[pendulum, &csv, "--out", o], &out);
    assert!(e.contains("5"), "{e}");
    // A missing q column.
    let csv = write("noq.csv", "t,q0\n0,0\n");
    let e = fails("invert", &[pendulum, &csv, "--out", o], &out);
    assert!(e.contains("`q1`"), "{e}");

    // simulate: an unknown integrator, a bad grid (a fault in a run: `a_fault_keeps_…`).
    let e = fails(
        "simulate",
        &[
            pendulum,
            "--t-end",
            "1",
            "--dt",
            "0.01",
            "--integrator",
            "leapfrog",
            "--out",
            o,
        ],
        &out,
    );
    assert!(e.contains("leapfrog"), "{e}");
    let e = fails(
        "simulate",
        &[pendulum, "--t-end", "1", "--dt", "-0.01", "--out", o],
        &out,
    );
    assert!(e.contains("--dt"), "{e}");
    // A light link against stiff stops, stepped far too long: the adaptive integrator takes
    // it through the stop (`a_fault_keeps_…` shows what a fixed step does).
    let light = write(
        "light.chain",
        "chain Light {\n\
         body a { mass: 0.01, com: [0.1, 0.0, 0.0], inertia: diag(1e-6, 1e-6, 1e-6) }\n\
         joint j: revolute(y) { parent: world, child: a, lower: -0.1, upper: 0.1 }\n}\n",
    );
    let (ok, stdout, stderr) = run(
        "simulate",
        &[
            &light,
            "--t-end",
            "1",
            "--dt",
            "0.001",
            "--drives",
            "--integrator",
            "dopri5",
            "--out",
            o,
        ],
    );
    assert!(ok, "{stderr}");
    assert!(stdout.contains("1001 states"), "{stdout}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Issue 31: a run that stops on a fault writes what it has, whole: the CSV (its usual
/// header) of every state up to the last good one, the sidecar naming the fault, the plot;
/// the exit status is non-zero and stderr says what failed and what was written.
#[test]
fn a_fault_keeps_the_trajectory_up_to_it() {
    let dir = scratch("fault");
    let (out, plot) = (dir.join("light.csv"), dir.join("light.svg"));
    let sidecar = dir.join("light.csv.json");
    // A light link thrown against stiff stops, stepped by Euler far too long for them: the
    // state runs away from the first contact on, until the acceleration overflows.
    let light = dir.join("light.chain");
    std::fs::write(
        &light,
        "chain Light {\n\
         body a { mass: 0.01, com: [0.1, 0.0, 0.0], inertia: diag(1e-6, 1e-6, 1e-6) }\n\
         joint j: revolute(y) { parent: world, child: a, lower: -0.1, upper: 0.1 }\n}\n",
    )
    .unwrap();
    let (ok, stdout, stderr) = run(
        "simulate",
        &[
            light.to_str().unwrap(),
            "--t-end",
            "1",
            "--dt",
            "0.001",
            "--integrator",
            "euler",
            "--drives",
            "--out",
            out.to_str().unwrap(),
            "--plot",
            plot.to_str().unwrap(),
        ],
    );
    assert!(!ok, "succeeded: {stdout}");
    // Said before the run, with the step that would do and the integrator that copes.
    assert!(
        stderr.contains("warning: joint `j`'s position stop is too stiff for --dt 0.001")
            && stderr.contains("--integrator dopri5"),
        "{stderr}"
    );
    // The fault, where the last good state stood, and what was written.
    assert!(
        stderr.contains("error: the simulation stopped")
            && stderr.contains("acceleration[0] is not finite")
            && stderr.contains("max |v| = ")
            && !stderr.contains("singular"),
        "{stderr}"
    );
    for file in [&out, &sidecar, &plot] {
        assert!(stderr.contains(file.to_str().unwrap()), "{stderr}");
    }
    let description = read_json(&sidecar);
    let fault = &description["outcome"];
    assert_eq!(fault["status"], "fault");
    assert_eq!(fault["message"], "acceleration[0] is not finite");
    let (t_fault, step) = (
        fault["t"].as_f64().unwrap(),
        fault["step"].as_u64().unwrap(),
    );
    assert!(t_fault > 0.0 && t_fault < 1.0, "{t_fault}");
    // The CSV: the interface's header, then the initial state and one row per completed step,
    // up to the step that failed, every number finite.
    let (header, rows) = read_csv(&out);
    assert_eq!(header, ["t", "q0", "v0"]);
    assert_eq!(rows.len() as u64, step + 1);
    assert_eq!(description["rows"], rows.len());
    for (k, row) in rows.iter().enumerate() {
        assert!((row[0] - k as f64 * 0.001).abs() < 1e-12, "{row:?}");
        assert!(row.iter().all(|x| x.is_finite()), "{row:?}");
    }
    let t_last = rows.last().unwrap()[0];
    assert!(t_last <= t_fault && t_fault - t_last < 0.001 + 1e-12);
    assert_eq!(description["t_last"], t_last);
    // What went wrong is in it: the link past its stop, then running away.
    assert!(rows.iter().any(|r| r[1].abs() > 0.1));
    assert!(rows.last().unwrap()[2].abs() > 1e6);
    let svg = std::fs::read_to_string(&plot).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("Light: angles"));

    // A fault in the first step (the inverted pendulum exactly at its Euler angles' gimbal
    // lock): the initial state alone.
    let (ok, _, stderr) = run(
        "simulate",
        &[
            "models/inverted_pendulum.chain",
            "--t-end",
            "1",
            "--dt",
            "0.01",
            "--q0",
            "0,1.5707963267948966,0",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(!ok);
    assert!(
        stderr.contains("t = ") && stderr.contains("singular"),
        "{stderr}"
    );
    let (_, rows) = read_csv(&out);
    assert_eq!(rows.len(), 1);
    assert_eq!(rows[0][1..4], [0.0, std::f64::consts::FRAC_PI_2, 0.0]);
    let description = read_json(&sidecar);
    assert_eq!(description["outcome"]["status"], "fault");
    assert_eq!(description["outcome"]["step"], 0);
    assert!(description["outcome"]["message"]
        .as_str()
        .unwrap()
        .contains("singular"));
    std::fs::remove_dir_all(&dir).ok();
}

/// Issue 31: without `--drives` a joint's limits are not applied; a joint that leaves its
/// range gets one note on stderr, with how far it went and when. A joint that stays in its
/// range gets none, nor does a run with `--drives`.
#[test]
fn leaving_a_range_without_drives_is_noted() {
    let dir = scratch("limits");
    let chain = dir.join("slider.chain");
    // Three bodies on the world: a finger falling along its slide from 0.02 m (its range
    // [0, 0.04] m), an arm swinging within ±0.5 rad (range ±3 rad), and a flap swinging
    // within ±0.1 rad, out of its range [-0.05, 0.2] rad on one side.
    std::fs::write(
        &chain,
        "chain Slider {\n\
         body finger { mass: 0.1, com: [0.0, 0.0, 0.0], inertia: diag(1e-4, 1e-4, 1e-4) }\n\
         joint finger1: prismatic(z) { parent: world, child: finger, lower: 0.0, upper: 0.04 }\n\
         body arm { mass: 1.0, com: [0.0, 0.0, -0.5], inertia: diag(0.01, 0.01, 0.01) }\n\
         joint shoulder: revolute(y) { parent: world, child: arm, lower: -3.0, upper: 3.0 }\n\
         body flap { mass: 1.0, com: [0.0, 0.0, -0.5], inertia: diag(0.01, 0.01, 0.01) }\n\
         joint hinge: revolute(x) { parent: world, child: flap, lower: -0.05, upper: 0.2 }\n\
         }\n",
    )
    .unwrap();
    let out = dir.join("out.csv");
    let simulate = |drives: bool| {
        let mut args = vec![
            chain.to_str().unwrap(),
            "--t-end",
            "1",
            "--dt",
            "0.001",
            "--q0",
            "0.02,0.5,0.1",
            "--out",
            out.to_str().unwrap(),
        ];
        if drives {
            args.extend(["--drives", "--integrator", "dopri5"]);
        }
        let (ok, _, stderr) = run("simulate", &args);
        assert!(ok, "{stderr}");
        stderr
    };
    let stderr = simulate(false);
    let notes: Vec<&str> = stderr.lines().filter(|l| l.starts_with("note: ")).collect();
    assert_eq!(notes.len(), 2, "{stderr}");
    // Free fall for 1 s: 0.02 − 9.81/2 m at the end.
    assert_eq!(
        notes[0],
        "note: joint `finger1` left its range [0, 0.04] m (reached -4.885 m at t = 1 s): \
         limits are applied only with --drives"
    );
    // The flap: its lowest angle and when, read from the trajectory.
    let (_, rows) = read_csv(&out);
    let lowest = rows.iter().min_by(|a, b| a[3].total_cmp(&b[3])).unwrap();
    assert!(lowest[3] < -0.09 && lowest[0] > 0.5, "{lowest:?}");
    let note = notes[1]
        .strip_prefix("note: joint `hinge` left its range [-0.05, 0.2] rad (reached ")
        .and_then(|n| n.strip_suffix(" s): limits are applied only with --drives"))
        .unwrap_or_else(|| panic!("{}", notes[1]));
    let (angle, t) = note.split_once(" rad at t = ").unwrap();
    let (angle, t): (f64, f64) = (angle.parse().unwrap(), t.parse().unwrap());
    assert!((angle - lowest[3]).abs() <= 5e-5, "{angle} vs {lowest:?}");
    assert_eq!(t, lowest[0]);
    assert!(!stderr.contains("shoulder"), "{stderr}");
    let stderr = simulate(true);
    assert!(!stderr.contains("note:"), "{stderr}");
    std::fs::remove_dir_all(&dir).ok();
}

/// `simulate --q-order pinocchio`: TIAGo's initial state as Pinocchio wrote it (free flyer
/// `[x, y, z, qx, qy, qz, qw]`, continuous wheels as `(cos θ, sin θ)`, its joint order) starts
/// the same run as the state in our layout, converted by hand here from Pinocchio's joint
/// table; a quaternion far from unit is refused before any step.
#[test]
fn simulate_takes_pinocchios_layout() {
    let dir = scratch("q-order");
    let text =
        std::fs::read_to_string(repo().join("tests/data/pinocchio_layout/pinocchio-layout.json"))
            .unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let m = &json["models"]["tiago"];
    let urdf = repo().join("tests/data").join(m["urdf"].as_str().unwrap());
    let urdf = urdf.to_str().unwrap();
    let q_pin: Vec<f64> = m["states"][0]["q"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    // Ours, by hand: the joints in the file's order (read off the model), each joint's
    // positions from Pinocchio's `idx_q`.
    let model = load_model(
        Path::new(urdf),
        articulated_codegen::load::FloatingBase::Quaternion,
    )
    .unwrap();
    let joints = m["joints"].as_array().unwrap();
    let mut q = Vec::new();
    for j in model.joints.iter().filter(|j| j.nv() > 0) {
        let p = joints
            .iter()
            .find(|p| p["name"] == j.name.as_str())
            .unwrap();
        let at = p["idx_q"].as_u64().unwrap() as usize;
        match p["nq"].as_u64().unwrap() {
            7 => q.extend([0, 1, 2, 6, 3, 4, 5].map(|k| q_pin[at + k])),
            2 => q.push(q_pin[at + 1].atan2(q_pin[at])),
            _ => q.push(q_pin[at]),
        }
    }
    let list = |x: &[f64]| {
        x.iter()
            .map(|x| format!("{x:?}"))
            .collect::<Vec<_>>()
            .join(",")
    };
    let simulate = |q0: &str, order: &str, out: &Path| {
        run(
            "simulate",
            &[
                urdf,
                "--floating=quaternion",
                "--t-end",
                "0.002",
                "--dt",
                "0.001",
                "--q-order",
                order,
                "--q0",
                q0,
                "--out",
                out.to_str().unwrap(),
            ],
        )
    };
    let (ours, theirs) = (dir.join("ours.csv"), dir.join("theirs.csv"));
    let (ok, _, stderr) = simulate(&list(&q), "articulated", &ours);
    assert!(ok, "{stderr}");
    let (ok, _, stderr) = simulate(&list(&q_pin), "pinocchio", &theirs);
    assert!(ok, "{stderr}");
    let (a, b) = (read_csv(&ours).1, read_csv(&theirs).1);
    let worst = a
        .iter()
        .flatten()
        .zip(b.iter().flatten())
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(worst < 1e-12, "{worst}");
    // Pinocchio's q read as ours: the lengths differ (57 against 56), refused.
    let (ok, _, stderr) = simulate(&list(&q_pin), "articulated", &dir.join("x.csv"));
    assert!(!ok && stderr.contains("--q0 has 57 values"), "{stderr}");
    // A quaternion scaled by 2 (our layout): refused, with its norm.
    let mut scaled = q.clone();
    for x in &mut scaled[3..7] {
        *x *= 2.0;
    }
    let (ok, _, stderr) = simulate(&list(&scaled), "articulated", &dir.join("y.csv"));
    assert!(!ok && stderr.contains("has norm 2.0000"), "{stderr}");
}

/// The cube's eight corners in `--contact-points` form.
fn block_corners() -> String {
    let mut points = Vec::new();
    for z in [-0.1, 0.1] {
        for y in [-0.1, 0.1] {
            for x in [-0.1, 0.1] {
                points.push(format!("block@{x}:{y}:{z}"));
            }
        }
    }
    points.join(",")
}

/// `simulate --ground`: the cube on a flat ground under a gravity tilted by θ (a slope of
/// angle θ, `tan θ = 1.2·μ`) slides with `a = g·(sin θ − μ·cos θ)`, and pushed along a level
/// ground stops after `v²/(2μg)`; the contact forces written on request hold its weight.
#[test]
fn simulate_with_a_ground_slides_and_stops_as_friction_says() {
    let dir = scratch("ground");
    let out = dir.join("block.csv");
    let corners = block_corners();
    let (g, mu) = (9.81_f64, 0.5_f64);
    let theta = (1.2 * mu).atan();
    let gravity = format!("{},0,{}", g * theta.sin(), -g * theta.cos());
    let common = |extra: &[&str]| {
        let mut args = vec![
            "models/block.chain",
            "--t-end",
            "0.5",
            "--dt",
            "0.001",
            "--q0",
            "0,0,0.1,1,0,0,0",
            "--ground",
            "0,0,1,0",
            "--contact-points",
            &corners,
            "--friction",
            "0.5",
            "--contact-forces",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let (ok, stdout, stderr) = run("simulate", &args);
        assert!(ok, "{stderr}");
        assert!(stdout.contains("with contacts"), "{stdout}");
        read_csv(&out)
    };
    let (header, rows) = common(&["--gravity", &gravity]);
    assert_eq!(header.len(), 1 + 7 + 6 + 8 * 3);
    assert_eq!(header[14], "f.block@-0.1:-0.1:-0.1.x");
    let last = rows.last().unwrap();
    let a = g * (theta.sin() - mu * theta.cos());
    // Symplectic Euler from rest: x_N = a·h²·N(N + 1)/2.
    let expected = 0.5 * a * 0.25 * (1.0 + 0.002);
    assert!(
        (last[1] - expected).abs() < 0.01 * expected,
        "{} against {expected}",
        last[1]
    );
    assert!((last[3] - 0.1).abs() < 1e-6, "height {}", last[3]);
    // The ground pushes back the gravity's normal part: m·g·cos θ.
    let normal: f64 = (0..8).map(|k| last[14 + 3 * k + 2]).sum();
    assert!((normal - g * theta.cos()).abs() < 1e-6, "{normal}");

    let (_, rows) = common(&["--v0", "2,0,0,0,0,0"]);
    let stop = rows.iter().find(|r| r[8] <= 1e-9).unwrap();
    let distance = 2.0 * 2.0 / (2.0 * mu * g);
    assert!(
        (stop[1] - distance).abs() < 0.01 * distance,
        "stopped after {}",
        stop[1]
    );
    assert!((rows.last().unwrap()[1] - stop[1]).abs() < 1e-9);

    // A scene declared in the description is stepped without `--ground`.
    let declared = dir.join("crate.chain");
    std::fs::write(
        &declared,
        "chain Crate {\n\
         grounds: [floor: [0.0, 0.0, 1.0, 0.0]];\n\
         spheres: [a: sphere(box_body, [-0.1, -0.1, -0.1], 0.0), b: sphere(box_body, [0.1, -0.1, -0.1], 0.0),\n\
                   c: sphere(box_body, [-0.1, 0.1, -0.1], 0.0), d: sphere(box_body, [0.1, 0.1, -0.1], 0.0)];\n\
         friction: 0.5;\n\
         body box_body { mass: 1.0, inertia: diag(0.0066666666666666671, 0.0066666666666666671, 0.0066666666666666671) }\n\
         joint base: free(quaternion) { parent: world, child: box_body }\n\
         }\n",
    )
    .unwrap();
    let (ok, stdout, stderr) = run(
        "simulate",
        &[
            declared.to_str().unwrap(),
            "--t-end",
            "0.6",
            "--dt",
            "0.001",
            "--q0",
            "0,0,0.1,1,0,0,0",
            "--v0",
            "2,0,0,0,0,0",
            "--contact-forces",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(ok && stdout.contains("with contacts"), "{stderr}");
    let (header, rows) = read_csv(&out);
    assert_eq!(header[14], "f.a.x");
    let stop = rows.iter().find(|r| r[8] <= 1e-9).unwrap();
    assert!(
        (stop[1] - distance).abs() < 0.01 * distance,
        "stopped after {}",
        stop[1]
    );

    // Errors name their argument, and nothing is written.
    std::fs::remove_file(&out).ok();
    let o = out.to_str().unwrap();
    let base = [
        "models/block.chain",
        "--t-end",
        "0.1",
        "--dt",
        "0.001",
        "--out",
        o,
    ];
    let with = |extra: &[&str]| -> Vec<String> {
        base.iter().chain(extra).map(|s| s.to_string()).collect()
    };
    for (extra, expected) in [
        (
            "--ground 0,0,0,0 --contact-points block --friction 1",
            "--ground",
        ),
        (
            "--ground 0,0,1 --contact-points block --friction 1",
            "--ground",
        ),
        (
            "--ground 0,0,1,0 --contact-points heel --friction 1",
            "`heel`",
        ),
        (
            "--ground 0,0,1,0 --contact-points block@1:2 --friction 1",
            "FRAME@X:Y:Z",
        ),
        ("--ground 0,0,1,0 --contact-points block", "--friction"),
        ("--ground 0,0,1,0 --friction 1", "--contact-points"),
        ("--contact-points block", "--ground"),
        (
            "--ground 0,0,1,0 --contact-points block --friction -1",
            "--friction",
        ),
        (
            "--ground 0,0,1,0 --contact-points block --friction 1 --restitution 2",
            "--restitution",
        ),
        (
            "--ground 0,0,1,0 --contact-points block --friction 1 --integrator rk4",
            "--integrator",
        ),
        ("--gravity 0,0", "gravity"),
    ] {
        let extra: Vec<&str> = extra.split_whitespace().collect();
        let args = with(&extra);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let e = fails("simulate", &args, &out);
        assert!(e.contains(expected), "{extra:?}: {e}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
