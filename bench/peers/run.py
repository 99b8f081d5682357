"""The driver of the comparison against Pinocchio and MuJoCo; `bench/peers/run.sh` runs it.

For every model of MODELS it
  1. builds Pinocchio's model (Python `pin`, the same library as the C++ program) and MuJoCo's
     (URDF -> MjSpec, a free joint for floating models, contacts/constraints/passive forces
     off, saved as a binary .mjb so no digit is lost);
  2. draws the random states once, in Pinocchio's convention, and writes one states file per
     program in that program's own convention and joint order;
  3. checks the values: every program's outputs at the first state, mapped back to Pinocchio's
     convention, against Pinocchio's; ours to a relative 1e-9 (else it stops; the quantities
     of the whole system to 1e-10; the derivatives, where ours has them, to 1e-9; the frame
     outputs, where ours has them, to 1e-10; the constrained forward dynamics, where ours has
     contacts, to 1e-9), MuJoCo to a looser bound (its worst difference is reported either
     way);
  4. times: ROUNDS rounds, each running every program once per model in a rotating order;
     each run reports per output the fastest and the median of its ~1 ms batches; the driver
     keeps the fastest over rounds (and the median of the medians);
  5. counts instructions with callgrind: (Ir(K) - Ir(0)) / K with K = CALLS;
and writes BENCHMARKS.md (to a temporary file, then renamed).

Usage: python bench/peers/run.py [--rounds R] [--batches N] [--quick]   (from the repo root,
after run.sh has built the programs; run.sh passes its arguments through).

It also runs bench/python/timing.py (the speed from Python: `articulated` against `pin`, in the
Python running this script, which needs `articulated` installed: run.sh installs ./python into
its venv) for the section "From Python". `--python-only` reruns only that: it measures, then
rewrites that one section of BENCHMARKS.md in place (the rest of the file unchanged), in any
Python with `articulated`, `pin` and `mujoco`, e.g. `python bench/peers/run.py --python-only`.
"""

import argparse
import datetime
import importlib.util
import json
import os
import platform
import re
import subprocess
import sys
import tempfile
import zlib

import mujoco
import numpy as np
import pinocchio as pin

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
OUT = os.path.join(ROOT, "target", "peers")

# (name, chain file, URDF file, floating base). The name is the model's in `peers.rs`.
MODELS = [
    ("arm7", "models/arm7.chain", "models/arm7.urdf", False),
    ("arm7_floating", "bench/peers/arm7_floating.chain", "models/arm7.urdf", True),
    ("humanoid", "models/humanoid.chain", "models/humanoid.urdf", True),
    ("chain50", "models/chain50.chain", "models/chain50.urdf", False),
]

# The rows of each model's table: our output name, Pinocchio's program outputs (the first is
# the default call; the fastest of them is the figure), MuJoCo's program output.
ROWS = [
    ("mass_matrix", ["mass_matrix", "mass_matrix_world"], "mass_matrix"),
    ("nonlinear_effects", ["nonlinear_effects"], "nonlinear_effects"),
    ("gravity", ["gravity"], "gravity"),
    ("inverse_dynamics", ["inverse_dynamics"], "inverse_dynamics"),
    ("forward_dynamics", ["forward_dynamics", "forward_dynamics_world"], "forward_dynamics"),
    (
        "mass_matrix_and_nonlinear_effects",
        ["mass_matrix_and_nonlinear_effects"],
        "mass_matrix_and_nonlinear_effects",
    ),
]

# Our `M` into memory the caller keeps, each against Pinocchio's `crba` (which writes `data.M`,
# its upper triangle only), reported under each model's table: the output, what it writes.
KEPT_ROWS = [
    (
        "mass_matrix_update",
        "`M` into a `KeptMassMatrix`, which keeps its zeros between calls, as Pinocchio's `crba` "
        "writes into `data.M`",
    ),
    (
        "mass_matrix_lower",
        "the lower triangle of `M` into a `KeptMassMatrixLower`, diagonal included: one triangle, as "
        "Pinocchio's `crba` fills one (the upper)",
    ),
]

# The quantities of the whole system (their own table): our output name, Pinocchio's program
# outputs (the first is the default call; the fastest of them is the figure). MuJoCo's program
# times none of them (see WHOLE_MUJOCO).
WHOLE_ROWS = [
    ("center_of_mass", ["center_of_mass"]),
    ("center_of_mass_velocity", ["center_of_mass_velocity"]),
    ("center_of_mass_jacobian", ["center_of_mass_jacobian"]),
    ("centroidal_momentum", ["centroidal_momentum"]),
    ("centroidal_momentum_matrix", ["centroidal_momentum_matrix", "centroidal_map"]),
    ("kinetic_energy", ["kinetic_energy"]),
    ("potential_energy", ["potential_energy"]),
    ("coriolis_matrix", ["coriolis_matrix"]),
]
WHOLE_TOL = 1e-10

# The analytical derivatives (their own table), for the models generated with them (`peers
# --layout` says which): our output name, Pinocchio's program output, our central differences
# of the value they differentiate (the kernel `peers` times), the value itself. MuJoCo has none.
DERIV_ROWS = [
    ("inverse_dynamics_derivatives", "inverse_dynamics_derivatives", "inverse_dynamics_differences", "inverse_dynamics"),
    ("forward_dynamics_derivatives", "forward_dynamics_derivatives", "forward_dynamics_differences", "forward_dynamics"),
    ("mass_matrix_inverse", "mass_matrix_inverse", None, None),
]
DERIV_TOL = 1e-9

# The frame outputs (their own table), for the models generated with frames (`peers --layout`
# lists them; Pinocchio's program is given the same with --frames): our output name, Pinocchio's
# program outputs (the first is the call the comparison names; the fastest of them is the
# figure). Every call computes all the model's frames. MuJoCo's program times none of them.
FRAME_ROWS = [
    ("frame_placements", ["frame_placements"]),
    (
        "frame_jacobians_local_world_aligned",
        ["frame_jacobians_local_world_aligned", "frame_jacobians_local_world_aligned_joint_jacobians"],
    ),
    (
        "frame_jacobian_time_variations_local_world_aligned",
        ["frame_jacobian_time_variations_local_world_aligned"],
    ),
]
FRAME_TOL = 1e-10

# Constrained forward dynamics (its own section), for the models given contacts (`peers
# --layout` lists them, each a six-dimensional contact; Pinocchio's program is given the same
# with --contacts): the output both programs time (ours: the function generated for the declared
# contacts), and ours alone, the runtime's solve of the same contacts from five generated
# functions (what a contact set chosen at run time costs). Every call holds all the model's
# contacts. MuJoCo's program times neither.
CONSTRAINED = "constrained_forward_dynamics"
CONSTRAINED_RUNTIME = "constrained_forward_dynamics_runtime"
CONSTRAINED_DERIVATIVES = "constrained_forward_dynamics_derivatives"
CONSTRAINED_DERIVATIVES_RUNTIME = "constrained_forward_dynamics_derivatives_runtime"
# q̈ relative to its largest entry, the wrenches relative to their largest entry.
CONSTRAINED_TOL = 1e-9
# Central differences (step 1e-6) against the analytical values: a sanity check of the kernel.
DIFFERENCES_TOL = 1e-4

SEED = 0x5EED_2024
STATES = 16
GRAVITY = np.array([0.0, 0.0, -9.81])
OURS_TOL = 1e-9
MUJOCO_TOL = 1e-6
CALLS = 1024


def log(msg):
    print(f"[run.py] {msg}", flush=True)


def ours_binary(build):
    return os.path.join(OUT, f"rust-{build}", "release", "peers")


def programs(model, frames, contacts):
    """The timing programs of one model: key -> command (without the mode arguments). `frames`:
    the links whose frame outputs ours has; `contacts`: the links of ours' constrained forward
    dynamics (Pinocchio's program times the same)."""
    name, _chain, urdf, floating = model
    pin_args = ["--urdf", os.path.join(ROOT, urdf)] + (["--floating"] if floating else [])
    if frames:
        pin_args += ["--frames", ",".join(frames)]
    if contacts:
        pin_args += ["--contacts", ",".join(contacts)]

    def states(conv):
        return ["--states", os.path.join(OUT, "states", f"{name}.{conv}.txt")]

    return {
        "ours_v3": [ours_binary("v3")] + states("ours"),
        "ours_default": [ours_binary("default")] + states("ours"),
        "pin_v3": [os.path.join(OUT, "bin", "pinocchio_v3")] + pin_args + states("pin"),
        "pin_wheel": [os.path.join(OUT, "bin", "pinocchio_wheel")] + pin_args + states("pin"),
        "ours_native": [ours_binary("native")] + states("ours"),
        "pin_native": [os.path.join(OUT, "bin", "pinocchio_native")] + pin_args + states("pin"),
        "mujoco": [os.path.join(OUT, "bin", "mujoco_timing"), "--mjb", mjb_path(name)]
        + states("mujoco"),
    }


def run_json(cmd):
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"[run.py] failed: {' '.join(cmd)}\n{out.stderr}")
    return json.loads(out.stdout)


def mjb_path(name):
    return os.path.join(OUT, "models", f"{name}.mjb")


# ---------------------------------------------------------------------------------------------
# Models and coordinate maps


def pinocchio_model(urdf, floating):
    path = os.path.join(ROOT, urdf)
    model = (
        pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer())
        if floating
        else pin.buildModelFromUrdf(path)
    )
    model.gravity.linear = GRAVITY
    return model


def pinocchio_joints(model):
    """Pinocchio's joints with coordinates: the common convention and order."""
    joints = []
    for j in range(1, model.njoints):
        jm = model.joints[j]
        short = jm.shortname()
        if short == "JointModelFreeFlyer":
            kind = "free"
        elif short.startswith("JointModelR") and jm.nq == 1:
            kind = "revolute"
        elif short.startswith("JointModelP") and jm.nq == 1:
            kind = "prismatic"
        else:
            sys.exit(f"[run.py] joint {model.names[j]}: {short} is not handled by the maps")
        joints.append(
            dict(name=model.names[j], kind=kind, iq=jm.idx_q, nq=jm.nq, iv=jm.idx_v, nv=jm.nv)
        )
    return joints


def mujoco_model(name, urdf, floating):
    """MuJoCo's model of the URDF, saved as .mjb; returns the compiled mjModel."""
    spec = mujoco.MjSpec.from_file(os.path.join(ROOT, urdf))
    # Keep the URDF's inertias as they are: never from geoms, no balancing, no bounds.
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
    spec.compiler.balanceinertia = False
    spec.compiler.boundmass = 0.0
    spec.compiler.boundinertia = 0.0
    if floating:
        roots = [b for b in spec.bodies if b.parent is not None and b.parent.name == "world"]
        if len(roots) != 1:
            sys.exit(f"[run.py] {urdf}: expected one root link, found {[b.name for b in roots]}")
        roots[0].add_freejoint(name="root_joint")
    flags = mujoco.mjtDisableBit
    spec.option.disableflags |= int(
        flags.mjDSBL_CONSTRAINT
        | flags.mjDSBL_CONTACT
        | flags.mjDSBL_LIMIT
        | flags.mjDSBL_EQUALITY
        | flags.mjDSBL_FRICTIONLOSS
        | flags.mjDSBL_SPRING
        | flags.mjDSBL_DAMPER
        | flags.mjDSBL_ACTUATION
        | flags.mjDSBL_SENSOR
    )
    spec.option.gravity = GRAVITY
    m = spec.compile()
    for field in ("dof_armature", "dof_damping", "dof_frictionloss", "jnt_stiffness"):
        if np.any(getattr(m, field) != 0):
            sys.exit(f"[run.py] {urdf}: MuJoCo's {field} is not zero")
    if floating:
        root = m.jnt_bodyid[0]
        if np.any(m.body_pos[root] != 0) or np.any(m.body_quat[root] != [1, 0, 0, 0]):
            sys.exit(f"[run.py] {urdf}: the root body's frame is not the world's at q = 0")
    os.makedirs(os.path.dirname(mjb_path(name)), exist_ok=True)
    mujoco.mj_saveModel(m, mjb_path(name), None)
    with open(os.path.join(OUT, "models", f"{name}.xml"), "w") as f:
        f.write(spec.to_xml())  # for reading only: the XML rounds to 6 digits, the .mjb does not
    return m


def mujoco_joints(m):
    kinds = {int(mujoco.mjtJoint.mjJNT_FREE): ("free", 7, 6), int(mujoco.mjtJoint.mjJNT_HINGE): ("revolute", 1, 1), int(mujoco.mjtJoint.mjJNT_SLIDE): ("prismatic", 1, 1)}
    joints = []
    for j in range(m.njnt):
        if int(m.jnt_type[j]) not in kinds:
            sys.exit(f"[run.py] MuJoCo joint {m.joint(j).name}: type {m.jnt_type[j]} not handled")
        kind, nq, nv = kinds[int(m.jnt_type[j])]
        joints.append(
            dict(name=m.joint(j).name, kind=kind, iq=int(m.jnt_qposadr[j]), nq=nq,
                 iv=int(m.jnt_dofadr[j]), nv=nv)
        )
    return joints


def quat_matrix(xyzw):
    x, y, z, w = xyzw
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


