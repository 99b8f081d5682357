"""MuJoCo's side of the contact comparison: the same three scenes our time stepper (exact
Coulomb cones) runs, simulated with MuJoCo's soft, convex contact model.

Scenes (z up, every option as in `settings()`; MuJoCo's default contact softness kept):
  sliding_box        a 1 kg cube of side 0.2 m with a contact sphere (radius 1 mm) at each corner,
                     starting on the floor at 2 m/s along +x, mu = 0.5, 0.5 s: the deceleration
                     (linear fit of vx(t) over [0.05, 0.3] s) against mu*g, the stopping distance
                     against v0^2 / (2 mu g), the deepest penetration, the final height error;
  resting_box        the same cube at rest, 0.5 s: the sum of the normal forces / (m g), the height
                     error;
  humanoid_standing  models/humanoid.urdf on a free base, four contact spheres under each foot,
                     mu = 0.8, every hinge held by a passive spring (2000 N m/rad about 0) and
                     damper (50 N m s/rad), 2 s: steps per second of mj_step (one thread, best of
                     5 runs of 2000 steps after 100 warm-up steps), Newton iterations per step,
                     the pelvis height drift, the sum of the normal forces / (m g) at the end.

Usage (from the repository root, with the venv `bench/peers/run.sh` builds):
    target/peers/venv/bin/python bench/peers/contact_mujoco.py [--out PATH]
It prints one JSON object to stdout; with --out it also writes it to PATH (atomically).
"""

import argparse
import json
import os
import platform
import tempfile
import time

import mujoco
import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
HUMANOID_URDF = os.path.join(ROOT, "models", "humanoid.urdf")


def settings():
    """The MuJoCo options every scene uses (also written into the JSON)."""
    return {
        "timestep": 0.001,
        "gravity": [0.0, 0.0, -9.81],
        "cone": "elliptic",
        "solver": "Newton",
        "tolerance": 1e-10,
        "iterations": 100,
        "integrator": "Euler (MuJoCo's default: semi-implicit, joint damping implicit)",
        "impratio": 1.0,
        "noslip_iterations": 0,
        "contact_solref": [0.02, 1.0],
        "contact_solimp": [0.9, 0.95, 0.001, 0.5, 2.0],
        "contact_margin": 0.0,
        "condim": 3,
        "friction_rule": "MuJoCo takes the element-wise max of the two geoms' friction "
        "(equal priorities); spheres and floor both carry the same mu, so max = mu",
        "friction_vectors": {"box": [0.5, 0.005, 0.0001], "humanoid": [0.8, 0.005, 0.0001]},
        "collisions": "contact spheres (contype=conaffinity=1) against the floor plane "
        "(contype=conaffinity=1) only; every other geom contype=conaffinity=0",
        "actuators": 0,
        "sensors": 0,
        "threads": 1,
    }


def option_xml(s):
    g = " ".join(repr(v) for v in s["gravity"])
    return (
        f'<option timestep="{s["timestep"]}" gravity="{g}" cone="{s["cone"]}" '
        f'solver="{s["solver"]}" tolerance="{s["tolerance"]}" iterations="{s["iterations"]}" '
        f'impratio="{s["impratio"]}" noslip_iterations="{s["noslip_iterations"]}"/>'
    )


def apply_options(spec, s):
    """The same options as `option_xml`, on an MjSpec (the humanoid comes from a URDF)."""
    spec.option.timestep = s["timestep"]
    spec.option.gravity = s["gravity"]
    spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    spec.option.solver = mujoco.mjtSolver.mjSOL_NEWTON
    spec.option.tolerance = s["tolerance"]
    spec.option.iterations = s["iterations"]
    spec.option.impratio = s["impratio"]
    spec.option.noslip_iterations = s["noslip_iterations"]


