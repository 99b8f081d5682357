"""The interpreted model from Python against Pinocchio's Python bindings (`pip install pin`), on
the shipped URDF models and the test models of tests/data/pinocchio: every value to 1e-12 of
the largest entry of Pinocchio's, accelerations by their residual `M·a + nle − τ`. Pinocchio is
the independent side: our values never enter its computation, and the states go to it through
`to_pinocchio_q`/`_v`, whose own correctness this checks too (a wrong quaternion order or joint
order fails every comparison)."""

from pathlib import Path

import numpy as np
import pytest

import articulated

pin = pytest.importorskip("pinocchio")

ROOT = Path(__file__).resolve().parents[2]
MODELS = [
    ("models/arm7.urdf", None),
    ("models/two_link.urdf", None),
    ("models/double_pendulum.urdf", None),
    ("models/inverted_pendulum.urdf", None),
    ("models/tree.urdf", None),
    ("models/humanoid.urdf", "quaternion"),
    ("models/chain50.urdf", None),
    ("tests/data/pinocchio/arm6_mixed.urdf", None),
    ("tests/data/pinocchio/tree_two_arms.urdf", None),
]
# The models the slower comparisons (derivatives, frames) run on.
FEWER = MODELS[:6]
TOL = 1e-12


def close(ours, theirs, tol=TOL):
    """`ours` within `tol` of the largest entry of `theirs` (and of 1)."""
    ours, theirs = np.asarray(ours), np.asarray(theirs)
    assert ours.shape == theirs.shape
    scale = max(1.0, float(np.max(np.abs(theirs))))
    err = float(np.max(np.abs(ours - theirs)))
    assert err <= tol * scale, f"error {err:.3e} of scale {scale:.3e}"


def swap(x):
    """Angular-first rows (ours) to Pinocchio's linear-first, or back."""
    return np.concatenate([x[3:6], x[0:3]], axis=0)


def in_pin_order(model, matrix, rows=True, cols=True):
    """A matrix over our `v` with its rows and columns in Pinocchio's joint order."""
    m = np.asarray(matrix)
    if cols:
        m = model.to_pinocchio_v(m)
    if rows:
        m = model.to_pinocchio_v(m.T).T
    return m


def states(model, n, seed):
    """`n` random states: unit quaternions, angles in ±π, velocities and accelerations ~N(0, 1)."""
    rng = np.random.default_rng(seed)
    q = rng.uniform(-np.pi, np.pi, (n, model.nq))
    for k, name in enumerate(model.q_names):
        if name.endswith(".qw"):
            quat = rng.standard_normal(4)
            q[:, k:k + 4] = quat / np.linalg.norm(quat)
        elif name.endswith((".x", ".y", ".z")):
            q[:, k] = rng.uniform(-1, 1, n)
    return q, rng.standard_normal((n, model.nv)), rng.standard_normal((n, model.nv))


def load(path, floating):
    ours = articulated.Model.load(ROOT / path, floating=floating)
    if floating:
        theirs = pin.buildModelFromUrdf(str(ROOT / path), pin.JointModelFreeFlyer())
    else:
        theirs = pin.buildModelFromUrdf(str(ROOT / path))
    assert theirs.nq == ours.nq_pinocchio and theirs.nv == ours.nv
    return ours, theirs


