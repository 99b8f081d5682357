"""``generate()``: a model's generated code, built with the user's cargo into its own
extension module, cached by everything that decides what it is."""

from __future__ import annotations

import hashlib
import importlib.util
import json
import os
import platform
import shutil
import subprocess
import sys
import sysconfig
import threading
from collections import namedtuple
from pathlib import Path

from . import _native
from ._native import Error

#: One output the generator knows (from its table, where each output is described once).
Output = namedtuple("Output", "name args group default equation kept frames")

_LOADED: dict = {}
_HERE = Path(__file__).resolve().parent


def outputs():
    """Every output the generator knows, as ``Output(name, args, group, default, equation,
    kept, frames)``: ``args`` the arguments in order (``q``, ``v``, ``a``, ``tau``, ``base``),
    ``default`` whether a model that names none gets it, ``frames`` whether it is per frame."""
    return [Output(*o) for o in _native.outputs()]


def _choose(names, frames):
    """The outputs to generate: ``names`` (outputs or groups) or the defaults."""
    table = {o.name: o for o in outputs()}
    groups = {}
    for o in table.values():
        if o.group:
            groups.setdefault(o.group, []).append(o.name)
    if names is None:
        names = [o.name for o in table.values() if o.default]
    chosen = []
    for n in names:
        if n in groups:
            members = [m for m in groups[n] if not table[m].kept and (frames or not table[m].frames)]
            chosen.extend(m for m in members if m not in chosen)
        elif n not in table:
            raise Error(
                f"outputs: unknown output `{n}`: expected one of {', '.join(table)} "
                f"or a group ({', '.join(groups)})"
            )
        elif table[n].kept:
            raise Error(
                f"outputs: `{n}` fills a matrix that Rust code keeps between calls; from Python "
                "ask for `mass_matrix`"
            )
        elif table[n].frames and not frames:
            raise Error(f"outputs: `{n}` is per frame: name the frames with frames=[...]")
        elif n not in chosen:
            chosen.append(n)
    return [table[n] for n in chosen]


def _cargo():
    cargo = os.environ.get("CARGO") or shutil.which("cargo")
    if cargo is None:
        raise Error(
            "generate() builds the model's code with cargo, which is not on PATH: install Rust "
            "(https://rustup.rs: `curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs | sh`) "
            "and open a new shell, or set CARGO to its path"
        )
    return cargo