class Map:
    """From the common (Pinocchio) coordinates to one program's, joint by joint.

    `world_linear`: a free joint's linear velocity is in the world frame (MuJoCo), not in the
    body frame (Pinocchio, ours). Then, with R the base orientation, the program's velocity is
    v' = A v (A permutes and applies R to the linear part), its acceleration a' = A a + c with
    c = R (omega x v_lin) on the linear part, its forces f' = A f (A is orthogonal), and back:
    M = A' M' A, tau = A' tau', nle = A' (nle' + M' c), a = A' (a' - c).
    """

    def __init__(self, common, theirs, nq, nv, world_linear):
        self.nq, self.nv, self.world_linear = nq, nv, world_linear
        by_name = {j["name"]: j for j in common if j["kind"] != "free"}
        free = [j for j in common if j["kind"] == "free"]
        self.pairs = []
        for t in theirs:
            c = free[0] if t["kind"] == "free" and len(free) == 1 else by_name.get(t["name"])
            if c is None or c["kind"] != t["kind"]:
                sys.exit(f"[run.py] joint {t['name']} ({t['kind']}) has no match in Pinocchio's model")
            self.pairs.append((c, t))
        if len(self.pairs) != len(common) or sum(t["nv"] for t in theirs) != nv:
            sys.exit("[run.py] the programs' joints do not match Pinocchio's one to one")

    def a_matrix(self, q):
        A = np.zeros((self.nv, self.nv))
        for c, t in self.pairs:
            for k in range(c["nv"]):
                A[t["iv"] + k, c["iv"] + k] = 1.0
            if t["kind"] == "free" and self.world_linear:
                R = quat_matrix(q[c["iq"] + 3 : c["iq"] + 7])
                A[t["iv"] : t["iv"] + 3, c["iv"] : c["iv"] + 3] = R
        return A

    def c_vector(self, q, v):
        out = np.zeros(self.nv)
        for c, t in self.pairs:
            if t["kind"] == "free" and self.world_linear:
                R = quat_matrix(q[c["iq"] + 3 : c["iq"] + 7])
                lin, ang = v[c["iv"] : c["iv"] + 3], v[c["iv"] + 3 : c["iv"] + 6]
                out[t["iv"] : t["iv"] + 3] = R @ np.cross(ang, lin)
        return out

    def q(self, q):
        out = np.zeros(self.nq)
        for c, t in self.pairs:
            x = q[c["iq"] : c["iq"] + c["nq"]]
            if t["kind"] == "free":  # [p, x, y, z, w] -> [p, w, x, y, z]
                x = np.concatenate([x[:3], x[6:7], x[3:6]])
            out[t["iq"] : t["iq"] + t["nq"]] = x
        return out

    def state(self, s):
        """A common state (q, v, a, tau) in the program's coordinates."""
        A = self.a_matrix(s["q"])
        c = self.c_vector(s["q"], s["v"])
        return dict(q=self.q(s["q"]), v=A @ s["v"], a=A @ s["a"] + c, tau=A @ s["tau"])

    def back(self, values, s, mass_keys=(), accel_keys=(), nle_keys=(), force_keys=()):
        """The program's outputs at state s, in the common coordinates."""
        A = self.a_matrix(s["q"])
        c = self.c_vector(s["q"], s["v"])
        out = {}
        M = None
        for k in mass_keys:
            M = np.array(values[k])
            out[k] = A.T @ M @ A
        for k in force_keys:
            out[k] = A.T @ np.array(values[k])
        for k in nle_keys:
            Mfull = np.triu(M) + np.triu(M, 1).T
            out[k] = A.T @ (np.array(values[k]) + Mfull @ c)
        for k in accel_keys:
            out[k] = A.T @ (np.array(values[k]) - c)
        return out


def draw_states(model, name):
    """STATES random states in Pinocchio's convention; tau = Pinocchio's rnea(q, v, a)."""
    rng = np.random.default_rng(SEED ^ zlib.crc32(name.encode()))
    data = model.createData()
    states = []
    for _ in range(STATES):
        q = rng.uniform(-1.0, 1.0, model.nq)
        for j in range(1, model.njoints):
            if model.joints[j].shortname() == "JointModelFreeFlyer":
                quat = rng.normal(size=4)
                q[model.joints[j].idx_q + 3 : model.joints[j].idx_q + 7] = quat / np.linalg.norm(quat)
        v = rng.uniform(-2.0, 2.0, model.nv)
        a = rng.uniform(-5.0, 5.0, model.nv)
        tau = pin.rnea(model, data, q, v, a).copy()
        states.append(dict(q=q, v=v, a=a, tau=tau))
    return states


def write_states(path, states, nq, nv):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(f"{nq} {nv} {len(states)}\n")
        for s in states:
            for k in ("q", "v", "a", "tau"):
                f.write(" ".join(repr(float(x)) for x in s[k]) + "\n")


# ---------------------------------------------------------------------------------------------
# Values check


def rel(x, ref):
    x, ref = np.asarray(x, float), np.asarray(ref, float)
    return float(np.max(np.abs(x - ref)) / max(np.max(np.abs(ref)), 1e-300))


def sym(upper):
    """The symmetric matrix whose upper triangle is that of `upper` (Pinocchio's M and M^-1)."""
    m = np.asarray(upper, float)
    return np.triu(m) + np.triu(m, 1).T


def pin_derivatives(vals):
    """Pinocchio's derivative outputs (program JSON) as named matrices, M^-1 symmetrized."""
    idd, fdd = vals["inverse_dynamics_derivatives"], vals["forward_dynamics_derivatives"]
    return {
        "dtau_dq": np.asarray(idd["dtau_dq"], float),
        "dtau_dv": np.asarray(idd["dtau_dv"], float),
        "ddq_dq": np.asarray(fdd["ddq_dq"], float),
        "ddq_dv": np.asarray(fdd["ddq_dv"], float),
        "minv (aba derivatives)": sym(fdd["minv"]),
        "mass_matrix_inverse": sym(vals["mass_matrix_inverse"]),
    }


def check_derivatives(name, key, vals, ref, P):
    """Our derivative outputs (program JSON, our joint order) against Pinocchio's: with P the
    permutation v_ours = P v_pin, each NV x NV derivative maps back as P' X P. Stops above
    DERIV_TOL; returns the worst difference and those of the central differences."""
    idd, fdd = vals["inverse_dynamics_derivatives"], vals["forward_dynamics_derivatives"]
    if fdd is None or vals["mass_matrix_inverse"] is None:
        sys.exit(f"[run.py] {name} {key}: the derivatives found M singular at the first state")
    back = lambda x: P.T @ np.asarray(x, float) @ P
    ours = {
        "dtau_dq": back(idd["dtau_dq"]),
        "dtau_dv": back(idd["dtau_dv"]),
        "ddq_dq": back(fdd["ddq_dq"]),
        "ddq_dv": back(fdd["ddq_dv"]),
        "minv (aba derivatives)": back(fdd["minv"]),
        "mass_matrix_inverse": back(vals["mass_matrix_inverse"]),
    }
    worst = 0.0
    for what, x in ours.items():
        e = rel(x, ref[what])
        worst = max(worst, e)
        if e > DERIV_TOL:
            sys.exit(
                f"[run.py] VALUES DISAGREE: {name}: ours ({key}) {what} differs from Pinocchio's "
                f"by {e:.3g} (relative) > {DERIV_TOL}\n  ours:      {x.ravel()[:8]}\n"
                f"  Pinocchio: {ref[what].ravel()[:8]}"
            )
    differences = {
        "dtau_dq": rel(back(vals["inverse_dynamics_differences"]), ref["dtau_dq"]),
        "ddq_dq": rel(back(vals["forward_dynamics_differences"]), ref["ddq_dq"]),
    }
    for what, e in differences.items():
        if not e <= DIFFERENCES_TOL:
            sys.exit(f"[run.py] {name} {key}: central differences of {what} off by {e:.3g} > {DIFFERENCES_TOL}")
    return worst, differences


def frame_arrays(vals, P=None):
    """The frame outputs of a program's JSON as {(quantity, frame index): array}: the rotation
    and translation of each placement, each J and dJ (angular rows first on both sides); with
    P (v_ours = P v_pin), our Jacobians' columns mapped to Pinocchio's joint order (J P)."""
    cols = (lambda m: np.asarray(m, float) @ P) if P is not None else (lambda m: np.asarray(m, float))
    out = {}
    for k, p in enumerate(vals["frame_placements"]):
        out[("rotation", k)] = np.asarray(p["rotation"], float)
        out[("translation", k)] = np.asarray(p["translation"], float)
    for key, what in (
        ("frame_jacobians_local_world_aligned", "J lwa"),
        ("frame_jacobians_local_world_aligned_joint_jacobians", "J lwa (computeJointJacobians)"),
        ("frame_jacobian_time_variations_local_world_aligned", "dJ lwa"),
    ):
        for k, m in enumerate(vals.get(key, [])):
            out[(what, k)] = cols(m)
    return out


def check_frames(name, key, frames, x, ref):
    """Frame outputs x against ref ({(quantity, frame index): array}, frame_arrays), each to
    FRAME_TOL relative to the largest entry of ref's; stops above it, returns the worst."""
    worst = 0.0
    for (what, k), r in ref.items():
        if (what, k) not in x:
            continue
        e = rel(x[(what, k)], r)
        worst = max(worst, e)
        if e > FRAME_TOL:
            sys.exit(
                f"[run.py] VALUES DISAGREE: {name} {key}: frame {frames[k]} {what} differs from "
                f"Pinocchio's by {e:.3g} (relative) > {FRAME_TOL}\n  ours:      {x[(what, k)].ravel()[:8]}\n"
                f"  Pinocchio: {r.ravel()[:8]}"
            )
    return worst


def constrained_arrays(name, key, vals, P=None):
    """constrained_forward_dynamics of a program's JSON: (q̈, the wrenches of all contacts
    concatenated, [n; f] each); with P (v_ours = P v_pin), our q̈ mapped to Pinocchio's joint
    order (P' q̈). Stops where ours failed on a state."""
    c = vals["constrained_forward_dynamics"]
    if c.get("errors"):
        sys.exit(f"[run.py] {name} {key}: constrained forward dynamics failed: {'; '.join(c['errors'])}")
    if c.get("iterations", 1) != 1:
        sys.exit(f"[run.py] {name} {key}: constraintDynamics made {c['iterations']} iterations, not 1")
    a = np.asarray(c["acceleration"], float)
    return (P.T @ a if P is not None else a), np.concatenate([np.asarray(f, float) for f in c["forces"]])


def check_constrained(name, key, x, ref):
    """Constrained forward dynamics x against ref ((q̈, forces), constrained_arrays), each to
    CONSTRAINED_TOL relative to the largest entry of ref's; stops above it, returns the worst."""
    worst = 0.0
    for what, a, r in (("q̈", x[0], ref[0]), ("contact wrenches", x[1], ref[1])):
        e = rel(a, r)
        worst = max(worst, e)
        if e > CONSTRAINED_TOL:
            sys.exit(
                f"[run.py] VALUES DISAGREE: {name} {key}: constrained forward dynamics, {what} differs "
                f"from Pinocchio's by {e:.3g} (relative) > {CONSTRAINED_TOL}\n  ours:      {a[:8]}\n"
                f"  Pinocchio: {r[:8]}"
            )
    return worst


