"""Pinocchio's frame kinematics -> `tests/data/pinocchio_frames/pinocchio-frames.json`, for the
reference's frames (`articulated_dynamics::reference::frames`, tests/tests/pinocchio_frames.rs).

Runs on our machines, NOT in CI (CI has no Pinocchio). To regenerate (from anywhere):

    pip install pin numpy            # Pinocchio 4.1
    python tests/data/pinocchio_frames/make_pinocchio_frames.py

The states are seeded, so a rerun reproduces the JSON byte for byte (up to Pinocchio's own
changes). The file is written whole, through a temporary file and a rename.

Models (`models`, keyed by name): `models/arm7.urdf` on a fixed base (`arm7`), `models/tree.urdf`
on a fixed base (`tree`: branching, a link welded by a fixed joint), and `models/humanoid.urdf`
on Pinocchio's free flyer (`humanoid_free_flyer`, `pin.JointModelFreeFlyer()`) and on our Euler
base (`humanoid_euler`). Each has `urdf` (relative to the repository root), `floating` (`fixed`,
`quaternion` or `euler`: the importer's `FloatingBase`), `nq`, `nv` (ours), `joints` (the joints
with coordinates in OUR order: the base `root_joint` first, then the URDF's movable joints depth
first from the root link, children in document order), `frames`, `declared`, `states`.

The Euler base: Pinocchio's values come from six single-axis joints (`euler_chain`: PX, PY, PZ
along the world axes, then RZ, RY, RX, with the URDF's tree appended under the last), not from
the composite `JointModelComposite(Translation, SphericalZYX)` of `euler_base()` in
`tests/data/real_robots/make_real_robots.py`. Both give the same placements, velocities,
classical accelerations and Jacobians (checked here to 1e-10), but Pinocchio 4.1's
`computeJointJacobiansTimeVariation` takes the columns of a joint's motion subspace `S` as fixed
in the joint's frame (`dJ = v x J`), which `SphericalZYX` and the composite's translation are
not, so with the composite `getFrameJacobianTimeVariation` is not dJ/dt (the classical
acceleration is then not J a + dJ v either, while `getFrameClassicalAcceleration` matches finite
differences of the velocity). The single-axis joints have constant `S`, so their `dJ` is exact.
`composite_time_variation_error` records how far the composite's `dJ` is from the chain's (the
largest difference relative to the largest entry, over frames, states and reference frames).

Frames (`frames`, in this order): every URDF link as Pinocchio's BODY frame (on a fixed base the
root link sits at the world origin, on joint 0, the universe; a link welded by a fixed joint is a
frame of the moving body above it, as the importer keeps it), then the declared frames
(`declared`): each `{name, link, xyz, rpy}`, an OP_FRAME placed at `xyz` then
`Rz(yaw)·Ry(pitch)·Rx(roll)` in the frame of the link `link`, added with
`model.addFrame(pin.Frame(name, parent_joint, parent_frame, placement, pin.FrameType.OP_FRAME))`
where `placement` = the link's placement in its joint composed with that. The Rust test adds the
same frames to `model.frames` (composing with the link's own placement where the link is itself
a frame).

Conventions of the stored values, ALL IN OUR LAYOUT:
- `q` ours: a free flyer `[x, y, z, w, qx, qy, qz]` (Pinocchio's is `[x, y, z, qx, qy, qz, qw]`),
  the Euler base `[x, y, z, rz, ry, rx]` (R = Rz Ry Rx, as Pinocchio's SphericalZYX), then one
  angle per revolute joint in our joint order. `v`, `a`: the base's six (free flyer: linear then
  angular velocity, both in the base's frame; Euler base: the coordinates' rates), then one per
  joint in our order. The script permutes them into Pinocchio's order by joint name (Pinocchio
  takes a link's child joints by name: the humanoid's `left_hip_yaw` before `waist_yaw`).
- Spatial vectors are ANGULAR FIRST `[w; v]` (Pinocchio's are linear first: the halves are
  swapped here), Jacobian rows likewise, Jacobian columns in our velocity order.
- Per state (`states[i]`: `q`, `v`, `a`, `frames`), per frame name:
  - `rotation`: world_R_frame, rows; `translation`: the frame origin in the world
    (`framesForwardKinematics`, then `data.oMf`);
  - `velocity`: `getFrameVelocity(..., LOCAL)`;
  - `acceleration`: `getFrameClassicalAcceleration(..., LOCAL_WORLD_ALIGNED)` after
    `forwardKinematics(q, v, a)`;
  - `jacobian.{local, world, local_world_aligned}`: `getFrameJacobian` after
    `computeJointJacobians(q)` and `updateFramePlacements`, 6 x nv rows;
  - `jacobian_time_variation.{...}`: `getFrameJacobianTimeVariation` after
    `computeJointJacobiansTimeVariation(q, v)`, 6 x nv rows.

States: `numpy.random.default_rng(SEED)` drawn in this order per model and state: the base
(free flyer: position uniform in [-1, 1], quaternion uniform on the sphere; Euler base: position
in [-1, 1], angles rz, rx in [-pi, pi], ry in [-1.2, 1.2]), the joint angles uniform in [-1.2, 1.2],
v in [-2, 2], a in [-3, 3].

Checks before writing (against Pinocchio's own values): J_local v = velocity; the classical
acceleration = J_lwa a + dJ_lwa v (1e-10 relative).
"""
import json
import math
import os
import re
import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, '..', '..', '..'))
SEED = 20261204
STATES = 3
TOL = 1e-10
RF = {'local': pin.ReferenceFrame.LOCAL, 'world': pin.ReferenceFrame.WORLD,
      'local_world_aligned': pin.ReferenceFrame.LOCAL_WORLD_ALIGNED}

