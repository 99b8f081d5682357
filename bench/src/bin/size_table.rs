//! `docs/size.md`: what the generated code costs in size and build time, per shipped model and
//! function, and how its operation count grows with the number of joints.
//!
//! ```text
//! cargo run --release -p articulated-bench --bin size_table                # everything (~1 h)
//! cargo run --release -p articulated-bench --bin size_table -- --repeats 1 --models arm7,tree
//!                                                 # a quick look: printed, docs/size.md untouched
//! ```
//!
//! What it does, in order, with progress on stderr:
//! 1. **ops and lines**: each model's seven outputs generated in-process by
//!    `articulated_codegen` (the count the generator reports; the lines of each function's impl
//!    as `articulated expand` formats it, doc comments and blank lines left out);
//! 2. **scratch crates** under `target/size/` (gitignored): a workspace of its own, outside the
//!    project's, with per model a `bytes_<model>` crate (`#[derive(articulated::Chain)]` with
//!    all seven outputs, plus, on ARM only, the same in `f32`) and a `time_<model>` crate (the
//!    derive with the default outputs, what a user writes), and an empty `time_empty` crate;
//!    all of them depend on `articulated = { path = "…/runtime" }`;
//! 3. **machine-code bytes**: the workspace built with `cargo build --release` for the default
//!    target, for `RUSTFLAGS="-C target-cpu=x86-64-v3"` and for `thumbv7em-none-eabihf`
//!    (no_std: `--no-default-features`), each in its own target directory; each trait method
//!    (`<bytes_arm7::Arm7 as articulated::generated::MassMatrix<…>>::mass_matrix_with`) read
//!    with `nm --print-size -C` from the crate's rlib, and the `.rodata` sections (the
//!    constants) with `size -A`;
//! 4. **build time added to a user crate**: per model, `touch src/lib.rs` then
//!    `cargo build --release -p time_<model>` (its dependencies already built), wall clock,
//!    median of `--repeats` runs, for the default target and for x86-64-v3;
//! 5. **macro expansion time**: `RUSTC_BOOTSTRAP=1 cargo rustc --release -p time_<model> --
//!    -Z time-passes`, the `macro_expand_crate` line (an unstable flag, used for this
//!    measurement only; `RUSTC_BOOTSTRAP` lets the stable compiler accept it), with the
//!    procedural macro compiled as cargo does by default in release builds (`opt-level = 0`)
//!    and, in a second scratch workspace, with `[profile.release.build-override] opt-level = 3`;
//! 6. **op counts against n**: runs the `op_counts` binary (which also writes
//!    `docs/figures/op_counts.svg`) and includes its section.
//!
//! Then writes `docs/size.md` whole (a temporary file renamed over it), or, with `--models` or
//! `--repeats` other than 3, prints it instead. Needs `nm` and `size` (GNU binutils),
//! `lscpu`, and the `thumbv7em-none-eabihf` target (`rustup target add thumbv7em-none-eabihf`;
//! without it the ARM columns say "n/a" and the page says why).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Output as Run, Stdio};
use std::time::Instant;

use articulated::files::write_atomically;
use articulated::OpCounts;
use articulated_codegen::emit;
use articulated_codegen::generate::generate;
use articulated_codegen::load::load;
use articulated_codegen::options::Output;

/// A shipped model: its file stem under `models/` and the struct the scratch crates derive.
struct Model {
    /// The file stem under `models/`.
    stem: &'static str,
    /// The struct the scratch crates derive.
    ty: &'static str,
}

/// Every `.chain` file of `models/`, smallest first.
const MODELS: [Model; 7] = [
    Model {
        stem: "double_pendulum",
        ty: "DoublePendulum",
    },
    Model {
        stem: "inverted_pendulum",
        ty: "InvertedPendulum",
    },
    Model {
        stem: "two_link",
        ty: "TwoLink",
    },
    Model {
        stem: "arm7",
        ty: "Arm7",
    },
    Model {
        stem: "tree",
        ty: "Tree",
    },
    Model {
        stem: "humanoid",
        ty: "Humanoid",
    },
    Model {
        stem: "chain50",
        ty: "Chain50",
    },
];

/// The outputs measured: the five defaults, then the two that users opt into.
const OUTPUTS: [Output; 7] = [
    Output::MassMatrix,
    Output::Bias,
    Output::Gravity,
    Output::InverseDynamics,
    Output::ForwardDynamics,
    Output::NonlinearEffects,
    Output::MassMatrixAndNonlinearEffects,
];

/// The trait each output's function implements (`articulated::generated::…`).
fn trait_name(output: Output) -> &'static str {
    match output {
        Output::MassMatrix => "MassMatrix",
        Output::Bias => "Bias",
        Output::Gravity => "Gravity",
        Output::InverseDynamics => "InverseDynamics",
        Output::ForwardDynamics => "ForwardDynamics",
        Output::NonlinearEffects => "NonlinearEffects",
        Output::MassMatrixAndNonlinearEffects => "MassMatrixAndNonlinearEffects",
        Output::JointWrenches => "JointWrenches",
        Output::JointWrenchesBottomUp => "JointWrenchesBottomUp",
    }
}

