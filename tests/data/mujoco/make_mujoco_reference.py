"""MuJoCo reference values for the MJCF front end -> `tests/data/mujoco/mujoco-values.json`.

Runs on our machines, NOT in CI (CI has no MuJoCo): `pip install mujoco==4.0.0 numpy`, then
`python tests/data/mujoco/make_mujoco_reference.py` from anywhere. The JSON it writes is
committed and read by `tests/tests/mjcf.rs`. The states are seeded, so a rerun reproduces the
file (up to changes in MuJoCo itself).

Models: every `.xml` under `features/` (written for these tests: each orientation form, default
classes, frames, includes, joints at anchors with `ref`, every geom shape's inertia, the
compiler's mass rules), under `exported/` (the shipped models written by `articulated export
--mjcf`, each file's first line naming the command) and under `real/` (verbatim copies of the MJCF files that PyPI packages
ship inside their wheels: `real/README.md`). A model MuJoCo does not load is recorded with its
error and no values; a file included by another (a `<mujoco>` with no `<worldbody>`) is not a
model and is skipped.

Physics: MuJoCo's contacts, constraints (limits, equalities, friction loss), passive forces
(springs, dampers) and actuation are disabled, so that what is compared is the rigid-body
dynamics: `M` (`mj_fullM`, armature included), `qfrc_bias` (Coriolis, centrifugal and gravity:
our `nonlinear_effects`), `mj_inverse`'s `qfrc_inverse` at `qacc`, and `mj_forward`'s `qacc`
for an applied `qfrc_applied`. Every vector is in MuJoCo's coordinates: a free joint's `qvel`
is `[v (world); ω (body)]`, its `qpos` `[x, y, z, qw, qx, qy, qz]`; `free_dofs` lists the
`dofadr` of each free joint so that the test can convert.

States (three per model, seeded): hinge and slide `qpos0 + U(-1, 1)`, ball and free quaternions
uniform on the sphere, free positions `U(-1, 1)`, `qvel`, `qacc` `U(-2, 2)`, `qfrc_applied`
`U(-5, 5)`. `spring`: `qfrc_spring` with the joints' springs alone (tendons' stiffness set to 0). Sites: `site_xpos` and `site_xmat` (row-major) at each state's `qpos`, by name.
Bodies: for each body that moves and has no other body welded to it (the model keeps it whole),
by name (`body{id}` if it has none): `body_mass`, `xipos` (its centre of mass in the world) and
its inertia tensor about it in world axes, `ximat·diag(body_inertia)·ximatᵀ` (row-major):
MuJoCo's principal axes are its own choice, the tensor is not.
"""
import glob
import os

import mujoco
import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
rng = np.random.default_rng(20261128)
DISABLED = (mujoco.mjtDisableBit.mjDSBL_CONTACT | mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
            | mujoco.mjtDisableBit.mjDSBL_SPRING | mujoco.mjtDisableBit.mjDSBL_DAMPER
            | mujoco.mjtDisableBit.mjDSBL_ACTUATION | mujoco.mjtDisableBit.mjDSBL_FRICTIONLOSS
            | mujoco.mjtDisableBit.mjDSBL_LIMIT | mujoco.mjtDisableBit.mjDSBL_EQUALITY)


def unit_quaternion():
    q = rng.normal(size=4)
    return q / np.linalg.norm(q)


def draw_qpos(m):
    q = m.qpos0.copy()
    for j in range(m.njnt):
        a = m.jnt_qposadr[j]
        t = m.jnt_type[j]
        if t == mujoco.mjtJoint.mjJNT_FREE:
            q[a:a + 3] = rng.uniform(-1, 1, 3)
            q[a + 3:a + 7] = unit_quaternion()
        elif t == mujoco.mjtJoint.mjJNT_BALL:
            q[a:a + 4] = unit_quaternion()
        else:
            q[a] += rng.uniform(-1, 1)
    return q