def check_values(model_entry, progs, maps, state0, derivatives, frames, contacts):
    """Every program's outputs against Pinocchio's (pin_v3); returns the worst MuJoCo difference.
    `derivatives`: whether our program has the derivative outputs of this model; `frames`: the
    frames of its frame outputs (none: empty); `contacts`: the contacts of its constrained
    forward dynamics (none: empty)."""
    name = model_entry[0]
    ref = run_json(progs["pin_v3"] + ["--values", name])
    up = lambda m: np.triu(np.asarray(m, float))
    refs = {
        "mass_matrix": up(ref["mass_matrix"]),
        "nonlinear_effects": ref["nonlinear_effects"],
        "gravity": ref["gravity"],
        "inverse_dynamics": ref["inverse_dynamics"],
        "forward_dynamics": ref["forward_dynamics"],
    }
    report = []
    # Pinocchio's own variants and the wheel build agree with the default call.
    own = [
        ("pin_v3", ref),
        ("pin_wheel", run_json(progs["pin_wheel"] + ["--values", name])),
        ("pin_native", run_json(progs["pin_native"] + ["--values", name])),
    ]
    for key, vals in own:
        pairs = [
            ("mass_matrix", up(vals["mass_matrix"]), refs["mass_matrix"]),
            ("mass_matrix_world", up(vals["mass_matrix_world"]), refs["mass_matrix"]),
            ("forward_dynamics_world", vals["forward_dynamics_world"], refs["forward_dynamics"]),
            ("m+nle: M", up(vals["mass_matrix_and_nonlinear_effects"]["mass_matrix"]), refs["mass_matrix"]),
            ("m+nle: nle", vals["mass_matrix_and_nonlinear_effects"]["nonlinear_effects"], refs["nonlinear_effects"]),
        ] + [(k, vals[k], refs[k]) for k in ("nonlinear_effects", "gravity", "inverse_dynamics", "forward_dynamics")]
        for what, x, r in pairs:
            e = rel(x, r)
            if e > OURS_TOL:
                sys.exit(f"[run.py] VALUES DISAGREE: {name} {key} {what}: relative difference {e:.3g} > {OURS_TOL}")
        whole_pairs = [(k, vals[k], ref[k]) for k, _ in WHOLE_ROWS]
        whole_pairs.append(("centroidal_map", vals["centroidal_map"], ref["centroidal_momentum_matrix"]))
        for what, x, r in whole_pairs:
            e = rel(x, r)
            if e > WHOLE_TOL:
                sys.exit(f"[run.py] VALUES DISAGREE: {name} {key} {what}: relative difference {e:.3g} > {WHOLE_TOL}")
        theirs, ref_d = pin_derivatives(vals), pin_derivatives(ref)
        for what, x in theirs.items():
            e = rel(x, ref_d[what])
            if e > DERIV_TOL:
                sys.exit(f"[run.py] VALUES DISAGREE: {name} {key} {what}: relative difference {e:.3g} > {DERIV_TOL}")
        e = rel(ref_d["minv (aba derivatives)"], ref_d["mass_matrix_inverse"])
        if e > DERIV_TOL:
            sys.exit(f"[run.py] VALUES DISAGREE: {name} {key}: Minv of computeABADerivatives and computeMinverse differ by {e:.3g}")
        if frames:
            ref_f = frame_arrays(ref)
            check_frames(name, key, frames, frame_arrays(vals), ref_f)
            # Both ways to the Jacobians agree.
            both = {("J lwa", k): m for (w, k), m in frame_arrays(vals).items() if w == "J lwa (computeJointJacobians)"}
            check_frames(name, f"{key} computeJointJacobians", frames, both, ref_f)
        if contacts:
            check_constrained(name, key, constrained_arrays(name, key, vals), constrained_arrays(name, "pin_v3", ref))
    # Ours, every build.
    for key in ("ours_v3", "ours_default", "ours_native"):
        vals = run_json(progs[key] + ["--values", name])
        if vals["forward_dynamics"] is None:
            sys.exit(f"[run.py] {name} {key}: forward dynamics found M singular at the first state")
        both = vals["mass_matrix_and_nonlinear_effects"]
        vals["mm_nle_M"], vals["mm_nle_nle"] = both["mass_matrix"], both["nonlinear_effects"]
        m = maps["ours"].back(
            vals, state0,
            mass_keys=("mass_matrix", "mm_nle_M", "mass_matrix_lower"),
            force_keys=("nonlinear_effects", "gravity", "inverse_dynamics", "mm_nle_nle"),
            accel_keys=("forward_dynamics",),
        )
        worst = 0.0
        for what, r in [
            ("mass_matrix", "mass_matrix"), ("mm_nle_M", "mass_matrix"),
            ("mass_matrix_lower", "mass_matrix"),
            ("nonlinear_effects", "nonlinear_effects"), ("mm_nle_nle", "nonlinear_effects"),
            ("gravity", "gravity"), ("inverse_dynamics", "inverse_dynamics"),
            ("forward_dynamics", "forward_dynamics"),
        ]:
            x = up(m[what]) if what in ("mass_matrix", "mm_nle_M", "mass_matrix_lower") else m[what]
            e = rel(x, refs[r])
            worst = max(worst, e)
            if e > OURS_TOL:
                sys.exit(
                    f"[run.py] VALUES DISAGREE: {name}: ours ({key}) {what} differs from Pinocchio's "
                    f"by {e:.3g} (relative) > {OURS_TOL}\n  ours:      {np.asarray(x).ravel()[:8]}\n"
                    f"  Pinocchio: {np.asarray(refs[r]).ravel()[:8]}"
                )
        report.append((key, worst))
        log(f"{name}: {key} agrees with Pinocchio to {worst:.1e} (relative)")
        # The quantities of the whole system. Ours are in our joint order: with P the
        # permutation (v_ours = P v_pin), J_pin = J_ours P and C_pin = P' C_ours P; the centre
        # of mass, h_G and the energies do not depend on the order. h_G and A_G are angular
        # first on both sides (pinocchio_timing.cpp swaps Pinocchio's halves).
        P = maps["ours"].a_matrix(state0["q"])
        mapped = {
            "center_of_mass": vals["center_of_mass"],
            "center_of_mass_velocity": vals["center_of_mass_velocity"],
            "center_of_mass_jacobian": np.array(vals["center_of_mass_jacobian"]) @ P,
            "centroidal_momentum": vals["centroidal_momentum"],
            "centroidal_momentum_matrix": np.array(vals["centroidal_momentum_matrix"]) @ P,
            "kinetic_energy": vals["kinetic_energy"],
            "potential_energy": vals["potential_energy"],
            "coriolis_matrix": P.T @ np.array(vals["coriolis_matrix"]) @ P,
        }
        worst_whole = 0.0
        for what, x in mapped.items():
            e = rel(x, ref[what])
            worst_whole = max(worst_whole, e)
            if e > WHOLE_TOL:
                sys.exit(
                    f"[run.py] VALUES DISAGREE: {name}: ours ({key}) {what} differs from Pinocchio's "
                    f"by {e:.3g} (relative) > {WHOLE_TOL}\n  ours:      {np.asarray(x).ravel()[:8]}\n"
                    f"  Pinocchio: {np.asarray(ref[what]).ravel()[:8]}"
                )
        report.append((f"{key} (whole system)", worst_whole))
        log(f"{name}: {key} agrees with Pinocchio on the whole-system outputs to {worst_whole:.1e} (relative)")
        if derivatives:
            worst_d, differences = check_derivatives(name, key, vals, pin_derivatives(ref), P)
            report.append((f"{key} (derivatives)", worst_d))
            report.append((f"{key} (central differences, ∂τ/∂q)", differences["dtau_dq"]))
            report.append((f"{key} (central differences, ∂q̈/∂q)", differences["ddq_dq"]))
            log(
                f"{name}: {key} agrees with Pinocchio on the derivatives to {worst_d:.1e} (relative); "
                f"central differences {differences['dtau_dq']:.1e} (∂τ/∂q), {differences['ddq_dq']:.1e} (∂q̈/∂q)"
            )
        if frames:
            # Ours: the same frames in the same order; Jacobian columns in our joint order.
            worst_f = check_frames(name, key, frames, frame_arrays(vals, P), frame_arrays(ref))
            report.append((f"{key} (frames)", worst_f))
            log(f"{name}: {key} agrees with Pinocchio on the frame outputs ({', '.join(frames)}) to {worst_f:.1e} (relative)")
        if contacts:
            # Ours: q̈ in our joint order; the wrenches [n; f] in each contact's frame on both sides.
            worst_c = check_constrained(
                name, key, constrained_arrays(name, key, vals, P), constrained_arrays(name, "pin_v3", ref)
            )
            report.append((f"{key} (constrained)", worst_c))
            log(f"{name}: {key} agrees with Pinocchio on the constrained forward dynamics ({', '.join(contacts)}) to {worst_c:.1e} (relative)")
    # MuJoCo: reported, with a looser bound.
    vals = run_json(progs["mujoco"] + ["--values", name])
    m = maps["mujoco"].back(
        vals, state0,
        mass_keys=("mass_matrix",),
        force_keys=("gravity", "inverse_dynamics", "mj_inverse"),
        nle_keys=("nonlinear_effects",),
        accel_keys=("forward_dynamics", "mj_forward"),
    )
    diffs = {}
    for what, r in [
        ("mass_matrix", "mass_matrix"), ("nonlinear_effects", "nonlinear_effects"),
        ("gravity", "gravity"), ("inverse_dynamics", "inverse_dynamics"),
        ("mj_inverse", "inverse_dynamics"), ("forward_dynamics", "forward_dynamics"),
        ("mj_forward", "forward_dynamics"),
    ]:
        x = up(m[what]) if what == "mass_matrix" else m[what]
        diffs[what] = rel(x, refs[r])
    worst = max(diffs.values())
    log(f"{name}: MuJoCo agrees with Pinocchio to {worst:.1e} (relative; worst: {max(diffs, key=diffs.get)})")
    if worst > MUJOCO_TOL:
        log(f"WARNING: {name}: MuJoCo differs from Pinocchio by {worst:.3g} > {MUJOCO_TOL}: {diffs}")
    return report, worst, diffs


# ---------------------------------------------------------------------------------------------
# Timing and instructions


def time_all(models, progs, rounds, batches):
    """results[model][program][output] = (min over rounds, median of the medians)."""
    runs = {m[0]: {k: {} for k in progs[m[0]]} for m in models}
    keys = list(progs[models[0][0]].keys())
    for r in range(rounds):
        order = keys[r % len(keys):] + keys[: r % len(keys)]
        for m in models:
            name = m[0]
            for k in order:
                log(f"timing round {r + 1}/{rounds}: {name} {k}")
                out = run_json(progs[name][k] + ["--time", "--batches", str(batches), name])
                for output, v in out.items():
                    runs[name][k].setdefault(output, []).append((v["min"], v["median"]))
    results = {}
    for name, by_prog in runs.items():
        results[name] = {}
        for k, by_out in by_prog.items():
            results[name][k] = {
                o: (min(x[0] for x in xs), float(np.median([x[1] for x in xs])))
                for o, xs in by_out.items()
            }
    return results


def callgrind(cmd):
    out = subprocess.run(
        ["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null"] + cmd,
        capture_output=True, text=True,
    )
    found = re.search(r"Collected : (\d+)", out.stderr)
    if out.returncode != 0 or not found:
        sys.exit(f"[run.py] callgrind failed: {' '.join(cmd)}\n{out.stderr[-2000:]}")
    return int(found.group(1))


def instructions(models, progs, which):
    """instr[model][program][output] = instructions per call; which(model) gives the outputs of
    each program."""
    instr = {}
    for m in models:
        name = m[0]
        instr[name] = {}
        for k, outputs in which(name).items():
            instr[name][k] = {}
            for o in outputs:
                log(f"callgrind: {name} {k} {o}")
                base = callgrind(progs[name][k] + ["--calls", "0", name, o])
                full = callgrind(progs[name][k] + ["--calls", str(CALLS), name, o])
                instr[name][k][o] = (full - base) / CALLS
    return instr


# ---------------------------------------------------------------------------------------------
# Report


def sh(cmd):
    try:
        return subprocess.run(cmd, capture_output=True, text=True, shell=True).stdout.strip()
    except OSError:
        return "?"


def native_cpu(target_cpus):
    """The CPU `-C target-cpu=native` stands for, from `rustc --print target-cpus`."""
    found = re.search(r"^\s*native\b.*\(currently ([^)]*)\)", target_cpus, re.M)
    return found.group(1) if found else "?"


def environment():
    lscpu = sh("lscpu")
    model_name = re.search(r"Model name:\s*(.*)", lscpu)
    mem = re.search(r"MemTotal:\s*(\d+) kB", open("/proc/meminfo").read())
    commit = sh(f"git -C {ROOT} rev-parse --short HEAD")
    dirty = sh(f"git -C {ROOT} status --porcelain --untracked-files=no -- . ':!BENCHMARKS.md'")
    return dict(
        cpu=model_name.group(1).strip() if model_name else "?",
        nproc=sh("nproc"),
        ram=f"{int(mem.group(1)) / 1024 / 1024:.0f} GiB" if mem else "?",
        kernel=platform.release(),
        rustc=sh("rustc --version"),
        gxx=sh("g++ --version | head -1"),
        # What `-march=native` and `-C target-cpu=native` (the native column pair) resolve to.
        gcc_native=sh("g++ -march=native -Q --help=target 2>/dev/null | sed -n 's/^ *-march= *//p' | head -1")
        + (" with AVX-512" if "__AVX512F__" in sh("g++ -march=native -dM -E - </dev/null") else ""),
        rustc_native=native_cpu(sh("rustc --print target-cpus")),
        valgrind=sh("valgrind --version"),
        python=platform.python_version(),
        pinocchio=pin.__version__,
        mujoco=mujoco.mj_versionString(),
        eigen=sh(f"{sys.executable} -m pip show cmeel-eigen 2>/dev/null | sed -n 's/^Version: //p'"),
        commit=commit + (" (with uncommitted changes)" if dirty else ""),
        date=datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        load=open("/proc/loadavg").read().split()[:3],
    )


def fmt_ns(x):
    return "–" if x is None else (f"{x:.0f}" if x >= 100 else f"{x:.1f}")


def fmt_ratio(x):
    return "–" if x is None else f"{x:.1f}×"


# The states per second (`throughput`): our binary and Pinocchio's OpenMP build, at one thread
# and at every thread of the machine; the models of `bench/src/bin/throughput.rs`.
THROUGHPUT_MODELS = [("arm7", "models/arm7.urdf", False), ("humanoid", "models/humanoid.urdf", True)]
THROUGHPUT_OUTPUTS = [
    "mass_matrix", "nonlinear_effects", "inverse_dynamics", "forward_dynamics",
    "inverse_dynamics_derivatives", "forward_dynamics_derivatives",
]


def throughput(nproc):
    """States per second: ours (`throughput`: the scalar loop, lanes, lanes and the scalar loop on
    every thread) and Pinocchio's (`pinocchio_omp --throughput`: rneaInParallel, abaInParallel,
    and an OpenMP loop with one Data per thread for the rest), at 1 and `nproc` threads."""
    threads = sorted({1, nproc})
    tlist = ",".join(map(str, threads))
    path = os.path.join(OUT, "throughput.json")
    log(f"states per second, ours, threads {tlist}")
    subprocess.run(
        [os.path.join(OUT, "rust-v3", "release", "throughput"), "--threads", tlist, "--json", path],
        check=True,
    )
    with open(path) as f:
        ours = json.load(f)
    # The same binary for the default target and for this machine's CPU, one thread: what lanes
    # give without AVX2 (two-lane SSE2 halves) and with all this CPU has.
    targets = {}
    for target in ("default", "native"):
        binary = os.path.join(OUT, f"rust-{target}", "release", "throughput")
        if not os.path.exists(binary):
            continue
        tpath = os.path.join(OUT, f"throughput-{target}.json")
        log(f"states per second, ours, {target} target, one thread")
        subprocess.run([binary, "--threads", "1", "--json", tpath], check=True)
        with open(tpath) as f:
            targets[target] = json.load(f)
    pin = {}
    for name, urdf, floating in THROUGHPUT_MODELS:
        log(f"states per second, Pinocchio (OpenMP), {name}, threads {tlist}")
        cmd = [os.path.join(OUT, "bin", "pinocchio_omp"), "--urdf", os.path.join(ROOT, urdf)]
        cmd += ["--floating"] if floating else []
        cmd += ["--states", os.path.join(OUT, "states", f"{name}.pin.txt"), "--throughput", tlist, name]
        pin[name] = run_json(cmd)
    when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    return dict(threads=threads, ours=ours, pinocchio=pin, targets=targets, date=when,
                commit=environment()["commit"])


def throughput_states():
    """The states files Pinocchio's throughput reads, drawn as a full run draws them where a
    `--throughput-only` run finds none."""
    for name, urdf, floating in THROUGHPUT_MODELS:
        path = os.path.join(OUT, "states", f"{name}.pin.txt")
        if not os.path.exists(path):
            pm = pinocchio_model(urdf, floating)
            write_states(path, draw_states(pm, name), pm.nq, pm.nv)


THROUGHPUT_HEADING = "## Many states per call"


def splice_throughput(text, thr):
    """BENCHMARKS.md's `text` with its section "Many states per call" replaced by one from
    `thr`, every other line unchanged."""
    lines = text.split("\n")
    if THROUGHPUT_HEADING not in lines:
        raise SystemExit(f"BENCHMARKS.md has no section \"{THROUGHPUT_HEADING[3:]}\": run the whole run.sh")
    new = []
    throughput_report(new.append, thr)
    start = lines.index(THROUGHPUT_HEADING)
    end = next((i for i, line in enumerate(lines) if i > start and line.startswith("## ")), len(lines))
    return "\n".join(lines[:start] + new[1:] + [""] + lines[end:])


def contact():
    """The contact simulation, one thread, same run: ours (`contact_steps`: the humanoid standing
    on eight points, timed; the sliding and resting block) and MuJoCo's (`contact_mujoco.py`, the
    same scenes with elliptic cones)."""
    log("contact simulation, ours and MuJoCo")
    ours = run_json([os.path.join(OUT, "rust-v3", "release", "contact_steps")])
    theirs = run_json([sys.executable, os.path.join(ROOT, "bench", "peers", "contact_mujoco.py")])
    when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    return dict(ours=ours, mujoco=theirs, date=when, commit=environment()["commit"])


