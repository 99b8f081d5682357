"""Pinocchio reference values with rotor inertia (armature) -> `tests/data/pinocchio-armature.json`.

Runs on our machines, NOT in CI (CI has no Pinocchio): `pip install pin numpy`, then
`python tests/data/make_armature_reference.py` from anywhere. The JSON it writes is committed and
read by `tests/tests/generated_drives.rs`. The random states are seeded, so a rerun reproduces
the file (up to Pinocchio's own changes).

Model: `tests/data/arm7_armature.urdf`, the 7-DOF arm of `models/arm7.urdf` with a
`<dynamics armature="...">` on every joint. Pinocchio's URDF parser does not read that attribute
(it is not URDF 1.0), so this script reads it with ElementTree and sets `model.armature`, which
Pinocchio adds to M's diagonal in crba, to tau in rnea (armature * a) and to each joint's D in aba.
Conventions as `make_arm7_reference.py` (fixed base, URDF joint order, gravity (0, 0, -9.81)):
mass_matrix = crba(q) (symmetrized), tau_out = rnea(q, v, a), qdd = aba(q, v, tau), and from
computeABADerivatives(q, v, tau): ddq_dq, ddq_dv, minv (= dq''/dtau, symmetrized).
The script checks that M - M(armature = 0) is diag(armature) before writing anything.
"""
import os
import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin

from pinocchio_io import draw_state, symmetric, write_json

here = os.path.dirname(os.path.abspath(__file__))
urdf = os.path.join(here, 'arm7_armature.urdf')
rng = np.random.default_rng(20261124)

model = pin.buildModelFromUrdf(urdf)
armature = np.zeros(model.nv)
for joint in ET.parse(urdf).getroot().iter('joint'):
    dynamics = joint.find('dynamics')
    if dynamics is not None and 'armature' in dynamics.attrib:
        j = model.joints[model.getJointId(joint.attrib['name'])]
        armature[j.idx_v:j.idx_v + j.nv] = float(dynamics.attrib['armature'])
assert (armature > 0).all(), armature
rigid = model.copy()
model.armature = armature
d, d_rigid = model.createData(), rigid.createData()


states = []
for s in range(4):
    q, v, a, tau = draw_state(rng, model)
    M = symmetric(pin.crba(model, d, q))
    M_rigid = symmetric(pin.crba(rigid, d_rigid, q))
    assert np.abs(M - M_rigid - np.diag(armature)).max() < 1e-12, s
    tau_out = pin.rnea(model, d, q, v, a)
    qdd = pin.aba(model, d, q, v, tau)
    assert np.abs(M @ qdd + pin.nonLinearEffects(model, d, q, v) - tau).max() < 1e-10, s
    pin.computeABADerivatives(model, d, q, v, tau)
    states.append(dict(q=q.tolist(), v=v.tolist(), a=a.tolist(), tau=tau.tolist(),
                       mass_matrix=M.tolist(), tau_out=tau_out.tolist(), qdd=qdd.tolist(),
                       ddq_dq=np.array(d.ddq_dq).tolist(), ddq_dv=np.array(d.ddq_dv).tolist(),
                       minv=symmetric(np.array(d.Minv)).tolist()))

out = {
    "generator": f"Pinocchio {pin.__version__} (pip package `pin`), "
                 "tests/data/make_armature_reference.py",
    "model": "tests/data/arm7_armature.urdf",
    "conventions": (
        "fixed base; q, v, a, tau in URDF joint order; gravity (0, 0, -9.81); model.armature set "
        "from each joint's <dynamics armature>. mass_matrix = crba(q); tau_out = rnea(q,v,a); "
        "qdd = aba(q,v,tau); ddq_dq, ddq_dv, minv from computeABADerivatives(q,v,tau)."
    ),
    "armature": armature.tolist(),
    "states": states,
}
path = os.path.join(here, 'pinocchio-armature.json')
write_json(path, out)
print(path, model.nq, model.nv)
