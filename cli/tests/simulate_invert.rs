//! `articulated simulate` and `articulated invert`, end to end through the binary: the trajectory
//! file's form, its physics (energy kept by RK4, checked with the reference), the couples
//! recovered from it (zero for a chain left to itself), a plot, and every bad input giving a
//! message, a non-zero exit and no file.

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

    // simulate: an unknown integrator, a bad grid, a state that diverges into a singular M.
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
    // The inverted pendulum starting exactly at its xyz Euler angles' gimbal lock.
    let e = fails(
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
            o,
        ],
        &out,
    );
    assert!(e.contains("t = ") && e.contains("singular"), "{e}");
    // A light link against stiff stops, stepped far too long: the state runs away, and the
    // message says where (the acceleration, not a singular M) and how far it got.
    let light = write(
        "light.chain",
        "chain Light {\n\
         body a { mass: 0.01, com: [0.1, 0.0, 0.0], inertia: diag(1e-6, 1e-6, 1e-6) }\n\
         joint j: revolute(y) { parent: world, child: a, lower: -0.1, upper: 0.1 }\n}\n",
    );
    let e = fails(
        "simulate",
        &[
            &light, "--t-end", "1", "--dt", "0.001", "--drives", "--out", o,
        ],
        &out,
    );
    assert!(
        e.contains("acceleration[0] is not finite") && e.contains("max |v| = "),
        "{e}"
    );
    assert!(!e.contains("singular"), "{e}");
    // Said before the run, with the step that would do and the integrator that copes.
    assert!(
        e.contains("warning: joint `j`'s position stop is too stiff for --dt 0.001")
            && e.contains("--integrator dopri5"),
        "{e}"
    );
    // And the advice holds: the adaptive integrator takes it through the stop.
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