/// The ARM target of the embedded columns.
const THUMB: &str = "thumbv7em-none-eabihf";

/// The repository's root (this crate is `bench/`).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap_or_else(|| Path::new("."))
        .to_path_buf()
}

/// What went wrong, for the one line on stderr before exiting.
type Result<T> = std::result::Result<T, String>;

/// Progress on stderr.
macro_rules! say {
    ($($arg:tt)*) => { eprintln!("size_table: {}", format!($($arg)*)) };
}

// ---------------------------------------------------------------------------------------------
// 1. Operations and lines, from the generator in-process.

/// One generated function's static figures.
#[derive(Clone, Copy, Debug, Default)]
struct Static {
    /// The generator's operation count.
    ops: OpCounts,
    /// Lines of the formatted impl, without doc comments and blank lines.
    lines: usize,
}

/// The number of positions and velocities of a model, and each output's figures.
struct ModelStatic {
    /// Position coordinates.
    nq: usize,
    /// Velocity coordinates.
    nv: usize,
    /// Each output's figures.
    functions: BTreeMap<Output, Static>,
}

/// The lines of the impl of `trait_` in `text` (formatted code): from its `impl` line to the
/// closing brace, without doc comments and blank lines.
fn impl_lines(text: &str, trait_: &str) -> Option<usize> {
    let head = format!("::articulated::{trait_}<");
    let mut lines = text
        .lines()
        .skip_while(|l| !(l.starts_with("impl") && l.contains(&head)));
    let first = lines.next()?;
    let mut n = usize::from(!first.trim().is_empty());
    for line in lines {
        let t = line.trim();
        if !(t.is_empty() || t.starts_with("///") || t.starts_with("//")) {
            n += 1;
        }
        if line == "}" {
            return Some(n);
        }
    }
    None
}

/// Generates `model`'s seven outputs as the derive would and measures each function.
fn static_figures(model: &Model) -> Result<ModelStatic> {
    let path = root().join("models").join(format!("{}.chain", model.stem));
    let mut chain = load(&path, false).map_err(|e| e.to_string())?;
    chain.options.set_outputs(OUTPUTS);
    let g = generate(&chain.model, &chain.options).map_err(|e| e.to_string())?;
    let text = emit::format(g.tokens).map_err(|e| e.to_string())?;
    let mut functions = BTreeMap::new();
    for f in &g.functions {
        let lines = impl_lines(&text, trait_name(f.output))
            .ok_or_else(|| format!("{}: no impl of {:?} in the code", model.stem, f.output))?;
        functions.insert(f.output, Static { ops: f.ops, lines });
    }
    Ok(ModelStatic {
        nq: chain.model.nq(),
        nv: chain.model.nv(),
        functions,
    })
}

// ---------------------------------------------------------------------------------------------
// 2. Scratch crates.

/// The scratch area: `target/size/` (gitignored).
fn scratch() -> PathBuf {
    root().join("target").join("size")
}

/// Writes `contents` to `path` unless it already holds them (so cargo sees no change).
fn write_if_changed(path: &Path, contents: &str) -> Result<()> {
    if std::fs::read_to_string(path).is_ok_and(|old| old == contents) {
        return Ok(());
    }
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    std::fs::write(path, contents).map_err(|e| format!("{}: {e}", path.display()))
}

/// The outputs as the derive's `outputs = [...]` takes them.
fn outputs_list() -> String {
    OUTPUTS.map(Output::name).join(", ")
}

/// One member crate of a scratch workspace: `name`, its `lib.rs`.
fn member(dir: &Path, name: &str, lib: &str) -> Result<()> {
    let runtime = root().join("runtime");
    let manifest = format!(
        "# Written by bench/src/bin/size_table.rs; rewritten on every run.\n\
         [package]\nname = \"{name}\"\nversion = \"0.0.0\"\nedition = \"2021\"\npublish = false\n\n\
         [lib]\npath = \"src/lib.rs\"\n\n\
         [features]\ndefault = [\"std\"]\nstd = [\"articulated/std\"]\n\n\
         [dependencies]\narticulated = {{ path = \"{}\", default-features = false }}\n",
        runtime.display()
    );
    write_if_changed(&dir.join(name).join("Cargo.toml"), &manifest)?;
    write_if_changed(&dir.join(name).join("src/lib.rs"), lib)
}

/// The derive of `model` (absolute path), with `extra` keys after the file.
fn derive(model: &Model, ty: &str, extra: &str) -> String {
    let file = root().join("models").join(format!("{}.chain", model.stem));
    format!(
        "#[derive(articulated::Chain)]\n#[chain(file = \"{}\"{extra})]\npub struct {ty};\n",
        file.display()
    )
}

