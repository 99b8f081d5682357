"""The dm_control suite's dog against MuJoCo, on our machines (its 20 MB of meshes are not
copied here): `M` and gravity (`qfrc_bias` at v = 0, free bases at the identity orientation) at
one seeded state, through `articulated eval`. Usage, from the repository root:

    pip download --no-deps dm_control==1.0.50 && unzip -q dm_control-*.whl 'dm_control/suite/*'
    cargo build --release -p articulated-cli
    python tests/data/mujoco/check_dog.py dm_control/suite target/release/articulated

Prints the dog's sizes, its mesh geoms and the two relative errors (largest entry's difference
over MuJoCo's largest entry)."""
import json
import os
import subprocess
import sys

import mujoco
import numpy as np

suite, binary = sys.argv[1], os.path.abspath(sys.argv[2])
os.chdir(suite)
m = mujoco.MjModel.from_xml_path('dog.xml')
for bit in ('CONTACT', 'CONSTRAINT', 'SPRING', 'DAMPER', 'ACTUATION'):
    m.opt.disableflags |= int(getattr(mujoco.mjtDisableBit, 'mjDSBL_' + bit))
d = mujoco.MjData(m)
rng = np.random.default_rng(1)
q = m.qpos0.copy()
for j in range(m.njnt):
    a = m.jnt_qposadr[j]
    if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE:
        q[a:a + 7] = [0.1, 0.2, 0.5, 1, 0, 0, 0]
    elif m.jnt_type[j] == mujoco.mjtJoint.mjJNT_BALL:
        v = rng.normal(size=4)
        q[a:a + 4] = v / np.linalg.norm(v)
    else:
        q[a] += rng.uniform(-0.5, 0.5)
d.qpos[:] = q
mujoco.mj_forward(m, d)
full = np.zeros((m.nv, m.nv))
mujoco.mj_fullM(m, d, full)
out = subprocess.run([binary, 'eval', 'dog.xml', '--q', ','.join(repr(float(x)) for x in q)],
                     capture_output=True, text=True, check=True)
ours = json.loads(out.stdout)
err_m = np.abs(np.array(ours['mass_matrix']) - full).max() / np.abs(full).max()
err_g = np.abs(np.array(ours['gravity']) - d.qfrc_bias).max() / np.abs(d.qfrc_bias).max()
print(f'dog: nv {m.nv}, {int(sum(m.geom_type == mujoco.mjtGeom.mjGEOM_MESH))} mesh geoms; '
      f'M off by {err_m:.1e}, gravity by {err_g:.1e}')
