"""Pinocchio reference values for the models for scale -> `tests/data/pinocchio-scale.json`.

Runs on our machines, NOT in CI (CI has no Pinocchio): `pip install pin numpy`, then
`python tests/data/make_scale_reference.py`. The JSON it writes is committed and read by
`tests/tests/generated_scale.rs`. Seeded: a rerun reproduces the file.

Models (see `models/make_scale_models.py`):
- `humanoid` from `models/humanoid.urdf`, twice:
  - `free_flyer`: Pinocchio's `JointModelFreeFlyer` under the pelvis, which is what
    `models/humanoid.chain` writes as `free(quaternion)`. Stored in OUR convention: q = position,
    then the quaternion as [w, x, y, z] (Pinocchio stores [x, y, z, w]: reordered here);
    v = [linear; angular], both in the pelvis frame, as in Pinocchio.
  - `floating`: a translation (world frame) then Euler angles z-y-x (R = Rz Ry Rx) under the pelvis,
    v = coordinate rates: what `load_model(humanoid.urdf, floating = true)` builds.
- `chain50` from `models/chain50.urdf`, `fixed`.

Joint order: every vector and the matrix are stored in OUR coordinate order, depth first from the
root with children in document order (the URDF importer's and the `.chain` grammar's order).
Pinocchio may order siblings otherwise (urdfdom keeps joints by name), so the values are permuted
here by joint name; `joint_names` lists our order.

Fields as in `tests/data/pinocchio/README.md`: mass_matrix = M(q) (full, symmetrized from crba's
upper triangle); bias = N(q,v)v WITHOUT gravity; nonlinear_effects = bias + gravity; gravity =
g(q); tau_out = rnea(q, v, a); qdd = aba(q, v, tau). Gravity (0, 0, -9.81).
"""
import json
import os
import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin

here = os.path.dirname(os.path.abspath(__file__))
models_dir = os.path.join(here, '..', '..', 'models')
rng = np.random.default_rng(20261124)


def document_order(urdf):
    """Names of the movable joints, depth first from the root, children in document order."""
    root = ET.parse(urdf).getroot()
    joints = [j for j in root.findall('joint')]
    children = {}
    child_links = set()
    for j in joints:
        children.setdefault(j.find('parent').get('link'), []).append(j)
        child_links.add(j.find('child').get('link'))
    (base,) = [l.get('name') for l in root.findall('link') if l.get('name') not in child_links]
    order = []

    def visit(link):
        for j in children.get(link, []):
            if j.get('type') != 'fixed':
                order.append(j.get('name'))
            visit(j.find('child').get('link'))

    visit(base)
    return order


def permutation(model, names, base):
    """Index maps (q, v) from our order to Pinocchio's: ours[i] = pinocchio[perm[i]]."""
    pq, pv = list(range(base[0])), list(range(base[1]))
    for n in names:
        j = model.joints[model.getJointId(n)]
        assert j.nq == 1 and j.nv == 1, n
        pq.append(j.idx_q)
        pv.append(j.idx_v)
    assert sorted(pq) == list(range(model.nq)) and sorted(pv) == list(range(model.nv))
    return np.array(pq), np.array(pv)


def states(model, names, kind, count):
    base = {'fixed': (0, 0), 'floating': (6, 6), 'free_flyer': (7, 6)}[kind]
    pq, pv = permutation(model, names, base)
    d = model.createData()
    out = []
    for _ in range(count):
        q = rng.uniform(-1.0, 1.0, model.nq)
        if kind == 'free_flyer':
            quat = rng.normal(size=4)
            q[3:7] = quat / np.linalg.norm(quat)  # Pinocchio's [x, y, z, w]
        v = rng.uniform(-2, 2, model.nv)
        a = rng.uniform(-3, 3, model.nv)
        tau = rng.uniform(-5, 5, model.nv)
        M = pin.crba(model, d, q)
        M = np.triu(M) + np.triu(M, 1).T
        nle = pin.nonLinearEffects(model, d, q, v)
        g = pin.computeGeneralizedGravity(model, d, q)
        qdd = pin.aba(model, d, q, v, tau)
        rnea = pin.rnea(model, d, q, v, a)
        err = np.abs(rnea - M @ a - nle).max() / max(1, np.abs(rnea).max())
        assert err < 1e-11, (kind, err)
        ours_q = q[pq]
        if kind == 'free_flyer':
            ours_q[3:7] = [q[6], q[3], q[4], q[5]]  # [w, x, y, z]
        vec = lambda x: x[pv].tolist()
        out.append(dict(
            q=ours_q.tolist(), v=vec(v), a=vec(a), tau=vec(tau),
            mass_matrix=M[np.ix_(pv, pv)].tolist(), bias=vec(nle - g), nonlinear_effects=vec(nle),
            gravity=vec(g), tau_out=vec(rnea), qdd=vec(qdd)))
    return dict(nq=model.nq, nv=model.nv, joint_names=names, states=out)



def main():
    out = {
        "generator": f"Pinocchio {pin.__version__} (pip package `pin`), tests/data/make_scale_reference.py",
        "conventions": __doc__,
        "models": {},
    }

    humanoid = os.path.join(models_dir, 'humanoid.urdf')
    names = document_order(humanoid)
    euler = pin.JointModelComposite(2)
    euler.addJoint(pin.JointModelTranslation())
    euler.addJoint(pin.JointModelSphericalZYX())
    out['models']['humanoid'] = {
        'free_flyer': states(pin.buildModelFromUrdf(humanoid, pin.JointModelFreeFlyer()), names, 'free_flyer', 4),
        'floating': states(pin.buildModelFromUrdf(humanoid, euler), names, 'floating', 4),
    }
    chain50 = os.path.join(models_dir, 'chain50.urdf')
    out['models']['chain50'] = {
        'fixed': states(pin.buildModelFromUrdf(chain50), document_order(chain50), 'fixed', 3),
    }

    path = os.path.join(here, 'pinocchio-scale.json')
    with open(path + '.tmp', 'w') as f:
        json.dump(out, f, indent=None, separators=(',', ':'))
    os.replace(path + '.tmp', path)
    print(path, {m: {k: (v['nq'], v['nv']) for k, v in e.items()} for m, e in out['models'].items()})


if __name__ == '__main__':
    main()
