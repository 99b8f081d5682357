"""Pinocchio's rate of the centroidal momentum ->
`tests/data/pinocchio_centroidal_rate/pinocchio-centroidal-rate.json`, for the generated
`centroidal_momentum_rate` and `centroidal_momentum_drift`
(tests/tests/generated_free_floating.rs).

Runs on our machines, NOT in CI (CI has no Pinocchio). To regenerate (from anywhere):

    pip install pin numpy            # Pinocchio 4.1
    python tests/data/pinocchio_centroidal_rate/make_pinocchio_centroidal_rate.py

The states are seeded, so a rerun reproduces the JSON byte for byte (up to Pinocchio's own
changes). The file is written whole, through a temporary file and a rename.

Model (`models.humanoid_free_flyer`): `models/humanoid.urdf` on Pinocchio's free flyer
(`pin.JointModelFreeFlyer()`), what `models/humanoid.chain` writes as `free(quaternion)`. It holds
`urdf`, `floating`, `nq`, `nv`, `mass`, `gravity`, `joints` (the joints with coordinates in OUR
order: `root_joint`, then the URDF's movable joints depth first from the root link, children in
document order) and `states`.

Conventions of the stored values, ALL IN OUR LAYOUT (the layout helpers are the frames script's,
tests/data/pinocchio_frames/make_pinocchio_frames.py):
- `q` ours: `[x, y, z, w, qx, qy, qz]` (Pinocchio's is `[x, y, z, qx, qy, qz, qw]`), then one
  angle per revolute joint in our order; `v`, `a`: the base's six (linear then angular, both in
  the base's frame, as Pinocchio's), then one per joint in our order.
- `centroidal_momentum`: h_G = [k_G; p], ANGULAR FIRST, about the centre of mass, world axes
  (`computeCentroidalMomentum` -> `data.hg`, linear first: halves swapped here).
- `centroidal_momentum_rate`: dh_G/dt = A_G a + dA_G v, ANGULAR FIRST, about the centre of mass,
  world axes (`computeCentroidalMomentumTimeVariation(model, data, q, v, a)` -> `data.dhg`,
  linear first: halves swapped here). No gravity in it: it is the rate of the momentum, not the
  external wrench.
- `centroidal_momentum_drift`: dA_G v, the same at a = 0.

States: `numpy.random.default_rng(SEED)`, per state: the base position uniform in [-1, 1], the
quaternion uniform in the ball then normalized, the joint angles uniform in [-1.2, 1.2], v in
[-2, 2], a in [-3, 3].

Checks before writing (Pinocchio against itself, 1e-12 relative to the largest entry): the rate
is A_G a + dA_G v (`computeCentroidalMapTimeVariation`: `data.Ag`, `data.dAg`); its linear part is
m times the centre of mass's acceleration (`centerOfMass(q, v, a)` -> `data.acom[0]`); h_G = A_G v;
at v = 0, a = 0 it is zero.
"""
import os
import sys

import numpy as np
import pinocchio as pin

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, '..', '..', '..'))
sys.path.insert(0, os.path.join(HERE, '..', 'pinocchio_frames'))
sys.dont_write_bytecode = True  # no __pycache__ beside the frames script
from make_pinocchio_frames import (  # noqa: E402
    angular_first, layout, links_and_order, load, rel, write_json)

SEED = 20261220
STATES = 4
TOL = 1e-12
URDF = 'models/humanoid.urdf'


def draw_state(rng, n_joints):
    """Our (q, v, a): the free flyer's seven, then the joints."""
    x = rng.uniform(-1, 1, 3)
    while True:
        quat = rng.uniform(-1, 1, 4)
        if 0.01 < quat @ quat <= 1.0:
            break
    q = np.array(list(x) + list(quat / np.linalg.norm(quat)) + list(rng.uniform(-1.2, 1.2, n_joints)))
    nv = n_joints + 6
    return q, rng.uniform(-2, 2, nv), rng.uniform(-3, 3, nv)


def main():
    rng = np.random.default_rng(SEED)
    path = os.path.join(ROOT, URDF)
    _, order = links_and_order(path)
    model = load(path, 'quaternion')
    data = model.createData()
    perm_v, q_to_pinocchio = layout(model, 'quaternion', order)
    assert np.allclose(model.gravity.linear, [0, 0, -9.81])
    mass = pin.computeTotalMass(model)

    def to_pinocchio_v(v):
        out = np.zeros(model.nv)
        out[perm_v] = v
        return out

    zero = np.zeros(model.nv)
    states = []
    for _ in range(STATES):
        q, v, a = draw_state(rng, len(order))
        qp, vp, ap = q_to_pinocchio(q), to_pinocchio_v(v), to_pinocchio_v(a)
        hg = np.array(pin.computeCentroidalMomentum(model, data, qp, vp).vector)
        dhg = np.array(pin.computeCentroidalMomentumTimeVariation(model, data, qp, vp, ap).vector)
        drift = np.array(pin.computeCentroidalMomentumTimeVariation(model, data, qp, vp, zero).vector)
        still = np.array(pin.computeCentroidalMomentumTimeVariation(model, data, qp, zero, zero).vector)

        pin.computeCentroidalMapTimeVariation(model, data, qp, vp)
        ag, dag = np.array(data.Ag), np.array(data.dAg)
        pin.centerOfMass(model, data, qp, vp, ap)
        acom = data.acom[0].copy()
        assert rel(ag @ ap + dag @ vp, dhg) < TOL, ('A_G a + dA_G v', rel(ag @ ap + dag @ vp, dhg))
        assert rel(dag @ vp, drift) < TOL, ('dA_G v', rel(dag @ vp, drift))
        assert rel(mass * acom, dhg[0:3]) < TOL, ('m acom', rel(mass * acom, dhg[0:3]))
        assert rel(ag @ vp, hg) < TOL, ('A_G v', rel(ag @ vp, hg))
        assert np.abs(still).max() == 0.0, still

        states.append({
            'q': q.tolist(), 'v': v.tolist(), 'a': a.tolist(),
            'centroidal_momentum': angular_first(hg).tolist(),
            'centroidal_momentum_rate': angular_first(dhg).tolist(),
            'centroidal_momentum_drift': angular_first(drift).tolist(),
        })

    out = {
        'generator': f'Pinocchio {pin.__version__} (pip package `pin`), '
                     'tests/data/pinocchio_centroidal_rate/make_pinocchio_centroidal_rate.py',
        'seed': SEED,
        'conventions': __doc__,
        'models': {'humanoid_free_flyer': {
            'urdf': URDF, 'floating': 'quaternion', 'nq': model.nq, 'nv': model.nv,
            'mass': mass, 'gravity': model.gravity.linear.tolist(),
            'joints': ['root_joint'] + order, 'states': states}},
    }
    write_json(os.path.join(HERE, 'pinocchio-centroidal-rate.json'), out)


if __name__ == '__main__':
    main()