def values(m):
    m.opt.disableflags |= DISABLED
    d = mujoco.MjData(m)
    # The bodies that move (mocap bodies do not) and have no body welded to them: the model
    # keeps each as one body.
    moving = [b for b in range(1, m.nbody) if m.body_weldid[b] == b and m.body_mocapid[b] < 0
              and not any(m.body_weldid[c] == b for c in range(1, m.nbody) if c != b)]
    states = []
    for _ in range(3):
        qpos = draw_qpos(m)
        qvel = rng.uniform(-2, 2, m.nv)
        qacc = rng.uniform(-2, 2, m.nv)
        tau = rng.uniform(-5, 5, m.nv)
        d.qpos[:], d.qvel[:], d.qfrc_applied[:], d.ctrl[:] = qpos, qvel, 0, 0
        mujoco.mj_forward(m, d)
        full = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, d, full)
        bias = d.qfrc_bias.copy()
        sites = {}
        for s in range(m.nsite):
            name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_SITE, s)
            if name:
                sites[name] = {'pos': d.site_xpos[s].tolist(), 'mat': d.site_xmat[s].tolist()}
        bodies = {}
        for b in moving:
            name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b) or f'body{b}'
            r = d.ximat[b].reshape(3, 3)
            bodies[name] = {'mass': float(m.body_mass[b]), 'com': d.xipos[b].tolist(),
                            'inertia': (r @ np.diag(m.body_inertia[b]) @ r.T).flatten().tolist()}
        # The joints' springs alone (the one passive force kept on; tendons' springs, which the
        # model does not represent, taken out).
        m.opt.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_SPRING)
        tendon_stiffness = m.tendon_stiffness.copy()
        m.tendon_stiffness[:] = 0
        mujoco.mj_forward(m, d)
        spring = d.qfrc_spring.copy()
        m.tendon_stiffness[:] = tendon_stiffness
        m.opt.disableflags |= DISABLED
        mujoco.mj_forward(m, d)
        d.qacc[:] = qacc
        mujoco.mj_inverse(m, d)
        tau_inverse = d.qfrc_inverse.copy()
        d.qfrc_applied[:] = tau
        mujoco.mj_forward(m, d)
        states.append({
            'qpos': qpos.tolist(), 'qvel': qvel.tolist(), 'qacc': qacc.tolist(),
            'mass_matrix': full.tolist(), 'bias': bias.tolist(),
            'tau_inverse': tau_inverse.tolist(),
            'tau': tau.tolist(), 'qacc_forward': d.qacc.tolist(),
            'sites': sites, 'bodies': bodies, 'spring': spring.tolist(),
        })
    free = [int(m.jnt_dofadr[j]) for j in range(m.njnt)
            if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE]
    return {'nq': m.nq, 'nv': m.nv, 'free_dofs': free, 'states': states}


def main():
    out = {'mujoco': mujoco.__version__, 'models': {}}
    files = sorted(glob.glob(os.path.join(here, 'features', '*.xml'))
                   + glob.glob(os.path.join(here, 'exported', '*.xml'))
                   + glob.glob(os.path.join(here, 'real', '**', '*.xml'), recursive=True))
    for path in files:
        rel = os.path.relpath(path, here)
        with open(path) as f:
            if '<worldbody' not in f.read():
                continue
        try:
            m = mujoco.MjModel.from_xml_path(path)
        except Exception as e:  # MuJoCo's own refusal, recorded
            out['models'][rel] = {'loads': False, 'error': str(e).strip()}
            print(f'{rel}: MuJoCo refuses it: {e}')
            continue
        out['models'][rel] = {'loads': True, **values(m)}
        print(f'{rel}: nq {m.nq}, nv {m.nv}')
    tmp = os.path.join(here, 'mujoco-values.json.tmp')
    import json
    with open(tmp, 'w') as f:
        json.dump(out, f, indent=1)
    os.replace(tmp, os.path.join(here, 'mujoco-values.json'))


if __name__ == '__main__':
    main()
