"""Contacts chosen at call time, from Python, against Pinocchio's `constraintDynamics` and
`impulseDynamics` (Pinocchio 4.1's bindings, exact proximal settings: mu = 0): the humanoid on
both soles (six-dimensional, LOCAL), on one sole and a hand point (LOCAL_WORLD_ALIGNED), and
the arm with its flange welded; accelerations to 1e-9 of their largest entry, forces to 1e-9 of
m·‖g‖ (the scale of the support)."""

from pathlib import Path

import numpy as np
import pytest

import articulated
from states import random_states

pin = pytest.importorskip("pinocchio")
ROOT = Path(__file__).resolve().parents[2]
CASES = [
    ("models/humanoid.urdf", "quaternion", [("left_foot", "six_d"), ("right_foot", "six_d")]),
    ("models/humanoid.urdf", "quaternion", [("left_foot", "six_d"), ("right_hand", "point")]),
    ("models/arm7.urdf", None, [("link7", "six_d")]),
]
KIND = {"six_d": ("CONTACT_6D", "LOCAL"), "point": ("CONTACT_3D", "LOCAL_WORLD_ALIGNED")}


def pinocchio_side(path, floating, contacts):
    if floating:
        model = pin.buildModelFromUrdf(str(ROOT / path), pin.JointModelFreeFlyer())
    else:
        model = pin.buildModelFromUrdf(str(ROOT / path))
    cms = []
    for frame, kind in contacts:
        f = model.frames[model.getFrameId(frame)]
        ctype, rf = KIND[kind]
        cms.append(pin.RigidConstraintModel(getattr(pin.ContactType, ctype), model, f.parentJoint,
                                            f.placement, 0, pin.SE3.Identity(),
                                            getattr(pin.ReferenceFrame, rf)))
    return model, cms


def ours(vector, kind):
    """Pinocchio's contact force (linear first) as ours: six_d angular first, point linear."""
    vector = np.asarray(vector)
    return np.concatenate([vector[3:], vector[:3]]) if kind == "six_d" else vector[:3]


@pytest.mark.parametrize("path,floating,contacts", CASES,
                         ids=["humanoid-feet", "humanoid-foot-hand", "arm7-welded"])
def test_against_pinocchio(path, floating, contacts):
    model = articulated.Model.load(ROOT / path, floating=floating)
    theirs, cms = pinocchio_side(path, floating, contacts)
    weight = sum(i.mass for i in theirs.inertias) * 9.81
    q, v, tau = random_states(model, 4, seed=len(contacts), spread=0.5, scale=10.0)
    a, forces, residual = model.constrained_forward_dynamics(q, v, tau, dict(contacts))
    v_plus, impulses, _ = model.impulse_dynamics(q, v, dict(contacts), restitution=0.5)
    assert np.max(residual) < 1e-9
    for k in range(len(q)):
        qp, vp = model.to_pinocchio_q(q[k]), model.to_pinocchio_v(v[k])
        data = theirs.createData()
        cds = [cm.createData() for cm in cms]
        pin.initConstraintDynamics(theirs, data, cms, cds)
        ap = pin.constraintDynamics(theirs, data, qp, vp, model.to_pinocchio_v(tau[k]), cms, cds,
                                    pin.ProximalSettings(1e-12, 0.0, 10))
        scale = max(1.0, np.max(np.abs(ap)))
        assert np.max(np.abs(model.to_pinocchio_v(a[k]) - ap)) <= 1e-9 * scale
        fp = np.concatenate([ours(cd.contact_force.vector, kind)
                             for cd, (_, kind) in zip(cds, contacts)])
        assert np.max(np.abs(forces[k] - fp)) <= 1e-9 * weight
        data = theirs.createData()
        cds = [cm.createData() for cm in cms]
        pin.initConstraintDynamics(theirs, data, cms, cds)
        vp_plus = pin.impulseDynamics(theirs, data, qp, vp, cms, cds, 0.5,
                                      pin.ProximalSettings(1e-12, 0.0, 1))
        scale = max(1.0, np.max(np.abs(vp_plus)))
        assert np.max(np.abs(model.to_pinocchio_v(v_plus[k]) - vp_plus)) <= 1e-9 * scale
        pp = np.concatenate([ours(cd.contact_force.vector, kind)
                             for cd, (_, kind) in zip(cds, contacts)])
        assert np.max(np.abs(impulses[k] - pp)) <= 1e-9 * max(1.0, np.max(np.abs(pp)))


def test_contact_errors():
    arm = articulated.Model.load(ROOT / "models" / "arm7.urdf")
    z = np.zeros(7)
    with pytest.raises(articulated.Error, match="no frame `hand`"):
        arm.constrained_forward_dynamics(z, z, z, {"hand": "six_d"})
    with pytest.raises(articulated.Error, match='kind "glued"'):
        arm.constrained_forward_dynamics(z, z, z, {"link7": "glued"})
    with pytest.raises(articulated.Error, match="at least one"):
        arm.constrained_forward_dynamics(z, z, z, {})
    # Two welds of the same flange are redundant: refused exactly, solved with mu > 0.
    twice = [("link7", "six_d"), ("link7", "point")]
    with pytest.raises(articulated.Error):
        arm.constrained_forward_dynamics(z, z, z, twice)
    a, forces, residual = arm.constrained_forward_dynamics(z, z, z, twice, mu=1e-6)
    assert forces.shape == (9,) and residual < 1e-6