def check_model(m, s):
    """Fail loudly if the compiled model differs from the stated settings."""
    assert m.opt.timestep == s["timestep"]
    assert list(m.opt.gravity) == s["gravity"]
    assert m.opt.cone == mujoco.mjtCone.mjCONE_ELLIPTIC
    assert m.opt.solver == mujoco.mjtSolver.mjSOL_NEWTON
    assert m.opt.integrator == mujoco.mjtIntegrator.mjINT_EULER
    assert m.opt.tolerance == s["tolerance"] and m.opt.iterations == s["iterations"]
    assert m.nu == 0 and m.nsensor == 0
    for g in range(m.ngeom):
        colliding = m.geom_contype[g] != 0 or m.geom_conaffinity[g] != 0
        if colliding:
            assert m.geom_contype[g] == 1 and m.geom_conaffinity[g] == 1
            assert m.geom_condim[g] == s["condim"]
            assert list(m.geom_solref[g]) == s["contact_solref"]
            assert np.allclose(m.geom_solimp[g], s["contact_solimp"])
            assert m.geom_margin[g] == s["contact_margin"]
            assert int(m.geom_type[g]) in (int(mujoco.mjtGeom.mjGEOM_PLANE), int(mujoco.mjtGeom.mjGEOM_SPHERE))


def box_xml(s):
    """The cube: explicit inertial, contact spheres at the corners, floor plane at z = 0."""
    mu = " ".join(repr(v) for v in s["friction_vectors"]["box"])
    side, m, r = 0.2, 1.0, 0.001
    inertia = m * side**2 / 6.0
    c = side / 2 - r  # sphere centres 0.099: the contact points are the corners at +-0.1
    spheres = "\n".join(
        f'      <geom type="sphere" size="{r}" pos="{x * c} {y * c} {z * c}" mass="0" '
        f'contype="1" conaffinity="1" condim="3" friction="{mu}"/>'
        for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)
    )
    return f"""
<mujoco model="box">
  {option_xml(s)}
  <compiler inertiafromgeom="false" boundmass="0" boundinertia="0" balanceinertia="false"/>
  <worldbody>
    <geom name="floor" type="plane" size="0 0 1" contype="1" conaffinity="1" condim="3"
          friction="{mu}"/>
    <body name="box" pos="0 0 {side / 2}">
      <freejoint name="base"/>
      <inertial pos="0 0 0" mass="{m}" diaginertia="{inertia} {inertia} {inertia}"/>
      <geom type="box" size="{side / 2} {side / 2} {side / 2}" mass="0" contype="0"
            conaffinity="0"/>
{spheres}
    </body>
  </worldbody>
</mujoco>"""


def box_model(s, vx0):
    m = mujoco.MjModel.from_xml_string(box_xml(s))
    check_model(m, s)
    assert m.nbody == 2 and abs(m.body_mass[1] - 1.0) < 1e-15
    d = mujoco.MjData(m)
    d.qvel[0] = vx0
    return m, d


def normal_force_sum(m, d):
    """The sum over the active contacts of the normal force (contact frame, component 0)."""
    f = np.zeros(6)
    total = 0.0
    for i in range(d.ncon):
        mujoco.mj_contactForce(m, d, i, f)
        total += f[0]
    return total


def min_dist(d):
    return float(np.min(d.contact.dist[: d.ncon])) if d.ncon else np.inf


def sliding_box(s):
    v0, mu, g, seconds = 2.0, s["friction_vectors"]["box"][0], -s["gravity"][2], 0.5
    m, d = box_model(s, v0)
    x0, z0 = d.qpos[0], 0.1
    ts, xs, vxs, zs, ncons, normals, deepest = [], [], [], [], [], [], np.inf
    for _ in range(round(seconds / m.opt.timestep)):
        mujoco.mj_step(m, d)  # d.contact: the contacts this step used (at its start)
        deepest = min(deepest, min_dist(d))
        ts.append(d.time)
        xs.append(d.qpos[0])
        vxs.append(d.qvel[0])
        zs.append(d.qpos[2])
        ncons.append(d.ncon)
        normals.append(normal_force_sum(m, d))
    ts, xs, vxs, zs = np.array(ts), np.array(xs), np.array(vxs), np.array(zs)
    ncons, normals = np.array(ncons), np.array(normals)
    fit = (ts >= 0.05) & (ts <= 0.3)
    slope = np.polyfit(ts[fit], vxs[fit], 1)[0]
    stopped = np.nonzero(np.abs(vxs) < 1e-3)[0]
    stop = int(stopped[0]) if stopped.size else None
    sliding = slice(0, stop)
    weight = m.body_mass[1] * g
    return {
        "mu": mu,
        "v0": v0,
        "seconds": seconds,
        "deceleration": -slope,
        "deceleration_closed_form": mu * g,
        "deceleration_rel_error": (-slope - mu * g) / (mu * g),
        "stop_time": None if stop is None else ts[stop],
        "stop_time_closed_form": v0 / (mu * g),
        "stop_distance": None if stop is None else xs[stop] - x0,
        "stop_distance_closed_form": v0**2 / (2 * mu * g),
        "stop_distance_rel_error": None
        if stop is None
        else (xs[stop] - x0 - v0**2 / (2 * mu * g)) / (v0**2 / (2 * mu * g)),
        "final_vx": vxs[-1],
        "creep_after_stop": None if stop is None else xs[-1] - xs[stop],
        "max_penetration": -deepest,
        "final_height_error": d.qpos[2] - z0,
        # MuJoCo's convex contact model lets a sliding contact push apart (cf. Anitescu's
        # relaxation, where a sliding contact separates at mu |v_t|): the box hops.
        "steps_without_contact_while_sliding": int(np.sum(ncons[sliding] == 0)),
        "steps_while_sliding": len(ncons[sliding]),
        "max_lift_while_sliding": float(np.max(zs[sliding]) - z0),
        "max_normal_sum_over_mg": float(np.max(normals) / weight),
    }


