"""Pinocchio's constrained forward dynamics with loop closures ->
`tests/data/pinocchio_loops/pinocchio-loops.json`, for the runtime's `constraint::Loop` and the
generated `constrained_forward_dynamics` of a description with `loops: […]` (DESIGN §9
"Constraints").

Runs on our machines, NOT in CI (CI has no Pinocchio). To regenerate (from anywhere):

    pip install pin numpy            # Pinocchio 4.1
    python tests/data/pinocchio_loops/make_pinocchio_loops.py

Seeded: a rerun reproduces the JSON byte for byte. Written whole (a temporary file, a rename).
The model, its layout and the states are those of
`tests/data/pinocchio_constraints/make_pinocchio_constraints.py` (imported from there): the
humanoid (`models/humanoid.urdf`) on Pinocchio's free flyer, our coordinates.

A loop holds frame `a` on frame `b`, two URDF links (Pinocchio's BODY frames), as Pinocchio's
two-joint `pin.RigidConstraintModel(type, model, joint_a, placement_a, joint_b, placement_b,
reference_frame)`, each frame's parent joint and its placement there:
- `point`: `CONTACT_3D`, `LOCAL_WORLD_ALIGNED`. Rows: the linear rows of `a`'s
  LOCAL_WORLD_ALIGNED Jacobian less `b`'s; drift: `a`'s classical linear acceleration at q̈ = 0
  (`getFrameClassicalAcceleration`) less `b`'s; the force on `a`'s body in world axes (its
  opposite on `b`'s); the position error `p_a − p_b` (world).
- `six_d`: `CONTACT_6D`, `LOCAL`. Rows: `J_a − ᵃX_b·J_b` (LOCAL Jacobians, `ᵃX_b` the action
  of `M_a⁻¹·M_b`); drift `γ_a − ᵃX_b·γ_b + v_a × (ᵃX_b·v_b)` (`getFrameAcceleration`, LOCAL,
  at q̈ = 0; `getFrameVelocity`, LOCAL), which the checks below find to be Pinocchio's (the
  alternative without the cross product, the rate of the world-axes relative velocity, is
  computed too and printed: it differs wherever the frames move apart); the wrench `[n; f]` on
  `a`'s body about its origin in its axes, ANGULAR FIRST; the position error
  `−log6(M_a⁻¹·M_b) = log6(M_b⁻¹·M_a)`, angular first.
Solved by `constraintDynamics` with `ProximalSettings(1e-12, mu = 0, 10)` (the exact solve).
With gains (`baumgarte`, Kp = 10, Kd = 3 on every row): `J·q̈ + γ = −Kd·J·v − Kp·e`.

Cases (`cases`): `loops` (a list of `{name, kind, a, b}` in row order, after the `contacts`,
`{frame, kind}` as in the constraints' data), `baumgarte` (`null` or `{kp, kd}`), `states`:
- `hands_six_d`: the left foot flat (six_d), the hands holding a rigid bar (a six_d loop
  `left_hand` on `right_hand`);
- `hands_point`: the hands' origins held together (a point loop), no contact;
- `hands_six_d_baumgarte`, `hands_point_baumgarte`: the same loops alone, with gains (the hands
  are apart in every state, so each error is large).
Per state, our layout: `q`, `v`, `tau`, `qdd`, `forces` (stacked, row order, ours), `error`
(with gains: e stacked, row order), `residual` (max |J·q̈ + γ − target| with J, γ computed here).

Checks before writing: `M·q̈ + nle = τ + Jᵀ·f` (1e-9 relative); the residual below 1e-10
relative to the largest of |J·q̈|, |γ| and 1; the errors against `contact_placement_error`
(1e-10).
"""
import os
import sys

import numpy as np
import pinocchio as pin

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, '..', 'pinocchio_constraints'))
sys.path.insert(0, os.path.join(HERE, '..', 'pinocchio_frames'))
sys.dont_write_bytecode = True
from make_pinocchio_frames import angular_first, rel, write_json  # noqa: E402
from make_pinocchio_constraints import (  # noqa: E402
    KIND, Setup, draw_state, mass_and_nle, ours, rows)

SEED = 20261127
STATES = 3
TOL = 1e-9
GAINS = {'kp': 10.0, 'kd': 3.0}
MODEL = 'humanoid_free_flyer'
# (name, contacts, loops as (name, kind, a, b), gains).
CASES = [
    ('hands_six_d', [('left_foot', 'six_d')], [('bar', 'six_d', 'left_hand', 'right_hand')], None),
    ('hands_point', [], [('clasp', 'point', 'left_hand', 'right_hand')], None),
    ('hands_six_d_baumgarte', [], [('bar', 'six_d', 'left_hand', 'right_hand')], GAINS),
    ('hands_point_baumgarte', [], [('clasp', 'point', 'left_hand', 'right_hand')], GAINS),
]


def loop_rows(setup, qp, vp, kind, a, b):
    """J (our columns), γ (with and without the cross product, for six_d) and e of a loop."""
    model, data = setup.model, setup.data
    pin.computeJointJacobians(model, data, qp)
    pin.forwardKinematics(model, data, qp, vp, np.zeros(model.nv))
    pin.updateFramePlacements(model, data)
    fa, fb = setup.fid(a), setup.fid(b)
    ma, mb = data.oMf[fa], data.oMf[fb]
    if kind == 'point':
        lwa = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        j = (pin.getFrameJacobian(model, data, fa, lwa)[:3]
             - pin.getFrameJacobian(model, data, fb, lwa)[:3])
        g = (pin.getFrameClassicalAcceleration(model, data, fa, lwa).linear
             - pin.getFrameClassicalAcceleration(model, data, fb, lwa).linear)
        return j[:, setup.perm_v], g, g, ma.translation - mb.translation
    local = pin.ReferenceFrame.LOCAL
    x = (ma.inverse() * mb)
    j = (pin.getFrameJacobian(model, data, fa, local)
         - x.action @ pin.getFrameJacobian(model, data, fb, local))
    va, vb = (pin.getFrameVelocity(model, data, f, local) for f in (fa, fb))
    ga, gb = (pin.getFrameAcceleration(model, data, f, local) for f in (fa, fb))
    world = ga - x.act(gb)
    crossed = world + va.cross(x.act(vb))
    e = pin.log6(mb.inverse() * ma).vector
    return (angular_first(j[:, setup.perm_v]), angular_first(crossed.vector),
            angular_first(world.vector), angular_first(e))