# (name, urdf, base, declared frames: (name, link, xyz, rpy)).
MODELS = [
    ('arm7', 'models/arm7.urdf', 'fixed', [
        ('tool', 'link7', [0.02, -0.03, 0.11], [0.3, -0.4, 1.2]),
        ('camera_mount', 'link4', [-0.05, 0.08, 0.0], [1.1, 0.2, -2.3]),
        ('on_base', 'base', [0.2, 0.1, 0.05], [0.0, 0.5, 0.7]),
    ]),
    ('tree', 'models/tree.urdf', 'fixed', [
        ('left_tip', 'left2', [0.0, 0.03, -0.25], [-0.6, 0.1, 0.4]),
        ('right_tip', 'right2', [0.01, -0.02, -0.24], [0.2, 0.9, -1.5]),
        ('eye', 'head', [0.08, 0.04, 0.1], [0.0, -0.3, 0.25]),
    ]),
    ('humanoid_free_flyer', 'models/humanoid.urdf', 'quaternion', [
        ('left_sole', 'left_foot', [0.04, 0.0, -0.09], [0.05, -0.1, 0.2]),
        ('right_palm', 'right_hand', [0.0, -0.03, -0.08], [1.4, 0.3, -0.6]),
        ('lens', 'camera', [0.02, 0.0, 0.01], [-0.2, 0.4, 2.9]),
    ]),
    ('humanoid_euler', 'models/humanoid.urdf', 'euler', [
        ('left_sole', 'left_foot', [0.04, 0.0, -0.09], [0.05, -0.1, 0.2]),
        ('right_palm', 'right_hand', [0.0, -0.03, -0.08], [1.4, 0.3, -0.6]),
        ('lens', 'camera', [0.02, 0.0, 0.01], [-0.2, 0.4, 2.9]),
    ]),
]


def rpy_matrix(rpy):
    """URDF's fixed-axis roll-pitch-yaw: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    return pin.rpy.rpyToMatrix(*rpy)


def euler_base():
    """Our Euler floating base, as in tests/data/real_robots/make_real_robots.py."""
    root = pin.JointModelComposite(2)
    root.addJoint(pin.JointModelTranslation())
    root.addJoint(pin.JointModelSphericalZYX())
    return root


def links_and_order(path):
    """The URDF's links (document order) and its movable joints depth first from the root link,
    children in document order (our order)."""
    root = ET.parse(path).getroot()
    links = [l.get('name') for l in root.findall('link')]
    children, child_links = {}, set()
    for j in root.findall('joint'):
        children.setdefault(j.find('parent').get('link'), []).append(j)
        child_links.add(j.find('child').get('link'))
    roots = [l for l in links if l not in child_links]
    assert len(roots) == 1, roots
    order = []

    def visit(link):
        for j in children.get(link, []):
            if j.get('type') != 'fixed':
                assert j.get('type') == 'revolute', j.get('type')
                order.append(j.get('name'))
            visit(j.find('child').get('link'))
    visit(roots[0])
    return links, order


def euler_chain(path):
    """Our Euler floating base as six single-axis joints, `root_joint_x`, `_y`, `_z` (along the
    world axes) then `root_joint_rz`, `_ry`, `_rx` (R = Rz Ry Rx), with the URDF's tree appended
    under the last (`pin.appendModel`; the root link's inertia is lost with its fixed-base
    load, which changes nothing here: frames are kinematics)."""
    base = pin.Model()
    parent = 0
    for name, jm in [('x', pin.JointModelPX()), ('y', pin.JointModelPY()),
                     ('z', pin.JointModelPZ()), ('rz', pin.JointModelRZ()),
                     ('ry', pin.JointModelRY()), ('rx', pin.JointModelRX())]:
        parent = base.addJoint(parent, jm, pin.SE3.Identity(), 'root_joint_' + name)
        base.addJointFrame(parent)
    under = base.getFrameId('root_joint_rx', pin.FrameType.JOINT)
    return pin.appendModel(base, pin.buildModelFromUrdf(path), under, pin.SE3.Identity())


def load(path, base):
    if base == 'quaternion':
        return pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer())
    if base == 'euler':
        return euler_chain(path)
    if base == 'euler_composite':
        return pin.buildModelFromUrdf(path, euler_base())
    return pin.buildModelFromUrdf(path)


def declare(model, name, link, xyz, rpy):
    """An OP_FRAME at (xyz, rpy) in `link`'s frame."""
    parent = model.getFrameId(link, pin.FrameType.BODY)
    assert parent < len(model.frames), link
    f = model.frames[parent]
    placement = f.placement * pin.SE3(rpy_matrix(rpy), np.array(xyz, dtype=float))
    model.addFrame(pin.Frame(name, f.parentJoint, parent, placement, pin.FrameType.OP_FRAME))