/// Writes a scratch workspace at `dir`: the `time_*` crates, and the `bytes_*` crates if
/// `bytes`; with `[profile.release.build-override] opt-level = 3` if `o3`.
fn write_workspace(dir: &Path, models: &[&Model], bytes: bool, o3: bool) -> Result<()> {
    let mut members = vec!["\"time_empty\"".to_string()];
    for m in models {
        members.push(format!("\"time_{}\"", m.stem));
        if bytes {
            members.push(format!("\"bytes_{}\"", m.stem));
        }
    }
    let mut manifest = format!(
        "# A scratch workspace written by bench/src/bin/size_table.rs (not part of the project's).\n\
         [workspace]\nresolver = \"2\"\nmembers = [{}]\n",
        members.join(", ")
    );
    if o3 {
        manifest.push_str(
            "\n# Procedural macros (and build scripts) optimized, which release builds do not do\n\
             # by default.\n[profile.release.build-override]\nopt-level = 3\n",
        );
    }
    write_if_changed(&dir.join("Cargo.toml"), &manifest)?;
    let header = "//! A scratch crate of bench/src/bin/size_table.rs.\n#![no_std]\n\n";
    member(
        dir,
        "time_empty",
        &format!("{header}use articulated as _;\n"),
    )?;
    for m in models {
        member(
            dir,
            &format!("time_{}", m.stem),
            &format!("{header}/// The default outputs.\n{}", derive(m, m.ty, "")),
        )?;
        if bytes {
            let all = format!(", outputs = [{}]", outputs_list());
            let lib = format!(
                "{header}/// Every output measured, in `f64`.\n{}\n\
                 /// The same in `f32`, on ARM only (the Cortex-M4F's FPU is single precision).\n\
                 #[cfg(target_arch = \"arm\")]\n{}",
                derive(m, m.ty, &all),
                derive(m, &format!("{}F32", m.ty), &format!(", scalar = f32{all}")),
            );
            member(dir, &format!("bytes_{}", m.stem), &lib)?;
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Running cargo.

/// A build configuration: its target directory, target triple and `RUSTFLAGS`.
#[derive(Clone, Copy)]
struct Config {
    /// A short name, for progress.
    name: &'static str,
    /// The target directory, under the workspace.
    target_dir: &'static str,
    /// `--target`, if not the host.
    triple: Option<&'static str>,
    /// `RUSTFLAGS` (none: unset).
    rustflags: Option<&'static str>,
    /// `RUSTC_BOOTSTRAP=1`, for `-Z time-passes`. Cargo rebuilds dependencies when it changes
    /// (`proc-macro2`'s build script reads it), so these builds have a target directory of
    /// their own.
    bootstrap: bool,
}

/// The default target, as a user builds.
const DEFAULT: Config = Config {
    name: "x86-64",
    target_dir: "target",
    triple: None,
    rustflags: None,
    bootstrap: false,
};
/// `-C target-cpu=x86-64-v3`: AVX2 and FMA.
const V3: Config = Config {
    name: "x86-64-v3",
    target_dir: "target-v3",
    triple: None,
    rustflags: Some("-C target-cpu=x86-64-v3"),
    bootstrap: false,
};
/// The Cortex-M4F/M7 target, `no_std`.
const ARM: Config = Config {
    name: THUMB,
    target_dir: "target-thumb",
    triple: Some(THUMB),
    rustflags: None,
    bootstrap: false,
};
/// The default target with `RUSTC_BOOTSTRAP=1`: the `-Z time-passes` builds.
const TIME_PASSES: Config = Config {
    name: "x86-64, -Z time-passes",
    target_dir: "target-time-passes",
    triple: None,
    rustflags: None,
    bootstrap: true,
};

/// `cargo` with the configuration's environment, in the workspace `dir`.
fn cargo(dir: &Path, config: Config) -> Command {
    let mut c = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    c.current_dir(dir)
        .env_remove("CARGO_ENCODED_RUSTFLAGS")
        .env_remove("CARGO_TARGET_DIR")
        .env("CARGO_TERM_COLOR", "never");
    if config.bootstrap {
        c.env("RUSTC_BOOTSTRAP", "1");
    } else {
        c.env_remove("RUSTC_BOOTSTRAP");
    }
    match config.rustflags {
        Some(flags) => c.env("RUSTFLAGS", flags),
        None => c.env_remove("RUSTFLAGS"),
    };
    c
}

/// The arguments every build takes: release, the target directory and the target.
fn build_args(dir: &Path, config: Config) -> Vec<String> {
    let mut args = vec![
        "--release".to_string(),
        "--target-dir".into(),
        dir.join(config.target_dir).display().to_string(),
    ];
    if let Some(t) = config.triple {
        args.push("--target".into());
        args.push(t.into());
    }
    args
}

/// Runs `c`, returning its output, or cargo's messages on failure.
fn run(mut c: Command) -> Result<Run> {
    let shown = format!("{c:?}");
    let out = c
        .stdin(Stdio::null())
        .output()
        .map_err(|e| format!("{shown}: {e}"))?;
    if out.status.success() {
        Ok(out)
    } else {
        Err(format!(
            "{shown} failed:\n{}",
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

/// Marks `time_<stem>`'s source as changed, so that the next build recompiles that crate only.
fn touch(dir: &Path, package: &str) -> Result<()> {
    let lib = dir.join(package).join("src/lib.rs");
    let file = std::fs::File::options()
        .append(true)
        .open(&lib)
        .map_err(|e| format!("{}: {e}", lib.display()))?;
    file.set_modified(std::time::SystemTime::now())
        .map_err(|e| format!("{}: {e}", lib.display()))
}

/// The median of `xs` (the lower middle for an even count).
fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs.get(xs.len().saturating_sub(1) / 2)
        .copied()
        .unwrap_or(f64::NAN)
}

// ---------------------------------------------------------------------------------------------
// 3. Machine-code bytes.

/// Sizes read from one built rlib: each trait method's bytes by (type, output), and the bytes
/// of its `.rodata` sections.
#[derive(Default)]
struct Bytes {
    /// Each trait method's bytes, by the type it is implemented for and the output.
    functions: BTreeMap<(String, Output), u64>,
    /// The bytes of the sections `.rodata*` (constants).
    rodata: u64,
}

/// Builds every `bytes_*` crate of `dir` in `config` and returns the rlib of each package.
fn build_bytes(dir: &Path, config: Config, models: &[&Model]) -> Result<BTreeMap<String, PathBuf>> {
    let mut c = cargo(dir, config);
    c.arg("build")
        .args(build_args(dir, config))
        .arg("--message-format=json-render-diagnostics");
    if config.triple.is_some() {
        // no_std: the packages without their default `std` feature.
        c.arg("--no-default-features");
    }
    for m in models {
        c.args(["-p", &format!("bytes_{}", m.stem)]);
    }
    let out = run(c)?;
    let mut rlibs = BTreeMap::new();
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let Ok(msg) = serde_json::from_str::<serde_json::Value>(line) else {
            continue;
        };
        let Some(name) = msg["target"]["name"].as_str() else {
            continue;
        };
        if msg["reason"] != "compiler-artifact" || !name.starts_with("bytes_") {
            continue;
        }
        let files = msg["filenames"].as_array().cloned().unwrap_or_default();
        if let Some(rlib) = files
            .iter()
            .filter_map(|f| f.as_str())
            .find(|f| f.ends_with(".rlib"))
        {
            rlibs.insert(name.to_string(), PathBuf::from(rlib));
        }
    }
    Ok(rlibs)
}

/// Reads the trait methods' sizes and the `.rodata` bytes of `rlib`.
fn read_bytes(rlib: &Path, krate: &str) -> Result<Bytes> {
    let mut nm = Command::new("nm");
    nm.args(["--print-size", "--defined-only", "-C"]).arg(rlib);
    let out = run(nm)?;
    let mut bytes = Bytes::default();
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        // `address size type name`, the name demangled: `<krate::Ty as
        // articulated::generated::Trait<f64,7_usize,7_usize>>::method_with`.
        let mut parts = line.splitn(4, ' ');
        let (Some(_), Some(size), Some(_), Some(name)) =
            (parts.next(), parts.next(), parts.next(), parts.next())
        else {
            continue;
        };
        let Some(rest) = name.strip_prefix(&format!("<{krate}::")) else {
            continue;
        };
        let Some((ty, rest)) = rest.split_once(" as articulated::generated::") else {
            continue;
        };
        for output in OUTPUTS {
            let method = format!(">>::{}_with", output.name());
            if rest.starts_with(&format!("{}<", trait_name(output))) && rest.ends_with(&method) {
                let size = u64::from_str_radix(size, 16).map_err(|e| format!("{line}: {e}"))?;
                *bytes.functions.entry((ty.to_string(), output)).or_default() += size;
            }
        }
    }
    let mut size = Command::new("size");
    size.args(["-A", "-d"]).arg(rlib);
    let out = run(size)?;
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let mut parts = line.split_whitespace();
        if let (Some(section), Some(n)) = (parts.next(), parts.next()) {
            if section.starts_with(".rodata") {
                bytes.rodata += n.parse::<u64>().unwrap_or(0);
            }
        }
    }
    Ok(bytes)
}

// ---------------------------------------------------------------------------------------------
// 4–5. Build and expansion times.

/// Wall-clock seconds of `cargo build --release -p package` after touching its source.
fn build_time(dir: &Path, config: Config, package: &str) -> Result<f64> {
    touch(dir, package)?;
    let mut c = cargo(dir, config);
    c.arg("build")
        .args(build_args(dir, config))
        .args(["-p", package]);
    let start = Instant::now();
    let out = run(c)?;
    let secs = start.elapsed().as_secs_f64();
    let stderr = String::from_utf8_lossy(&out.stderr);
    let others: Vec<&str> = stderr
        .lines()
        .filter(|l| l.trim_start().starts_with("Compiling") && !l.contains(package))
        .collect();
    if !others.is_empty() {
        return Err(format!(
            "timing {package}: cargo rebuilt dependencies ({}); warm up first",
            others.join("; ")
        ));
    }
    Ok(secs)
}

/// `macro_expand_crate`'s seconds from `-Z time-passes`, and the whole build's wall clock.
fn expansion_time(dir: &Path, config: Config, package: &str) -> Result<(f64, f64)> {
    touch(dir, package)?;
    let mut c = cargo(dir, config);
    c.arg("rustc").args(build_args(dir, config)).args([
        "-p",
        package,
        "--lib",
        "--",
        "-Z",
        "time-passes",
    ]);
    let start = Instant::now();
    let out = run(c)?;
    let wall = start.elapsed().as_secs_f64();
    let stderr = String::from_utf8_lossy(&out.stderr);
    // `time:   0.123; rss:   40MB ->   60MB (  +20MB)	macro_expand_crate`
    let line = stderr
        .lines()
        .find(|l| l.trim_end().ends_with("macro_expand_crate"))
        .ok_or_else(|| format!("{package}: no macro_expand_crate in -Z time-passes"))?;
    let secs = line
        .trim_start()
        .strip_prefix("time:")
        .and_then(|r| r.split(';').next())
        .and_then(|t| t.trim().parse::<f64>().ok())
        .ok_or_else(|| format!("{package}: cannot read `{line}`"))?;
    Ok((secs, wall))
}

/// Per model: the medians of every timing.
#[derive(Clone, Copy, Debug, Default)]
struct Times {
    /// `macro_expand_crate`, the macros at opt-level 0 (cargo's default in release).
    expand_o0: f64,
    /// `macro_expand_crate`, the macros at opt-level 3.
    expand_o3: f64,
    /// The crate's build, default target.
    build_default: f64,
    /// The crate's build, x86-64-v3.
    build_v3: f64,
    /// The wall clock of the `-Z time-passes` builds with optimized macros.
    build_o3: f64,
}

// ---------------------------------------------------------------------------------------------
// The page.

/// A byte count, or `n/a`.
fn bytes_cell(x: Option<u64>) -> String {
    x.map_or_else(|| "n/a".into(), |x| x.to_string())
}

/// Seconds with two decimals.
fn secs(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.2}")
    } else {
        "n/a".into()
    }
}

/// The first line of `cmd args…`'s stdout, or `unknown`.
fn first_line(cmd: &str, args: &[&str]) -> String {
    Command::new(cmd)
        .args(args)
        .output()
        .ok()
        .and_then(|o| {
            String::from_utf8_lossy(&o.stdout)
                .lines()
                .next()
                .map(str::to_string)
        })
        .unwrap_or_else(|| "unknown".into())
}

/// `lscpu`'s model name.
fn cpu_model() -> String {
    Command::new("lscpu")
        .output()
        .ok()
        .and_then(|o| {
            String::from_utf8_lossy(&o.stdout)
                .lines()
                .find_map(|l| l.strip_prefix("Model name:").map(|m| m.trim().to_string()))
        })
        .unwrap_or_else(|| "unknown".into())
}

/// The 1-minute load average.
fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|s| s.split_whitespace().next().map(str::to_string))
        .unwrap_or_else(|| "unknown".into())
}

