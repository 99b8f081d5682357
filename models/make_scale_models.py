"""Writes the two models for scale, each as `.chain` and URDF from the same numbers:

- `humanoid.{chain,urdf}`: a floating-base humanoid, 31 joints plus the free base (37 velocity
  coordinates): a 3-DOF waist, a 2-DOF neck, 7-DOF arms (shoulder pitch/roll/yaw, elbow,
  wrist yaw/pitch/roll), 6-DOF legs (hip yaw/roll/pitch, knee, ankle pitch/roll), and two
  bodies on fixed joints (an IMU in the chest, a camera in the head) that the front ends merge.
- `chain50.{chain,urdf}`: a 50-body serial chain on a fixed base, revolute joints whose axes
  cycle z, y, x, y, with tilted joint frames.

The numbers are ours, documented here, not a vendor's. The humanoid's segment masses are de
Leva's (1996, "Adjustments to Zatsiorsky-Seluyanov's segment inertia parameters", male) for a
75 kg, 1.75 m person: pelvis 11.17 %, abdomen and chest together 32.29 %, head 6.94 %, upper
arm 2.71 %, forearm 1.62 %, hand 0.61 %, thigh 14.16 %, shank 4.33 %, foot 1.37 %; every
intermediate link between two joints of one group (the housings of a robot's motors) adds
0.4 kg. Segments are solid cylinders (boxes for the pelvis, the torso and the feet) about
their own principal axes, which are then tilted by a small fixed rotation, so that every
inertia tensor is full, as in real descriptions; centres of mass sit slightly off the joint
axes for the same reason. Joint frames follow a standing pose at q = 0 with the shoulders
rolled by ±0.2 rad, as on many robots.

The `.chain` files put the humanoid on a free base with a quaternion (`free(quaternion)`,
Pinocchio's free flyer); the URDF describes the tree under it, rooted at the pelvis (load it
with `floating` for a free base with Euler angles, or with Pinocchio's `JointModelFreeFlyer`).
Both files hold the same numbers, printed with `repr` (shortest round trip), so they are
identical in double precision.

Run from anywhere: `python3 models/make_scale_models.py` (no dependencies beyond Python 3).
"""
import math
import os
import random

HERE = os.path.dirname(os.path.abspath(__file__))


