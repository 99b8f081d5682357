"""`articulated.generate()`: the generated code built from Python against the interpreted
reference (an independent implementation: recursions over the model at run time, where the
generated code is straight-line code traced at build time), its batches, its f32 build, its
cache and its errors. Each distinct call builds a crate with cargo (about a minute here), so
the calls are few and shared."""

import os
from pathlib import Path

import numpy as np
import pytest

import articulated
from articulated import _generate

ROOT = Path(__file__).resolve().parents[2]
ARM = ROOT / "models" / "arm7.urdf"
OUTPUTS = ["mass_matrix", "inverse_dynamics", "forward_dynamics", "kinetic_energy",
           "inverse_dynamics_derivatives", "forward_dynamics_derivatives", "center_of_mass",
           "frame_placements", "frame_jacobians_local", "frame_velocities"]


@pytest.fixture(scope="session")
def cache(tmp_path_factory):
    return os.environ.get("ARTICULATED_TEST_CACHE") or tmp_path_factory.mktemp("cache")


@pytest.fixture(scope="session")
def generated(cache):
    return articulated.generate(ARM, outputs=OUTPUTS, frames=["link7"], cache_dir=cache,
                                verbose=False)


@pytest.fixture(scope="session")
def reference():
    return articulated.Model.load(ARM)


def states(n, seed=0):
    rng = np.random.default_rng(seed)
    return (rng.uniform(-3, 3, (n, 7)), rng.standard_normal((n, 7)), rng.standard_normal((n, 7)))


def close(ours, theirs, tol=1e-12):
    scale = max(1.0, float(np.max(np.abs(theirs))))
    assert np.max(np.abs(np.asarray(ours) - theirs)) <= tol * scale


def test_generated_against_the_interpreter(generated, reference):
    # 203 states: lanes of four with a remainder, spread over threads.
    q, v, a = states(203)
    assert (generated.nq, generated.nv, generated.scalar) == (7, 7, "f64")
    assert generated.q_names == reference.q_names and generated.frames == ["link7"]
    assert generated.outputs == OUTPUTS
    close(generated.mass_matrix(q), reference.mass_matrix(q))
    tau = generated.inverse_dynamics(q, v, a)
    close(tau, reference.inverse_dynamics(q, v, a))
    close(generated.forward_dynamics(q, v, tau), a, 1e-9)
    close(generated.kinetic_energy(q, v), reference.kinetic_energy(q, v))
    close(generated.center_of_mass(q), reference.center_of_mass(q))
    for ours, theirs in zip(generated.inverse_dynamics_derivatives(q, v, a),
                            reference.inverse_dynamics_derivatives(q, v, a)):
        close(ours, theirs, 1e-11)
    for ours, theirs in zip(generated.forward_dynamics_derivatives(q, v, tau),
                            reference.forward_dynamics_derivatives(q, v, tau)):
        close(ours, theirs, 1e-9)
    rotation, translation = generated.frame_placements(q)
    assert rotation.shape == (203, 1, 3, 3) and translation.shape == (203, 1, 3)
    r, p = reference.frame_placement(q, "link7")
    close(rotation[:, 0], r)
    close(translation[:, 0], p)
    close(generated.frame_jacobians_local(q)[:, 0], reference.frame_jacobian(q, "link7"))
    close(generated.frame_velocities(q, v)[:, 0], reference.frame_velocity(q, v, "link7"))


def test_one_state_and_batch_agree(generated):
    q, v, a = states(9, seed=1)
    batch = generated.inverse_dynamics(q, v, a)
    for k in range(9):
        assert np.array_equal(generated.inverse_dynamics(q[k], v[k], a[k]), batch[k])
    assert isinstance(generated.kinetic_energy(q[0], v[0]), float)
    # Any layout reads as the same rows: Fortran order, strided views, lists.
    assert np.array_equal(generated.inverse_dynamics(np.asfortranarray(q), v, a), batch)
    wide = np.zeros((9, 14))
    wide[:, 1::2] = q
    assert np.array_equal(generated.inverse_dynamics(wide[:, 1::2], v, a), batch)
    assert np.array_equal(generated.inverse_dynamics(q[0].tolist(), v[0], a[0]), batch[0])