/// Everything measured, for the page.
struct Report {
    /// Each model with its ops and lines.
    models: Vec<(&'static Model, ModelStatic)>,
    /// By configuration name: each crate's sizes.
    bytes: BTreeMap<&'static str, BTreeMap<String, Bytes>>,
    /// Why the ARM columns are empty, if they are.
    arm_missing: Option<String>,
    /// Each model's timings.
    times: BTreeMap<&'static str, Times>,
    /// The empty crate's timings.
    empty: Times,
    /// Runs per timing.
    repeats: usize,
    /// `lscpu`'s model name.
    cpu: String,
    /// `nproc`.
    nproc: String,
    /// `rustc --version`.
    rustc: String,
    /// The load average when the run started.
    load_before: String,
    /// The load average when it ended.
    load_after: String,
    /// How long the run took.
    minutes: f64,
    /// `op_counts`'s section.
    op_counts: String,
}

/// Lookups and the page.
impl Report {
    /// The bytes of `ty`'s function for `output` in `model`'s crate built in `config`.
    fn bytes_of(&self, config: &str, model: &Model, ty: &str, output: Output) -> Option<u64> {
        self.bytes
            .get(config)?
            .get(&format!("bytes_{}", model.stem))?
            .functions
            .get(&(ty.to_string(), output))
            .copied()
    }

