"""Pinocchio's constrained forward dynamics and impulse dynamics ->
`tests/data/pinocchio_constraints/pinocchio-constraints.json`, for the constraints (DESIGN §9
"Constraints": `constrained_forward_dynamics`, the runtime's `constraint` module, `articulated
eval --contacts`).

Runs on our machines, NOT in CI (CI has no Pinocchio). To regenerate (from anywhere):

    pip install pin numpy            # Pinocchio 4.1
    python tests/data/pinocchio_constraints/make_pinocchio_constraints.py

The states are seeded, so a rerun reproduces the JSON byte for byte (up to Pinocchio's own
changes). The file is written whole, through a temporary file and a rename. The URDF loading, the
joint order and the permutation between Pinocchio's coordinates and ours are those of
`tests/data/pinocchio_frames/make_pinocchio_frames.py` (imported from there).

Models (`models`, keyed by name): `models/humanoid.urdf` on Pinocchio's free flyer
(`humanoid_free_flyer`, `pin.JointModelFreeFlyer()`) and `models/arm7.urdf` on a fixed base
(`arm7`). Each has `urdf`, `floating` (`quaternion` or `fixed`), `nq`, `nv` (ours), `joints`
(ours: `root_joint` first, then the URDF's movable joints depth first from the root link, children
in document order), `mass` (`pin.computeTotalMass`: the moving bodies; the arm's fixed `base` link,
4 kg on Pinocchio's universe, is not in it) and `gravity` (Pinocchio's default `[0, 0, -9.81]`, as
ours).

Cases (`cases`, keyed by name), each a model, `contacts` (a list of `{frame, kind}`, in the
order of the constraint rows; every frame is a URDF link, Pinocchio's BODY frame) and `states`:
- `humanoid_feet`: `left_foot` six_d, `right_foot` six_d (with impulses);
- `humanoid_left_foot`: `left_foot` six_d;
- `humanoid_foot_and_hand`: `left_foot` six_d, `right_hand` point (with impulses);
- `humanoid_hand`: `left_hand` point;
- `arm7_welded`: `link7` six_d (with impulses);
- `arm7_point`: `link7` point;
- `humanoid_baumgarte`: `left_foot` six_d, `right_foot` six_d, with Baumgarte gains;
- `humanoid_baumgarte_point`: `left_foot` six_d, `right_hand` point, with Baumgarte gains (an
  extra case beyond the feet: it pins down the point contact's error too).
`baumgarte` is `null` or `{kp, kd}`: Pinocchio 4.1's `BaumgarteCorrectorParameters(Kp, Kd)` holds
two scalars, the same gain on every row of a contact (here Kp = 10, Kd = 3 on every contact).

Contacts, as Pinocchio models them: `pin.RigidConstraintModel(type, model, joint1_id,
joint1_placement, 0, joint2_placement, reference_frame)` with `joint1_id` the frame's parent joint,
`joint1_placement` the frame's placement in that joint, joint 2 the universe (0) and
`joint2_placement` the reference placement in the world (for the cases without gains, the frame's
current placement: then it plays no part).
- `six_d`: `CONTACT_6D`, `LOCAL`. The row block is the frame's spatial acceleration in its own
  frame: `J` = `getFrameJacobian(..., LOCAL)`, `gamma` = the frame's spatial acceleration at
  q̈ = 0 (`getFrameAcceleration(..., LOCAL)` after `forwardKinematics(q, v, 0)`). Its force is the
  wrench `[n; f]` the constraint exerts on the body, in the frame, ANGULAR FIRST (Pinocchio's
  `contact_force` is `[f; n]`: the halves are swapped here).
- `point`: `CONTACT_3D`, `LOCAL_WORLD_ALIGNED`. The rows are the frame origin's classical linear
  acceleration in world axes: `J` = the linear rows of `getFrameJacobian(...,
  LOCAL_WORLD_ALIGNED)`, `gamma` = the linear part of `getFrameClassicalAcceleration(...,
  LOCAL_WORLD_ALIGNED)` at q̈ = 0. Its force is in world axes.
With the contacts' blocks stacked: `M·q̈ + nle = τ + Σ Jᵀ·f` and `J·q̈ + γ = 0` (Pinocchio's
`contact_force` is the force on the body: no sign change). Pinocchio solves it by
`constraintDynamics` with `ProximalSettings(1e-12, mu = 0, 10)`: mu = 0 is no regularization,
so the solution is the exact one of the KKT system (the first iteration gives it, the second
confirms it: it stops there on its relative criterion; its `absolute_residual` then reads large,
about 1e3 on the arm, while J·q̈ + γ is 1e-13: not a measure of this solution), after
`initConstraintDynamics`.

Baumgarte, as Pinocchio 4.1 computes it (`src/algorithm/constrained-dynamics.hxx`,
`constraintDynamics`; `src/constraints/contact-info.hxx`, `calc`): `oMc1` = the frame's placement
M (world), `oMc2` = `joint2_placement` = the reference M_ref (joint 2 being the universe),
`c1Mc2 = oMc1⁻¹·oMc2 = M⁻¹·M_ref`.
- `CONTACT_6D`: `contact_placement_error = -log6(c1Mc2) = -log6(M⁻¹·M_ref)`, which is
  `log6(M_ref⁻¹·M)` (log6(X⁻¹) = -log6(X)): OUR convention, `e = log6(M_ref⁻¹·M)`, a twist
  `[v; ω]` in Pinocchio, stored here angular first `[ω; v]`. The velocity error is the frame's
  LOCAL spatial velocity (`vc1`, = J·v; joint 2 does not move), and the acceleration added to the
  rows is `-Kp·e - Kd·J·v` (in LOCAL, nothing rotated), Kp multiplying the log itself (a
  `Jexp6` factor is commented out in the source). So `J·q̈ + γ = -Kd·J·v - Kp·e`.
- `CONTACT_3D`: `contact_placement_error.linear = -c1Mc2.translation = R1ᵀ·(p - p_ref)` (in the
  contact frame), the velocity error the origin's velocity in the contact frame; with
  `LOCAL_WORLD_ALIGNED` both terms are rotated by R1 into world axes, so the rows get
  `-Kp·(p - p_ref) - Kd·ṗ` in world axes: OUR convention, `e = p - p_ref` (world).
Per Baumgarte state, each contact has `reference` (`rotation`: world_R_ref rows, `translation`:
its origin in the world: the frame's placement at a perturbed q, q ⊕ dq with dq uniform in
[-0.1, 0.1]) and `error` (e: 6 angular first for six_d, 3 in world for point; from Pinocchio's
`contact_placement_error` and checked against log6(M_ref⁻¹·M) and p - p_ref computed here).

Per state (`states[i]`), ALL IN OUR LAYOUT (as the frames script: a free flyer's q is
`[x, y, z, w, qx, qy, qz]`, v its linear then angular velocity in the base frame, then the joints
in our order):
- `q`, `v`, `tau`; `qdd` (Pinocchio's `constraintDynamics`); `forces`: keyed by frame name (6
  for six_d, 3 for point, as above); `residual`: max |J·q̈ + γ| over the rows (with gains: max
  |J·q̈ + γ + Kd·J·v + Kp·e|), J and γ from Pinocchio's own frame Jacobians and accelerations
  computed here apart from `constraintDynamics`;
- with gains, `contacts`: per frame `reference` and `error` (above);
- for the arm's cases without gains (`arm7_welded`, `arm7_point`), `derivatives`:
  Pinocchio's `computeConstraintDynamicsDerivatives` after `constraintDynamics`,
  `dqdd_dq`, `dqdd_dv`, `dqdd_dtau` (nv × nv) and `dforces_dq`, `dforces_dv`, `dforces_dtau`
  (rows × nv), row-major, rows q̈ in our order and the forces as ours (six_d angular first),
  columns our v (∂/∂q along the tangent, `pin.integrate`); each checked here against central
  differences of Pinocchio's own `constraintDynamics` (step 1e-6, to 1e-5 of the largest entry);
- for the cases marked "with impulses", `impulses`: a list, one per restitution `e` in (0, 0.5),
  each `{restitution, v_minus, v_plus, impulses}`: Pinocchio's `impulseDynamics(model, data, q,
  v, contact_models, contact_datas, e, ProximalSettings(1e-12, 0, 1))` (4.1's signature), every
  row bilateral: `M·(v⁺ - v⁻) = Σ Jᵀ·p`, `J·v⁺ = -e·J·v⁻`; `v_minus` is the state's v,
  `impulses` keyed by frame as `forces` (Pinocchio's `contact_force` after the impact, on the
  body, six_d `[n; f]` in the frame, point in world axes).

States: `numpy.random.default_rng(SEED)` drawn in this order per case (in the order above) and
state: the base (free flyer: position uniform in [-1, 1], quaternion uniform on the sphere), the
joint angles uniform in [-1.2, 1.2], v in [-2, 2], tau in [-20, 20], then for the Baumgarte cases
dq in [-0.1, 0.1] (nv, ours).

Checks before writing (against M = `crba` and nle = `nonLinearEffects`, J and γ as above):
`M·q̈ + nle = τ + Σ Jᵀ·f` (1e-9 relative), the residual below 1e-10 (relative to the largest of
|J·q̈|, |γ| and 1); the errors as above (1e-10); for impulses `M·(v⁺ - v⁻) = Σ Jᵀ·p` (1e-9
relative), `J·v⁺ = -e·J·v⁻` (1e-10 relative) and the energy loss `T⁺ - T⁻ = -½(1 - e²)·(J·v⁻)ᵀ·
G⁻¹·(J·v⁻)` with `G = J·M⁻¹·Jᵀ` (1e-9 relative). G is nonsingular in every case here (full row
rank J: the humanoid's 6-joint legs, the 7-joint arm); its largest condition number is printed
and asserted below 1e10, and G⁻¹·(J·v⁻) is a plain solve.
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

SEED = 20261211
STATES = 3
TOL = 1e-9
RESTITUTIONS = (0.0, 0.5)
GAINS = {'kp': 10.0, 'kd': 3.0}

# name -> (urdf, base).
MODELS = {
    'humanoid_free_flyer': ('models/humanoid.urdf', 'quaternion'),
    'arm7': ('models/arm7.urdf', 'fixed'),
}
# (name, model, contacts, impulses, Baumgarte gains).
CASES = [
    ('humanoid_feet', 'humanoid_free_flyer',
     [('left_foot', 'six_d'), ('right_foot', 'six_d')], True, None),
    ('humanoid_left_foot', 'humanoid_free_flyer', [('left_foot', 'six_d')], False, None),
    ('humanoid_foot_and_hand', 'humanoid_free_flyer',
     [('left_foot', 'six_d'), ('right_hand', 'point')], True, None),
    ('humanoid_hand', 'humanoid_free_flyer', [('left_hand', 'point')], False, None),
    ('arm7_welded', 'arm7', [('link7', 'six_d')], True, None),
    ('arm7_point', 'arm7', [('link7', 'point')], False, None),
    ('humanoid_baumgarte', 'humanoid_free_flyer',
     [('left_foot', 'six_d'), ('right_foot', 'six_d')], False, GAINS),
    ('humanoid_baumgarte_point', 'humanoid_free_flyer',
     [('left_foot', 'six_d'), ('right_hand', 'point')], False, GAINS),
]
# The models whose cases without gains carry the derivatives (the humanoid's would be 30 times
# the file; ours are checked on it against central differences instead).
DERIVATIVE_MODELS = ('arm7',)
KIND = {'six_d': (pin.ContactType.CONTACT_6D, pin.ReferenceFrame.LOCAL),
        'point': (pin.ContactType.CONTACT_3D, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)}


def draw_state(rng, base, nv_joints):
    """Our (q, v, tau): the base's q as the frames script draws it, then the joints."""
    q = []
    if base == 'quaternion':
        x = rng.uniform(-1, 1, 3)
        while True:
            quat = rng.uniform(-1, 1, 4)
            if 0.01 < quat @ quat <= 1.0:
                break
        q = list(x) + list(quat / np.linalg.norm(quat))  # [w, x, y, z]
    q = np.array(q + list(rng.uniform(-1.2, 1.2, nv_joints)))
    nv = nv_joints + (6 if base != 'fixed' else 0)
    return q, rng.uniform(-2, 2, nv), rng.uniform(-20, 20, nv)