def draw_state(rng, base, n_joints):
    """Our (q, v, a): the base, then the joints."""
    if base == 'quaternion':
        x = rng.uniform(-1, 1, 3)
        while True:
            quat = rng.uniform(-1, 1, 4)
            if 0.01 < quat @ quat <= 1.0:
                break
        q = list(x) + list(quat / np.linalg.norm(quat))  # [w, x, y, z]
    elif base == 'euler':
        q = list(rng.uniform(-1, 1, 3)) + [rng.uniform(-math.pi, math.pi),
                                          rng.uniform(-1.2, 1.2),
                                          rng.uniform(-math.pi, math.pi)]
    else:
        q = []
    q = np.array(q + list(rng.uniform(-1.2, 1.2, n_joints)))
    nv = n_joints + (6 if base != 'fixed' else 0)
    return q, rng.uniform(-2, 2, nv), rng.uniform(-3, 3, nv)


def layout(model, base, order):
    """For our coordinates: Pinocchio's `idx_v` of each velocity, and a function taking our q to
    Pinocchio's."""
    nb = 6 if base != 'fixed' else 0
    perm_v = list(range(nb))
    q_at = []
    for name in order:
        jm = model.joints[model.getJointId(name)]
        assert jm.nq == 1 and jm.nv == 1, (name, jm.shortname())
        perm_v.append(jm.idx_v)
        q_at.append(jm.idx_q)
    assert sorted(perm_v) == list(range(model.nv)), 'every velocity once'
    nqb = 0 if base == 'fixed' else 7 if base == 'quaternion' else 6

    def q_to_pinocchio(q):
        qp = np.zeros(model.nq)
        if base == 'quaternion':
            w, x, y, z = q[3:7]
            qp[:7] = list(q[:3]) + [x, y, z, w]
        else:
            qp[:nqb] = q[:nqb]
        for k, iq in enumerate(q_at):
            qp[iq] = q[nqb + k]
        return qp
    return np.array(perm_v, dtype=int), q_to_pinocchio


def angular_first(x):
    """A 6-vector or 6-row matrix, linear first -> angular first."""
    x = np.asarray(x)
    return np.concatenate([x[3:6], x[0:3]])


def rel(x, y):
    return float(np.abs(x - y).max(initial=0.0) / max(1.0, np.abs(y).max(initial=0.0)))


def evaluate(model, data, fid, vp, ap, perm_v, exact=True):
    """One frame's values, in our layout, the algorithms having run (`frame_values`). `exact`:
    Pinocchio's dJ is the time derivative of J (not with a composite Euler base)."""
    cols = lambda j: angular_first(np.asarray(j)[:, perm_v])
    out = {
        'rotation': data.oMf[fid].rotation.tolist(),
        'translation': data.oMf[fid].translation.tolist(),
        'velocity': angular_first(
            pin.getFrameVelocity(model, data, fid, pin.ReferenceFrame.LOCAL).vector).tolist(),
        'acceleration': angular_first(pin.getFrameClassicalAcceleration(
            model, data, fid, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED).vector).tolist(),
        'jacobian': {k: cols(pin.getFrameJacobian(model, data, fid, rf)).tolist()
                     for k, rf in RF.items()},
        'jacobian_time_variation': {
            k: cols(pin.getFrameJacobianTimeVariation(model, data, fid, rf)).tolist()
            for k, rf in RF.items()},
    }
    # Pinocchio against itself, in our layout.
    v, a = vp[perm_v], ap[perm_v]
    j_l = np.array(out['jacobian']['local'])
    assert rel(j_l @ v, np.array(out['velocity'])) < TOL
    j_a = np.array(out['jacobian']['local_world_aligned'])
    jd_a = np.array(out['jacobian_time_variation']['local_world_aligned'])
    if exact:
        assert rel(j_a @ a + jd_a @ v, np.array(out['acceleration'])) < TOL, model.frames[fid].name
    return out