    /// The `.rodata` bytes of `model`'s crate built in `config`.
    fn rodata_of(&self, config: &str, model: &Model) -> Option<u64> {
        Some(
            self.bytes
                .get(config)?
                .get(&format!("bytes_{}", model.stem))?
                .rodata,
        )
    }

    /// The whole page.
    fn markdown(&self) -> String {
        let mut s = String::new();
        let w = &mut s;
        let _ = writeln!(
            w,
            "# What the generated code costs: size, build time, operations\n"
        );
        let _ = writeln!(
            w,
            "Regenerate this page (about {:.0} minutes here) with\n\n\
             ```text\ncargo run --release -p articulated-bench --bin size_table\n```\n\n\
             It is written whole by `bench/src/bin/size_table.rs` (which also runs \
             `bench/src/bin/op_counts.rs`): edit those, not this file. Every figure below comes \
             from that one run.\n",
            self.minutes.max(1.0)
        );
        let _ = writeln!(w, "## The machine\n");
        let _ = writeln!(
            w,
            "- CPU: {} (`lscpu` model name), `nproc` = {}; a virtual machine shared with other \
             builds (1-minute load average {} at the start of the run, {} at the end), so the \
             times are medians of {} runs and can be off by tens of per cent from one run to the \
             next;\n- compiler: `{}`.\n",
            self.cpu, self.nproc, self.load_before, self.load_after, self.repeats, self.rustc
        );

        let _ = writeln!(w, "## Per model and function\n");
        let _ = writeln!(
            w,
            "- **ops**: the generator's operation count of the function (add/sub, mul, div, neg, \
             sin/cos, sqrt; the same figure as the `…_OPS` constants and `articulated expand`'s \
             header);\n\
             - **lines**: the function's impl as `articulated expand` formats it, without its doc \
             comments and blank lines;\n\
             - **bytes**: the machine code of the function (`nm --print-size` of the trait method \
             `<T as articulated::generated::Trait<…>>::…_with` in a release build of a user crate \
             with default settings): what a user pays in flash. Constants loaded from memory are \
             not in these bytes (on x86-64 they sit in `.rodata`; their total per model is in the \
             next table); the `sin`/`cos` fallback and, on ARM, the soft-float routines are \
             shared code outside the functions;\n\
             - **x86-64**: the default target (`x86_64-unknown-linux-gnu`, SSE2); **x86-64-v3**: \
             `RUSTFLAGS=\"-C target-cpu=x86-64-v3\"` (AVX2 and FMA: generated sums of products \
             become fused multiply–adds); **{THUMB}**: a Cortex-M4F/M7 with `no_std` \
             (`articulated` without default features). Its FPU is single-precision only, so \
             `f64` arithmetic is calls to soft-float routines; the **f32** column is the same \
             model generated with `scalar = f32`, what such a target would use.\n"
        );
        if let Some(why) = &self.arm_missing {
            let _ = writeln!(w, "The {THUMB} columns are empty: {why}\n");
        }
        let _ = writeln!(
            w,
            "| model | function | ops | lines | bytes x86-64 | bytes x86-64-v3 | bytes {THUMB} f64 | bytes {THUMB} f32 |"
        );
        let _ = writeln!(w, "|---|---|---:|---:|---:|---:|---:|---:|");
        for (m, st) in &self.models {
            for output in OUTPUTS {
                let f = st.functions.get(&output).copied().unwrap_or_default();
                let f32_ty = format!("{}F32", m.ty);
                let _ = writeln!(
                    w,
                    "| {} | `{}` | {} | {} | {} | {} | {} | {} |",
                    m.stem,
                    output.name(),
                    f.ops.total(),
                    f.lines,
                    bytes_cell(self.bytes_of(DEFAULT.name, m, m.ty, output)),
                    bytes_cell(self.bytes_of(V3.name, m, m.ty, output)),
                    bytes_cell(self.bytes_of(ARM.name, m, m.ty, output)),
                    bytes_cell(self.bytes_of(ARM.name, m, &f32_ty, output)),
                );
            }
        }

        let _ = writeln!(w, "\n## Per model: build cost\n");
        let _ = writeln!(
            w,
            "A user crate holding one `#[derive(articulated::Chain)]` of the model with the \
             default outputs (`mass_matrix`, `bias`, `gravity`, `inverse_dynamics`, \
             `forward_dynamics`), its dependencies already built; the medians of {} runs, in \
             seconds.\n\n\
             - **expansion**: the `macro_expand_crate` pass of `RUSTC_BOOTSTRAP=1 cargo rustc \
             --release -- -Z time-passes` (an unstable flag, used here for the measurement only): \
             the time the derive takes to read the file and generate the code, with the \
             procedural macro compiled as cargo does by default in release builds (opt-level 0) \
             and with\n\n  ```toml\n  [profile.release.build-override]\n  opt-level = 3\n  \
             ```\n\n  in the user's `Cargo.toml` (which also compiles `syn` and the generator \
             optimized: a one-time cost when the dependencies are built);\n\
             - **build**: the wall clock of `touch src/lib.rs && cargo build --release`, \
             expansion included, for the default target and for x86-64-v3 (opt-level 0 macros), \
             and, in the last column, of the `-Z time-passes` builds with opt-level 3 macros;\n\
             - the **empty** row is a crate with no model (`use articulated as _;`): cargo's and \
             rustc's fixed cost, included in every other row.\n",
            self.repeats
        );
        let _ = writeln!(
            w,
            "| model | nq / nv | expansion, macros opt 0 | expansion, macros opt 3 | build x86-64 | build x86-64-v3 | build x86-64, macros opt 3 | .rodata bytes x86-64 / v3 |"
        );
        let _ = writeln!(w, "|---|---:|---:|---:|---:|---:|---:|---:|");
        let e = &self.empty;
        let _ = writeln!(
            w,
            "| (empty) | – | {} | {} | {} | {} | {} | – |",
            secs(e.expand_o0),
            secs(e.expand_o3),
            secs(e.build_default),
            secs(e.build_v3),
            secs(e.build_o3)
        );
        for (m, st) in &self.models {
            let t = self.times.get(m.stem).copied().unwrap_or_default();
            let _ = writeln!(
                w,
                "| {} | {} / {} | {} | {} | {} | {} | {} | {} / {} |",
                m.stem,
                st.nq,
                st.nv,
                secs(t.expand_o0),
                secs(t.expand_o3),
                secs(t.build_default),
                secs(t.build_v3),
                secs(t.build_o3),
                bytes_cell(self.rodata_of(DEFAULT.name, m)),
                bytes_cell(self.rodata_of(V3.name, m)),
            );
        }
        let _ = writeln!(
            w,
            "\nThe `.rodata` column is the constants of all seven functions of the model's \
             `bytes_` crate (`size -A`: the sections `.rodata*` of its rlib; on ARM the constants \
             sit in literal pools inside the functions, so they are in the bytes above).\n"
        );

        let _ = writeln!(w, "## Operations against the number of joints\n");
        let _ = writeln!(w, "![Operations against n](figures/op_counts.svg)\n");
        let _ = writeln!(w, "{}", self.op_counts.trim_end());
        let _ = writeln!(
            w,
            "\nWhat is compared: the generator traces the recursions on symbolic values and \
             emits only the operations whose result is not a known constant. Every product with a \
             structural zero (joint axes along coordinate axes, the zero entries of `S`, the \
             base's zero velocity) and every sum with a zero is gone, constants are multiplied \
             out, and shared subexpressions are computed once; of several formulations it keeps \
             the one with the fewest operations. Published counts are for an algorithm run on a \
             general model, with the model's numbers as data (a generic joint axis, a full \
             spatial inertia): they count what a library computes, ours what one model's \
             specialized code computes. Our counts also include the sines and cosines (one \
             sin/cos per joint) and, for `forward_dynamics`, the pivot checks; the published \
             ones count multiplications and additions only."
        );
        s
    }
}

// ---------------------------------------------------------------------------------------------

/// Command-line options.
struct Args {
    /// Runs per timing (3 for the page).
    repeats: usize,
    /// The models measured (all for the page).
    models: Vec<&'static Model>,
}

/// Reads the command line.
fn parse_args() -> Result<Args> {
    let mut args = Args {
        repeats: 3,
        models: MODELS.iter().collect(),
    };
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        match arg.as_str() {
            "--repeats" => {
                args.repeats = it
                    .next()
                    .and_then(|r| r.parse().ok())
                    .filter(|r| *r >= 1)
                    .ok_or("--repeats takes a count of at least 1")?;
            }
            "--models" => {
                let list = it.next().ok_or("--models takes a list: arm7,tree")?;
                args.models = list
                    .split(',')
                    .map(|name| {
                        MODELS
                            .iter()
                            .find(|m| m.stem == name.trim())
                            .ok_or_else(|| format!("no model `{name}` in models/"))
                    })
                    .collect::<Result<_>>()?;
            }
            _ => {
                return Err(format!(
                    "unknown argument `{arg}`\nusage: size_table [--repeats R] [--models a,b,…]"
                ))
            }
        }
    }
    Ok(args)
}