@pytest.mark.parametrize("path,floating", MODELS, ids=[Path(p).stem for p, _ in MODELS])
def test_dynamics_against_pinocchio(path, floating):
    ours, model = load(path, floating)
    data = model.createData()
    q, v, a = states(ours, 4, seed=len(path))
    qp, vp, ap = ours.to_pinocchio_q(q), ours.to_pinocchio_v(v), ours.to_pinocchio_v(a)
    tau = ours.inverse_dynamics(q, v, a)
    m = ours.mass_matrix(q)
    for k in range(len(q)):
        close(ours.to_pinocchio_v(tau[k]), pin.rnea(model, data, qp[k], vp[k], ap[k]))
        mp = pin.crba(model, data, qp[k]).copy()
        mp = np.triu(mp) + np.triu(mp, 1).T
        close(in_pin_order(ours, m[k]), mp)
        nle = pin.nonLinearEffects(model, data, qp[k], vp[k])
        gravity = pin.computeGeneralizedGravity(model, data, qp[k])
        close(ours.to_pinocchio_v(ours.nonlinear_effects(q[k], v[k])), nle)
        close(ours.to_pinocchio_v(ours.gravity(q[k])), gravity)
        close(ours.to_pinocchio_v(ours.bias(q[k], v[k])), nle - gravity)
        # q̈ by its residual against Pinocchio's M and nle, relative to τ's scale.
        qdd = ours.forward_dynamics(q[k], v[k], tau[k])
        residual = mp @ ours.to_pinocchio_v(qdd) + nle - ours.to_pinocchio_v(tau[k])
        assert np.max(np.abs(residual)) <= 1e-10 * max(1.0, np.max(np.abs(tau[k])))
        close(ours.kinetic_energy(q[k], v[k]), pin.computeKineticEnergy(model, data, qp[k], vp[k]))
        close(ours.potential_energy(q[k]), pin.computePotentialEnergy(model, data, qp[k]))
        close(ours.center_of_mass(q[k]), pin.centerOfMass(model, data, qp[k]))
        close(in_pin_order(ours, ours.center_of_mass_jacobian(q[k]), rows=False),
              pin.jacobianCenterOfMass(model, data, qp[k]))
        h = pin.computeCentroidalMomentum(model, data, qp[k], vp[k])
        close(ours.centroidal_momentum(q[k], v[k]), np.concatenate([h.angular, h.linear]))
        pin.computeCentroidalMomentumTimeVariation(model, data, qp[k], vp[k], ap[k])
        close(ours.centroidal_momentum_rate(q[k], v[k], a[k]),
              np.concatenate([data.dhg.angular, data.dhg.linear]), 1e-11)
        # The wrench across each joint: Pinocchio's data.f after rnea, in the joint's frame.
        pin.rnea(model, data, qp[k], vp[k], ap[k])
        wrenches = ours.joint_wrenches(q[k], v[k], a[k])
        compared = 0
        for i, name in enumerate(model.names):
            if name in ours.joints:
                f = data.f[i]
                close(wrenches[ours.joints.index(name)], np.concatenate([f.angular, f.linear]),
                      1e-11)
                compared += 1
        assert compared == model.njoints - 1


@pytest.mark.parametrize("path,floating", FEWER, ids=[Path(p).stem for p, _ in FEWER])
def test_derivatives_against_pinocchio(path, floating):
    ours, model = load(path, floating)
    data = model.createData()
    q, v, a = states(ours, 2, seed=7)
    qp, vp, ap = ours.to_pinocchio_q(q), ours.to_pinocchio_v(v), ours.to_pinocchio_v(a)
    dq, dv = ours.inverse_dynamics_derivatives(q, v, a)
    tau = ours.inverse_dynamics(q, v, a)
    fq, fv, minv = ours.forward_dynamics_derivatives(q, v, tau)
    for k in range(len(q)):
        pdq, pdv, _ = pin.computeRNEADerivatives(model, data, qp[k], vp[k], ap[k])
        close(in_pin_order(ours, dq[k]), pdq, 1e-11)
        close(in_pin_order(ours, dv[k]), pdv, 1e-11)
        pfq, pfv, pminv = pin.computeABADerivatives(model, data, qp[k], vp[k],
                                                    ours.to_pinocchio_v(tau[k]))
        pminv = np.triu(pminv) + np.triu(pminv, 1).T
        close(in_pin_order(ours, minv[k]), pminv, 1e-10)
        close(in_pin_order(ours, fq[k]), pfq, 1e-9)
        close(in_pin_order(ours, fv[k]), pfv, 1e-9)


@pytest.mark.parametrize("path,floating", FEWER, ids=[Path(p).stem for p, _ in FEWER])
def test_frames_against_pinocchio(path, floating):
    ours, model = load(path, floating)
    data = model.createData()
    q, v, a = states(ours, 2, seed=11)
    qp, vp, ap = ours.to_pinocchio_q(q), ours.to_pinocchio_v(v), ours.to_pinocchio_v(a)
    names = [f.name for f in model.frames if f.name in ours.frames]
    assert names, "no frame in common"
    for name in names[-3:]:
        fid = model.getFrameId(name)
        rotation, translation = ours.frame_placement(q, name)
        for k in range(len(q)):
            pin.forwardKinematics(model, data, qp[k], vp[k], ap[k])
            pin.updateFramePlacements(model, data)
            placement = data.oMf[fid]
            close(rotation[k], placement.rotation)
            close(translation[k], placement.translation)
            close(ours.frame_velocity(q[k], v[k], name),
                  swap(pin.getFrameVelocity(model, data, fid, pin.LOCAL).vector))
            close(ours.frame_acceleration(q[k], v[k], a[k], name),
                  swap(pin.getFrameClassicalAcceleration(
                      model, data, fid, pin.LOCAL_WORLD_ALIGNED).vector), 1e-11)
            pin.computeJointJacobians(model, data, qp[k])
            for ref, frame in [("local", pin.LOCAL), ("world", pin.WORLD),
                               ("local_world_aligned", pin.LOCAL_WORLD_ALIGNED)]:
                j = ours.frame_jacobian(q[k], name, reference=ref)
                theirs = pin.getFrameJacobian(model, data, fid, frame)
                close(in_pin_order(ours, swap(j), rows=False), theirs)
