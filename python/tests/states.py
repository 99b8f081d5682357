"""Random states for the tests: unit quaternions, other coordinates uniform in ±`spread`,
velocities and the third argument normal (scaled by `scale`)."""

import numpy as np


def random_states(model, n, seed=0, spread=2.0, scale=1.0):
    rng = np.random.default_rng(seed)
    q = np.tile(model.neutral(), (n, 1))
    for k, name in enumerate(model.q_names):
        if name.endswith(".qw"):
            quat = rng.standard_normal((n, 4))
            q[:, k:k + 4] = quat / np.linalg.norm(quat, axis=1, keepdims=True)
        elif not name.endswith((".qx", ".qy", ".qz")):
            q[:, k] = rng.uniform(-spread, spread, n)
    return q, rng.standard_normal((n, model.nv)), scale * rng.standard_normal((n, model.nv))