def rot(rpy):
    """R = Rz(yaw) Ry(pitch) Rx(roll), URDF's convention."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]


def tilted(principal, rpy):
    """R diag(principal) Rᵀ, symmetrized exactly."""
    R = rot(rpy)
    I = [[sum(R[i][k] * principal[k] * R[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
    for i in range(3):
        for j in range(i):
            I[i][j] = I[j][i]
    return I


def cylinder(mass, length, radius, axis):
    """Principal moments of a solid cylinder about its centre, its length along `axis`."""
    along = 0.5 * mass * radius**2
    across = mass * (3 * radius**2 + length**2) / 12
    return [along if a == axis else across for a in "xyz"]


def box(mass, x, y, z):
    return [mass * (y * y + z * z) / 12, mass * (x * x + z * z) / 12, mass * (x * x + y * y) / 12]


class Model:
    def __init__(self, name, type_name, doc):
        self.name, self.type_name, self.doc = name, type_name, doc
        self.bodies = []  # (name, mass, com, inertia)
        self.joints = []  # (name, kind, axis, parent, child, xyz, rpy)

    def body(self, name, mass, com, inertia):
        self.bodies.append((name, mass, com, inertia))

    def joint(self, name, kind, axis, parent, child, xyz, rpy=(0.0, 0.0, 0.0)):
        self.joints.append((name, kind, axis, parent, child, list(xyz), list(rpy)))

    def chain_text(self, root_joint):
        v = repr
        vec = lambda x: "[" + ", ".join(v(float(c)) for c in x) + "]"
        mat = lambda m: "[" + ", ".join(vec(r) for r in m) + "]"
        out = [f"/// {line}".rstrip() for line in self.doc]
        out.append(f"/// Written by `models/make_scale_models.py`; edit that script, not this file.")
        out.append(f"pub chain {self.type_name} {{")
        out.append("    gravity: [0.0, 0.0, -9.81];")
        out.append("")
        for name, mass, com, inertia in self.bodies:
            out.append(f"    body {name} {{ mass: {v(float(mass))}, com: {vec(com)}, inertia: {mat(inertia)} }}")
        out.append("")
        if root_joint:
            out.append(root_joint)
        for name, kind, axis, parent, child, xyz, rpy in self.joints:
            k = "fixed" if kind == "fixed" else f"revolute({axis})"
            extra = f", xyz: {vec(xyz)}"
            if any(rpy):
                extra += f", rpy: {vec(rpy)}"
            out.append(f"    joint {name}: {k} {{ parent: {parent}, child: {child}{extra} }}")
        out.append("}")
        return "\n".join(out) + "\n"

    def urdf_text(self, base_link):
        v = lambda x: repr(float(x))
        out = ['<?xml version="1.0"?>', f"<!-- {' '.join(self.doc)} -->",
               "<!-- Written by models/make_scale_models.py; edit that script, not this file. -->",
               f'<robot name="{self.name}">']
        if base_link:
            # The base carries mass, as a robot's does: a URDF loaded with a free base above it
            # then has a regular mass matrix. Fixed to the world, it adds nothing.
            I = box(4.0, 0.2, 0.2, 0.1)
            out.append(
                f'  <link name="{base_link}"><inertial><origin xyz="0.0 0.0 0.05" rpy="0.0 0.0 0.0"/>'
                f'<mass value="4.0"/><inertia ixx="{v(I[0])}" iyy="{v(I[1])}" izz="{v(I[2])}" '
                f'ixy="0.0" ixz="0.0" iyz="0.0"/></inertial></link>'
            )
        unit = {"x": "1.0 0.0 0.0", "y": "0.0 1.0 0.0", "z": "0.0 0.0 1.0"}
        for name, mass, com, I in self.bodies:
            out.append(
                f'  <link name="{name}"><inertial><origin xyz="{v(com[0])} {v(com[1])} {v(com[2])}" rpy="0.0 0.0 0.0"/>'
                f'<mass value="{v(mass)}"/><inertia ixx="{v(I[0][0])}" iyy="{v(I[1][1])}" izz="{v(I[2][2])}" '
                f'ixy="{v(I[0][1])}" ixz="{v(I[0][2])}" iyz="{v(I[1][2])}"/></inertial></link>'
            )
        for name, kind, axis, parent, child, xyz, rpy in self.joints:
            parent = base_link if parent == "world" else parent
            origin = f'<origin xyz="{v(xyz[0])} {v(xyz[1])} {v(xyz[2])}" rpy="{v(rpy[0])} {v(rpy[1])} {v(rpy[2])}"/>'
            if kind == "fixed":
                out.append(f'  <joint name="{name}" type="fixed"><parent link="{parent}"/><child link="{child}"/>{origin}</joint>')
            else:
                out.append(
                    f'  <joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>{origin}'
                    f'<axis xyz="{unit[axis]}"/><limit lower="-10" upper="10" effort="1000" velocity="100"/></joint>'
                )
        out.append("</robot>")
        return "\n".join(out) + "\n"


def humanoid():
    m = Model(
        "humanoid",
        "Humanoid",
        [
            "A floating-base humanoid: pelvis on a free quaternion base, a 3-DOF waist, a 2-DOF neck,",
            "7-DOF arms and 6-DOF legs (31 joints, 37 velocity coordinates), and an IMU and a camera on",
            "fixed joints. Segment masses from de Leva (1996) for a 75 kg, 1.75 m person; full inertia",
            "tensors; see `make_scale_models.py` for every number. `humanoid.urdf` holds the same tree",
            "under the pelvis.",
        ],
    )
    total = 75.0
    housing = 0.4
    tilt = [0.06, -0.04, 0.05]

    def seg(name, mass, com, principal, rpy=tilt):
        m.body(name, mass, com, tilted(principal, rpy))

    def housing_link(name):
        seg(name, housing, [0.003, -0.002, 0.004], cylinder(housing, 0.06, 0.035, "z"))

    # Pelvis and torso.
    seg("pelvis", 0.1117 * total, [0.0, 0.0, 0.02], box(0.1117 * total, 0.18, 0.30, 0.14))
    housing_link("waist_yaw_link")
    housing_link("waist_roll_link")
    torso_mass = 0.3229 * total
    seg("torso", torso_mass, [0.01, 0.0, 0.22], box(torso_mass, 0.22, 0.34, 0.50))
    seg("imu", 0.1, [0.0, 0.0, 0.0], box(0.1, 0.04, 0.04, 0.02))
    housing_link("neck_yaw_link")
    head_mass = 0.0694 * total
    seg("head", head_mass, [0.01, 0.0, 0.11], box(head_mass, 0.20, 0.16, 0.24))
    seg("camera", 0.15, [0.0, 0.0, 0.0], box(0.15, 0.03, 0.10, 0.03))

    m.joint("waist_yaw", "revolute", "z", "world", "waist_yaw_link", [0.0, 0.0, 0.1])
    m.joint("waist_roll", "revolute", "x", "waist_yaw_link", "waist_roll_link", [0.0, 0.0, 0.04])
    m.joint("waist_pitch", "revolute", "y", "waist_roll_link", "torso", [0.0, 0.0, 0.04])
    m.joint("imu_mount", "fixed", None, "torso", "imu", [0.05, 0.0, 0.25], [0.0, 0.0, 0.1])
    m.joint("neck_yaw", "revolute", "z", "torso", "neck_yaw_link", [0.0, 0.0, 0.5])
    m.joint("neck_pitch", "revolute", "y", "neck_yaw_link", "head", [0.0, 0.0, 0.05])
    m.joint("camera_mount", "fixed", None, "head", "camera", [0.09, 0.0, 0.12], [0.0, 0.15, 0.0])

    # Arms: left (+y) and right (−y), mirrored.
    for side, s in (("left", 1.0), ("right", -1.0)):
        housing_link(f"{side}_shoulder_pitch_link")
        housing_link(f"{side}_shoulder_roll_link")
        upper = 0.0271 * total
        seg(f"{side}_upper_arm", upper, [0.005, s * 0.01, -0.13], cylinder(upper, 0.30, 0.045, "z"))
        fore = 0.0162 * total
        seg(f"{side}_forearm", fore, [0.0, s * 0.005, -0.12], cylinder(fore, 0.27, 0.035, "z"))
        housing_link(f"{side}_wrist_yaw_link")
        housing_link(f"{side}_wrist_pitch_link")
        hand = 0.0061 * total
        seg(f"{side}_hand", hand, [0.01, 0.0, -0.06], box(hand, 0.04, 0.09, 0.16))
        m.joint(f"{side}_shoulder_pitch", "revolute", "y", "torso", f"{side}_shoulder_pitch_link",
                [0.0, s * 0.2, 0.42], [s * 0.2, 0.0, 0.0])
        m.joint(f"{side}_shoulder_roll", "revolute", "x", f"{side}_shoulder_pitch_link",
                f"{side}_shoulder_roll_link", [0.0, s * 0.05, 0.0], [-s * 0.2, 0.0, 0.0])
        m.joint(f"{side}_shoulder_yaw", "revolute", "z", f"{side}_shoulder_roll_link",
                f"{side}_upper_arm", [0.0, 0.0, -0.04])
        m.joint(f"{side}_elbow", "revolute", "y", f"{side}_upper_arm", f"{side}_forearm", [0.0, 0.0, -0.30])
        m.joint(f"{side}_wrist_yaw", "revolute", "z", f"{side}_forearm", f"{side}_wrist_yaw_link", [0.0, 0.0, -0.27])
        m.joint(f"{side}_wrist_pitch", "revolute", "y", f"{side}_wrist_yaw_link", f"{side}_wrist_pitch_link",
                [0.0, 0.0, -0.03])
        m.joint(f"{side}_wrist_roll", "revolute", "x", f"{side}_wrist_pitch_link", f"{side}_hand",
                [0.0, 0.0, -0.03])

    # Legs.
    for side, s in (("left", 1.0), ("right", -1.0)):
        housing_link(f"{side}_hip_yaw_link")
        housing_link(f"{side}_hip_roll_link")
        thigh = 0.1416 * total
        seg(f"{side}_thigh", thigh, [0.01, s * 0.005, -0.18], cylinder(thigh, 0.42, 0.075, "z"))
        shank = 0.0433 * total
        seg(f"{side}_shank", shank, [0.0, 0.0, -0.17], cylinder(shank, 0.42, 0.05, "z"))
        housing_link(f"{side}_ankle_pitch_link")
        foot = 0.0137 * total
        seg(f"{side}_foot", foot, [0.04, 0.0, -0.045], box(foot, 0.25, 0.10, 0.06))
        m.joint(f"{side}_hip_yaw", "revolute", "z", "world", f"{side}_hip_yaw_link", [0.0, s * 0.09, -0.07])
        m.joint(f"{side}_hip_roll", "revolute", "x", f"{side}_hip_yaw_link", f"{side}_hip_roll_link",
                [0.0, 0.0, -0.05])
        m.joint(f"{side}_hip_pitch", "revolute", "y", f"{side}_hip_roll_link", f"{side}_thigh", [0.0, 0.0, -0.03])
        m.joint(f"{side}_knee", "revolute", "y", f"{side}_thigh", f"{side}_shank", [0.0, 0.0, -0.42])
        m.joint(f"{side}_ankle_pitch", "revolute", "y", f"{side}_shank", f"{side}_ankle_pitch_link",
                [0.0, 0.0, -0.42])
        m.joint(f"{side}_ankle_roll", "revolute", "x", f"{side}_ankle_pitch_link", f"{side}_foot", [0.0, 0.0, -0.03])

    # The free base's child is the pelvis: joints written with parent "world" above hang from it.
    m.joints = [(n, k, a, "pelvis" if p == "world" else p, c, x, r) for (n, k, a, p, c, x, r) in m.joints]
    chain = m.chain_text("    joint base: free(quaternion) { parent: world, child: pelvis }")
    return chain, m.urdf_text(None)


def chain50():
    rng = random.Random(50)
    m = Model(
        "chain50",
        "Chain50",
        [
            "A 50-body serial chain on a fixed base: revolute joints whose axes cycle z, y, x, y, links",
            "0.08 to 0.12 m long, masses from 2 kg down to 0.25 kg, full inertia tensors, joint frames",
            "tilted by up to 0.1 rad (seeded; see `make_scale_models.py`). `chain50.urdf` holds the same",
            "numbers.",
        ],
    )
    axes = "zyxy"
    parent = "world"
    length = 0.1
    for i in range(50):
        mass = round(2.0 - 1.75 * i / 49, 6)
        next_length = round(rng.uniform(0.08, 0.12), 4)
        com = [round(rng.uniform(-0.01, 0.01), 4), round(rng.uniform(-0.01, 0.01), 4), round(next_length / 2, 4)]
        principal = cylinder(mass, next_length, 0.03, "z")
        rpy = [round(rng.uniform(-0.3, 0.3), 3) for _ in range(3)]
        name = f"link{i + 1}"
        m.body(name, mass, com, tilted(principal, rpy))
        joint_rpy = [round(rng.uniform(-0.1, 0.1), 3) for _ in range(3)]
        m.joint(f"j{i + 1}", "revolute", axes[i % 4], parent, name, [0.0, 0.0, length], joint_rpy)
        parent, length = name, next_length
    return m.chain_text(None), m.urdf_text("base")


def write(name, text):
    path = os.path.join(HERE, name)
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)
    print("wrote", path)


if __name__ == "__main__":
    chain, urdf = humanoid()
    write("humanoid.chain", chain)
    write("humanoid.urdf", urdf)
    chain, urdf = chain50()
    write("chain50.chain", chain)
    write("chain50.urdf", urdf)