def test_errors_of_generated_calls(generated):
    q, v, a = states(5)
    q[3, 1] = np.nan
    with pytest.raises(articulated.Error, match="state 3 of the batch"):
        generated.forward_dynamics(q, v, a)
    with pytest.raises(articulated.Error, match=r"argument `v` has shape \[3, 7\]"):
        generated.inverse_dynamics(q, v[:3], a)
    with pytest.raises(articulated.Error, match="shape"):
        generated.mass_matrix(np.zeros(6))


def test_second_call_is_cached(generated, cache, monkeypatch):
    def no_build(*args):
        raise AssertionError("rebuilt a cached model")

    monkeypatch.setattr(_generate, "_build", no_build)
    # In this process: the same module. From disk (as a new process finds it): no build.
    again = articulated.generate(ARM, outputs=OUTPUTS, frames=["link7"], cache_dir=cache,
                                 verbose=False)
    assert type(again) is type(generated)
    monkeypatch.setattr(_generate, "_LOADED", {})
    articulated.generate(ARM, outputs=OUTPUTS, frames=["link7"], cache_dir=cache, verbose=False)
    # Another option is another key: it would build.
    with pytest.raises(AssertionError, match="rebuilt"):
        articulated.generate(ARM, outputs=["gravity"], cache_dir=cache, verbose=False)
    # So is a change to the sources it builds from (a checkout's generator), same version.
    monkeypatch.setattr(_generate, "_crate_sources", lambda: "another generator")
    with pytest.raises(AssertionError, match="rebuilt"):
        articulated.generate(ARM, outputs=OUTPUTS, frames=["link7"], cache_dir=cache,
                             verbose=False)


def test_sources_digest_follows_the_crates(tmp_path, monkeypatch):
    # A tree laid out as the clone: the digest changes with a source file of the crates a
    # generated crate builds from, not with another file.
    for crate in _generate._SOURCE_CRATES:
        (tmp_path / crate / "src").mkdir(parents=True)
        (tmp_path / crate / "Cargo.toml").write_text(f"[package]\nname = '{crate}'\n")
        (tmp_path / crate / "src" / "lib.rs").write_text("// lib\n")
    (tmp_path / "python").mkdir()
    monkeypatch.setattr(_generate._native, "_CRATES", str(tmp_path / "python"))
    before = _generate._crate_sources()
    assert _generate._crate_sources() == before
    (tmp_path / "README.md").write_text("not a source")
    assert _generate._crate_sources() == before
    (tmp_path / "codegen" / "src" / "emit.rs").write_text("// a new pass\n")
    assert _generate._crate_sources() != before


def test_f32(cache, reference):
    model = articulated.generate(ARM, outputs=["inverse_dynamics"], scalar="f32",
                                 cache_dir=cache, verbose=False)
    q, v, a = states(50, seed=2)
    tau = model.inverse_dynamics(q, v, a)
    assert tau.dtype == np.float32 and model.scalar == "f32"
    close(tau, reference.inverse_dynamics(q, v, a), 1e-4)


def test_options_are_checked(cache, monkeypatch):
    with pytest.raises(articulated.Error, match="unknown output `mass`"):
        articulated.generate(ARM, outputs=["mass"], cache_dir=cache)
    with pytest.raises(articulated.Error, match="per frame"):
        articulated.generate(ARM, outputs=["frame_placements"], cache_dir=cache)
    with pytest.raises(articulated.Error, match="keeps"):
        articulated.generate(ARM, outputs=["mass_matrix_update"], cache_dir=cache)
    with pytest.raises(articulated.Error, match="scalar='f16'"):
        articulated.generate(ARM, scalar="f16", cache_dir=cache)
    with pytest.raises(articulated.Error, match="cannot read"):
        articulated.generate(ROOT / "missing.urdf", cache_dir=cache)
    monkeypatch.delenv("CARGO", raising=False)
    monkeypatch.setenv("PATH", "")
    with pytest.raises(articulated.Error, match="install Rust"):
        articulated.generate(ARM, outputs=["gravity"], cache_dir=cache)


def test_output_table():
    table = {o.name: o for o in articulated.outputs()}
    assert table["inverse_dynamics"].args == ["q", "v", "a"]
    assert table["mass_matrix"].default and table["mass_matrix_update"].kept
    assert table["frame_placements"].frames
