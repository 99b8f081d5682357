//! `docs/size.md`: what the generated code costs in size and build time, per shipped model and
//! function, and how its operation count grows with the number of joints.
//!
//! ```text
//! cargo run --release -p articulated-bench --bin size_table                # everything (~1 h)
//! cargo run --release -p articulated-bench --bin size_table -- --repeats 1 --models arm7,tree
//!                                                 # a quick look: printed, docs/size.md untouched
//! cargo run --release -p articulated-bench --bin size_table -- --render
//!                                                 # the page again from bench/size/size.json
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
//! Then saves the measurements in `bench/size/size.json` and writes `docs/size.md`, each whole
//! (a temporary file renamed over it); with `--models` or `--repeats` other than 3 it prints
//! the page instead and writes nothing. `--render` rewrites the page from `size.json` without
//! measuring (after a change to the page's text). Needs `nm` and `size` (GNU binutils),
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
use serde_json::{json, Value};

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

/// The trait each output's function implements (`articulated::generated::…`): its name in
/// CamelCase (`mass_matrix` → `MassMatrix`).
fn trait_name(output: Output) -> String {
    output
        .name()
        .split('_')
        .map(|w| {
            let mut c = w.chars();
            c.next()
                .map(|f| f.to_ascii_uppercase().to_string() + c.as_str())
                .unwrap_or_default()
        })
        .collect()
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
        let lines = impl_lines(&text, &trait_name(f.output))
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

/// Per model: the medians of every timing, in seconds.
#[derive(Clone, Copy, Debug)]
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

/// Not measured: `n/a` on the page.
impl Default for Times {
    /// Every time missing (`NaN`).
    fn default() -> Self {
        Times {
            expand_o0: f64::NAN,
            expand_o3: f64::NAN,
            build_default: f64::NAN,
            build_v3: f64::NAN,
            build_o3: f64::NAN,
        }
    }
}

/// The JSON of `bench/size/size.json`.
impl Times {
    /// The field names, in the order of the struct.
    const KEYS: [&'static str; 5] = [
        "expand_o0",
        "expand_o3",
        "build_default",
        "build_v3",
        "build_o3",
    ];

    /// The values, in the order of [`Times::KEYS`].
    fn values(&self) -> [f64; 5] {
        [
            self.expand_o0,
            self.expand_o3,
            self.build_default,
            self.build_v3,
            self.build_o3,
        ]
    }

    /// As a JSON object (a missing value as `null`).
    fn to_json(self) -> Value {
        let mut o = serde_json::Map::new();
        for (k, v) in Self::KEYS.iter().zip(self.values()) {
            o.insert((*k).into(), json!(v.is_finite().then_some(v)));
        }
        Value::Object(o)
    }

    /// From [`Times::to_json`].
    fn from_json(v: &Value) -> Times {
        let [expand_o0, expand_o3, build_default, build_v3, build_o3] =
            Self::KEYS.map(|k| v[k].as_f64().unwrap_or(f64::NAN));
        Times {
            expand_o0,
            expand_o3,
            build_default,
            build_v3,
            build_o3,
        }
    }
}

/// The byte columns of the page, in order.
const COLUMNS: [&str; 4] = [
    "x86-64",
    "x86-64-v3",
    "thumbv7em-none-eabihf f64",
    "thumbv7em-none-eabihf f32",
];

/// One function of one model: everything measured.
#[derive(Clone, Debug)]
struct Function {
    /// Which output.
    output: Output,
    /// The generator's operation count.
    ops: OpCounts,
    /// Lines of the formatted impl, without doc comments and blank lines.
    lines: usize,
    /// Machine-code bytes per column of [`COLUMNS`] (`None`: not built).
    bytes: [Option<u64>; 4],
}

/// One model: its functions, its constants, its timings.
#[derive(Clone, Debug)]
struct ModelRow {
    /// The file stem under `models/`.
    stem: String,
    /// Position coordinates.
    nq: usize,
    /// Velocity coordinates.
    nv: usize,
    /// The seven functions, in the order of [`OUTPUTS`].
    functions: Vec<Function>,
    /// The `.rodata` bytes of its `bytes_` crate, x86-64 and x86-64-v3.
    rodata: [Option<u64>; 2],
    /// The medians of its timings.
    times: Times,
}

/// Everything measured: the page's data, saved as `bench/size/size.json`.
#[derive(Clone, Debug)]
struct Report {
    /// Each model's figures.
    models: Vec<ModelRow>,
    /// The empty crate's timings.
    empty: Times,
    /// Why the ARM columns are empty, if they are.
    arm_missing: Option<String>,
    /// Runs per timing.
    repeats: usize,
    /// `lscpu`'s model name.
    cpu: String,
    /// `nproc`.
    nproc: String,
    /// `rustc --version`.
    rustc: String,
    /// The 1-minute load average when the run started.
    load_before: String,
    /// The same when it ended.
    load_after: String,
    /// How long the measurements took, in minutes.
    minutes: f64,
}

/// An operation count as JSON.
fn ops_json(o: &OpCounts) -> Value {
    json!({
        "adds": o.adds, "muls": o.muls, "divs": o.divs,
        "negs": o.negs, "sin_cos": o.sin_cos, "sqrts": o.sqrts,
    })
}

/// From [`ops_json`].
fn ops_from_json(v: &Value) -> OpCounts {
    let n = |k: &str| v[k].as_u64().unwrap_or(0) as usize;
    OpCounts {
        adds: n("adds"),
        muls: n("muls"),
        divs: n("divs"),
        negs: n("negs"),
        sin_cos: n("sin_cos"),
        sqrts: n("sqrts"),
    }
}

/// A string field of a JSON object, or `unknown`.
fn text_of(v: &Value, k: &str) -> String {
    v[k].as_str().unwrap_or("unknown").to_string()
}

/// The JSON of the data file and the page.
impl Report {
    /// As the JSON of `bench/size/size.json`.
    fn to_json(&self) -> Value {
        let models: Vec<Value> = self
            .models
            .iter()
            .map(|m| {
                let functions: Vec<Value> = m
                    .functions
                    .iter()
                    .map(|f| {
                        let bytes: serde_json::Map<String, Value> = COLUMNS
                            .iter()
                            .zip(f.bytes)
                            .map(|(c, b)| ((*c).to_string(), json!(b)))
                            .collect();
                        json!({
                            "output": f.output.name(), "ops": ops_json(&f.ops),
                            "lines": f.lines, "bytes": bytes,
                        })
                    })
                    .collect();
                json!({
                    "model": m.stem, "nq": m.nq, "nv": m.nv, "functions": functions,
                    "rodata": { "x86-64": m.rodata[0], "x86-64-v3": m.rodata[1] },
                    "times": m.times.to_json(),
                })
            })
            .collect();
        json!({
            "written_by": "cargo run --release -p articulated-bench --bin size_table",
            "cpu": self.cpu, "nproc": self.nproc, "rustc": self.rustc,
            "load_before": self.load_before, "load_after": self.load_after,
            "minutes": self.minutes, "repeats": self.repeats, "arm_missing": self.arm_missing,
            "empty": self.empty.to_json(), "models": models,
        })
    }

    /// From [`Report::to_json`].
    fn from_json(v: &Value) -> Result<Report> {
        let models = v["models"]
            .as_array()
            .ok_or("no `models` in the data file")?
            .iter()
            .map(|m| {
                let functions = m["functions"]
                    .as_array()
                    .ok_or("a model without `functions`")?
                    .iter()
                    .map(|f| {
                        let name = f["output"].as_str().unwrap_or("");
                        Ok(Function {
                            output: Output::from_name(name)
                                .ok_or_else(|| format!("unknown output `{name}`"))?,
                            ops: ops_from_json(&f["ops"]),
                            lines: f["lines"].as_u64().unwrap_or(0) as usize,
                            bytes: COLUMNS.map(|c| f["bytes"][c].as_u64()),
                        })
                    })
                    .collect::<Result<Vec<_>>>()?;
                Ok(ModelRow {
                    stem: text_of(m, "model"),
                    nq: m["nq"].as_u64().unwrap_or(0) as usize,
                    nv: m["nv"].as_u64().unwrap_or(0) as usize,
                    functions,
                    rodata: ["x86-64", "x86-64-v3"].map(|c| m["rodata"][c].as_u64()),
                    times: Times::from_json(&m["times"]),
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Report {
            models,
            empty: Times::from_json(&v["empty"]),
            arm_missing: v["arm_missing"].as_str().map(str::to_string),
            repeats: v["repeats"].as_u64().unwrap_or(0) as usize,
            cpu: text_of(v, "cpu"),
            nproc: text_of(v, "nproc"),
            rustc: text_of(v, "rustc"),
            load_before: text_of(v, "load_before"),
            load_after: text_of(v, "load_after"),
            minutes: v["minutes"].as_f64().unwrap_or(f64::NAN),
        })
    }

    /// The whole page, with `op_counts`' section.
    fn markdown(&self, op_counts: &str) -> String {
        let mut s = String::new();
        let w = &mut s;
        let _ = writeln!(
            w,
            "# What the generated code costs: size, build time, operations\n\n\
             Regenerate this page with\n\n\
             ```text\ncargo run --release -p articulated-bench --bin size_table\n```\n\n\
             It is written whole by `bench/src/bin/size_table.rs`, which also runs \
             `bench/src/bin/op_counts.rs` and keeps its measurements in `bench/size/size.json` \
             (`-- --render` rewrites the page from that file without measuring): edit those, not \
             this file. The measurements took {:.0} minutes here, with the scratch crates' \
             dependencies already compiled by an earlier run; a first run also compiles them for \
             each target, which takes about as long again.\n",
            self.minutes.max(1.0)
        );
        let _ = writeln!(
            w,
            "## The machine\n\n\
             - CPU: {} (`lscpu` model name), `nproc` = {}: a virtual machine shared with other \
             builds (1-minute load average {} when the measurements started, {} when they \
             ended). The times are medians of {} runs; on a loaded machine they can move by tens \
             of per cent from one run to the next, so read them as orders of magnitude and \
             ratios;\n- compiler: `{}`.\n",
            self.cpu, self.nproc, self.load_before, self.load_after, self.repeats, self.rustc
        );
        self.summary(w);
        self.function_table(w);
        self.size_table(w);
        self.time_table(w);
        let _ = writeln!(
            w,
            "## Operations against the number of joints\n\n\
             ![Operations against n](figures/op_counts.svg)\n\n{}\n",
            op_counts.trim_end()
        );
        let _ = writeln!(
            w,
            "What is compared: the generator traces the recursions on symbolic values and \
             emits only the operations whose result is not a known constant. Every product with a \
             structural zero (the zero entries of a joint's motion subspace, a base at rest) and \
             every sum with a zero is gone, constants are multiplied out, shared subexpressions \
             are computed once, and of several formulations the one with the fewest operations \
             is kept. Published operation counts are for an algorithm run on a general model \
             whose numbers are data (a generic joint axis, a full spatial inertia): they count \
             what a library computes for any robot, ours what one robot's specialized code \
             computes. Our totals also count the sines and cosines (one per joint angle) and, \
             in `forward_dynamics`, the pivot checks, which published counts of multiplications \
             and additions leave out."
        );
        s
    }

    /// The model with the most operations in its default functions (the largest).
    fn largest(&self) -> Option<&ModelRow> {
        self.models.iter().max_by_key(|m| default_ops(m))
    }

    /// The findings, each computed from the tables below.
    fn summary(&self, w: &mut String) {
        let _ = writeln!(w, "## In short\n");
        let per_op: Vec<String> = COLUMNS
            .iter()
            .enumerate()
            .filter_map(|(k, column)| {
                bytes_per_op(&self.models, k).map(|r| format!("{r:.0} on {column}"))
            })
            .collect();
        let _ = writeln!(
            w,
            "- **Size follows the operation count**: over all functions of all models, the \
             bytes of machine code per operation are {} (`f64` on ARM is soft float: every \
             operation a call).",
            per_op.join(", ")
        );
        if let Some(big) = self.largest() {
            let sum = |k: usize| default_bytes(big, k).map_or("n/a".into(), kib);
            let mm = big
                .functions
                .iter()
                .find(|f| f.output == Output::MassMatrix);
            let _ = writeln!(
                w,
                "- **The largest model**, `{}` ({} velocity coordinates), takes {} of machine \
                 code for its five default functions on x86-64 and, on {THUMB}, {} in `f64` and \
                 {} in `f32`; its `mass_matrix` alone has {} operations ({} on x86-64), because \
                 `M` has n² entries (see the last section): a long serial chain is where \
                 straight-line code costs the most flash.",
                big.stem,
                big.nv,
                sum(0),
                sum(2),
                sum(3),
                mm.map_or(0, |f| f.ops.total()),
                mm.and_then(|f| f.bytes[0]).map_or("n/a".into(), kib),
            );
            let t = &big.times;
            let saved = t.expand_o0 - t.expand_o3;
            let small_saved = self
                .models
                .iter()
                .filter(|m| m.times.build_default < 1.0)
                .map(|m| m.times.expand_o0 - m.times.expand_o3)
                .fold(f64::NAN, f64::max);
            let _ = writeln!(
                w,
                "- **Build time**: the crate holding `{}` builds in {} s in release ({} s for \
                 x86-64-v3), of which the derive's expansion is {} s; the rest is compiling and \
                 optimizing the generated code. With the procedural macro optimized \
                 (`[profile.release.build-override] opt-level = 3` in the user's `Cargo.toml`) \
                 the expansion takes {} s: {} s saved on every build of that crate ({:.0} % of \
                 it), against at most {} s on the small models. Worth setting for large models \
                 that are rebuilt often; the price is a one-time optimized build of `syn` and of \
                 the generator with the other dependencies.",
                big.stem,
                secs(t.build_default),
                secs(t.build_v3),
                secs(t.expand_o0),
                secs(t.expand_o3),
                secs(saved),
                100.0 * saved / t.build_default,
                secs(small_saved),
            );
        }
        let small: Vec<&ModelRow> = self
            .models
            .iter()
            .filter(|m| m.times.build_default < 1.0)
            .collect();
        if let Some(max_nv) = small.iter().map(|m| m.nv).max() {
            let _ = writeln!(
                w,
                "- **Small models cost little**: the {} models with up to {max_nv} velocity \
                 coordinates each add under a second to a release build ({} s for an empty \
                 crate) and at most {} of x86-64 code for the five default functions.",
                small.len(),
                secs(self.empty.build_default),
                small
                    .iter()
                    .filter_map(|m| default_bytes(m, 0))
                    .max()
                    .map_or("n/a".into(), kib),
            );
        }
        let _ = writeln!(w);
    }

    /// The table per model and function.
    fn function_table(&self, w: &mut String) {
        let _ = writeln!(
            w,
            "## Per model and function\n\n\
             - **ops**: the generator's operation count (add/sub, mul, div, neg, sin/cos, sqrt; \
             the figure of the `…_OPS` constants and of `articulated expand`'s header);\n\
             - **lines**: the function's impl as `articulated expand` formats it, without its \
             doc comments and blank lines;\n\
             - **bytes**: the function's machine code, `nm --print-size` of the trait method \
             (`<bytes_arm7::Arm7 as articulated::generated::MassMatrix<f64,7_usize,7_usize>>::\
             mass_matrix_with`) in a release build of a user crate with cargo's defaults \
             (opt-level 3, 16 codegen units, no LTO): what a user pays in flash for it. Not in \
             these bytes: constants that x86-64 loads from `.rodata` (their total per model is in \
             the next table), and the shared code the functions call (the `sin`/`cos` fallback \
             for large angles; on ARM, the soft-float routines);\n\
             - **x86-64**: the default target (`x86_64-unknown-linux-gnu`, SSE2); **x86-64-v3**: \
             `RUSTFLAGS=\"-C target-cpu=x86-64-v3\"` (AVX2 and FMA, so sums of products become \
             fused multiply–adds); **{THUMB}**: Cortex-M4F/M7, `no_std` (`articulated` without \
             default features). Its FPU is single precision, so in `f64` every operation is a \
             call to a soft-float routine; **f32** is the same model generated with \
             `scalar = f32`, what such a target would run;\n\
             - **sines and cosines**: an `f64` function that needs those of two or more angles \
             computes them with `articulated::math::sincos_array`, which is inlined: its \
             polynomials are in the function's bytes (about 500 bytes on x86-64, 2 KiB in \
             soft-float `f64` on ARM; the floor of the small models' sizes). With one angle, and \
             in `f32` on ARM (`articulated::math::sincosf_array` is `libm`'s `sincosf` angle by \
             angle where the target has no `f64` vectors), the function calls `libm`'s \
             `sincos`/`sincosf`, shared code that is not in its bytes: so the `f32` column is smaller than the `f64` one by more than the width \
             of the numbers.\n"
        );
        if let Some(why) = &self.arm_missing {
            let _ = writeln!(w, "The {THUMB} columns are empty: {why}\n");
        }
        let _ = writeln!(
            w,
            "| model | function | ops | lines | bytes {} | bytes {} | bytes {} | bytes {} |",
            COLUMNS[0], COLUMNS[1], COLUMNS[2], COLUMNS[3]
        );
        let _ = writeln!(w, "|---|---|---:|---:|---:|---:|---:|---:|");
        for m in &self.models {
            for f in &m.functions {
                let b = f.bytes.map(bytes_cell);
                let _ = writeln!(
                    w,
                    "| {} | `{}` | {} | {} | {} | {} | {} | {} |",
                    m.stem,
                    f.output.name(),
                    f.ops.total(),
                    f.lines,
                    b[0],
                    b[1],
                    b[2],
                    b[3]
                );
            }
        }
        let _ = writeln!(w);
    }

    /// The table per model: the five default functions together.
    fn size_table(&self, w: &mut String) {
        let _ = writeln!(
            w,
            "## Per model: the five default functions together\n\n\
             What a crate with one `#[derive(articulated::Chain)]` and the default outputs \
             (`mass_matrix`, `bias`, `gravity`, `inverse_dynamics`, `forward_dynamics`) adds to \
             the program: the sums of the table above, and the constants of the model's \
             functions in `.rodata` on x86-64 (`size -A` of the crate's rlib, all seven \
             functions; on ARM the constants sit in literal pools inside the functions, so they \
             are already in its bytes).\n"
        );
        let _ = writeln!(
            w,
            "| model | nq / nv | ops | bytes {} | bytes {} | bytes {} | bytes {} | .rodata bytes x86-64 / v3 (7 functions) |",
            COLUMNS[0], COLUMNS[1], COLUMNS[2], COLUMNS[3]
        );
        let _ = writeln!(w, "|---|---:|---:|---:|---:|---:|---:|---:|");
        for m in &self.models {
            let ops = default_ops(m);
            let sums = [0, 1, 2, 3].map(|k| bytes_cell(default_bytes(m, k)));
            let _ = writeln!(
                w,
                "| {} | {} / {} | {ops} | {} | {} | {} | {} | {} / {} |",
                m.stem,
                m.nq,
                m.nv,
                sums[0],
                sums[1],
                sums[2],
                sums[3],
                bytes_cell(m.rodata[0]),
                bytes_cell(m.rodata[1])
            );
        }
        let _ = writeln!(w);
    }

    /// The table per model: expansion and build times.
    fn time_table(&self, w: &mut String) {
        let _ = writeln!(
            w,
            "## Per model: build time\n\n\
             A user crate holding one `#[derive(articulated::Chain)]` of the model with the \
             default outputs, its dependencies already built; medians of {} runs, in seconds.\n\n\
             - **expansion**: the `macro_expand_crate` line of `RUSTC_BOOTSTRAP=1 cargo rustc \
             --release -- -Z time-passes` (an unstable flag, used here for the measurement \
             only): the time the derive takes to read the file and generate the code. \
             **opt 0**: the procedural macro compiled as cargo does by default in release \
             builds (`[profile.release.build-override]` defaults to opt-level 0); **opt 3**: \
             with\n\n  ```toml\n  [profile.release.build-override]\n  opt-level = 3\n  ```\n\n  \
             in the user's `Cargo.toml`, which also compiles `syn` and the generator optimized \
             (a one-time cost, when the dependencies are built);\n\
             - **build**: the wall clock of `touch src/lib.rs && cargo build --release`, \
             expansion included: for the default target and for x86-64-v3 with the default \
             opt-0 macros, and, in the last column, of the `-Z time-passes` builds with opt-3 \
             macros (default target);\n\
             - **(empty)** is a crate without a model (`use articulated as _;`): cargo's and \
             rustc's fixed cost, included in every other row.\n",
            self.repeats
        );
        let _ = writeln!(
            w,
            "| model | expansion, macros opt 0 | expansion, macros opt 3 | build x86-64 | build x86-64-v3 | build x86-64, macros opt 3 |"
        );
        let _ = writeln!(w, "|---|---:|---:|---:|---:|---:|");
        let rows = std::iter::once(("(empty)", &self.empty))
            .chain(self.models.iter().map(|m| (m.stem.as_str(), &m.times)));
        for (name, t) in rows {
            let v = t.values().map(secs);
            let _ = writeln!(
                w,
                "| {name} | {} | {} | {} | {} | {} |",
                v[0], v[1], v[2], v[3], v[4]
            );
        }
        let _ = writeln!(w);
    }
}

/// The operations of a model's five default functions.
fn default_ops(m: &ModelRow) -> usize {
    m.functions
        .iter()
        .filter(|f| Output::DEFAULT.contains(&f.output))
        .map(|f| f.ops.total())
        .sum()
}

/// The bytes of a model's five default functions in column `k` of [`COLUMNS`], if measured.
fn default_bytes(m: &ModelRow, k: usize) -> Option<u64> {
    m.functions
        .iter()
        .filter(|f| Output::DEFAULT.contains(&f.output))
        .map(|f| f.bytes[k])
        .sum()
}

/// Bytes per operation in column `k`, over every measured function of `models`.
fn bytes_per_op(models: &[ModelRow], k: usize) -> Option<f64> {
    let (mut bytes, mut ops) = (0u64, 0u64);
    for f in models.iter().flat_map(|m| &m.functions) {
        if let Some(b) = f.bytes[k] {
            bytes += b;
            ops += f.ops.total() as u64;
        }
    }
    (ops > 0).then(|| bytes as f64 / ops as f64)
}

/// `12.3 KiB`, `1.50 MiB`.
fn kib(bytes: u64) -> String {
    let k = bytes as f64 / 1024.0;
    if k >= 1024.0 {
        format!("{:.2} MiB", k / 1024.0)
    } else {
        format!("{k:.1} KiB")
    }
}

/// A byte count, or `n/a`.
fn bytes_cell(x: Option<u64>) -> String {
    x.map_or_else(|| "n/a".into(), |x| x.to_string())
}

/// Seconds with two decimals, or `n/a`.
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

// ---------------------------------------------------------------------------------------------

/// Operations, lines and bytes of machine code per model and function, and build times:
/// measures them, saves `bench/size/size.json` and writes `docs/size.md`.
#[derive(clap::Parser)]
#[command(
    name = "size_table",
    override_usage = "size_table [--repeats R] [--models a,b,…] | size_table --render"
)]
struct Cli {
    /// Runs per timing (3 for the page; fewer prints a partial page instead of writing it).
    #[arg(long, value_name = "R", default_value_t = 3,
          value_parser = clap::value_parser!(u64).range(1..))]
    repeats: u64,
    /// The models measured, by file stem under models/ (all for the page; fewer prints a
    /// partial page instead of writing it).
    #[arg(long, value_name = "a,b,…")]
    models: Option<String>,
    /// Rewrite the page from bench/size/size.json without measuring.
    #[arg(long)]
    render: bool,
}