class Setup:
    """A model with its layout, a data for the checks, and the contacts' frame ids."""

    def __init__(self, name):
        rel_path, base = MODELS[name]
        path = os.path.join(ROOT, rel_path)
        links, order = links_and_order(path)
        self.name, self.rel_path, self.base, self.order = name, rel_path, base, order
        self.model = load(path, base)
        self.data = self.model.createData()
        self.perm_v, self.q_to_pinocchio = layout(self.model, base, order)
        assert np.allclose(self.model.gravity.linear, [0, 0, -9.81])
        assert np.allclose(self.model.gravity.angular, 0)

    def fid(self, frame):
        f = self.model.getFrameId(frame, pin.FrameType.BODY)
        assert f < len(self.model.frames), frame
        return f

    def to_pinocchio_v(self, v):
        out = np.zeros(self.model.nv)
        out[self.perm_v] = v
        return out

    def description(self):
        m = self.model
        return {'urdf': self.rel_path, 'floating': self.base,
                'nq': m.nq, 'nv': m.nv,
                'joints': (['root_joint'] if self.base != 'fixed' else []) + self.order,
                'mass': pin.computeTotalMass(m),
                'gravity': m.gravity.linear.tolist()}


def rows(setup, qp, vp, contacts):
    """J (our columns, the contacts' rows as ours) and γ, from Pinocchio's frame algorithms."""
    model, data = setup.model, setup.data
    pin.computeJointJacobians(model, data, qp)
    pin.forwardKinematics(model, data, qp, vp, np.zeros(model.nv))
    pin.updateFramePlacements(model, data)
    js, gs = [], []
    for frame, kind in contacts:
        f = setup.fid(frame)
        if kind == 'six_d':
            j = pin.getFrameJacobian(model, data, f, pin.ReferenceFrame.LOCAL)
            js.append(angular_first(j[:, setup.perm_v]))
            gs.append(angular_first(
                pin.getFrameAcceleration(model, data, f, pin.ReferenceFrame.LOCAL).vector))
        else:
            j = pin.getFrameJacobian(model, data, f, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
            js.append(j[:3, setup.perm_v])
            gs.append(pin.getFrameClassicalAcceleration(
                model, data, f, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED).linear)
    return np.vstack(js), np.concatenate(gs)


def mass_and_nle(setup, qp, vp):
    model, data = setup.model, setup.data
    m = pin.crba(model, data, qp)
    m = np.triu(m) + np.triu(m, 1).T
    nle = pin.nonLinearEffects(model, data, qp, vp)
    p = setup.perm_v
    return m[np.ix_(p, p)], nle[p]


def placement(setup, qp, frame):
    pin.framesForwardKinematics(setup.model, setup.data, qp)
    return pin.SE3(setup.data.oMf[setup.fid(frame)])


def constraint_models(setup, qp, contacts, references, gains):
    models = []
    for (frame, kind), ref in zip(contacts, references):
        f = setup.model.frames[setup.fid(frame)]
        ctype, rf = KIND[kind]
        cm = pin.RigidConstraintModel(ctype, setup.model, f.parentJoint, f.placement,
                                      0, ref, rf)
        if gains is not None:
            cm.setBaumgarteCorrectorParameters(
                pin.BaumgarteCorrectorParameters(gains['kp'], gains['kd']))
        models.append(cm)
    return models


def ours(vector, kind):
    """A Pinocchio force or motion (linear first) of a contact, as ours."""
    return angular_first(vector) if kind == 'six_d' else np.asarray(vector)[:3]


def state_values(setup, rng, contacts, impulses, gains, worst):
    model = setup.model
    q, v, tau = draw_state(rng, setup.base, len(setup.order))
    qp, vp, taup = setup.q_to_pinocchio(q), setup.to_pinocchio_v(v), setup.to_pinocchio_v(tau)
    current = [placement(setup, qp, frame) for frame, _ in contacts]
    if gains is None:
        references = current
    else:
        dq = setup.to_pinocchio_v(rng.uniform(-0.1, 0.1, model.nv))
        perturbed = pin.integrate(model, qp, dq)
        references = [placement(setup, perturbed, frame) for frame, _ in contacts]

    cms = constraint_models(setup, qp, contacts, references, gains)
    cds = [cm.createData() for cm in cms]
    data = model.createData()
    pin.initConstraintDynamics(model, data, cms, cds)
    qdd_p = pin.constraintDynamics(model, data, qp, vp, taup, cms, cds,
                                   pin.ProximalSettings(1e-12, 0.0, 10))
    qdd = qdd_p[setup.perm_v]
    forces = {frame: ours(cd.contact_force.vector, kind)
              for (frame, kind), cd in zip(contacts, cds)}

    # Checks, from Pinocchio's M, nle, J and γ computed here.
    m, nle = mass_and_nle(setup, qp, vp)
    j, gamma = rows(setup, qp, vp, contacts)
    f_all = np.concatenate([forces[frame] for frame, _ in contacts])
    eom = rel(m @ qdd + nle, tau + j.T @ f_all)
    assert eom < TOL, eom
    target = np.zeros(len(gamma))
    out = {'q': q.tolist(), 'v': v.tolist(), 'tau': tau.tolist(), 'qdd': qdd.tolist(),
           'forces': {k: x.tolist() for k, x in forces.items()}}
    if setup.name in DERIVATIVE_MODELS and gains is None:
        out['derivatives'] = derivatives(setup, qp, vp, taup, cms, cds, data, contacts, worst)
    if gains is not None:
        out['contacts'] = {}
        errors = []
        for (frame, kind), cd, mc, ref in zip(contacts, cds, current, references):
            e_pin = cd.contact_placement_error.vector
            if kind == 'six_d':
                e = angular_first(e_pin)
                mine = angular_first(pin.log6(ref.inverse() * mc).vector)
            else:
                e = cd.oMc1.rotation @ e_pin[:3]
                mine = mc.translation - ref.translation
                assert rel(e_pin[3:], np.zeros(3)) == 0.0
            assert rel(e, mine) < 1e-10, (frame, e, mine)
            assert np.abs(e).max() > 1e-3, 'the reference differs from the placement'
            errors.append(e)
            out['contacts'][frame] = {
                'reference': {'rotation': ref.rotation.tolist(),
                              'translation': ref.translation.tolist()},
                'error': e.tolist()}
        target = -gains['kd'] * (j @ v) - gains['kp'] * np.concatenate(errors)
    deviation = j @ qdd + gamma - target
    residual = float(np.abs(deviation).max())
    scale = max(1.0, np.abs(j @ qdd).max(), np.abs(gamma).max())
    assert residual / scale < 1e-10, residual
    worst['residual'] = max(worst['residual'], residual)
    worst['eom'] = max(worst['eom'], eom)
    out['residual'] = residual

    if impulses:
        out['impulses'] = []
        minv = np.linalg.inv(m)
        g = j @ minv @ j.T
        worst['cond'] = max(worst['cond'], np.linalg.cond(g))
        assert np.linalg.cond(g) < 1e10
        jv = j @ v
        for e in RESTITUTIONS:
            data = model.createData()
            pin.initConstraintDynamics(model, data, cms, cds)
            v_plus = pin.impulseDynamics(model, data, qp, vp, cms, cds, e,
                                         pin.ProximalSettings(1e-12, 0.0, 1))[setup.perm_v]
            p = {frame: ours(cd.contact_force.vector, kind)
                 for (frame, kind), cd in zip(contacts, cds)}
            p_all = np.concatenate([p[frame] for frame, _ in contacts])
            assert rel(m @ (v_plus - v), j.T @ p_all) < TOL
            assert rel(j @ v_plus, -e * jv) / max(1.0, np.abs(jv).max()) < 1e-10
            loss = 0.5 * v_plus @ m @ v_plus - 0.5 * v @ m @ v
            predicted = -0.5 * (1 - e * e) * jv @ np.linalg.solve(g, jv)
            assert rel(loss, predicted) < TOL, (loss, predicted)
            worst['impulse'] = max(worst['impulse'], rel(m @ (v_plus - v), j.T @ p_all))
            out['impulses'].append({'restitution': e, 'v_minus': v.tolist(),
                                    'v_plus': v_plus.tolist(),
                                    'impulses': {k: x.tolist() for k, x in p.items()}})
    return out


def stacked_forces(setup, cds, contacts):
    """The contacts' forces, ours, stacked in order."""
    return np.concatenate([ours(cd.contact_force.vector, kind)
                           for (frame, kind), cd in zip(contacts, cds)])


def derivatives(setup, qp, vp, taup, cms, cds, data, contacts, worst):
    """Pinocchio's `computeConstraintDynamicsDerivatives` after `constraintDynamics`, in our
    layout (rows: q̈ in our order, the forces as ours; columns: our v), each checked against
    central differences of Pinocchio's own `constraintDynamics` (q moved by `pin.integrate`)."""
    model, p = setup.model, setup.perm_v
    d = pin.computeConstraintDynamicsDerivatives(model, data, cms, cds,
                                                 pin.ProximalSettings(1e-12, 0.0, 10))
    # Rows of the forces: Pinocchio's lambda stacks each contact's force linear first.
    rows, at = [], 0
    for _frame, kind in contacts:
        n = 6 if kind == 'six_d' else 3
        block = list(range(at, at + n))
        rows += block[3:] + block[:3] if kind == 'six_d' else block
        at += n
    ddq = [np.asarray(x)[np.ix_(p, p)] for x in d[:3]]
    dlambda = [np.asarray(x)[np.ix_(rows, p)] for x in d[3:]]

    def solve(qp, vp, taup):
        cds2 = [cm.createData() for cm in cms]
        data2 = model.createData()
        pin.initConstraintDynamics(model, data2, cms, cds2)
        qdd = pin.constraintDynamics(model, data2, qp, vp, taup, cms, cds2,
                                     pin.ProximalSettings(1e-12, 0.0, 10))
        return qdd[p], stacked_forces(setup, cds2, contacts)

    h = 1e-6
    fd = [np.zeros_like(x) for x in ddq], [np.zeros_like(x) for x in dlambda]
    for k in range(model.nv):
        e = np.zeros(model.nv)
        e[p[k]] = h
        moves = [(pin.integrate(model, qp, e), vp, taup), (pin.integrate(model, qp, -e), vp, taup),
                 (qp, vp + e, taup), (qp, vp - e, taup), (qp, vp, taup + e), (qp, vp, taup - e)]
        values = [solve(*m) for m in moves]
        for w in range(3):
            plus, minus = values[2 * w], values[2 * w + 1]
            fd[0][w][:, k] = (plus[0] - minus[0]) / (2 * h)
            fd[1][w][:, k] = (plus[1] - minus[1]) / (2 * h)
    for ours_, theirs in zip(ddq + dlambda, fd[0] + fd[1]):
        e = np.abs(ours_ - theirs).max() / max(1.0, np.abs(theirs).max())
        worst['derivatives'] = max(worst['derivatives'], e)
        assert e < 1e-5, e
    names = ['dqdd_dq', 'dqdd_dv', 'dqdd_dtau', 'dforces_dq', 'dforces_dv', 'dforces_dtau']
    return {n: x.tolist() for n, x in zip(names, ddq + dlambda)}


def main():
    rng = np.random.default_rng(SEED)
    setups = {name: Setup(name) for name in MODELS}
    worst = {'residual': 0.0, 'eom': 0.0, 'cond': 0.0, 'impulse': 0.0, 'derivatives': 0.0}
    cases = {}
    for name, model, contacts, impulses, gains in CASES:
        cases[name] = {
            'model': model,
            'contacts': [{'frame': f, 'kind': k} for f, k in contacts],
            'baumgarte': gains,
            'states': [state_values(setups[model], rng, contacts, impulses, gains, worst)
                       for _ in range(STATES)],
        }
    out = {
        'generator': f'Pinocchio {pin.__version__} (pip package `pin`), '
                     'tests/data/pinocchio_constraints/make_pinocchio_constraints.py',
        'seed': SEED,
        'conventions': __doc__,
        'models': {name: s.description() for name, s in setups.items()},
        'cases': cases,
    }
    print('largest residual {residual:.1e}, equation of motion {eom:.1e}, impulses {impulse:.1e}, '
          'cond(G) {cond:.1e}, derivatives against central differences {derivatives:.1e}'
          .format(**worst))
    write_json(os.path.join(HERE, 'pinocchio-constraints.json'), out)


if __name__ == '__main__':
    main()
