"""MJCF from Python: the mass matrix of every model without a free joint that
tests/data/mujoco/mujoco-values.json holds (MuJoCo's own values, committed with their script,
make_mujoco_reference.py), at MuJoCo's states (`q` is MuJoCo's `qpos` for hinges and slides)."""

import json
from pathlib import Path

import numpy as np
import pytest

import articulated

DATA = Path(__file__).resolve().parents[2] / "tests" / "data" / "mujoco"
VALUES = json.loads((DATA / "mujoco-values.json").read_text())["models"]
PLAIN = sorted(
    name for name, m in VALUES.items()
    if m["loads"] and m["nv"] and not m["free_dofs"] and m["states"] and (DATA / name).exists()
)


def test_there_are_models():
    assert len(PLAIN) >= 10


@pytest.mark.parametrize("name", PLAIN)
def test_mass_matrix_against_mujoco(name):
    model = articulated.Model.load(DATA / name)
    entry = VALUES[name]
    assert (model.nq, model.nv) == (entry["nq"], entry["nv"])
    for state in entry["states"]:
        q = np.array(state["qpos"])
        theirs = np.array(state["mass_matrix"]).reshape(model.nv, model.nv)
        ours = model.mass_matrix(q)
        assert np.max(np.abs(ours - theirs)) <= 1e-9 * max(1.0, np.max(np.abs(theirs))), name
