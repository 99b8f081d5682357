"""The Python model's own contract: batches equal the single-state calls, any array layout
reads the same, shapes, errors with the project's messages (never a crash), and the
simulation and the regulator against closed forms and conservation laws."""

from pathlib import Path

import numpy as np
import pytest

import articulated
from states import random_states

ROOT = Path(__file__).resolve().parents[2]
ARM = ROOT / "models" / "arm7.urdf"


@pytest.fixture(scope="module")
def arm():
    return articulated.Model.load(ARM)


@pytest.fixture(scope="module")
def humanoid():
    return articulated.Model.load(ROOT / "models" / "humanoid.urdf", floating="quaternion")


METHODS = [
    ("mass_matrix", "q"), ("bias", "qv"), ("gravity", "q"), ("nonlinear_effects", "qv"),
    ("inverse_dynamics", "qva"), ("forward_dynamics", "qva"), ("kinetic_energy", "qv"),
    ("potential_energy", "q"), ("center_of_mass", "q"), ("center_of_mass_velocity", "qv"),
    ("center_of_mass_jacobian", "q"), ("centroidal_momentum", "qv"),
    ("centroidal_momentum_matrix", "q"), ("coriolis_matrix", "qv"),
    ("mass_matrix_inverse", "q"), ("centroidal_momentum_rate", "qva"),
    ("centroidal_momentum_drift", "qv"), ("joint_wrenches", "qva"), ("inverse_dynamics_derivatives", "qva"),
    ("forward_dynamics_derivatives", "qva"),
]


@pytest.mark.parametrize("method,args", METHODS)
def test_batch_equals_single_states(humanoid, method, args):
    q, v, a = random_states(humanoid, 9, seed=3)
    values = {"q": q, "v": v, "a": a}
    batch = getattr(humanoid, method)(*[values[c] for c in args])
    for k in range(len(q)):
        one = getattr(humanoid, method)(*[values[c][k] for c in args])
        if isinstance(one, tuple):
            for b, o in zip(batch, one):
                assert np.array_equal(b[k], o)
        else:
            assert np.array_equal(batch[k], one)


def test_array_layouts_read_alike(arm):
    q, v, a = random_states(arm, 7, seed=1)
    tau = arm.inverse_dynamics(q, v, a)
    # Fortran order, strided views, lists and integers all read as the same values.
    assert np.array_equal(arm.inverse_dynamics(np.asfortranarray(q), v, a), tau)
    wide = np.zeros((7, 2 * arm.nq))
    wide[:, ::2] = q
    assert np.array_equal(arm.inverse_dynamics(wide[:, ::2], v, a), tau)
    assert np.array_equal(arm.inverse_dynamics(q[0].tolist(), list(v[0]), a[0]), tau[0])
    assert np.array_equal(arm.gravity(np.zeros(7, dtype=int)), arm.gravity(np.zeros(7)))
    # A matrix M read back transposed through a Fortran-ordered view is M itself (symmetric),
    # and M·a through a Fortran-ordered M equals the C-ordered product.
    m = arm.mass_matrix(q[0])
    assert np.array_equal(arm.to_pinocchio_v(np.asfortranarray(m)), arm.to_pinocchio_v(m))


def test_shapes(arm, humanoid):
    q, v, a = random_states(humanoid, 5)
    nv = humanoid.nv
    assert humanoid.mass_matrix(q).shape == (5, nv, nv)
    assert humanoid.mass_matrix(q[0]).shape == (nv, nv)
    assert isinstance(humanoid.kinetic_energy(q[0], v[0]), float)
    assert humanoid.kinetic_energy(q, v).shape == (5,)
    dq, dv = humanoid.inverse_dynamics_derivatives(q, v, a)
    assert dq.shape == dv.shape == (5, nv, nv)
    rotation, translation = humanoid.frame_placement(q, "left_foot")
    assert rotation.shape == (5, 3, 3) and translation.shape == (5, 3)
    assert humanoid.frame_jacobian(q, "left_foot", reference="world").shape == (5, 6, nv)
    assert humanoid.mass_matrix(np.zeros((0, humanoid.nq))).shape == (0, nv, nv)
    assert arm.nq == 7 and arm.nv == 7 and len(arm.q_names) == 7


def test_errors_carry_the_message(arm, tmp_path):
    with pytest.raises(articulated.Error, match=r"argument `q` has shape \[3\]"):
        arm.mass_matrix(np.ones(3))
    with pytest.raises(articulated.Error, match="differ"):
        arm.bias(np.zeros((2, 7)), np.zeros(7))
    with pytest.raises(articulated.Error, match="no frame `nowhere`"):
        arm.frame_placement(np.zeros(7), "nowhere")
    with pytest.raises(articulated.Error, match='reference="sideways"'):
        arm.frame_jacobian(np.zeros(7), arm.frames[0], reference="sideways")
    with pytest.raises(articulated.Error, match="cannot read"):
        articulated.Model.load(tmp_path / "missing.urdf")
    bad = tmp_path / "bad.chain"
    bad.write_text("chain Bad {\n    body b { mass: -1.0, com: [0.0, 0.0, 0.0], inertia: diag(1.0, 1.0, 1.0) }\n}\n")
    with pytest.raises(articulated.Error, match=r"bad\.chain:2"):
        articulated.Model.load(bad)
    with pytest.raises(articulated.Error, match="floating="):
        articulated.Model.load(ARM, floating="sideways")
    # A non-finite state in a batch: its index and the project's message, never a crash.
    q = np.zeros((3, 7))
    q[1, 2] = np.nan
    with pytest.raises(articulated.Error, match="state 1 of the batch"):
        arm.forward_dynamics(q, np.zeros((3, 7)), np.zeros((3, 7)))
    # The exception is a ValueError, so generic handlers catch it.
    assert issubclass(articulated.Error, ValueError)


