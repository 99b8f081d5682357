"""Pinocchio reference values for mimic joints -> `tests/data/pinocchio-mimic.json`.

Runs on our machines, NOT in CI (CI has no Pinocchio): `pip install pin numpy`, then
`python tests/data/make_mimic_reference.py` from anywhere. The JSON it writes is committed and read
by `tests/tests/generated_mimic.rs`. The random states are seeded, so a rerun reproduces the file
(up to Pinocchio's own changes).

Model: `tests/data/gripper_mimic.urdf`, loaded with `buildModelFromUrdf(path, mimic=True)`
(Pinocchio 3.4 and later): each mimic joint becomes a `JointModelMimic` without coordinates of its
own, so nq = nv = 5 (shoulder, elbow, wrist, finger_left, right_knuckle). Fixed base, gravity
(0, 0, -9.81). mass_matrix = crba(q) (symmetrized), tau_out = rnea(q, v, a),
gravity = computeGeneralizedGravity(q), nle = nonLinearEffects(q, v), and qdd solving
M qdd = tau - nle with numpy (Pinocchio's ABA does not take mimic joints).

Before writing anything the script checks Pinocchio's coupled values against the same URDF loaded
with every joint independent (mimic=False) and the coupling G written out here:
M = G^T M_full G and tau = G^T tau_full(G q + o, G v, G a).
"""
import os

import numpy as np
import pinocchio as pin

from pinocchio_io import draw_state, symmetric, write_json


here = os.path.dirname(os.path.abspath(__file__))
urdf = os.path.join(here, 'gripper_mimic.urdf')
rng = np.random.default_rng(20261125)

model = pin.buildModelFromUrdf(urdf, mimic=True)
full = pin.buildModelFromUrdf(urdf)
assert (model.nq, model.nv, full.nv) == (5, 5, 8), (model.nq, model.nv, full.nv)

# A fresh Data for every call: Pinocchio 4.1's crba on a model with mimic joints reads state left
# in Data by the previous call. Reusing one Data, M's entries between the arm's joints and
# right_knuckle (below the mimic joint finger_right) come out wrong by up to 2e-3 (against 1e-17
# with a fresh Data), depending on the previous configuration.
def fresh():
    return model.createData()

# Full joint order (depth first, children in document order): shoulder, elbow, wrist, finger_left,
# left_tip (= -0.5 elbow + 0.3), finger_right (= finger_left), right_knuckle,
# thumb (= 12 finger_left - 0.2). Reduced: shoulder, elbow, wrist, finger_left, right_knuckle.
assert list(full.names)[1:] == ['shoulder', 'elbow', 'wrist', 'finger_left', 'left_tip',
                                'finger_right', 'right_knuckle', 'thumb'], list(full.names)
G = np.zeros((8, 5))
for row, (col, k) in enumerate([(0, 1), (1, 1), (2, 1), (3, 1), (1, -0.5), (3, 1), (4, 1),
                                (3, 12)]):
    G[row, col] = k
o = np.array([0, 0, 0, 0, 0.3, 0, 0, -0.2])


states = []
for s in range(4):
    q, v, a, tau = draw_state(rng, model)
    M = symmetric(pin.crba(model, fresh(), q))
    tau_out = pin.rnea(model, fresh(), q, v, a)
    g = pin.computeGeneralizedGravity(model, fresh(), q)
    nle = pin.nonLinearEffects(model, fresh(), q, v)
    qdd = np.linalg.solve(M, tau - nle)
    qf, vf, af = G @ q + o, G @ v, G @ a
    M_full = symmetric(pin.crba(full, full.createData(), qf))
    assert np.abs(G.T @ M_full @ G - M).max() < 1e-12, s
    assert np.abs(G.T @ pin.rnea(full, full.createData(), qf, vf, af) - tau_out).max() < 1e-12, s
    # The stale state of the comment above, measured (it is not in the output).
    reused = model.createData()
    pin.crba(model, reused, rng.uniform(-1.2, 1.2, model.nq))
    stale = np.abs(symmetric(pin.crba(model, reused, q)) - M).max()
    print(f"state {s}: crba with a reused Data is off by {stale:.1e}")
    states.append(dict(q=q.tolist(), v=v.tolist(), a=a.tolist(), tau=tau.tolist(),
                       mass_matrix=M.tolist(), tau_out=tau_out.tolist(), gravity=g.tolist(),
                       bias=(nle - g).tolist(), nle=nle.tolist(), qdd=qdd.tolist()))

out = {
    "generator": f"Pinocchio {pin.__version__} (pip package `pin`), "
                 "tests/data/make_mimic_reference.py",
    "model": "tests/data/gripper_mimic.urdf",
    "nq": model.nq,
    "nv": model.nv,
    "conventions": (
        "fixed base; buildModelFromUrdf(mimic=True): q, v, a, tau over the 5 joints that do not "
        "mimic, in URDF depth-first order; gravity (0, 0, -9.81). mass_matrix = crba(q); "
        "tau_out = rnea(q,v,a); gravity = computeGeneralizedGravity(q); nle = "
        "nonLinearEffects(q,v); bias = nle - gravity; qdd = solve(M, tau - nle). Each call on a fresh Data (Pinocchio "
        "4.1's crba with mimic joints reads stale state from a reused one)."
    ),
    "states": states,
}
path = os.path.join(here, 'pinocchio-mimic.json')
write_json(path, out)
print(path, model.nq, model.nv)