def state_values(setup, rng, contacts, loops, gains, worst):
    model = setup.model
    q, v, tau = draw_state(rng, setup.base, len(setup.order))
    qp, vp, taup = setup.q_to_pinocchio(q), setup.to_pinocchio_v(v), setup.to_pinocchio_v(tau)
    pin.framesForwardKinematics(model, setup.data, qp)
    cms = []
    for frame, kind in contacts:
        f = model.frames[setup.fid(frame)]
        ctype, rf = KIND[kind]
        cms.append(pin.RigidConstraintModel(ctype, model, f.parentJoint, f.placement, 0,
                                            pin.SE3(setup.data.oMf[setup.fid(frame)]), rf))
    for _name, kind, a, b in loops:
        fa, fb = model.frames[setup.fid(a)], model.frames[setup.fid(b)]
        ctype, rf = KIND[kind]
        cms.append(pin.RigidConstraintModel(ctype, model, fa.parentJoint, fa.placement,
                                            fb.parentJoint, fb.placement, rf))
    if gains is not None:
        for cm in cms:
            cm.setBaumgarteCorrectorParameters(
                pin.BaumgarteCorrectorParameters(gains['kp'], gains['kd']))
    cds = [cm.createData() for cm in cms]
    data = model.createData()
    pin.initConstraintDynamics(model, data, cms, cds)
    qdd = pin.constraintDynamics(model, data, qp, vp, taup, cms, cds,
                                 pin.ProximalSettings(1e-12, 0.0, 10))[setup.perm_v]
    kinds = [k for _, k in contacts] + [k for _, k, _, _ in loops]
    forces = np.concatenate([ours(cd.contact_force.vector, k) for cd, k in zip(cds, kinds)])

    m, nle = mass_and_nle(setup, qp, vp)
    js, gammas, worlds, errors = [], [], [], []
    if contacts:
        j, g = rows(setup, qp, vp, contacts)
        js.append(j)
        gammas.append(g)
        worlds.append(g)
        errors.append(np.zeros(len(g)))
    for (_name, kind, a, b), cd in zip(loops, cds[len(contacts):]):
        j, g, w, e = loop_rows(setup, qp, vp, kind, a, b)
        e_pin = cd.contact_placement_error.vector
        theirs = angular_first(e_pin) if kind == 'six_d' else cd.oMc1.rotation @ e_pin[:3]
        if gains is not None:
            assert rel(e, theirs) < 1e-10, (e, theirs)
        js.append(j)
        gammas.append(g)
        worlds.append(w)
        errors.append(e)
    j, gamma, world, error = (np.concatenate(x) if x[0].ndim == 1 else np.vstack(x)
                              for x in (js, gammas, worlds, errors))
    eom = rel(m @ qdd + nle, tau + j.T @ forces)
    assert eom < TOL, eom
    target = np.zeros(len(gamma))
    if gains is not None:
        target = -gains['kd'] * (j @ v) - gains['kp'] * error
    scale = max(1.0, np.abs(j @ qdd).max(), np.abs(gamma).max())
    residual = float(np.abs(j @ qdd + gamma - target).max())
    other = float(np.abs(j @ qdd + world - target).max())
    worst['other'] = max(worst['other'], other / scale)
    assert residual / scale < 1e-10, (residual, other)
    worst['residual'] = max(worst['residual'], residual)
    worst['eom'] = max(worst['eom'], eom)
    out = {'q': q.tolist(), 'v': v.tolist(), 'tau': tau.tolist(), 'qdd': qdd.tolist(),
           'forces': forces.tolist(), 'residual': residual}
    if gains is not None:
        out['error'] = error.tolist()
    return out


def main():
    rng = np.random.default_rng(SEED)
    setup = Setup(MODEL)
    worst = {'residual': 0.0, 'eom': 0.0, 'other': 0.0}
    cases = {}
    for name, contacts, loops, gains in CASES:
        cases[name] = {
            'model': MODEL,
            'contacts': [{'frame': f, 'kind': k} for f, k in contacts],
            'loops': [{'name': n, 'kind': k, 'a': a, 'b': b} for n, k, a, b in loops],
            'baumgarte': gains,
            'states': [state_values(setup, rng, contacts, loops, gains, worst)
                       for _ in range(STATES)],
        }
    out = {
        'generator': f'Pinocchio {pin.__version__} (pip package `pin`), '
                     'tests/data/pinocchio_loops/make_pinocchio_loops.py',
        'seed': SEED,
        'conventions': __doc__,
        'models': {MODEL: setup.description()},
        'cases': cases,
    }
    print('largest residual {residual:.1e}, equation of motion {eom:.1e}; the six_d drift '
          'without the cross product misses by up to {other:.1e} (relative)'.format(**worst))
    write_json(os.path.join(HERE, 'pinocchio-loops.json'), out)


if __name__ == '__main__':
    main()