def frame_values(model, base, order, declared, links, states, exact=True):
    """Every frame's values at each of `states` (ours), in our layout."""
    for d in declared:
        declare(model, *d)
    data = model.createData()
    perm_v, q_to_pinocchio = layout(model, base, order)
    frames = links + [d[0] for d in declared]
    fids = {}
    for f in frames:
        kind = pin.FrameType.BODY if f in links else pin.FrameType.OP_FRAME
        fids[f] = model.getFrameId(f, kind)
        assert fids[f] < len(model.frames), f
    out = []
    for q, v, a in states:
        qp = q_to_pinocchio(q)
        vp, ap = np.zeros(model.nv), np.zeros(model.nv)
        vp[perm_v], ap[perm_v] = v, a
        pin.computeJointJacobians(model, data, qp)
        pin.computeJointJacobiansTimeVariation(model, data, qp, vp)
        pin.forwardKinematics(model, data, qp, vp, ap)
        pin.updateFramePlacements(model, data)
        out.append({f: evaluate(model, data, fids[f], vp, ap, perm_v, exact) for f in frames})
    return out


def worst_difference(a, b, skip=()):
    """The largest relative difference between two nests of values, leaving out the keys `skip`."""
    if isinstance(a, dict):
        return max(worst_difference(a[k], b[k], skip) for k in a if k not in skip)
    if isinstance(a, list) and a and isinstance(a[0], (dict, list)):
        return max(worst_difference(x, y, skip) for x, y in zip(a, b))
    return rel(np.array(a), np.array(b))


def model_values(rng, name, rel_path, base, declared):
    path = os.path.join(ROOT, rel_path)
    links, order = links_and_order(path)
    states = [draw_state(rng, base, len(order)) for _ in range(STATES)]
    values = frame_values(load(path, base), base, order, declared, links, states)
    out = {
        'urdf': rel_path, 'floating': base,
        'nq': len(states[0][0]), 'nv': len(states[0][1]),
        'joints': (['root_joint'] if base != 'fixed' else []) + order,
        'frames': links + [d[0] for d in declared],
        'declared': [{'name': n, 'link': l, 'xyz': list(xyz), 'rpy': list(rpy)}
                     for n, l, xyz, rpy in declared],
    }
    if base == 'euler':
        # Pinocchio's composite Euler base agrees but for the time variation of the Jacobians.
        composite = frame_values(load(path, 'euler_composite'), base, order, declared, links,
                                 states, exact=False)
        same = worst_difference(values, composite, skip=('jacobian_time_variation',))
        assert same < TOL, same
        out['composite_time_variation_error'] = worst_difference(
            [{f: x['jacobian_time_variation'] for f, x in s.items()} for s in values],
            [{f: x['jacobian_time_variation'] for f, x in s.items()} for s in composite])
        print(f'{name}: the composite base differs by {same:.1e} but for dJ, '
              f'off by {out["composite_time_variation_error"]:.2f}')
    out['states'] = [{'q': q.tolist(), 'v': v.tolist(), 'a': a.tolist(), 'frames': f}
                     for (q, v, a), f in zip(states, values)]
    return out


def compact(text):
    """Each innermost list of numbers on one line (a matrix row, a vector)."""
    return re.sub(r'\[\s+([-+0-9.eE,\s]+?)\s+\]',
                  lambda m: '[' + ', '.join(x.strip() for x in m.group(1).split(',')) + ']',
                  text)


def write_json(target, out):
    """`out` as compact JSON to `target`, whole or not at all (a temporary file, a rename)."""
    with open(target + '.tmp', 'w') as f:
        f.write(compact(json.dumps(out, indent=1)) + '\n')
    os.replace(target + '.tmp', target)
    print(f'wrote {target} ({os.path.getsize(target) / 1e3:.0f} kB)')


def main():
    rng = np.random.default_rng(SEED)
    out = {
        'generator': f'Pinocchio {pin.__version__} (pip package `pin`), '
                     'tests/data/pinocchio_frames/make_pinocchio_frames.py',
        'seed': SEED,
        'conventions': __doc__,
        'models': {name: model_values(rng, name, path, base, declared)
                   for name, path, base, declared in MODELS},
    }
    write_json(os.path.join(HERE, 'pinocchio-frames.json'), out)


if __name__ == '__main__':
    main()
