"""Pinocchio's own states and joint torques in Pinocchio's layout of q, for the conversions of
`articulated::pinocchio` (tests/tests/pinocchio_layout.rs).

Runs on our machines, NOT in CI (CI has no Pinocchio). To regenerate:

    pip install pin numpy            # Pinocchio 4.1
    python tests/data/pinocchio_layout/make_pinocchio_layout.py

Three URDFs of `tests/data/real_robots/urdf/` (example-robot-data 6.0.0), each with the joints
Pinocchio stores otherwise than we do: the Unitree G1 on a free flyer (`[x, y, z, qx, qy, qz,
qw]`), TIAGo on a free flyer with two continuous wheels and a continuous head/arm joint
(`(cos θ, sin θ)`), and the Kinova arm on a fixed base with continuous joints. For each, seeded
states `q` (Pinocchio's layout, from `pin.randomConfiguration` with the free flyer's translation
in [-1, 1]), `v`, `a`, and `rnea(q, v, a)`; the joints' names, `idx_q`, `nq`, `idx_v` in
Pinocchio's order. The Rust test converts `q` with `Layout::q_from_pinocchio` and compares
the reference's inverse dynamics with `tau`, and `q_to_pinocchio` with `q`. And for every
URDF there that Pinocchio loads, its joint order (`orders`), which the URDF importer predicts.
"""
import json
import os

import numpy as np
import pinocchio as pin

HERE = os.path.dirname(os.path.abspath(__file__))
URDF = os.path.join(HERE, '..', 'real_robots', 'urdf')
MODELS = [
    ('g1', 'g1_description/urdf/g1_29dof_rev_1_0.urdf', True),
    ('tiago', 'tiago_description/robots/tiago.urdf', True),
    ('kinova', 'kinova_description/robots/kinova.urdf', False),
]
STATES = 3


def main():
    np.random.seed(20261127)
    pin.seed(20261127)
    out = {
        'generator': f'Pinocchio {pin.__version__} (pip package `pin`), '
                     'tests/data/pinocchio_layout/make_pinocchio_layout.py',
        'models': {},
    }
    for name, rel, free in MODELS:
        path = os.path.join(URDF, rel)
        model = (pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if free
                 else pin.buildModelFromUrdf(path))
        data = model.createData()
        if free:
            model.lowerPositionLimit[:3] = -1.0
            model.upperPositionLimit[:3] = 1.0
        lo, hi = model.lowerPositionLimit.copy(), model.upperPositionLimit.copy()
        # Unbounded revolute joints (continuous) have infinite limits on their (cos, sin):
        # randomConfiguration draws the angle; other infinite limits are clamped to ±π.
        finite = lambda x: np.where(np.isfinite(x), x, np.sign(x) * np.pi)
        states = []
        for _ in range(STATES):
            q = pin.randomConfiguration(model, finite(lo), finite(hi))
            v = np.random.uniform(-1.0, 1.0, model.nv)
            a = np.random.uniform(-1.0, 1.0, model.nv)
            tau = pin.rnea(model, data, q, v, a)
            states.append({'q': q.tolist(), 'v': v.tolist(), 'a': a.tolist(),
                           'tau': tau.tolist()})
        joints = [{'name': model.names[i], 'kind': model.joints[i].shortname(),
                   'idx_q': model.joints[i].idx_q, 'nq': model.joints[i].nq,
                   'idx_v': model.joints[i].idx_v}
                  for i in range(1, model.njoints)]
        out['models'][name] = {'urdf': 'real_robots/urdf/' + rel, 'free_flyer': free,
                               'nq': model.nq, 'nv': model.nv, 'joints': joints,
                               'states': states}
    # Pinocchio's joint order on every URDF of the real robots that it loads (fixed base,
    # mimic=True so that mimic joints have no coordinates, as ours): the names of the joints
    # with coordinates, in Pinocchio's order.
    out['orders'] = {}
    for dirpath, _, files in sorted(os.walk(URDF)):
        for f in sorted(files):
            if not f.endswith('.urdf'):
                continue
            path = os.path.join(dirpath, f)
            rel = os.path.relpath(path, URDF)
            try:
                model = pin.buildModelFromUrdf(path, mimic=True)
            except Exception:
                try:
                    model = pin.buildModelFromUrdf(path)
                except Exception as e:
                    out['orders'][rel] = {'error': str(e)}
                    continue
            out['orders'][rel] = {
                'joints': [model.names[i] for i in range(1, model.njoints)
                           if model.joints[i].nv > 0]}
    text = json.dumps(out, indent=1) + '\n'
    target = os.path.join(HERE, 'pinocchio-layout.json')
    with open(target + '.tmp', 'w') as f:
        f.write(text)
    os.replace(target + '.tmp', target)
    print(f'wrote {target}')


if __name__ == '__main__':
    main()