def test_identities(humanoid):
    """`M·a + bias + g = τ` and forward(inverse(a)) = a: independent paths through the
    reference (CRBA and RNEA, ABA and RNEA)."""
    q, v, a = random_states(humanoid, 6, seed=5)
    tau = humanoid.inverse_dynamics(q, v, a)
    m = humanoid.mass_matrix(q)
    lhs = np.einsum("bij,bj->bi", m, a) + humanoid.bias(q, v) + humanoid.gravity(q)
    assert np.max(np.abs(lhs - tau)) < 1e-10 * np.max(np.abs(tau))
    assert np.max(np.abs(humanoid.forward_dynamics(q, v, tau) - a)) < 1e-9


def test_pinocchio_layout_round_trip(humanoid):
    q, v, _ = random_states(humanoid, 4)
    qp = humanoid.to_pinocchio_q(q)
    assert qp.shape == (4, humanoid.nq_pinocchio)
    # The free flyer's quaternion: ours [w, x, y, z] at 3..7, Pinocchio's [x, y, z, w].
    assert np.array_equal(qp[:, 3:7], np.concatenate([q[:, 4:7], q[:, 3:4]], axis=1))
    assert np.array_equal(humanoid.from_pinocchio_q(qp), q)
    assert np.array_equal(humanoid.from_pinocchio_v(humanoid.to_pinocchio_v(v)), v)
    assert humanoid.q_names_pinocchio[3:7] == [
        "root_joint.qx", "root_joint.qy", "root_joint.qz", "root_joint.qw"]


def test_params():
    payload = articulated.Model.load(ROOT / "models" / "payload.chain")
    names = payload.param_names
    assert "payload" in names
    heavier = list(payload.params)
    heavier[names.index("payload")] += 1.0
    other = payload.with_params(heavier)
    q = payload.neutral() + 0.3
    assert not np.array_equal(payload.gravity(q), other.gravity(q))
    with pytest.raises(articulated.Error, match="params has 1 values"):
        payload.with_params([1.0])


def test_simulation_conserves_energy():
    """The free double pendulum keeps its energy (a conservation law the integrator does not
    know): RK4 at 1 ms over a second of a half-radian swing, to 1e-9 of the swing's energy."""
    model = articulated.Model.load(ROOT / "models" / "double_pendulum.chain")
    q0 = np.array([0.5, -0.3])
    run = model.simulate(q0, np.zeros(model.nv), 1.0, 1e-3)
    assert run["q"].shape == (1001, model.nq) and run["faults"] is None
    assert run["t"][-1] == 1.0
    energy = model.kinetic_energy(run["q"], run["v"]) + model.potential_energy(run["q"])
    swing = energy[0] - model.potential_energy(np.zeros(model.nq))
    assert np.ptp(energy) < 1e-9 * abs(swing)
    # The motion is real: the pendulum leaves its start.
    assert np.max(np.abs(run["q"][:, 0] - q0[0])) > 0.1


def test_lqr_balances_the_two_link():
    model = articulated.Model.load(ROOT / "models" / "two_link.chain")
    q_eq = model.neutral()
    weights = np.diag([100.0] * model.nv + [1.0] * model.nv)
    gain, tau_eq = model.lqr(q_eq, weights, np.eye(model.nv))
    assert gain.shape == (model.nv, 2 * model.nv)
    # Held still at the equilibrium by tau_eq alone.
    assert np.allclose(model.forward_dynamics(q_eq, np.zeros(model.nv), tau_eq), 0, atol=1e-12)
    pushes = np.random.default_rng(0).normal(0, 0.05, (8, model.nv))
    run = model.simulate(np.tile(q_eq, (8, 1)), pushes, 5.0, 1e-3, gain=gain, q_ref=q_eq,
                         tau_ref=tau_eq)
    assert run["q"].shape == (8, 5001, model.nq)
    assert all(f is None for f in run["faults"])
    assert np.max(np.abs(run["q"][:, -1] - q_eq)) < 1e-3
    # Without the regulator the same pushes topple it (the upright is unstable).
    free = model.simulate(np.tile(q_eq, (8, 1)), pushes, 5.0, 1e-3)
    assert np.nanmax(np.abs(free["q"][:, -1] - q_eq)) > 0.1


def test_simulate_errors(arm):
    with pytest.raises(articulated.Error, match="integrator="):
        arm.simulate(np.zeros(7), np.zeros(7), 1.0, 0.1, integrator="leapfrog")
    with pytest.raises(articulated.Error, match="no time grid"):
        arm.simulate(np.zeros(7), np.zeros(7), 1.0, -0.1)
    with pytest.raises(articulated.Error, match="gain"):
        arm.simulate(np.zeros(7), np.zeros(7), 1.0, 0.1, gain=np.zeros((7, 7)))