/// Command-line options.
struct Args {
    /// Runs per timing (3 for the page).
    repeats: usize,
    /// The models measured (all for the page).
    models: Vec<&'static Model>,
    /// Rewrite the page from `bench/size/size.json` without measuring.
    render: bool,
}

/// Reads the command line.
fn parse_args() -> Result<Args> {
    let cli = <Cli as clap::Parser>::parse();
    let models = match &cli.models {
        None => MODELS.iter().collect(),
        Some(list) => list
            .split(',')
            .map(|name| {
                MODELS
                    .iter()
                    .find(|m| m.stem == name.trim())
                    .ok_or_else(|| format!("no model `{name}` in models/"))
            })
            .collect::<Result<_>>()?,
    };
    Ok(Args {
        repeats: usize::try_from(cli.repeats).map_err(|e| e.to_string())?,
        models,
        render: cli.render,
    })
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

/// Runs every measurement (steps 1 to 5 of the module docs), in order.
fn measure(args: &Args) -> Result<Report> {
    let start = Instant::now();
    let load_before = load_average();
    let models = &args.models;

    say!("generating the code of {} models in-process", models.len());
    let mut statics = Vec::new();
    for m in models {
        statics.push(static_figures(m)?);
    }

    let ws = scratch().join("ws");
    let ws_o3 = scratch().join("ws-o3");
    write_workspace(&ws, models, true, false)?;
    write_workspace(&ws_o3, models, false, true)?;

    // Bytes, and the warm-up of each configuration's dependencies.
    let mut bytes = BTreeMap::new();
    let arm_missing = (!arm_installed()).then(|| {
        format!(
            "the target is not installed here (`rustup target add {THUMB}` did not run or failed)."
        )
    });
    for config in [DEFAULT, V3, ARM] {
        if config.triple.is_some() && arm_missing.is_some() {
            continue;
        }
        say!(
            "{}: building the bytes_ crates (dependencies first: minutes)",
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

    let packages: Vec<String> = std::iter::once("time_empty".to_string())
        .chain(models.iter().map(|m| format!("time_{}", m.stem)))
        .collect();
    let total = packages.len() * 4 * args.repeats;
    let mut done = 0;
    let mut times = Vec::new();
    for package in &packages {
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
        let [expand_o0, expand_o3, build_default, build_v3, build_o3] = runs.map(median);
        times.push(Times {
            expand_o0,
            expand_o3,
            build_default,
            build_v3,
            build_o3,
        });
    }
    let load_after = load_average();

    // Everything measured, per model.
    let byte_of = |config: &str, stem: &str, ty: &str, output: Output| {
        bytes
            .get(config)
            .and_then(|per: &BTreeMap<String, Bytes>| per.get(&format!("bytes_{stem}")))
            .and_then(|b| b.functions.get(&(ty.to_string(), output)).copied())
    };
    let rodata_of = |config: &str, stem: &str| {
        bytes
            .get(config)
            .and_then(|per: &BTreeMap<String, Bytes>| per.get(&format!("bytes_{stem}")))
            .map(|b| b.rodata)
    };
    let mut rows = Vec::new();
    for ((m, st), t) in models.iter().zip(statics).zip(times.iter().skip(1)) {
        let f32_ty = format!("{}F32", m.ty);
        let functions = OUTPUTS
            .iter()
            .map(|&output| {
                let s = st.functions.get(&output).copied().unwrap_or_default();
                Function {
                    output,
                    ops: s.ops,
                    lines: s.lines,
                    bytes: [
                        byte_of(DEFAULT.name, m.stem, m.ty, output),
                        byte_of(V3.name, m.stem, m.ty, output),
                        byte_of(ARM.name, m.stem, m.ty, output),
                        byte_of(ARM.name, m.stem, &f32_ty, output),
                    ],
                }
            })
            .collect();
        rows.push(ModelRow {
            stem: m.stem.to_string(),
            nq: st.nq,
            nv: st.nv,
            functions,
            rodata: [rodata_of(DEFAULT.name, m.stem), rodata_of(V3.name, m.stem)],
            times: *t,
        });
    }
    Ok(Report {
        models: rows,
        empty: times.first().copied().unwrap_or_default(),
        arm_missing,
        repeats: args.repeats,
        cpu: cpu_model(),
        nproc: first_line("nproc", &[]),
        rustc: first_line("rustc", &["--version"]),
        load_before,
        load_after,
        minutes: start.elapsed().as_secs_f64() / 60.0,
    })
}

/// Runs the `op_counts` binary (which also writes the figure) and returns its section.
fn op_counts() -> Result<String> {
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
    Ok(String::from_utf8_lossy(&run(c)?.stdout).into_owned())
}

/// Measures (or, with `--render`, reads the last measurements), then writes
/// `bench/size/size.json` and `docs/size.md`, or prints a partial run's page.
fn main() -> ExitCode {
    match main_inner() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            say!("{e}");
            ExitCode::FAILURE
        }
    }
}

/// [`main`], with errors as values.
fn main_inner() -> Result<()> {
    let args = parse_args()?;
    let data = root().join("bench/size/size.json");
    let page = root().join("docs/size.md");
    if args.render {
        let text =
            std::fs::read_to_string(&data).map_err(|e| format!("{}: {e}", data.display()))?;
        let value: Value =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", data.display()))?;
        let report = Report::from_json(&value)?;
        let markdown = report.markdown(&op_counts()?);
        write_atomically(&page, markdown.as_bytes())
            .map_err(|e| format!("{}: {e}", page.display()))?;
        say!("wrote {} from {}", page.display(), data.display());
        return Ok(());
    }
    // The page is rendered from the data file's form of the measurements, as `--render` does.
    let value = measure(&args)?.to_json();
    let markdown = Report::from_json(&value)?.markdown(&op_counts()?);
    if args.repeats != 3 || args.models.len() != MODELS.len() {
        say!("a partial run (--models or --repeats): the page goes to stdout; docs/size.md and bench/size/size.json are left as they are");
        print!("{markdown}");
        return Ok(());
    }
    let json = serde_json::to_string_pretty(&value).map_err(|e| e.to_string())? + "\n";
    for (path, contents) in [(&data, json), (&page, markdown)] {
        write_atomically(path, contents.as_bytes())
            .map_err(|e| format!("{}: {e}", path.display()))?;
        say!("wrote {}", path.display());
    }
    Ok(())
}