def resting_box(s):
    seconds = 0.5
    m, d = box_model(s, 0.0)
    deepest = np.inf
    for _ in range(round(seconds / m.opt.timestep)):
        mujoco.mj_step(m, d)
        deepest = min(deepest, min_dist(d))
    weight = m.body_mass[1] * -m.opt.gravity[2]
    return {
        "seconds": seconds,
        "contacts_at_end": int(d.ncon),
        "normal_sum_over_mg": normal_force_sum(m, d) / weight,
        "height_error": d.qpos[2] - 0.1,
        "max_penetration": -deepest,
        "penetration_at_end": -min_dist(d),
        "final_speed": float(np.linalg.norm(d.qvel)),
    }


def humanoid_model(s):
    """models/humanoid.urdf through MuJoCo's own URDF import, edited as an MjSpec.

    The import works as is in MuJoCo 4.0 (the URDF has no geoms, no meshes); it gives the root
    link `pelvis` welded to the world, so a free joint is added to it. The URDF's joint limits
    (+-10 rad) come in as `limited="auto"` with a range: set to not limited. Fixed joints stay
    bodies (fusestatic off) so the tree matches ours; inertias are the URDF's, untouched.
    """
    spec = mujoco.MjSpec.from_file(HUMANOID_URDF)
    spec.compiler.fusestatic = False
    spec.compiler.discardvisual = True
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
    spec.compiler.balanceinertia = False
    spec.compiler.boundmass = 0.0
    spec.compiler.boundinertia = 0.0
    apply_options(spec, s)
    pelvis = spec.body("pelvis")
    assert pelvis.parent.name == "world"
    pelvis.add_freejoint(name="base")
    for j in spec.joints:
        if j.type == mujoco.mjtJoint.mjJNT_HINGE:
            j.limited = mujoco.mjtLimited.mjLIMITED_FALSE
            j.stiffness = [2000.0, 0.0, 0.0]  # MuJoCo 4.0: [linear, higher-order terms]
            j.springref = 0.0
            j.damping = [50.0, 0.0, 0.0]
            j.armature = 0.0
            j.frictionloss = 0.0
    mu = s["friction_vectors"]["humanoid"]
    spec.worldbody.add_geom(
        name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 1],
        contype=1, conaffinity=1, condim=3, friction=mu,
    )
    for foot in ("left_foot", "right_foot"):
        body = spec.body(foot)
        for x in (-0.06, 0.16):
            for y in (-0.05, 0.05):
                body.add_geom(
                    type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[0.01, 0, 0], pos=[x, y, -0.08],
                    mass=0.0, contype=1, conaffinity=1, condim=3, friction=mu,
                )
    m = spec.compile()
    check_model(m, s)
    hinges = m.jnt_type == mujoco.mjtJoint.mjJNT_HINGE
    assert m.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE and m.jnt_bodyid[0] == 1
    assert np.all(m.jnt_stiffness[hinges] == 2000.0) and np.all(m.jnt_limited == 0)
    assert np.all(m.dof_damping[6:] == 50.0) and np.all(m.dof_damping[:6] == 0.0)
    assert np.all(m.dof_armature == 0.0) and np.all(m.dof_frictionloss == 0.0)
    assert np.all(m.qpos_spring[7:] == 0.0)
    return m