def python_timing():
    """bench/python/timing.py as a module (its `section` renders the figures)."""
    spec = importlib.util.spec_from_file_location("python_timing", os.path.join(ROOT, "bench", "python", "timing.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def python_figures(nproc):
    """The speed from Python (`bench/python/timing.py`, in this Python: `articulated` against
    `pin`, batches of 1, 100 and 100,000 states) on `nproc` threads, both sides."""
    path = os.path.join(OUT, "python.json")
    os.makedirs(OUT, exist_ok=True)
    log(f"speed from Python, {nproc} threads (bench/python/timing.py)")
    subprocess.run(
        [sys.executable, os.path.join(ROOT, "bench", "python", "timing.py"), path,
         "--threads", str(nproc)],
        check=True, env=dict(os.environ, RAYON_NUM_THREADS=str(nproc)), stdout=subprocess.DEVNULL,
    )
    with open(path) as f:
        return json.load(f)


def python_report(w, figures):
    """The section "From Python" from `python_figures`' figures."""
    if not figures:
        return
    w("")
    for line in python_timing().section(figures):
        w(line)


PYTHON_HEADING = "## From Python"


def splice_python(text, figures):
    """BENCHMARKS.md's `text` with its section "From Python" replaced by one from `figures`
    (or added after "Many states per call" where it has none), every other line unchanged."""
    lines = text.split("\n")
    new = python_timing().section(figures) + [""]
    heads = [i for i, line in enumerate(lines) if line.startswith("## ")]
    if PYTHON_HEADING in lines:
        start = lines.index(PYTHON_HEADING)
    else:
        after = [i for i in heads if lines[i] == "## Many states per call"]
        before = [i for i in heads if lines[i] == "## What each figure includes"]
        if after:
            start = next((i for i in heads if i > after[0]), len(lines))
        elif before:
            start = before[0]
        else:
            raise SystemExit("BENCHMARKS.md has neither the section \"Many states per call\" nor \"What each figure includes\"")
        return "\n".join(lines[:start] + new + lines[start:])
    end = next((i for i in heads if i > start), len(lines))
    return "\n".join(lines[:start] + new + lines[end:])


def contact_report(w, c):
    """The section "Simulation with contacts" from `contact`'s figures."""
    if not c:
        return
    o, m = c["ours"], c["mujoco"]
    oh, mh = o["humanoid_standing"], m["scenes"]["humanoid_standing"]
    os_, ms = o["sliding_box"], m["scenes"]["sliding_box"]
    orr, mr = o["resting_box"], m["scenes"]["resting_box"]
    st = m["settings"]
    mm = lambda x: f"{x * 1e3:.3g} mm"
    w("")
    w("## Simulation with contacts")
    w("")
    w("Time stepping with unilateral contacts and friction cones, 1 ms steps, one thread, in the same")
    w("run. **Ours**: `articulated::contact` (semi-implicit Euler; the exact Coulomb problem by")
    w("projected Gauss–Seidel to 1e-10 m/s; `bench/src/bin/contact_steps.rs`, x86-64-v3). **MuJoCo**")
    w(f"{m['mujoco_version']}: `mj_step` (`bench/peers/contact_mujoco.py`), {st['cone']} cones, "
      f"{st['solver']} solver, tolerance {st['tolerance']:g}, its default soft contacts "
      f"(solref {st['contact_solref']}), only the contact spheres colliding with the floor, no")
    w("actuators or sensors. **Humanoid standing**: `models/humanoid.chain` on eight points (four under")
    w("each sole), μ = 0.8, the pelvis at 1.11 m, every joint held about zero by a spring of")
    w("2,000 N·m/rad and a damper of 50 N·m·s/rad (MuJoCo's joint `stiffness` and `damping`; ours a")
    w("controller and `TimeStepper::set_damping`, both dampers implicit); best of 5 runs of 2,000 steps.")
    w("**Block**: `models/block.chain`, 1 kg, its eight corners as contacts, μ = 0.5, pushed at 2 m/s")
    w(f"(sliding) or at rest. Measured {c.get('date', '?')} at commit `{c.get('commit', '?')}`.")
    w("")
    w(f"Ours takes **{oh['steps_per_second'] / mh['timing']['steps_per_second']:.2f}×** MuJoCo's steps per second on the standing humanoid.")
    w("")
    w("| | ours | MuJoCo |")
    w("|---|---:|---:|")
    w(f"| humanoid standing: steps per second | {oh['steps_per_second']:,.0f} | {mh['timing']['steps_per_second']:,.0f} |")
    w(f"| µs per step | {oh['microseconds_per_step']:.1f} | {mh['timing']['microseconds_per_step']:.1f} |")
    w(f"| solver iterations per step, mean / max | {oh['iterations_mean']:.1f} / {oh['iterations_max']} (sweeps) | {mh['solver_iterations_mean']:.1f} / {mh['solver_iterations_max']} (Newton) |")
    w(f"| pelvis height drift over 2 s | {mm(oh['pelvis_height_drift'])} | {mm(mh['pelvis_height_drift'])} |")
    w(f"| deepest penetration | {mm(oh['max_penetration'])} | {mm(mh['max_penetration'])} |")
    w(f"| normal forces / m·g at 2 s | {oh['normal_sum_over_mg']:.4f} | {mh['normal_sum_over_mg']:.4f} |")
    w(f"| sliding block: deceleration (μ·g = {os_['deceleration_closed_form']:.4g} m/s²) | {os_['deceleration']:.4f} | {ms['deceleration']:.4f} |")
    w(f"| stopping distance (v²/(2μg) = {os_['stop_distance_closed_form']:.4f} m) | {os_['stop_distance']:.4f} | {ms['stop_distance']:.4f} |")
    w(f"| time to stop (v/(μg) = {2.0 / os_['deceleration_closed_form']:.4f} s) | {os_['stop_time']:.3f} | {ms['stop_time']:.3f} |")
    w(f"| highest lift while sliding | {mm(os_['max_lift_while_sliding'])} | {mm(ms['max_lift_while_sliding'])} |")
    w(f"| steps with no contact while sliding | 0 | {ms['steps_without_contact_while_sliding']} of {ms['steps_while_sliding']} |")
    w(f"| deepest penetration while sliding | {mm(os_['max_penetration'])} | {mm(ms['max_penetration'])} |")
    w(f"| resting block: normal forces / m·g | {orr['normal_sum_over_mg']:.6f} | {mr['normal_sum_over_mg']:.6f} |")
    w(f"| resting block: height error | {mm(orr['height_error'])} | {mm(mr['height_error'])} |")
    w("")
    w("MuJoCo's contacts are soft and its cone problem convex: a resting body sinks until the")
    w("contact's spring carries it, and a sliding contact pushes the bodies apart (its block hops")
    w("while it slides, as Anitescu's relaxation predicts). Ours holds the gap to rounding and a")
    w("sliding contact on the ground; what it gives up is a convex problem: Painlevé's")
    w("configurations may not converge, and say so ([the runtime guide](docs/guide/runtime.md#simulation-with-contacts)).")


def throughput_report(w, thr):
    """The section "Many states per call" from `throughput`'s figures."""
    if not thr:
        return
    w("")
    w("## Many states per call")
    w("")
    w("States per second (millions). **scalar**: our generated function called state by state;")
    w("**lanes**: its batch function (`inverse_dynamics_batch`, …) in lanes of four states in `f64`,")
    w("eight in `f32` (`lanes: 4`, `articulated::lanes`; the gathering of the states from the")
    w("caller's slices into lanes and the scattering of the results included); **lanes, T threads**:")
    w("the same batch on T threads (`_par_batch`, rayon); **scalar, T threads**: the scalar loop on")
    w("T threads. **Pinocchio** is `rneaInParallel` and `abaInParallel` (OpenMP, a `ModelPool`) for")
    w("inverse and forward dynamics, and the same OpenMP loop with one `Data` per thread for the")
    w("others, which it does not parallelize (`pinocchio_timing --throughput`, built with")
    w("`-O3 -march=x86-64-v3 -fopenmp`). Ours built for x86-64-v3 (`bench/src/bin/throughput.rs`);")
    w("256 states per call on one thread; on T threads, T shares of 256 to 4096 states, as many as")
    w("fit 1 MiB of inputs and results (a core's L2: the humanoid's mass matrices, 11 KB a state,")
    w("256 a thread); best of 7 rounds. Ratios: lanes over the scalar loop on one thread;")
    w("ours over Pinocchio at the same thread count, per state. Read the humanoid's figures as")
    w("within tens of per cent: its functions are tens of kilobytes of straight-line code, whose")
    w("speed on this machine moves from run to run and build to build (the scalar `mass_matrix`")
    w("loop ran at 0.91 M states/s in two runs of one binary and at 1.47 in a third minutes")
    w("later), so a ratio moves where neither function changed.")
    if thr.get("commit"):
        w(f"Measured {thr['date']} at commit {thr['commit']} (`bash bench/peers/run.sh --throughput-only`")
        w("rewrites this section alone).")
    threads = thr["threads"]
    top = max(threads)
    ours = thr["ours"]

    def get(model, output, prec, mode, t):
        for f in ours:
            if (f["model"], f["output"], f["scalar"], f["mode"], f["threads"]) == (model, output, prec, mode, t):
                return f["states_per_second"]
        return None

    def pin(model, output, t):
        for f in thr["pinocchio"].get(model, []):
            if (f["output"], f["threads"]) == (output, t):
                return f["states_per_second"]
        return None

    def m(x):
        # Two decimals, but three significant digits below 1 M/s (the humanoid's derivatives,
        # tens of thousands of states per second).
        if x is None:
            return "–"
        return f"{x / 1e6:.2f}" if x >= 1e6 else f"{x / 1e6:.3g}"

    def r(a, b):
        return "–" if a is None or b is None else f"{a / b:.1f}×"

    for model, _, _ in THROUGHPUT_MODELS:
        w("")
        w(f"### {model}")
        w("")
        w(f"| output | scalar | lanes | lanes / scalar | Pinocchio, 1 thread | lanes / Pinocchio | "
          f"lanes, {top} threads | scalar, {top} threads | Pinocchio, {top} threads | ours / Pinocchio, {top} threads |")
        w("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for prec in ("f64", "f32"):
            for output in THROUGHPUT_OUTPUTS:
                sc = get(model, output, prec, "scalar", 1)
                if sc is None:
                    continue
                ln = get(model, output, prec, "lanes", 1)
                lt = get(model, output, prec, "lanes_threads", top)
                st = get(model, output, prec, "scalar_threads", top)
                p1 = pin(model, output, 1) if prec == "f64" else None
                pt = pin(model, output, top) if prec == "f64" else None
                label = f"`{output}`" + (" (f32)" if prec == "f32" else "")
                w(f"| {label} | {m(sc)} | {m(ln)} | {r(ln, sc)} | {m(p1)} | {r(ln, p1)} | "
                  f"{m(lt)} | {m(st)} | {m(pt)} | {r(lt, pt)} |")
    targets = thr.get("targets", {})
    if targets:
        w("")
        w("### By target, one thread")
        w("")
        w("The same binary built for the default target (`x86-64`: SSE2, each lane type in two-lane")
        w("halves, but the outputs of a thousand operations or more in the two lanes of one register,")
        w("`articulated::lanes::fit`),")
        w("for x86-64-v3 (AVX2 and FMA, the tables above) and for this machine's CPU")
        w("(`-C target-cpu=native`): states per second (millions) of the scalar loop and of lanes.")
        w("")
        cols = [t for t in ("default", "v3", "native") if t == "v3" or t in targets]
        w("| model | output | " + " | ".join(f"scalar, {t} | lanes, {t} | lanes / scalar, {t}" for t in cols) + " |")
        w("|---|---|" + "---:|---:|---:|" * len(cols))

        def get_in(figures, model, output, prec, mode):
            for f in figures:
                if (f["model"], f["output"], f["scalar"], f["mode"], f["threads"]) == (model, output, prec, mode, 1):
                    return f["states_per_second"]
            return None

        for model, _, _ in THROUGHPUT_MODELS:
            for prec in ("f64", "f32"):
                for output in THROUGHPUT_OUTPUTS:
                    cells = []
                    for t in cols:
                        figures = ours if t == "v3" else targets[t]
                        sc = get_in(figures, model, output, prec, "scalar")
                        ln = get_in(figures, model, output, prec, "lanes")
                        cells += [m(sc), m(ln), r(ln, sc)]
                    if all(c == "–" for c in cells):
                        continue
                    label = f"`{output}`" + (" (f32)" if prec == "f32" else "")
                    w(f"| {model} | {label} | " + " | ".join(cells) + " |")
    w("")
    w(f"This machine has {top} threads; the scaling to 16 cores is in `docs/throughput.md`")
    w("where a session measured it. Pinocchio has no `f32` build here (its wheel is `double`).")


def report(env, models, ops, results, instr, checks, args, load_end, thr=None, contact_figures=None,
           py_figures=None):
    L = []
    w = L.append
    w("# Benchmarks: `articulated` against Pinocchio and MuJoCo")
    w("")
    w("Written by `bash bench/peers/run.sh` (the driver is `bench/peers/run.py`); do not edit by hand.")
    w("Nanoseconds per call, the fastest of the ~1 ms batches over all rounds, on the same random")
    w("states for every program; instruction counts from callgrind.")
    w("")
    w("## Machine and versions")
    w("")
    w(f"- CPU: {env['cpu']}, `nproc` {env['nproc']}, RAM {env['ram']}, Linux {env['kernel']} (a shared VM)")
    w(f"- load average at the start {' '.join(env['load'])}, at the end {' '.join(load_end)}")
    w(f"- {env['rustc']}; {env['gxx']}; {env['valgrind']}; Python {env['python']}")
    w(f"- Pinocchio {env['pinocchio']} (pip `pin`), Eigen {env['eigen']} (pip `cmeel-eigen`), MuJoCo {env['mujoco']} (pip `mujoco`)")
    w(f"- commit `{env['commit']}`, run {env['date']}")
    w(f"- {args.rounds} rounds × {args.batches} batches of ~1 ms per output and program; callgrind K = {CALLS}")
    w("")
    w("The one command, from the repository root (first run: creates `target/peers/venv` and")
    w("installs the wheels; later runs rebuild only what changed):")
    w("")
    w("```sh")
    w("bash bench/peers/run.sh")
    w("```")
    w("")
    w("## Results")
    w("")
    w("Columns: **ours** is the code `#[derive(Chain)]` generates (`bench/src/bin/peers.rs`), built")
    w("with `RUSTFLAGS=\"-C target-cpu=x86-64-v3\"` (AVX2, FMA) and for the default target (x86-64,")
    w("SSE2). **Pinocchio v3** is Pinocchio's algorithms compiled from its headers with")
    w("`g++ -O3 -DNDEBUG -march=x86-64-v3` (`bench/peers/pinocchio_timing.cpp`); **Pinocchio wheel** is")
    w("the same calls going to the wheel's prebuilt `libpinocchio_default` (baseline x86-64), what a")
    w("CMake user of `pinocchio::pinocchio` gets. **MuJoCo** is its C API from the wheel's `libmujoco`")
    w("(`bench/peers/mujoco_timing.c`; the wheel's library uses AVX, not FMA). Ratios are Pinocchio")
    w("v3 over ours; instructions are per call.")
    w("A ᵂ marks a Pinocchio figure where the WORLD convention was faster than the default call")
    w("(LOCAL); the faster one is shown and used in the ratios.")
    w("")
    w("In short (fastest batches; a ratio above 1 means ours is faster; the range runs over the six")
    w("outputs of each model's table):")
    w("")
    for (name, _chain, _urdf, _floating) in models:
        res = results[name]

        def span(other, ours):
            ratios = [(other(r) / res[ours][r[0]][0], r[0]) for r in ROWS]
            (lo, lo_out), (hi, hi_out) = min(ratios), max(ratios)
            return f"{lo:.1f}× ({lo_out}) to {hi:.1f}× ({hi_out})"

        pin3 = lambda r: min(res["pin_v3"][p][0] for p in r[1])
        mj = lambda r: res["mujoco"][r[2]][0]
        w(
            f"- **{name}**: Pinocchio v3 / ours v3 {span(pin3, 'ours_v3')}; Pinocchio v3 / ours "
            f"default {span(pin3, 'ours_default')}; MuJoCo / ours v3 {span(mj, 'ours_v3')}"
        )
    for (name, chain, urdf, floating) in models:
        res, ins = results[name], instr.get(name, {})
        w("")
        w(f"### {name} ({'floating base, ' if floating else ''}nq {ops[name]['nq']}, nv {ops[name]['nv']}; `{chain}`, `{urdf}`)")
        w("")
        w("| output | ops | ours v3 (ns) | ours default (ns) | Pinocchio v3 (ns) | Pinocchio wheel (ns) | MuJoCo (ns) | Pinocchio / ours (v3) | Pinocchio / ours (default) | instructions ours v3 / Pinocchio v3 |")
        w("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for ours_out, pin_outs, mj_out in ROWS:
            o3 = res["ours_v3"][ours_out][0]
            od = res["ours_default"][ours_out][0]
            pv = [(res["pin_v3"][p][0], p) for p in pin_outs]
            p3, p3_which = min(pv)
            pw = min(res["pin_wheel"][p][0] for p in pin_outs)
            mark = "ᵂ" if p3_which != pin_outs[0] else ""
            mj = res["mujoco"][mj_out][0]
            i_ours = ins.get("ours_v3", {}).get(ours_out)
            i_pin = ins.get("pin_v3", {}).get(p3_which)
            instr_cell = (
                f"{i_ours:.0f} / {i_pin:.0f} ({i_pin / i_ours:.1f}×)" if i_ours and i_pin else "–"
            )
            w(
                f"| {ours_out} | {ops[name]['ops'][ours_out]} | {fmt_ns(o3)} | {fmt_ns(od)} | "
                f"{fmt_ns(p3)}{mark} | {fmt_ns(pw)} | {fmt_ns(mj)} | {fmt_ratio(p3 / o3)} | "
                f"{fmt_ratio(p3 / od)} | {instr_cell} |"
            )
        w("")
        w("Medians (ns; the median over rounds of each run's median batch; two Pinocchio figures")
        w("are the default call (LOCAL) / `Convention::WORLD`), then the other calls and checks:")
        w("")
        w("| output | ours v3 | ours default | Pinocchio v3 | Pinocchio wheel | MuJoCo |")
        w("|---|---:|---:|---:|---:|---:|")
        for ours_out, pin_outs, mj_out in ROWS:
            w(
                f"| {ours_out} | {fmt_ns(res['ours_v3'][ours_out][1])} | {fmt_ns(res['ours_default'][ours_out][1])} | "
                f"{' / '.join(fmt_ns(res['pin_v3'][p][1]) for p in pin_outs)} | "
                f"{' / '.join(fmt_ns(res['pin_wheel'][p][1]) for p in pin_outs)} | {fmt_ns(res['mujoco'][mj_out][1])} |"
            )
        w("")
        extra = []
        for p in ("mass_matrix_world", "forward_dynamics_world"):
            extra.append(
                f"Pinocchio `{p}` (Convention::WORLD): v3 {fmt_ns(res['pin_v3'][p][0])} ns, wheel {fmt_ns(res['pin_wheel'][p][0])} ns"
            )
        for kept, what in KEPT_ROWS:
            if kept not in res["ours_v3"]:
                continue
            u3, ud = res["ours_v3"][kept][0], res["ours_default"][kept][0]
            p3 = min(res["pin_v3"][p][0] for p in ("mass_matrix", "mass_matrix_world"))
            i_u = ins.get("ours_v3", {}).get(kept)
            extra.append(
                f"ours `{kept}` ({what}): v3 {fmt_ns(u3)} ns ({fmt_ratio(p3 / u3)} "
                f"against Pinocchio v3), default {fmt_ns(ud)} ns"
                + (f"; {i_u:.0f} instructions per call (v3)" if i_u else "")
            )
        for p, what in (
            ("mass_matrix_dense", "M then `mj_fullM`"),
            ("mj_forward", "the whole `mj_forward`"),
            ("mj_inverse", "the whole `mj_inverse`"),
        ):
            extra.append(f"MuJoCo {what}: {fmt_ns(res['mujoco'][p][0])} ns")
        if ins:
            parts = []
            for k, label in (("ours_default", "ours default"), ("mujoco", "MuJoCo")):
                if k in ins:
                    parts.append(
                        f"{label}: "
                        + ", ".join(f"{o} {v:.0f}" for o, v in ins[k].items() if o in {r[0] for r in ROWS})
                    )
            extra.append("instructions per call, " + "; ".join(parts))
        (key_worst, mj_worst, mj_diffs) = checks[name]
        extra.append(
            "values at the first state against Pinocchio's (relative to the largest entry): "
            + ", ".join(
                f"{k} {e:.1e}" for k, e in key_worst
                if "derivatives" not in k and "differences" not in k and "frames" not in k
                and "constrained" not in k
            )
            + f"; MuJoCo {mj_worst:.1e} (worst: {max(mj_diffs, key=mj_diffs.get)})"
            + (f" — **above {MUJOCO_TOL:g}: MuJoCo's model differs**" if mj_worst > MUJOCO_TOL else "")
        )
        for e in extra:
            w(f"- {e}")
    whole_report(w, models, ops, results, instr)
    derivatives_report(w, models, ops, results, instr, checks)
    frames_report(w, models, ops, results, instr, checks)
    constrained_report(w, models, ops, results, instr, checks)
    native_report(w, models, ops, results, env)
    throughput_report(w, thr)
    python_report(w, py_figures)
    contact_report(w, contact_figures)
    bytes_report(w, models, results, code_bytes(os.path.join(OUT, "rust-v3", "release", "peers")))
    w("")
    w(WHAT)
    return "\n".join(L) + "\n"


WHOLE_MUJOCO = """MuJoCo: n/a. Its program (`bench/peers/mujoco_timing.c`) times the dynamics terms only.
MuJoCo computes some of these quantities on the way (the subtree centres of mass in
`mj_comPos`, their velocities and angular momenta in `mj_subtreeVel`, `mj_jacSubtreeCom`, the
energies with `mjENBL_ENERGY`), but it has no Coriolis matrix and no centroidal momentum
matrix; those calls are not timed here yet."""


def whole_report(w, models, ops, results, instr):
    """The section of the quantities of the whole system."""
    w("")
    w("## Whole-system outputs")
    w("")
    w("The centre of mass, its velocity and Jacobian, the centroidal momentum and its matrix, the")
    w("kinetic and potential energy and the Coriolis matrix, timed in the same runs as the tables")
    w("above, on the same states, after the same values check (ours against Pinocchio's to 1e-10")
    w("relative, with `h_G = [k_G; p]` and the rows of `A_G` angular first on both sides). Columns")
    w("as above; ratios are Pinocchio v3 over ours. A ᶜ marks a `centroidal_momentum_matrix` figure")
    w("where `computeCentroidalMap` (A_G alone) was faster than `ccrba` (which also computes h_G and")
    w("the centroidal inertia); the faster is shown and used in the ratios.")
    w("")
    w(WHOLE_MUJOCO)
    w("")
    w("Every model is generated with all eight. The largest function is `chain50`'s `coriolis_matrix`")
    w("(126,436 operations: 2,500 entries on a chain 50 bodies deep): about 10 s of CI's test-profile")
    w("build of `bench/src/bin/peers.rs` and 85 s of each of `run.sh`'s two release builds of it")
    w("(measured once while adding these outputs; the humanoid's, 15,393 operations, was within the")
    w("noise of the test-profile build).")
    w("")
    w("In short (fastest batches; a ratio above 1 means ours is faster):")
    w("")
    for (name, *_rest) in models:
        res = results[name]
        def span(ours):
            ratios = [(min(res["pin_v3"][p][0] for p in r[1]) / res[ours][r[0]][0], r[0]) for r in WHOLE_ROWS]
            (lo, lo_out), (hi, hi_out) = min(ratios), max(ratios)
            return f"{lo:.1f}× ({lo_out}) to {hi:.1f}× ({hi_out})"

        w(f"- **{name}**: Pinocchio v3 / ours v3 {span('ours_v3')}; Pinocchio v3 / ours default {span('ours_default')}")
    for (name, chain, urdf, floating) in models:
        res, ins = results[name], instr.get(name, {})
        w("")
        w(f"### {name}: whole system ({'floating base, ' if floating else ''}nq {ops[name]['nq']}, nv {ops[name]['nv']})")
        w("")
        w("| output | ops | ours v3 (ns) | ours default (ns) | Pinocchio v3 (ns) | Pinocchio wheel (ns) | MuJoCo (ns) | Pinocchio / ours (v3) | Pinocchio / ours (default) | instructions ours v3 / Pinocchio v3 |")
        w("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for ours_out, pin_outs in WHOLE_ROWS:
            pv = [(res["pin_v3"][p][0], p) for p in pin_outs]
            p3, p3_which = min(pv, key=lambda x: x[0])  # the default call on a tie
            pw = min(res["pin_wheel"][p][0] for p in pin_outs)
            mark = "ᶜ" if p3_which != pin_outs[0] else ""
            i_pin = ins.get("pin_v3", {}).get(p3_which)
            o3 = res["ours_v3"][ours_out][0]
            od = res["ours_default"][ours_out][0]
            i_ours = ins.get("ours_v3", {}).get(ours_out)
            instr_cell = (
                f"{i_ours:.0f} / {i_pin:.0f} ({i_pin / i_ours:.1f}×)" if i_ours and i_pin else "–"
            )
            w(
                f"| {ours_out} | {ops[name]['ops'][ours_out]} | {fmt_ns(o3)} | {fmt_ns(od)} | "
                f"{fmt_ns(p3)}{mark} | {fmt_ns(pw)} | n/a | {fmt_ratio(p3 / o3)} | "
                f"{fmt_ratio(p3 / od)} | {instr_cell} |"
            )
        w("")
        med = lambda k, o: fmt_ns(res[k][o][1])
        w(
            "- medians (ns; ours v3 / ours default / Pinocchio v3 / Pinocchio wheel): "
            + "; ".join(
                f"{o} {med('ours_v3', o)} / {med('ours_default', o)} / "
                f"{' or '.join(med('pin_v3', p) for p in ps)} / {' or '.join(med('pin_wheel', p) for p in ps)}"
                for o, ps in WHOLE_ROWS
            )
        )
        w(
            f"- Pinocchio `ccrba` / `computeCentroidalMap`: v3 {fmt_ns(res['pin_v3']['centroidal_momentum_matrix'][0])}"
            f" / {fmt_ns(res['pin_v3']['centroidal_map'][0])} ns, wheel {fmt_ns(res['pin_wheel']['centroidal_momentum_matrix'][0])}"
            f" / {fmt_ns(res['pin_wheel']['centroidal_map'][0])} ns"
        )
        if "ours_default" in ins:
            w(
                "- instructions per call, ours default: "
                + ", ".join(f"{o} {ins['ours_default'][o]:.0f}" for o, _ in WHOLE_ROWS)
            )


def code_bytes(binary):
    """bytes[(model, output)]: the size of each generated function that the binary keeps as a
    symbol of its own (`nm -S`); the small ones are inlined into their caller and have none."""
    listing = subprocess.run(["nm", "-S", "-C", binary], capture_output=True, text=True).stdout
    sizes = {}
    for line in listing.splitlines():
        found = re.match(r"\S+ (\S+) \S <peers::(\w+) as articulated::generated::\w+<[^>]*>>::(\w+)_with$", line)
        if found:
            model = re.sub(r"(?<=[a-z0-9])(?=[A-Z])", "_", found.group(2)).lower()
            sizes[(model, found.group(3))] = int(found.group(1), 16)
    return sizes


def bytes_report(w, models, results, sizes):
    """Machine-code bytes beside time, per generated function (v3 build)."""
    rows = []
    for (name, *_rest) in models:
        for output, (fastest, _median) in results[name]["ours_v3"].items():
            if (name, output) in sizes:
                rows.append((sizes[(name, output)], name, output, fastest))
    if not rows:
        return
    rows.sort()
    rates = [b / ns for b, _n, _o, ns in rows]
    w("")
    w("## Code size and time")
    w("")
    w("Every generated function of the v3 build that is a function of its own in `peers` (the small")
    w("ones are inlined into their caller), with its machine-code bytes (`nm -S`) beside its time.")
    w("Straight-line code runs through all its bytes once per call, and around and past the 32 KiB")
    w("of a level-1 instruction cache the time follows the bytes, whatever the operations: the")
    w(f"{len(rates)} functions here, {rows[0][0] / 1000:.0f} KB to {rows[-1][0] / 1000:.0f} KB, ran at "
      f"{min(rates):.0f} to {max(rates):.0f} bytes per nanosecond (median {float(np.median(rates)):.0f}).")
    w("That they wait on fetching code from level 2 is an inference from that steady rate: this")
    w("VM exposes no performance counters. For such functions fewer bytes (spills, constants,")
    w("stores: see `ARCHITECTURE.md`) is what makes them faster.")
    w("")
    w("| model | output | bytes | ours v3 (ns) | bytes per ns |")
    w("|---|---|---:|---:|---:|")
    for b, name, output, ns in rows:
        w(f"| {name} | {output} | {b} | {fmt_ns(ns)} | {b / ns:.0f} |")


FRAMES_MUJOCO = """MuJoCo: n/a. Its program (`bench/peers/mujoco_timing.c`) times the dynamics terms only.
MuJoCo's `mj_kinematics` places every body (its `xpos`, `xmat`) and `mj_jacBody` gives a
body's Jacobian (world axes, at its origin); they are not timed here yet."""


def frames_report(w, models, ops, results, instr, checks):
    """The section of the frame outputs."""
    with_f = [m for m in models if ops[m[0]]["frames"]]
    if not with_f:
        return
    w("")
    w("## Frames")
    w("")
    w("The placements of a model's named frames, their Jacobians in LOCAL_WORLD_ALIGNED (the frame's")
    w("origin, world axes) and the time variations of those Jacobians, timed in the same runs as the")
    w("tables above, on the same states, after a values check: ours against Pinocchio's to 1e-10")
    w("relative to the largest entry of each frame's value, rows angular first and columns in")
    w("Pinocchio's joint order on both sides (Pinocchio's rows are linear first: its halves are")
    w("swapped). The frames are URDF links (Pinocchio's BODY frames); every call, on either side,")
    w("computes all of the model's frames listed in the heading.")
    w("")
    w("**ours**: `C::frame_placements(&q)` → `[FramePlacement; NF]` (rotation and translation),")
    w("`C::frame_jacobians_local_world_aligned(&q)` → `[SMatrix<f64, 6, NV>; NF]`,")
    w("`C::frame_jacobian_time_variations_local_world_aligned(&q, &v)` → `[SMatrix<f64, 6, NV>; NF]`,")
    w("one call each (`#[chain(…, frames = [link7])]`). **Pinocchio**: `forwardKinematics(model, data,")
    w("q)` then `updateFramePlacement(model, data, id)` per frame (not `framesForwardKinematics`, which")
    w("updates every frame of the model); `computeFrameJacobian(model, data, q, id, LOCAL_WORLD_ALIGNED,")
    w("J)` per frame (each runs the kinematics of that frame's support), and besides")
    w("`computeJointJacobians(model, data, q)` then `getFrameJacobian(model, data, id,")
    w("LOCAL_WORLD_ALIGNED, J)` per frame (the whole tree once), the faster of the two being the")
    w("figure (a ᴶ marks where that was the second); `computeJointJacobiansTimeVariation(model, data,")
    w("q, v)` then `getFrameJacobianTimeVariation(model, data, id, LOCAL_WORLD_ALIGNED, dJ)` per frame.")
    w("Each frame has its own `J` and `dJ` (6 × nv, zeroed once), as a user keeps them.")
    w("")
    w(FRAMES_MUJOCO)
    w("")
    w("In short (fastest batches; a ratio above 1 means ours is faster):")
    w("")

    def pin_best(res, k, pins):
        return min((res[k][p][0], p) for p in pins)

    for (name, *_rest) in with_f:
        res = results[name]
        parts = []
        for o, pins in FRAME_ROWS:
            p3 = pin_best(res, "pin_v3", pins)[0]
            parts.append(
                f"{o} {fmt_ratio(p3 / res['ours_v3'][o][0])} (v3), {fmt_ratio(p3 / res['ours_default'][o][0])} (default)"
            )
        w(f"- **{name}** ({', '.join(ops[name]['frames'])}), Pinocchio v3 / ours: " + "; ".join(parts))
    for (name, chain, urdf, floating) in with_f:
        res, ins = results[name], instr.get(name, {})
        frames = ops[name]["frames"]
        w("")
        w(
            f"### {name}: frames ({len(frames)} frame{'s' if len(frames) > 1 else ''}: "
            f"{', '.join(f'`{f}`' for f in frames)}; {'floating base, ' if floating else ''}"
            f"nq {ops[name]['nq']}, nv {ops[name]['nv']})"
        )
        w("")
        w("| output | ops | ours v3 (ns) | ours default (ns) | Pinocchio v3 (ns) | Pinocchio wheel (ns) | MuJoCo (ns) | Pinocchio / ours (v3) | Pinocchio / ours (default) | instructions ours v3 / Pinocchio v3 |")
        w("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for o, pins in FRAME_ROWS:
            p3, p3_which = pin_best(res, "pin_v3", pins)
            pw = pin_best(res, "pin_wheel", pins)[0]
            mark = "ᴶ" if p3_which != pins[0] else ""
            o3, od = res["ours_v3"][o][0], res["ours_default"][o][0]
            i_ours = ins.get("ours_v3", {}).get(o)
            i_pin = ins.get("pin_v3", {}).get(p3_which)
            instr_cell = (
                f"{i_ours:.0f} / {i_pin:.0f} ({i_pin / i_ours:.1f}×)" if i_ours and i_pin else "–"
            )
            w(
                f"| {o} | {ops[name]['ops'][o]} | {fmt_ns(o3)} | {fmt_ns(od)} | {fmt_ns(p3)}{mark} | "
                f"{fmt_ns(pw)} | n/a | {fmt_ratio(p3 / o3)} | {fmt_ratio(p3 / od)} | {instr_cell} |"
            )
        w("")
        med = lambda k, o: fmt_ns(res[k][o][1])
        w(
            "- medians (ns; ours v3 / ours default / Pinocchio v3 / Pinocchio wheel): "
            + "; ".join(
                f"{o} {med('ours_v3', o)} / {med('ours_default', o)} / "
                f"{' or '.join(med('pin_v3', p) for p in ps)} / {' or '.join(med('pin_wheel', p) for p in ps)}"
                for o, ps in FRAME_ROWS
            )
        )
        jac, joint = FRAME_ROWS[1][1]
        w(
            f"- Pinocchio `computeFrameJacobian` per frame / `computeJointJacobians` + `getFrameJacobian` per frame: "
            f"v3 {fmt_ns(res['pin_v3'][jac][0])} / {fmt_ns(res['pin_v3'][joint][0])} ns, "
            f"wheel {fmt_ns(res['pin_wheel'][jac][0])} / {fmt_ns(res['pin_wheel'][joint][0])} ns"
            + (
                f"; instructions (v3) {ins['pin_v3'][jac]:.0f} / {ins['pin_v3'][joint]:.0f}"
                if jac in ins.get("pin_v3", {}) and joint in ins.get("pin_v3", {})
                else ""
            )
        )
        if "ours_default" in ins:
            w(
                "- instructions per call, ours default: "
                + ", ".join(f"{o} {ins['ours_default'][o]:.0f}" for o, _ in FRAME_ROWS)
            )
        key_worst = checks[name][0]
        w(
            "- values at the first state against Pinocchio's (relative to the largest entry of each "
            "frame's value): " + ", ".join(f"{k} {e:.1e}" for k, e in key_worst if "frames" in k)
        )


CONSTRAINED_MUJOCO = """MuJoCo: n/a. Its program (`bench/peers/mujoco_timing.c`) times the dynamics terms only.
MuJoCo's equality constraints (a `weld`) are soft and solved with its contacts by its own
solver inside `mj_forward` (`mj_fwdConstraint`); they are not timed here."""


def constrained_report(w, models, ops, results, instr, checks):
    """The section of the constrained forward dynamics."""
    with_c = [m for m in models if ops[m[0]]["contacts"]]
    if not with_c:
        return
    w("")
    w("## Constrained dynamics")
    w("")
    w("Forward dynamics under contacts, `q̈` and the contact wrenches: the humanoid on its free flyer")
    w("standing on both soles, `left_foot` and `right_foot` each a six-dimensional contact (12 rows),")
    w("and the arm with its flange `link7` welded (6 rows), timed in the same runs as the tables")
    w("above, on the same states (each contact held where the state puts it, with the state's")
    w("velocities and τ), after a values check: ours against Pinocchio's, `q̈` to 1e-9 relative to")
    w("its largest entry and in Pinocchio's joint order, the wrenches `[n; f]` (in each contact's")
    w("frame, angular first on both sides: Pinocchio's `contact_force` is linear first) to 1e-9")
    w("relative to their largest entry; ours must solve every one of the 16 states.")
    w("")
    w("**Pinocchio**: `constraintDynamics(model, data, q, v, tau, contact_models, contact_datas,")
    w("settings)`, each contact a `RigidConstraintModel(CONTACT_6D, model, frame.parentJoint,")
    w("frame.placement, 0, SE3::Identity(), LOCAL)` (the link's BODY frame held to the universe, as")
    w("`tests/data/pinocchio_constraints/make_pinocchio_constraints.py` builds them),")
    w("`initConstraintDynamics` once outside the timing, `ProximalSettings(1e-12, mu = 0, max_iter =")
    w("1)`: no regularization, one solve, the exact solution (more iterations allowed, it makes a")
    w("second that only confirms the first). Each call computes its own kinematics (every joint's")
    w("placement, velocity and acceleration at q̈ = 0), `M` by CRBA and the nonlinear effects on the")
    w("way, the contacts' placements, Jacobians and drifts (and each contact's placement error, a")
    w("`log6`, which only Baumgarte gains use), then a Cholesky factorization of the KKT system (its")
    w("`ContactCholeskyDecomposition`, `M` and the contact rows together) and the solve. The wheel")
    w("column calls the wheel's prebuilt instantiation (it takes `VectorXd` inputs, which this")
    w("call passes).")
    w("")
    w("**ours**: `C::constrained_forward_dynamics(&q, &v, &τ)`, generated for the contacts `C`")
    w("declares (`contacts = [left_foot: six_d, right_foot: six_d]`; `codegen/src/trace/constrained.rs`):")
    w("one traced pass computes `M`, the nonlinear effects, the contacts' Jacobians and drifts, a")
    w("sparse `LᵀDL` of `M`, `G = J·M⁻¹·Jᵀ` through `L⁻ᵀ·Jᵀ` (which keeps each row's sparsity) and")
    w("its factorization, the forces and `q̈`, each pivot checked. `C` is a type")
    w("`bench/src/bin/peers.rs` generates for this from the model's `.chain` file (`HumanoidFeet`:")
    w("`left_foot`, `right_foot`, 12 rows; `Arm7Welded`: `link7`, 6 rows), so that each call computes")
    w("the contacts' kinematics and nothing more, like Pinocchio's contact models. Below each table,")
    w(f"`{CONSTRAINED_RUNTIME}`: the runtime's `constraint::constrained_forward_dynamics::<C, NQ, NV,")
    w("NF, R>(&q, &v, &τ, &contacts, None, &Settings::default())` on the same contacts, what a set")
    w("chosen at run time costs (a foot that lifts): five generated functions")
    w("(`mass_matrix_and_nonlinear_effects`, `frame_placements`, `frame_jacobians_local`,")
    w("`frame_velocities`, `frame_accelerations`) then a dense solve (`runtime/src/constraint.rs`:")
    w("Cholesky of `M`, `W = L⁻¹·Jᵀ`, `G = Wᵀ·W`, its Cholesky, the residual `max |J·q̈ + γ|`). *ops*")
    w("counts the generated function; for the runtime's, the five functions' (its solve not counted).")
    w("")
    w(f"`{CONSTRAINED_DERIVATIVES}` (the models generated with derivatives): **Pinocchio**")
    w("`constraintDynamics` as above, then `computeConstraintDynamicsDerivatives(model, data,")
    w("contact_models, contact_datas, settings)` (it needs the solution: a user calls both): `q̈`, the")
    w("forces and their derivatives with respect to `q`, `v` and `τ`. **ours**: `C::constrained_forward_dynamics_derivatives(&q,")
    w("&v, &τ)`, generated for the same declared contacts (`C` is generated with the derivative")
    w("outputs; `forward_dynamics_derivatives` gives it this function; `codegen/src/trace/constrained.rs`): the solve above,")
    w("then the residuals `ID(q, v, q̈) − Jᵀ·f` and `J·q̈ + γ` differentiated at the solution by")
    w("forward mode through one Newton–Euler pass with the contact wrenches as external forces, and")
    w("each column of the KKT system solved with the solve's sparse factorizations: one traced")
    w("function where that is at most 20,000 operations (the arm), composed past it (the humanoid:")
    w("257,915 operations traced; `codegen/src/generate/constrained_composed.rs`) of the solve,")
    w("`mass_matrix_inverse`, `inverse_dynamics_derivatives` at `q̈`, a traced part for the contact")
    w("terms, and at run time the KKT matrix's inverse from `M⁻¹` and `J` and its products with the")
    w("residuals' derivatives (`constraint::derivatives::composed`). Beside it,")
    w(f"`{CONSTRAINED_DERIVATIVES_RUNTIME}`: the runtime's `constraint::derivatives::forward_dynamics_derivatives_of::<C, NQ,")
    w("NV, NF, R>(&q, &v, &τ, &contacts, &[])` on the same contacts, what any subset chosen at run")
    w("time costs (`runtime/src/constraint/derivatives.rs`: generated `inverse_dynamics_derivatives`")
    w("at `q̈`, one `frame_jacobian_time_variations_local` per velocity coordinate,")
    w("`frame_acceleration_derivatives`, `frame_velocity_derivatives`, and dense products with the")
    w("blocks of the KKT matrix's inverse). Their values are checked against Pinocchio's, each other")
    w("and central differences in `tests/tests/constraint_derivatives.rs`, not here.")
    w("")
    w(CONSTRAINED_MUJOCO)
    w("")
    w("In short (fastest batches; a ratio above 1 means ours is faster):")
    w("")
    for (name, *_rest) in with_c:
        res = results[name]
        p3 = res["pin_v3"][CONSTRAINED][0]
        w(
            f"- **{name}** ({', '.join(ops[name]['contacts'])}), Pinocchio v3 / ours: "
            f"{fmt_ratio(p3 / res['ours_v3'][CONSTRAINED][0])} (v3), "
            f"{fmt_ratio(p3 / res['ours_default'][CONSTRAINED][0])} (default)"
            + (
                f"; the derivatives {fmt_ratio(res['pin_v3'][CONSTRAINED_DERIVATIVES][0] / res['ours_v3'][CONSTRAINED_DERIVATIVES][0])} (v3)"
                if CONSTRAINED_DERIVATIVES in res["ours_v3"] and CONSTRAINED_DERIVATIVES in res["pin_v3"]
                else ""
            )
        )
    for (name, chain, urdf, floating) in with_c:
        res, ins = results[name], instr.get(name, {})
        contacts = ops[name]["contacts"]
        w("")
        w(
            f"### {name}: constrained ({len(contacts)} six-dimensional contact{'s' if len(contacts) > 1 else ''}: "
            f"{', '.join(f'`{c}`' for c in contacts)}, {6 * len(contacts)} rows; "
            f"{'floating base, ' if floating else ''}nq {ops[name]['nq']}, nv {ops[name]['nv']})"
        )
        w("")
        w("| output | ops | ours v3 (ns) | ours default (ns) | Pinocchio v3 (ns) | Pinocchio wheel (ns) | MuJoCo (ns) | Pinocchio / ours (v3) | Pinocchio / ours (default) | instructions ours v3 / Pinocchio v3 |")
        w("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        o3, od = res["ours_v3"][CONSTRAINED][0], res["ours_default"][CONSTRAINED][0]
        p3, pw = res["pin_v3"][CONSTRAINED][0], res["pin_wheel"][CONSTRAINED][0]
        i_ours = ins.get("ours_v3", {}).get(CONSTRAINED)
        i_pin = ins.get("pin_v3", {}).get(CONSTRAINED)
        instr_cell = f"{i_ours:.0f} / {i_pin:.0f} ({i_pin / i_ours:.1f}×)" if i_ours and i_pin else "–"
        w(
            f"| {CONSTRAINED} | {ops[name]['ops'][CONSTRAINED]} | {fmt_ns(o3)} | {fmt_ns(od)} | {fmt_ns(p3)} | "
            f"{fmt_ns(pw)} | n/a | {fmt_ratio(p3 / o3)} | {fmt_ratio(p3 / od)} | {instr_cell} |"
        )
        w("")
        g3, gd = res["ours_v3"][CONSTRAINED_RUNTIME][0], res["ours_default"][CONSTRAINED_RUNTIME][0]
        i_g = ins.get("ours_v3", {}).get(CONSTRAINED_RUNTIME)
        w(
            f"- ours, the runtime's solve of the same contacts (`{CONSTRAINED_RUNTIME}`, "
            f"{ops[name]['ops'][CONSTRAINED_RUNTIME]} ops in its five generated functions): v3 {fmt_ns(g3)} ns "
            f"({fmt_ratio(p3 / g3)} against Pinocchio v3), default {fmt_ns(gd)} ns"
            + (f"; {i_g:.0f} instructions per call (v3)" if i_g else "")
        )
        if CONSTRAINED_DERIVATIVES in res["ours_v3"] and CONSTRAINED_DERIVATIVES in res["pin_v3"]:
            d3, dd = res["ours_v3"][CONSTRAINED_DERIVATIVES][0], res["ours_default"][CONSTRAINED_DERIVATIVES][0]
            q3, qw = res["pin_v3"][CONSTRAINED_DERIVATIVES][0], res["pin_wheel"][CONSTRAINED_DERIVATIVES][0]
            i_d = ins.get("ours_v3", {}).get(CONSTRAINED_DERIVATIVES)
            i_q = ins.get("pin_v3", {}).get(CONSTRAINED_DERIVATIVES)
            w(
                f"- the derivatives (`{CONSTRAINED_DERIVATIVES}`, {ops[name]['ops'].get(CONSTRAINED_DERIVATIVES, '–')} ops): "
                f"ours v3 {fmt_ns(d3)} ns, "
                f"default {fmt_ns(dd)} ns; Pinocchio v3 {fmt_ns(q3)} ns, wheel {fmt_ns(qw)} ns; Pinocchio / ours "
                f"{fmt_ratio(q3 / d3)} (v3), {fmt_ratio(q3 / dd)} (default)"
                + (f"; instructions ours v3 / Pinocchio v3 {i_d:.0f} / {i_q:.0f}" if i_d and i_q else "")
            )
            if CONSTRAINED_DERIVATIVES_RUNTIME in res["ours_v3"]:
                r3 = res["ours_v3"][CONSTRAINED_DERIVATIVES_RUNTIME][0]
                rd = res["ours_default"][CONSTRAINED_DERIVATIVES_RUNTIME][0]
                i_r = ins.get("ours_v3", {}).get(CONSTRAINED_DERIVATIVES_RUNTIME)
                w(
                    f"- the runtime's derivatives of the same contacts (`{CONSTRAINED_DERIVATIVES_RUNTIME}`): "
                    f"v3 {fmt_ns(r3)} ns ({fmt_ratio(q3 / r3)} against Pinocchio v3), default {fmt_ns(rd)} ns"
                    + (f"; {i_r:.0f} instructions per call (v3)" if i_r else "")
                )
        med = lambda k, o: fmt_ns(res[k][o][1])
        w(
            "- medians (ns; ours v3 / ours default / Pinocchio v3 / Pinocchio wheel): "
            f"{CONSTRAINED} {med('ours_v3', CONSTRAINED)} / {med('ours_default', CONSTRAINED)} / "
            f"{med('pin_v3', CONSTRAINED)} / {med('pin_wheel', CONSTRAINED)}; the runtime's "
            f"{med('ours_v3', CONSTRAINED_RUNTIME)} / {med('ours_default', CONSTRAINED_RUNTIME)}"
        )
        if "ours_default" in ins:
            w(
                "- instructions per call, ours default: "
                + ", ".join(f"{o} {ins['ours_default'][o]:.0f}" for o in (CONSTRAINED, CONSTRAINED_RUNTIME))
            )
        key_worst = checks[name][0]
        w(
            "- values at the first state against Pinocchio's (the worse of q̈ and the wrenches, each "
            "relative to its largest entry): " + ", ".join(f"{k} {e:.1e}" for k, e in key_worst if "constrained" in k)
        )


def native_report(w, models, ops, results, env):
    """The section of the builds for this machine's CPU, both sides."""
    w("")
    w("## Both built for this CPU")
    w("")
    w("The same calls, timed in the same rounds, with both sides built for the CPU of this")
    w(f"machine: ours with `RUSTFLAGS=\"-C target-cpu=native\"` (rustc resolves it to `{env['rustc_native']}`),")
    w(f"Pinocchio with `g++ -O3 -DNDEBUG -march=native` (`{env['gcc_native']}`), what a user who builds for")
    w("the machine gets; everything else as for v3. On a CPU with AVX-512 this adds its wider")
    w("registers and the CPU's own instruction scheduling to both. Values are checked as for the")
    w("other builds; no instruction counts (valgrind does not decode AVX-512).")
    w("")
    w("In short (Pinocchio native / ours native, the range over the six outputs of each model's")
    w("first table):")
    w("")
    pin_min = lambda res, outs: min(res["pin_native"][p][0] for p in outs)
    for (name, *_rest) in models:
        res = results[name]
        ratios = [(pin_min(res, r[1]) / res["ours_native"][r[0]][0], r[0]) for r in ROWS]
        (lo, lo_out), (hi, hi_out) = min(ratios), max(ratios)
        w(f"- **{name}**: {lo:.1f}× ({lo_out}) to {hi:.1f}× ({hi_out})")
    for (name, *_rest) in models:
        res = results[name]
        rows = [(o, pins) for o, pins, _mj in ROWS]
        rows += [(k, ["mass_matrix", "mass_matrix_world"]) for k, _ in KEPT_ROWS if k in res["ours_native"]]
        rows += [(o, pins) for o, pins in WHOLE_ROWS]
        if ops[name]["derivatives"]:
            rows += [(o, [p]) for o, p, _d, _v in DERIV_ROWS]
        if ops[name]["frames"]:
            rows += FRAME_ROWS
        if ops[name]["contacts"]:
            rows += [(CONSTRAINED, [CONSTRAINED])]
        w("")
        w(f"### {name}: native")
        w("")
        w("| output | ours native (ns) | Pinocchio native (ns) | Pinocchio / ours (native) | Pinocchio / ours (v3, above) |")
        w("|---|---:|---:|---:|---:|")
        for o, pins in rows:
            on, pn = res["ours_native"][o][0], pin_min(res, pins)
            o3, p3 = res["ours_v3"][o][0], min(res["pin_v3"][p][0] for p in pins)
            w(f"| {o} | {fmt_ns(on)} | {fmt_ns(pn)} | {fmt_ratio(pn / on)} | {fmt_ratio(p3 / o3)} |")


def derivatives_report(w, models, ops, results, instr, checks):
    """The section of the analytical derivatives."""
    with_d = [m for m in models if ops[m[0]]["derivatives"]]
    without = [m[0] for m in models if not ops[m[0]]["derivatives"]]
    w("")
    w("## Derivatives")
    w("")
    w("The analytical derivatives of inverse and forward dynamics and `M⁻¹`, timed in the same runs")
    w("as the tables above, on the same states, after a values check: ours against Pinocchio's to")
    w("1e-9 relative to the largest entry, every matrix mapped to Pinocchio's joint order;")
    w("derivatives in q along the configuration's tangent on both sides (for the free flyer the")
    w("body-frame increment). **ours**: `C::inverse_dynamics_derivatives(&q, &v, &a)` → `(∂τ/∂q,")
    w("∂τ/∂v)`, `C::forward_dynamics_derivatives(&q, &v, &τ)` → `Ok((∂q̈/∂q, ∂q̈/∂v, M⁻¹))`,")
    w("`C::mass_matrix_inverse(&q)` → `Ok(M⁻¹)`, full matrices. **Pinocchio**:")
    w("`computeRNEADerivatives(model, data, q, v, a)` (`data.dtau_dq`, `data.dtau_dv`, and `∂τ/∂a = M`")
    w("in the upper triangle of `data.M`), `computeABADerivatives(model, data, q, v, τ)` (`data.ddq_dq`,")
    w("`data.ddq_dv`, the upper triangle of `data.Minv`), `computeMinverse(model, data, q)` (the upper")
    w("triangle of `data.Minv`); the wheel column calls the same templates in the wheel's library.")
    w("**MuJoCo**: n/a, it has no analytical derivatives (`mjd_transitionFD` differentiates the")
    w("whole step by finite differences; not timed here).")
    w("")
    w("**Central differences of our own code**: the kernels `inverse_dynamics_differences` and")
    w("`forward_dynamics_differences` of `bench/src/bin/peers.rs` compute `∂τ/∂q` (resp. `∂q̈/∂q`) by")
    w("central differences of the generated `inverse_dynamics` (resp. `forward_dynamics`) along the")
    w("tangent (`control::tangent::retract`, step 1e-6): 2·NV calls and 2·NV retractions. That is")
    w("the q-half only: `∂/∂v` by differences would cost as much again, which the analytical")
    w("functions return besides (and `M⁻¹` for forward dynamics). The column \"2·NV × value\" is")
    w("2·NV times the value function's own figure in the table above, for comparison.")
    w("")
    if without:
        w(f"Models generated without the derivative outputs: {', '.join(without)}.")
    if "humanoid" in ops and ops["humanoid"]["derivatives"]:
        h = ops["humanoid"]["ops"]
        w("The humanoid's are behind the feature `humanoid-derivatives` of `articulated-bench`, which")
        w(f"`run.sh` turns on: `inverse_dynamics_derivatives` ({h['inverse_dynamics_derivatives']:,} operations),")
        w(f"`forward_dynamics_derivatives` ({h['forward_dynamics_derivatives']:,}) and `mass_matrix_inverse`")
        w(f"({h['mass_matrix_inverse']:,}) took the release build of the `peers` binary from 53 to 120 s for")
        w("x86-64-v3 and from 96 to 204 s for the default target (`cargo build --timings`, the binary's")
        w("own unit, measured once while adding them, with another build running beside it), when")
        w("`forward_dynamics_derivatives` was one traced function of 131,378 operations, 54 s of release")
        w("build on a crate of its own; it is now composed of the other two, `forward_dynamics` and two")
        w("products (`codegen/src/generate/composed.rs`), and compiles as nothing more than those.")
        w("In the test profile (opt-level 1, debug info) that CI's `cargo test --workspace` builds the")
        w("binary with they would cost 2.5–3 min more, hence the feature, off by default.")
    w("")
    w("In short (fastest batches; a ratio above 1 means ours is faster):")
    w("")
    for (name, *_rest) in with_d:
        res = results[name]
        parts = []
        for ours_out, pin_out, diff, _value in DERIV_ROWS:
            p3 = res["pin_v3"][pin_out][0]
            parts.append(
                f"{ours_out} {fmt_ratio(p3 / res['ours_v3'][ours_out][0])} (v3), "
                f"{fmt_ratio(p3 / res['ours_default'][ours_out][0])} (default)"
            )
        w(f"- **{name}**, Pinocchio v3 / ours: " + "; ".join(parts))
        parts = []
        for ours_out, _pin, diff, _value in DERIV_ROWS:
            if diff:
                parts.append(
                    f"{diff} / {ours_out} {fmt_ratio(res['ours_v3'][diff][0] / res['ours_v3'][ours_out][0])} (v3), "
                    f"{fmt_ratio(res['ours_default'][diff][0] / res['ours_default'][ours_out][0])} (default)"
                )
        w(f"- **{name}**, central differences of ours / ours analytical: " + "; ".join(parts))
    for (name, chain, urdf, floating) in with_d:
        res, ins = results[name], instr.get(name, {})
        nv = ops[name]["nv"]
        w("")
        w(f"### {name}: derivatives ({'floating base, ' if floating else ''}nq {ops[name]['nq']}, nv {nv})")
        w("")
        w("| output | ops | ours v3 (ns) | ours default (ns) | Pinocchio v3 (ns) | Pinocchio wheel (ns) | MuJoCo | Pinocchio / ours (v3) | Pinocchio / ours (default) | instructions ours v3 / Pinocchio v3 |")
        w("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for ours_out, pin_out, _diff, _value in DERIV_ROWS:
            o3, od = res["ours_v3"][ours_out][0], res["ours_default"][ours_out][0]
            p3, pw = res["pin_v3"][pin_out][0], res["pin_wheel"][pin_out][0]
            i_ours = ins.get("ours_v3", {}).get(ours_out)
            i_pin = ins.get("pin_v3", {}).get(pin_out)
            instr_cell = (
                f"{i_ours:.0f} / {i_pin:.0f} ({i_pin / i_ours:.1f}×)" if i_ours and i_pin else "–"
            )
            w(
                f"| {ours_out} | {ops[name]['ops'][ours_out]} | {fmt_ns(o3)} | {fmt_ns(od)} | "
                f"{fmt_ns(p3)} | {fmt_ns(pw)} | n/a | {fmt_ratio(p3 / o3)} | {fmt_ratio(p3 / od)} | {instr_cell} |"
            )
        w("")
        w(f"Against central differences of our own code (2·NV = {2 * nv} calls of the value function):")
        w("")
        w("| derivative | build | analytical (ns) | central differences in q (ns) | differences / analytical | 2·NV × value (ns) | instructions analytical / differences |")
        w("|---|---|---:|---:|---:|---:|---:|")
        for ours_out, _pin, diff, value in DERIV_ROWS:
            if not diff:
                continue
            for k, label in (("ours_v3", "v3"), ("ours_default", "default")):
                a, d = res[k][ours_out][0], res[k][diff][0]
                ia, idf = ins.get(k, {}).get(ours_out), ins.get(k, {}).get(diff)
                instr_cell = f"{ia:.0f} / {idf:.0f} ({idf / ia:.1f}×)" if ia and idf else "–"
                w(
                    f"| {ours_out} | {label} | {fmt_ns(a)} | {fmt_ns(d)} | {fmt_ratio(d / a)} | "
                    f"{fmt_ns(2 * nv * res[k][value][0])} | {instr_cell} |"
                )
        w("")
        med = lambda k, o: fmt_ns(res[k][o][1])
        w(
            "- medians (ns; ours v3 / ours default / Pinocchio v3 / Pinocchio wheel): "
            + "; ".join(
                f"{o} {med('ours_v3', o)} / {med('ours_default', o)} / {med('pin_v3', p)} / {med('pin_wheel', p)}"
                for o, p, _d, _v in DERIV_ROWS
            )
            + "; central differences (ours v3 / ours default): "
            + "; ".join(f"{d} {med('ours_v3', d)} / {med('ours_default', d)}" for _o, _p, d, _v in DERIV_ROWS if d)
        )
        if "ours_default" in ins:
            w(
                "- instructions per call, ours default: "
                + ", ".join(f"{o} {ins['ours_default'][o]:.0f}" for o, *_ in DERIV_ROWS)
            )
        key_worst = checks[name][0]
        w(
            "- values at the first state against Pinocchio's (relative to the largest entry): "
            + ", ".join(f"{k} {e:.1e}" for k, e in key_worst if "derivatives" in k or "differences" in k)
        )


WHAT = """## What each figure includes

Every program reads the same states (16, cycled; drawn once by `run.py` with a fixed seed: q
uniform in [−1, 1] per revolute coordinate, a random unit quaternion and a position in [−1, 1]³
for a free base, v in [−2, 2], a in [−5, 5], τ = Pinocchio's `rnea(q, v, a)`), each converted to
the program's own convention and joint order (Pinocchio's free-flyer quaternion is `[x, y, z, w]`,
ours `[w, x, y, z]`; MuJoCo's free joint takes its linear velocity in the world frame). Before any
timing, each program's outputs at the first state are mapped back and compared with Pinocchio's:
ours (both builds) must agree to 1e-9 relative (the quantities of the whole system to 1e-10) or
the run stops; MuJoCo's difference is shown above. A timed call's inputs and result go through `std::hint::black_box` (Rust) or an empty
`asm volatile` with a memory clobber (C, C++) so that nothing is hoisted out of the loop.

- **ours**: one call of the generated function, e.g. `Arm7::mass_matrix(&q)`, which returns the
  full symmetric `M` as an `SMatrix`; `forward_dynamics` returns `Result<SVector, _>` after its
  pivot checks; `mass_matrix_and_nonlinear_effects` is one function sharing the kinematics.
  *ops* is the generator's count of the function's arithmetic (`C::MASS_MATRIX_OPS.total()`, …).
- **Pinocchio**: `crba(model, data, q)` fills **only the upper triangle** of `data.M` (as a user
  calls it; ours fills both); `nonLinearEffects`, `computeGeneralizedGravity`, `rnea`,
  `aba(model, data, q, v, tau)`; "M and nle" is `crba` then `nonLinearEffects`. `crba` and `aba`
  are also timed with `Convention::WORLD`, and the faster of the two conventions is the figure.
  Inputs are `Eigen::Ref<const VectorXd>` views made once. The v3 build defines
  `EIGEN_MAX_ALIGN_BYTES=16` and `EIGEN_MALLOC_ALREADY_ALIGNED=1`: the URDF parser is the wheel's
  prebuilt `libpinocchio_parsers` (baseline x86-64, 16-byte Eigen alignment), and the model it
  fills must have the same layout and allocator on both sides; the algorithms themselves are
  compiled here with AVX2 and FMA.
- **MuJoCo**: each call copies its inputs into `mjData` (how MuJoCo takes them), then runs the
  smallest set of pipeline stages that yields the quantity: M = `mj_kinematics`, `mj_comPos`,
  `mj_crb` (MuJoCo's sparse `d->M`; with `mj_fullM` to a dense matrix in the list above); nle =
  `mj_kinematics`, `mj_comPos`, `mj_comVel`, `mj_rne(flg_acc = 0)`; gravity = `mj_kinematics`,
  `mj_comPos`, `mj_rne(flg_acc = 0)` at zero velocity (the velocity terms zeroed once, outside
  the loop); inverse dynamics = `mj_kinematics`, `mj_comPos`, `mj_comVel`, `mj_rne(flg_acc = 1)`;
  forward dynamics = `mj_kinematics`, `mj_comPos`, `mj_crb`, `mj_factorM`, `mj_comVel`,
  `mj_rne(flg_acc = 0)`, τ − bias, `mj_solveM`; "M and nle" = `mj_kinematics`, `mj_comPos`,
  `mj_crb`, `mj_comVel`, `mj_rne(flg_acc = 0)`. The whole `mj_forward` and `mj_inverse` are
  listed too. The model is MuJoCo's own import of the same URDF (`MjSpec.from_file`; a
  `freejoint` on the root link for floating models; contacts, constraints, limits, springs,
  dampers, actuation and sensors disabled; no armature or damping; inertias kept as written, not
  from geoms; fixed links fused into their parents, which does not change the dynamics), saved as
  a binary `.mjb` (`target/peers/models/`, with a rounded `.xml` beside it for reading). MuJoCo
  computes in its own coordinates (a body's inertia about its centre of mass, its
  principal axes), so its values differ from Pinocchio's in the last digits.
- **whole system, ours**: one call of the generated function, e.g. `Arm7::centroidal_momentum(&q, &v)`
  (`SVector<f64, 6>`, `[k_G; p]`), `Arm7::kinetic_energy(&q, &v)` (`f64`),
  `Arm7::coriolis_matrix(&q, &v)` (`SMatrix<f64, NV, NV>`). **Pinocchio**:
  `centerOfMass(model, data, q, false)` (`false`: not the subtrees' centres of mass),
  `centerOfMass(model, data, q, v, false)` (`data.vcom[0]`), `jacobianCenterOfMass(model, data, q,
  false)`, `computeCentroidalMomentum(model, data, q, v)`, `ccrba(model, data, q, v)` (A_G, and
  besides h_G = A_G v and the centroidal inertia `Ig`: more than our `centroidal_momentum_matrix`)
  or `computeCentroidalMap(model, data, q)` (A_G alone), `computeKineticEnergy(model, data, q, v)`,
  `computePotentialEnergy(model, data, q)` (−Σ m gᵀ x, as ours), `computeCoriolisMatrix(model,
  data, q, v)` (the same matrix as ours on these models: fixed bases and a free flyer).
- **frames, ours**: one call computes every frame of the model (`Arm7::frame_placements(&q)` →
  `[FramePlacement<f64>; 1]`; the humanoid's four in one call), as described in the section
  [Frames](#frames); **Pinocchio**: the calls listed there, one per frame after the kinematics.
- **constrained, ours**: one call of the runtime's `constraint::constrained_forward_dynamics`
  (the five generated functions it needs, then its solve), as described in the section
  [Constrained dynamics](#constrained-dynamics); **Pinocchio**: one call of `constraintDynamics`.
- **instructions**: `valgrind --tool=callgrind` on `PROGRAM --calls K MODEL OUTPUT`,
  (Ir(K = 1024) − Ir(K = 0)) / K: one call plus the loop around it, independent of the load.

## Notes

- This is a shared 2-core VM and another developer builds on it: take a single ns figure as
  ±15 %. The programs run alternately, in a rotating order, in each round, so the ratios within
  one run compare; the instruction counts do not depend on the load.
- Code placement moves our largest functions by more than that between builds: binaries that
  differ only in unrelated code (one more model in `peers.rs`, a few lines elsewhere) timed the
  very same machine code of arm7's `mass_matrix_and_nonlinear_effects` (default target) at
  180 and 250 ns, and `forward_dynamics` at 220 and 281 ns, steadily, run after run (the
  function 64-byte aligned in both, moved by 128 bytes). Such a figure belongs to one binary;
  the instruction counts do not move.
- The two Eigen definitions of the Pinocchio v3 build cost nothing measurable: a build without
  them, which loads the model from Pinocchio's own serialization instead of the URDF parser
  (so that no prebuilt code touches it), timed within ±5 % of it, some outputs faster and some
  slower (arm7, checked once while writing this comparison).
- The Pinocchio and MuJoCo figures include their generality (any model at run time: joint
  variants, loops over the tree, `Data` in memory); ours is straight-line code for one model,
  compiled with its constants. That is the point of the comparison, not a flaw of either side.
- Nothing from Pinocchio's or MuJoCo's sources is in this repository: the wheels are installed
  into `target/peers/venv` by `run.sh`.
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--batches", type=int, default=200)
    ap.add_argument("--quick", action="store_true", help="2 rounds of 20 batches, no callgrind (a dry run)")
    ap.add_argument(
        "--throughput-only", action="store_true",
        help="measure the states per second only, and rewrite BENCHMARKS.md with the other figures of the last full run "
        "(with none here, that section alone, in place)",
    )
    ap.add_argument(
        "--contact-only", action="store_true",
        help="measure the contact simulation only, and rewrite BENCHMARKS.md with the other figures of the last full run",
    )
    ap.add_argument(
        "--python-only", action="store_true",
        help="measure the speed from Python only (bench/python/timing.py), and rewrite that section of BENCHMARKS.md in place",
    )
    args = ap.parse_args()
    if args.python_only:
        figures = python_figures(int(environment()["nproc"]))
        last = os.path.join(OUT, "last_run.json")
        if os.path.exists(last):
            # Kept with the last full run's figures, for the other reruns' rewrites.
            with open(last) as f:
                d = json.load(f)
            d["python"] = figures
            with open(last, "w") as f:
                json.dump(d, f)
        with open(os.path.join(ROOT, "BENCHMARKS.md"), encoding="utf-8") as f:
            text = f.read()
        write_report(splice_python(text, figures))
        return
    if args.contact_only:
        with open(os.path.join(OUT, "last_run.json")) as f:
            d = json.load(f)
        # The header keeps the full run's commit and date; this section states its own.
        d["contact"] = contact()
        with open(os.path.join(OUT, "last_run.json"), "w") as f:
            json.dump(d, f)
        args.rounds, args.batches = d.get("rounds", 7), d.get("batches", 200)
        write_report(report(d["env"], MODELS, d["ops"], d["results"], d["instr"], d["checks"], args,
                            d["load_end"], d.get("thr"), d.get("contact"), d.get("python")))
        return
    if args.quick:
        args.rounds, args.batches = 2, 20
    if args.throughput_only and not os.path.exists(os.path.join(OUT, "last_run.json")):
        # No full run here to rewrite the rest from: this section alone, in place.
        throughput_states()
        thr = throughput(int(environment()["nproc"]))
        with open(os.path.join(ROOT, "BENCHMARKS.md"), encoding="utf-8") as f:
            text = f.read()
        write_report(splice_throughput(text, thr))
        return
    if args.throughput_only:
        with open(os.path.join(OUT, "last_run.json")) as f:
            d = json.load(f)
        # The header keeps the full run's commit and date; this section states its own.
        d["thr"] = throughput(int(d["env"]["nproc"]))
        with open(os.path.join(OUT, "last_run.json"), "w") as f:
            json.dump(d, f)
        args.rounds, args.batches = d.get("rounds", 7), d.get("batches", 200)
        write_report(report(d["env"], MODELS, d["ops"], d["results"], d["instr"], d["checks"], args, d["load_end"], d["thr"], d.get("contact"), d.get("python")))
        return
    env = environment()
    progs, ops, checks = {}, {}, {}
    for entry in MODELS:
        name, chain, urdf, floating = entry
        log(f"model {name}: building Pinocchio's and MuJoCo's models, drawing the states")
        pm = pinocchio_model(urdf, floating)
        common = pinocchio_joints(pm)
        mm = mujoco_model(name, urdf, floating)
        layout = run_json([ours_binary("v3"), "--layout", name])
        ops[name] = layout
        progs[name] = programs(entry, layout["frames"], layout["contacts"])
        maps = {
            "ours": Map(common, layout["joints"], layout["nq"], layout["nv"], False),
            "mujoco": Map(common, mujoco_joints(mm), mm.nq, mm.nv, True),
        }
        states = draw_states(pm, name)
        write_states(os.path.join(OUT, "states", f"{name}.pin.txt"), states, pm.nq, pm.nv)
        for conv in ("ours", "mujoco"):
            mp = maps[conv]
            write_states(
                os.path.join(OUT, "states", f"{name}.{conv}.txt"),
                [mp.state(s) for s in states], mp.nq, mp.nv,
            )
        log(f"model {name}: checking values")
        checks[name] = check_values(
            entry, progs[name], maps, states[0], layout["derivatives"], layout["frames"],
            layout["contacts"],
        )
    results = time_all(MODELS, progs, args.rounds, args.batches)
    thr = throughput(int(env["nproc"]))
    contact_figures = contact()
    py_figures = python_figures(int(env["nproc"]))
    instr = {}
    if not args.quick:
        def which(name):
            ours = [r[0] for r in ROWS + WHOLE_ROWS] + [k for k, _ in KEPT_ROWS]
            pin = sorted({p for r in ROWS + WHOLE_ROWS for p in r[1]})
            if ops[name]["derivatives"]:
                ours += [r[0] for r in DERIV_ROWS] + [r[2] for r in DERIV_ROWS if r[2]]
                pin += [r[1] for r in DERIV_ROWS]
            if ops[name]["frames"]:
                ours += [r[0] for r in FRAME_ROWS]
                pin += [p for r in FRAME_ROWS for p in r[1]]
            if ops[name]["contacts"]:
                ours += [CONSTRAINED, CONSTRAINED_RUNTIME]
                pin += [CONSTRAINED]
                if ops[name]["derivatives"]:
                    ours += [CONSTRAINED_DERIVATIVES, CONSTRAINED_DERIVATIVES_RUNTIME]
                    pin += [CONSTRAINED_DERIVATIVES]
            return {"ours_v3": ours, "ours_default": ours, "pin_v3": pin, "mujoco": [r[2] for r in ROWS]}

        instr = instructions(MODELS, progs, which)
    load_end = open("/proc/loadavg").read().split()[:3]
    # The raw figures, should the report need redoing (target/, not committed).
    with open(os.path.join(OUT, "last_run.json"), "w") as f:
        json.dump(dict(env=env, ops=ops, results=results, instr=instr, checks=checks, load_end=load_end,
                       thr=thr, contact=contact_figures, python=py_figures, rounds=args.rounds,
                       batches=args.batches), f)
    write_report(report(env, MODELS, ops, results, instr, checks, args, load_end, thr, contact_figures, py_figures))


def write_report(text):
    """BENCHMARKS.md, written whole (a temporary file renamed into place)."""
    target = os.path.join(ROOT, "BENCHMARKS.md")
    fd, tmp = tempfile.mkstemp(dir=ROOT, prefix=".BENCHMARKS.", suffix=".tmp")
    with os.fdopen(fd, "w") as f:
        f.write(text)
    os.replace(tmp, target)
    log(f"wrote {target}")


if __name__ == "__main__":
    main()