def _toolchain(cargo):
    """``rustc -vV`` as cargo would run it: a changed toolchain changes the key."""
    rustc = os.environ.get("RUSTC") or str(Path(cargo).with_name("rustc"))
    if not Path(rustc).exists():
        rustc = shutil.which("rustc") or "rustc"
    try:
        return subprocess.run([rustc, "-vV"], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        raise Error(f"generate(): `{rustc} -vV` failed ({e}): is the Rust toolchain installed?")


def _attribute(path, chosen, scalar, frames, floating, lanes):
    """The ``#[chain(...)]`` of the generated crate."""
    kind = {".chain": "file", ".urdf": "urdf", ".xml": "mjcf"}.get(path.suffix)
    if kind is None:
        raise Error(f"{path}: expected a .chain, .urdf or MJCF .xml file")
    items = [f"{kind} = {json.dumps(str(path))}"]
    if floating is not None:
        if floating not in ("euler", "quaternion"):
            raise Error(f'floating={floating!r}: expected None, "euler" or "quaternion"')
        items.append(f"floating = {floating}")
    items.append(f"scalar = {scalar}")
    items.append("outputs = [" + ", ".join(o.name for o in chosen) + "]")
    if frames:
        items.append("frames = [" + ", ".join(frames) + "]")
    items.append(f"lanes = {lanes}")
    return "#[chain(\n    " + ",\n    ".join(items) + ",\n)]"


_WIDTHS = {"q": "Generated::NQ", "v": "Generated::NV", "a": "Generated::NV",
           "tau": "Generated::NV", "base": "6"}


# The crates a generated crate builds from, by path: the workspace's runtime and what it uses.
_SOURCE_CRATES = ("runtime", "macros", "codegen", "dynamics")


def _crate_sources():
    """A digest of the Rust sources and manifests of the crates a generated crate builds from
    (the clone the package was installed from): the version alone stays the same while a
    checkout's generator changes, and a module cached before the change would be reused."""
    crates = Path(_native._CRATES).resolve().parent
    digest = hashlib.sha256()
    for name in _SOURCE_CRATES:
        root = crates / name
        files = [root / "Cargo.toml"] + sorted((root / "src").rglob("*.rs"))
        for f in files:
            if f.is_file():
                digest.update(str(f.relative_to(crates)).encode())
                digest.update(f.read_bytes())
    return digest.hexdigest()


def _sources(module, path, chosen, scalar, frames, floating, lanes):
    """``Cargo.toml`` and ``src/lib.rs`` of the crate."""
    crates = Path(_native._CRATES).resolve().parent
    if not (crates / "runtime" / "Cargo.toml").exists():
        raise Error(
            f"generate() builds against the crates of the clone the package was installed from, "
            f"{crates}, which is gone: install the package again from a clone "
            "(`pip install ./python`)"
        )
    manifest = f"""# Written by articulated.generate() for {path}: the model's generated code as the
# extension module `{module}`.
[package]
name = "{module.replace('_', '-')}"
version = "0.0.0"
edition = "2021"
publish = false

[lib]
name = "{module}"
crate-type = ["cdylib"]

[dependencies]
articulated = {{ path = {json.dumps(str(crates / "runtime"))}, features = ["rayon"] }}
pyo3 = {{ version = "0.30", features = ["extension-module"] }}
numpy = "0.30"
rayon = "1"
# A C-ordered batch read where it lies: its rows cast to nalgebra vectors.
bytemuck = "1"
nalgebra = {{ version = "0.34", default-features = false, features = ["convert-bytemuck"] }}

[workspace]
"""
    bindings = "\n".join(
        f"    {o.name}(" + ", ".join(f"{a}: {_WIDTHS[a]}" for a in o.args) + f") => {o.name}_batch;"
        for o in chosen
    )
    lib = f"""//! The generated code of {path} for Python, written by articulated.generate().
#![allow(missing_docs)]

/// The scalar the chain is generated in.
type Scalar = {scalar};
/// Its name, for `Model.scalar`.
const SCALAR: &str = "{scalar}";

/// The chain.
#[derive(articulated::Chain)]
{_attribute(path, chosen, scalar, frames, floating, lanes)}
pub struct Generated;

include!("glue.rs");

bindings! {{
{bindings}
}}

/// The module: one class, `Model`.
#[pymodule]
fn {module}(m: &Bound<'_, PyModule>) -> PyResult<()> {{
    m.add_class::<Model>()
}}
"""
    return manifest, lib


def _build(cargo, crate, target_dir, module, verbose):
    """``cargo build --release`` of ``crate``, a line of progress per compiled crate; the built
    library's path."""
    cmd = [cargo, "build", "--release", "--message-format=json-render-diagnostics",
           "--manifest-path", str(crate / "Cargo.toml")]
    env = dict(os.environ, CARGO_TARGET_DIR=str(target_dir))
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    built, library = 0, None
    errors = []

    def drain_stderr():
        for line in proc.stderr:
            errors.append(line)

    reader = threading.Thread(target=drain_stderr, daemon=True)
    reader.start()
    for line in proc.stdout:
        try:
            message = json.loads(line)
        except ValueError:
            continue
        if message.get("reason") == "compiler-artifact":
            built += 1
            name = message["target"]["name"]
            if verbose:
                print(f"\r[articulated] built {built} crates, last {name:<40}", end="",
                      file=sys.stderr, flush=True)
            if name == module:
                library = next((f for f in message["filenames"]
                                if f.endswith((".so", ".dylib", ".dll", ".pyd"))), None)
    proc.wait()
    reader.join()
    if verbose:
        print(file=sys.stderr)
    if proc.returncode != 0 or library is None:
        tail = "".join(errors[-60:])
        raise Error(f"generate(): cargo could not build the generated code of the model:\n{tail}")
    return Path(library)


def generate(path, outputs=None, scalar="f64", frames=(), floating=None, lanes=None,
             cache_dir=None, verbose=True):
    """The model in ``path`` (``.chain``, URDF or MJCF) as generated code: an object with the
    methods of ``Model`` for each output in ``outputs`` (names or groups; default: the
    description's defaults), in ``scalar`` (``"f64"`` or ``"f32"``: then its arrays are
    float32), ``frames`` the frames the frame outputs give, ``lanes`` states per SIMD vector
    (default 4 in f64, 8 in f32). Every call runs the outputs' batch twins in lanes on all
    cores.

    The first call writes a crate under ``cache_dir`` (default ``$ARTICULATED_CACHE`` or
    ``~/.cache/articulated``) and builds it with cargo (minutes; a line of progress on
    stderr unless ``verbose=False``); it is cached by the model as loaded, the options, the
    versions of ``articulated`` and rustc, the sources of the crates it builds from (the clone
    the package was installed from), the Python ABI and the target's flags, so a second
    call, in this process or another, imports what was built. Every model builds in one target
    directory (``ARTICULATED_TARGET_DIR``, default ``<cache_dir>/target``), so the dependencies
    build once."""
    path = Path(path).resolve()
    if scalar not in ("f64", "f32"):
        raise Error(f'scalar={scalar!r}: expected "f64" or "f32"')
    frames = list(frames)
    lanes = lanes if lanes is not None else (4 if scalar == "f64" else 8)
    if lanes not in (2, 4, 8, 16):
        raise Error(f"lanes={lanes!r}: expected 2, 4, 8 or 16")
    chosen = _choose(outputs, frames)
    description = _native.description_key(str(path), floating)
    cargo = _cargo()
    key_parts = {
        "description": description,
        "outputs": [o.name for o in chosen],
        "scalar": scalar, "frames": frames, "floating": floating, "lanes": lanes,
        "articulated": _native.__version__,
        "sources": _crate_sources(),
        "glue": (_HERE / "glue.rs").read_text(),
        "rustc": _toolchain(cargo),
        "python": [sys.implementation.cache_tag, sysconfig.get_config_var("EXT_SUFFIX")],
        "target": [platform.machine(), os.environ.get("RUSTFLAGS", ""),
                   os.environ.get("CARGO_ENCODED_RUSTFLAGS", "")],
    }
    key = hashlib.sha256(json.dumps(key_parts, sort_keys=True).encode()).hexdigest()[:20]
    module = f"articulated_gen_{key}"
    if module in _LOADED:
        return _LOADED[module].Model()
    root = Path(cache_dir or os.environ.get("ARTICULATED_CACHE")
                or Path.home() / ".cache" / "articulated")
    home = root / key
    library = home / (module + (sysconfig.get_config_var("EXT_SUFFIX") or ".so"))
    if not library.exists():
        crate = home / "crate"
        (crate / "src").mkdir(parents=True, exist_ok=True)
        manifest, lib = _sources(module, path, chosen, scalar, frames, floating, lanes)
        (crate / "Cargo.toml").write_text(manifest)
        (crate / "src" / "lib.rs").write_text(lib)
        shutil.copyfile(_HERE / "glue.rs", crate / "src" / "glue.rs")
        lock = Path(_native._CRATES).resolve().parent / "Cargo.lock"
        if lock.exists() and not (crate / "Cargo.lock").exists():
            # The versions the package was tested with (cargo drops what the crate does not use).
            shutil.copyfile(lock, crate / "Cargo.lock")
        # One target directory for every model, so the dependencies build once.
        target = os.environ.get("ARTICULATED_TARGET_DIR") or root / "target"
        built = _build(cargo, crate, Path(target), module, verbose)
        partial = library.with_suffix(".partial")
        shutil.copyfile(built, partial)
        os.replace(partial, library)  # whole or not at all
    spec = importlib.util.spec_from_file_location(module, library)
    loaded = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(loaded)
    _LOADED[module] = loaded
    return loaded.Model()