def humanoid_reset(m, d, z0):
    mujoco.mj_resetData(m, d)
    d.qpos[:3] = [0.0, 0.0, z0]
    d.qpos[3:7] = [1.0, 0.0, 0.0, 0.0]
    mujoco.mj_forward(m, d)


def humanoid_standing(s, runs=5, warmup=100, nstep=2000):
    z0 = 1.11
    m = humanoid_model(s)
    d = mujoco.MjData(m)
    humanoid_reset(m, d, z0)
    # Check the URDF's geometry: at q = 0 each foot frame sits 1.02 m below the pelvis frame,
    # so the lowest points of the spheres (0.09 m below it) touch z = 0.
    feet = [m.body(f).id for f in ("left_foot", "right_foot")]
    drops = [d.xpos[1][2] - d.xpos[f][2] for f in feet]
    assert np.allclose(drops, 1.02, atol=1e-12), drops
    assert np.allclose(d.xmat[feet], np.eye(3).ravel())
    spheres = np.nonzero(m.geom_type == mujoco.mjtGeom.mjGEOM_SPHERE)[0]
    lowest = d.geom_xpos[spheres][:, 2] - m.geom_size[spheres][:, 0]
    assert np.allclose(lowest, 0.0, atol=1e-12), lowest

    # Untimed: single steps, to collect the solver's iterations, contacts and the drift.
    iters, heights, deepest = [], [], np.inf
    for _ in range(nstep):
        mujoco.mj_step(m, d)
        iters.append(int(d.solver_niter[0]))
        heights.append(d.qpos[2])
        deepest = min(deepest, min_dist(d))
    weight = m.body_subtreemass[1] * -m.opt.gravity[2]
    untimed = {
        "pelvis_height_drift": d.qpos[2] - z0,
        "pelvis_height_change_last_second": heights[-1] - heights[nstep // 2 - 1],
        "pelvis_horizontal_drift": float(np.hypot(d.qpos[0], d.qpos[1])),
        "max_joint_deflection": float(np.max(np.abs(d.qpos[7:]))),
        "normal_sum_over_mg": normal_force_sum(m, d) / weight,
        "contacts_at_end": int(d.ncon),
        "max_penetration": -deepest,
        "penetration_at_end": -min_dist(d),
        "islands_at_end": int(d.nisland),
        "solver_iterations_mean": float(np.mean(iters)),
        "solver_iterations_max": int(np.max(iters)),
        "final_speed": float(np.linalg.norm(d.qvel)),
    }

    # Timed: best of `runs`, each from the reset state, warm-up, then one mj_step call.
    best = np.inf
    for _ in range(runs):
        humanoid_reset(m, d, z0)
        mujoco.mj_step(m, d, nstep=warmup)
        start = time.perf_counter()
        mujoco.mj_step(m, d, nstep=nstep)
        best = min(best, time.perf_counter() - start)
    return {
        "seconds": nstep * m.opt.timestep,
        "nq": int(m.nq),
        "nv": int(m.nv),
        "nbody": int(m.nbody),
        "total_mass": float(m.body_subtreemass[1]),
        "mu": s["friction_vectors"]["humanoid"][0],
        "joint_stiffness": 2000.0,
        "joint_damping": 50.0,
        "pelvis_z0": z0,
        "timing": {
            "warmup_steps": warmup,
            "steps": nstep,
            "runs": runs,
            "best_seconds": best,
            "steps_per_second": nstep / best,
            "microseconds_per_step": 1e6 * best / nstep,
        },
        **untimed,
    }


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def write_atomically(path, text):
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".contact_mujoco.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise


def to_json(value):
    """numpy scalars to plain Python numbers, recursively."""
    if isinstance(value, dict):
        return {k: to_json(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_json(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", help="also write the JSON to this path")
    args = parser.parse_args()
    s = settings()
    result = {
        "engine": "mujoco",
        "mujoco_version": mujoco.__version__,
        "threads": 1,
        "cpu": cpu_model(),
        "settings": s,
        "scenes": {
            "sliding_box": sliding_box(s),
            "resting_box": resting_box(s),
            "humanoid_standing": humanoid_standing(s),
        },
    }
    text = json.dumps(to_json(result), indent=2, allow_nan=False) + "\n"
    print(text, end="")
    if args.out:
        write_atomically(args.out, text)


if __name__ == "__main__":
    main()
