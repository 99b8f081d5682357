"""Pinocchio 4.1 reference values for `models/arm7.urdf` -> `tests/data/pinocchio-arm7.json`.

Runs on our machines, NOT in CI (CI has no Pinocchio): `pip install pin numpy`, then
`python tests/data/make_arm7_reference.py` from the repository root or anywhere else. The JSON it
writes is committed and read by `tests/tests/pinocchio.rs`. The random states are seeded, so a
rerun reproduces the file (up to Pinocchio's own changes).

Modelled on `tests/data/pinocchio/make_reference.py` and with the same fields and conventions
(see `tests/data/pinocchio/README.md`): q, v, a, tau in URDF joint order (depth first, document
order); mass_matrix = M(q); bias = N(q,v)v WITHOUT gravity; nonlinear_effects = bias + gravity;
gravity = g(q); tau_out = rnea(q, v, a); qdd = aba(q, v, tau). 'floating' puts a free base under
the URDF root (which keeps its inertial): a translation (world frame) then Euler angles z-y-x
(R = Rz Ry Rx), v = coordinate rates, these 6 coordinates first. Gravity (0, 0, -9.81).

One more field, `joint_wrenches`: after `rnea(q, v, a)`, Pinocchio's `data.f[i]` for every joint
i >= 1 (the universe, i = 0, is left out; in the floating model the first entry is the free base).
`data.f[i]` is the spatial force the parent transmits to body i through joint i (gravity
included, as rnea includes it), expressed in joint i's LOCAL frame (the child body frame, about
its origin). Stored exactly as Pinocchio's `Force.vector`: LINEAR FIRST, `[fx, fy, fz, nx, ny,
nz]`. Nothing is converted here; `articulated` orders spatial forces angular first, so the test
swaps the halves.
"""
import json
import os

import numpy as np
import pinocchio as pin

here = os.path.dirname(os.path.abspath(__file__))
urdf = os.path.join(here, '..', '..', 'models', 'arm7.urdf')
rng = np.random.default_rng(20261123)

out = {
    "generator": f"Pinocchio {pin.__version__} (pip package `pin`), tests/data/make_arm7_reference.py",
    "model": "models/arm7.urdf",
    "conventions": (
        "q, v, a, tau in URDF joint order (depth first, document order). mass_matrix = M(q); "
        "bias = N(q,v)v without gravity; nonlinear_effects = bias + gravity; gravity = g(q); "
        "tau_out = rnea(q,v,a); qdd = aba(q,v,tau). 'floating': a translation (world frame) then "
        "Euler z-y-x (R = Rz Ry Rx) under the URDF root, v = coordinate rates, these 6 first. "
        "gravity (0, 0, -9.81). joint_wrenches: Pinocchio data.f[i] after rnea(q,v,a) for joints "
        "i = 1.. (universe left out): the force of the parent on body i through joint i, in joint "
        "i's local frame (child body frame, about its origin), LINEAR FIRST [fx, fy, fz, nx, ny, nz]."
    ),
    "models": {},
}
entry = {}
for floating in (False, True):
    if floating:
        root = pin.JointModelComposite(2)
        root.addJoint(pin.JointModelTranslation())
        root.addJoint(pin.JointModelSphericalZYX())
        model = pin.buildModelFromUrdf(urdf, root)
    else:
        model = pin.buildModelFromUrdf(urdf)
    d = model.createData()
    states = []
    for s in range(4):
        q = rng.uniform(-1.2, 1.2, model.nq)
        v = rng.uniform(-2, 2, model.nv)
        a = rng.uniform(-3, 3, model.nv)
        tau = rng.uniform(-5, 5, model.nv)
        M = pin.crba(model, d, q)
        M = np.triu(M) + np.triu(M, 1).T
        nle = pin.nonLinearEffects(model, d, q, v)
        g = pin.computeGeneralizedGravity(model, d, q)
        aba = pin.aba(model, d, q, v, tau)
        rnea = pin.rnea(model, d, q, v, a)  # last, so that d.f belongs to (q, v, a)
        wrenches = [np.array(d.f[i].vector).tolist() for i in range(1, model.njoints)]
        err = np.abs(rnea - M @ a - nle).max() / max(1, np.abs(rnea).max())
        assert err < 1e-12, (floating, err)
        # Check of the frame: each joint's torque is its wrench projected on its motion subspace.
        for i in range(1, model.njoints):
            S = np.array(d.joints[i].S)
            j = model.joints[i]
            proj = S.T @ d.f[i].vector
            assert np.abs(proj - rnea[j.idx_v:j.idx_v + j.nv]).max() < 1e-9, (floating, i)
        states.append(dict(q=q.tolist(), v=v.tolist(), a=a.tolist(), tau=tau.tolist(),
                           mass_matrix=M.tolist(), bias=(nle - g).tolist(),
                           nonlinear_effects=nle.tolist(), gravity=g.tolist(),
                           tau_out=rnea.tolist(), qdd=aba.tolist(), joint_wrenches=wrenches))
    entry['floating' if floating else 'fixed'] = dict(
        nq=model.nq, nv=model.nv, joint_names=[n for n in model.names[1:]], states=states)
out['models']['arm7'] = entry
path = os.path.join(here, 'pinocchio-arm7.json')
with open(path, 'w') as f:
    json.dump(out, f, indent=1)
print(path, {k: (v['nq'], v['nv']) for k, v in entry.items()})