/// Whether the ARM target's standard library is installed (`rustup target list --installed`).
fn arm_installed() -> bool {
    Command::new("rustup")
        .args(["target", "list", "--installed"])
        .output()
        .is_ok_and(|o| {
            String::from_utf8_lossy(&o.stdout)
                .lines()
                .any(|l| l.trim() == THUMB)
        })
}

/// Runs every measurement (see the module docs), in order.
fn measure(args: &Args) -> Result<Report> {
    let start = Instant::now();
    let load_before = load_average();
    let models = &args.models;

    say!("generating the code of {} models in-process", models.len());
    let mut statics = Vec::new();
    for m in models {
        statics.push((*m, static_figures(m)?));
    }

    say!("op counts against n: running the op_counts binary");
    let mut c = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    c.current_dir(root())
        .args([
            "run",
            "--release",
            "-p",
            "articulated-bench",
            "--bin",
            "op_counts",
        ])
        .stderr(Stdio::inherit());
    let op_counts = String::from_utf8_lossy(&run(c)?.stdout).into_owned();

    let ws = scratch().join("ws");
    let ws_o3 = scratch().join("ws-o3");
    write_workspace(&ws, models, true, false)?;
    write_workspace(&ws_o3, models, false, true)?;

    // Bytes, and the warm-up of each configuration's dependencies.
    let mut bytes = BTreeMap::new();
    let arm_missing = (!arm_installed()).then(|| {
        format!(
            "the target is not installed here (`rustup target add {THUMB}` did not run or \
             failed)."
        )
    });
    for config in [DEFAULT, V3, ARM] {
        if config.triple.is_some() && arm_missing.is_some() {
            continue;
        }
        say!(
            "{}: building the bytes_ crates (dependencies first, this takes minutes)",
            config.name
        );
        let t = Instant::now();
        let rlibs = build_bytes(&ws, config, models)?;
        let mut per = BTreeMap::new();
        for (krate, rlib) in rlibs {
            per.insert(krate.clone(), read_bytes(&rlib, &krate)?);
        }
        say!(
            "{}: done in {:.0} s",
            config.name,
            t.elapsed().as_secs_f64()
        );
        bytes.insert(config.name, per);
    }

    // Warm-ups of the timing configurations: every dependency built once.
    for (dir, config) in [
        (&ws, DEFAULT),
        (&ws, V3),
        (&ws, TIME_PASSES),
        (&ws_o3, TIME_PASSES),
    ] {
        say!("warming up {} ({})", dir.display(), config.name);
        let mut c = cargo(dir, config);
        c.arg("build")
            .args(build_args(dir, config))
            .arg("--workspace");
        if dir == &ws {
            for m in models {
                c.args(["--exclude", &format!("bytes_{}", m.stem)]);
            }
        }
        run(c)?;
        if config.bootstrap {
            // `cargo rustc`'s extra flags are part of the crate's fingerprint, not of its
            // dependencies': one run first all the same, so that nothing but the crate is timed.
            expansion_time(dir, config, "time_empty")?;
        }
    }

    let packages: Vec<(String, Option<&Model>)> = std::iter::once(("time_empty".to_string(), None))
        .chain(
            models
                .iter()
                .map(|m| (format!("time_{}", m.stem), Some(*m))),
        )
        .collect();
    let total = packages.len() * 4 * args.repeats;
    let mut done = 0;
    let mut times = BTreeMap::new();
    let mut empty = Times::default();
    for (package, model) in &packages {
        let mut runs: [Vec<f64>; 5] = Default::default();
        for r in 0..args.repeats {
            let mut step = |what: &str, x: f64| {
                done += 1;
                say!(
                    "[{done}/{total}] {package}, {what}, run {}: {x:.2} s",
                    r + 1
                );
            };
            let (e0, _) = expansion_time(&ws, TIME_PASSES, package)?;
            step("expansion (macros opt 0)", e0);
            let (e3, b3) = expansion_time(&ws_o3, TIME_PASSES, package)?;
            step("expansion (macros opt 3)", e3);
            let bd = build_time(&ws, DEFAULT, package)?;
            step("build x86-64", bd);
            let bv = build_time(&ws, V3, package)?;
            step("build x86-64-v3", bv);
            for (k, x) in [e0, e3, bd, bv, b3].into_iter().enumerate() {
                runs[k].push(x);
            }
        }
        let [e0, e3, bd, bv, b3] = runs.map(median);
        let t = Times {
            expand_o0: e0,
            expand_o3: e3,
            build_default: bd,
            build_v3: bv,
            build_o3: b3,
        };
        match model {
            Some(m) => {
                times.insert(m.stem, t);
            }
            None => empty = t,
        }
    }

    Ok(Report {
        models: statics,
        bytes,
        arm_missing,
        times,
        empty,
        repeats: args.repeats,
        cpu: cpu_model(),
        nproc: first_line("nproc", &[]),
        rustc: first_line("rustc", &["--version"]),
        load_before,
        load_after: load_average(),
        minutes: start.elapsed().as_secs_f64() / 60.0,
        op_counts,
    })
}

/// Measures, then writes `docs/size.md` (or prints a partial run's page).
fn main() -> ExitCode {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            say!("{e}");
            return ExitCode::FAILURE;
        }
    };
    let report = match measure(&args) {
        Ok(r) => r,
        Err(e) => {
            say!("{e}");
            return ExitCode::FAILURE;
        }
    };
    let page = report.markdown();
    let whole = args.repeats == 3 && args.models.len() == MODELS.len();
    if !whole {
        say!("a partial run (--models or --repeats): the page goes to stdout, docs/size.md is left as it is");
        print!("{page}");
        return ExitCode::SUCCESS;
    }
    let path = root().join("docs/size.md");
    match write_atomically(&path, page.as_bytes()) {
        Ok(()) => {
            say!("wrote {}", path.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            say!("cannot write {}: {e}", path.display());
            ExitCode::FAILURE
        }
    }
}
