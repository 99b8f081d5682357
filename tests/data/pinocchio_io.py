"""Helpers the reference scripts share (`make_armature_reference.py`, `make_mimic_reference.py`):
a matrix symmetrized from its upper triangle, a seeded random state, and a JSON file written
whole or not at all."""
import json
import os

import numpy as np


def symmetric(m):
    """`m` symmetrized from its upper triangle (Pinocchio's crba fills only that)."""
    m = np.array(m)
    return np.triu(m) + np.triu(m, 1).T


def draw_state(rng, model):
    """`(q, v, a, tau)`, uniform in [-1.2, 1.2], [-2, 2], [-3, 3] and [-5, 5], drawn in that
    order (the committed files depend on it)."""
    q = rng.uniform(-1.2, 1.2, model.nq)
    v = rng.uniform(-2, 2, model.nv)
    a = rng.uniform(-3, 3, model.nv)
    tau = rng.uniform(-5, 5, model.nv)
    return q, v, a, tau


def write_json(path, out):
    """`out` to `path` with one-space indents, through a temporary file and a rename."""
    tmp = path + '.tmp'
    with open(tmp, 'w') as f:
        json.dump(out, f, indent=1)
    os.replace(tmp, path)
