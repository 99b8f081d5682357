"""Pinocchio reference values for every URDF of the PyPI package `example-robot-data` ->
`tests/data/real_robots/pinocchio-real-robots.json`, and verbatim copies of the URDFs it loads ->
`tests/data/real_robots/urdf/`.

Runs on our machines, NOT in CI (CI has no Pinocchio). To regenerate (from anywhere):

    pip install pin numpy                      # Pinocchio 4.1 (`pin` does not pull the robots in)
    pip download --no-deps example-robot-data==6.0.0 -d /tmp/erd
    unzip -q -o /tmp/erd/example_robot_data-6.0.0-0-py3-none-any.whl -d /tmp/erd/whl
    python tests/data/real_robots/make_real_robots.py /tmp/erd/whl

The argument is the unzipped wheel (or the `.../share/example-robot-data/robots` folder in it);
without one the script looks for `cmeel.prefix/share/example-robot-data/robots` on `sys.path`
(where `pip install example-robot-data==6.0.0` puts it). The package has no Python code: only
`cmeel.prefix/share/example-robot-data/{package.xml,robots/...}`. The script rewrites the JSON and
the copies (URDFs, the package's LICENSE and package.xml, each robot folder's README.md and
LICENSE); the states are seeded, so a rerun reproduces the JSON byte for byte (up to Pinocchio's
own changes).

Models: every `*.urdf` under `robots/`, keyed and processed by its path relative to `robots/`
(sorted). Each is loaded with `pin.buildModelFromUrdf(path)` (fixed base, mimic=False). If the file
has `<mimic>` on a joint that is not `fixed`, it is also loaded with `mimic=True` (each mimic joint
becomes a `JointModelMimic` without coordinates of its own); where that loads, ALL values of that
model come from the mimic=True model (`uses_mimic`), else from the mimic=False one (every joint
independent, the `<mimic>` ignored). `<mimic>` on a fixed joint changes nothing in Pinocchio.
Pinocchio 4.1's mimic=True refuses ("The parent joint of the mimic joint is not in the kinematic
tree") a mimic joint it meets before the joint it mimics in ITS order (siblings by name: romeo's
LFinger21 before LHand, talos_full_v2's gripper_left_inner_double_joint before gripper_left_joint)
or whose mimicked joint does not exist (alex_psyonic_hands: `index_q1`, the joints are
`Left_index_q1`, `Right_index_q1`).

Joint order: every vector and matrix is stored in OUR coordinate order: the URDF's movable joints
(`type` not `fixed`), depth first from the root link, children in document order, each joint that
does not mimic (in a `uses_mimic` model) taking one coordinate. Pinocchio orders siblings by joint
name (urdfdom keeps joints in a map), so the values are permuted here by joint name.
Continuous joints: Pinocchio's `JointModelRUB*` has nq = 2 (cos θ, sin θ) and nv = 1; ours has one
angle. `q` stores θ (drawn, then given to Pinocchio as (cos θ, sin θ)), so θ = atan2(sin, cos);
`v` and `a` are θ' and θ''. Every vector below therefore has length `nv`.

JSON fields:
- `generator`, `package` (name, version, where the files come from), `seed`, `conventions` (this
  docstring), `lower_triangle` (false: `mass_matrix` is stored whole, as rows).
- `models.<path>`, one per URDF found:
  - `sha256`: of the package's file; `urdf`: the committed copy, relative to this folder, or null
    where Pinocchio does not load the file (nothing copied).
  - `loads`: whether `buildModelFromUrdf(path)` succeeds; `error`: its message (null if it loads).
  - `mimic_joints`: movable joints with `<mimic>`, each `{name, joint, multiplier, offset}` (URDF
    defaults 1 and 0 filled in); `mimic_loads`: whether `buildModelFromUrdf(path, mimic=True)`
    succeeds (null where `mimic_joints` is empty: not tried); `mimic_error`: its message or null;
    `uses_mimic`: whether the values below come from the mimic=True model.
  - `root_link`: the URDF root (on a fixed base it and every link welded to it are the world).
  - `joints` (only where it loads): the movable joints in OUR order, mimic joints included, each
    `{name, type}` (the URDF type: revolute, continuous, prismatic), `pinocchio_type` (Pinocchio's
    shortname, e.g. JointModelRZ, JointModelRevoluteUnaligned, JointModelRUBX for a continuous
    joint, JointModelPY, JointModelMimic), `nq` and `nv` (Pinocchio's: continuous 2 and 1, mimic
    0 and 0 in a `uses_mimic` model, else 1 and 1), `mimic` (`{joint, multiplier, offset}` where
    the joint mimics another in a `uses_mimic` model, else null).
  - `quirks`: what a strict importer would see (analysed with numpy from the XML, no Pinocchio):
    `nv_zero` (nothing moves), `mimic_on_fixed_joints` (names), `mimic_of_unknown_joint` (movable
    joints whose `<mimic joint=...>` names no movable joint of the file), `empty_elements` (path of an
    element without attributes, children or text under a `<link>`, `<joint>` or top-level
    `<material>` -> count, e.g. `link/visual/material/texture` for `<texture/>` without a
    filename), `nonstandard_link_children` (children of `<link>` other than inertial, visual and
    collision -> count), `nonfinite` (attributes holding nan or inf), and `links`: one entry per
    link whose `<inertial>` has a problem, `{link, mass, problems, principal_moments,
    min_over_max, triangle_deficit, fixed_to_parent, body, body_is_root, merged_mass,
    merged_principal_moments, merged_min_over_max, merged_psd, merged_triangle_deficit}`.
    `principal_moments`: eigenvalues of the link's 3x3 inertia about its centre of mass
    (`numpy.linalg.eigvalsh`), ascending; `min_over_max` = λmin/λmax (null unless λmax > 0);
    `triangle_deficit` = (λmax - λmid - λmin)/λmax where it exceeds 1e-12 (the inequality needs
    λmin + λmid >= λmax), else null. `problems` among: `zero_mass` (mass 0, inertia 0: a dummy
    link), `zero_mass_nonzero_inertia`, `negative_mass`, `negative_principal_moment` (λmin <
    -1e-12 max|λ|), `singular_inertia` (|λmin| <= 1e-12 max|λ|: e.g. 1e-6 in all six entries,
    eigenvalues (0, 0, 3e-6), which the eigen-solver returns as ±1e-22), `triangle_inequality`
    (deficit > 1e-12), `negligible_inertia` (mass > 0 but every |λ| < 1e-12 kg m^2: numerical
    noise written as an inertia, iCub). `fixed_to_parent`: the link hangs on a fixed joint, so
    its inertia merges into a moving body. `body`: the top link of the rigid body it belongs to
    (follow fixed joints up); `body_is_root`: that body is the URDF root (welded to the world on
    a fixed base, so it matters only on a floating base). `merged_*`: that whole rigid body (every
    link welded to `body`) merged by the parallel-axis theorem in `body`'s frame: its mass, the
    principal moments about its centre of mass, λmin/λmax, `merged_psd` (λmin >= -1e-12 max|λ|:
    with a positive mass, the 6x6 spatial inertia is then positive semi-definite) and deficit.
  - `fixed` (where it loads) and `floating` (where the fixed-base model loads), or `{error}` where
    building that configuration failed: `nq`, `nv` (Pinocchio's), `total_mass`
    (`computeTotalMass`: on a fixed base WITHOUT the root link and the links welded to it, which
    Pinocchio merges into the world; on the floating base every link), and ONE seeded state with
    inputs `q`, `v`, `a` and outputs `mass_matrix` (M(q), crba symmetrized from its upper
    triangle, rows), `nonlinear_effects` (`nonLinearEffects(q, v)`: Coriolis, centrifugal and
    gravity), `gravity` (`computeGeneralizedGravity(q)`), `tau_out` (`rnea(q, v, a)` = M a + nle);
    and `massless_coordinates`: the joints (base coordinates `x y z rz ry rx`) whose diagonal entry
    of M is <= 1e-12 of the largest: they move neither mass nor inertia, M is singular and forward
    dynamics undefined (romeo's fingers on massless links, romeo_laas_small's grippers).
    Each Pinocchio call gets a fresh Data (Pinocchio 4.1's crba with mimic joints reads stale
    state from a reused one, see `tests/data/make_mimic_reference.py`).
  `floating` puts our Euler floating base under the URDF root, as in
  `tests/data/pinocchio/make_reference.py`: `JointModelComposite(Translation, SphericalZYX)`, a
  translation in the world frame then Euler angles z-y-x (R = Rz Ry Rx), velocities the
  coordinate rates, these six coordinates first (x, y, z, then the z, y, x angles); the root link
  keeps its inertia. Gravity (0, 0, -9.81).

State: per model and base a generator `default_rng([SEED, crc32(path), 0 fixed / 1 floating])`
(so one model's draws do not depend on the others), drawing in this order q uniform in
[-1.2, 1.2], v in [-2, 2], a in [-3, 3], each of length nv (the base's six included), whatever
the joint limits.

Checks before writing: tau_out = M a + nle and nle at v = 0 equals gravity (1e-10 relative); the
floating model has 6 more coordinates and its total mass equals the sum of the URDF's link masses;
for a `uses_mimic` model, M = G^T M_full G and tau_out = G^T rnea_full(G q + o, G v, G a) (1e-10
relative) against the mimic=False model, with G and o from the `<mimic>` multipliers and offsets.
"""
import glob
import hashlib
import math
import os
import shutil

# Robot folders whose files are not copied: CC-BY-NC-ND-4.0 (alex) forbids commercial use, which
# this repository's licence allows.
NOT_COPIED = {'alex_description'}
import sys
import tempfile
import xml.etree.ElementTree as ET
import zlib

import numpy as np
import pinocchio as pin

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(here))
from pinocchio_io import symmetric, write_json  # noqa: E402

SEED = 20261127
VERSION = '6.0.0'
ROBOTS = os.path.join('cmeel.prefix', 'share', 'example-robot-data', 'robots')
LOWER_TRIANGLE = False  # the whole JSON stays under ~6 MB with full matrices
TOL = 1e-10
BASE_NAMES = ['x', 'y', 'z', 'rz', 'ry', 'rx']  # the Euler base's coordinates


def find_robots(argv):
    """The package's `robots/` folder: the argument (the unzipped wheel or that folder), else on sys.path."""
    candidates = [argv[1], os.path.join(argv[1], ROBOTS)] if len(argv) > 1 else \
        [os.path.join(p, ROBOTS) for p in sys.path if p]
    for c in candidates:
        if os.path.isdir(c) and os.path.basename(os.path.normpath(c)) == 'robots':
            return os.path.abspath(c)
    sys.exit(f'no example-robot-data robots/ folder in {candidates}')


def package_version(robots):
    xml = ET.parse(os.path.join(robots, '..', 'package.xml')).getroot()
    return xml.find('version').text.strip()


# ---------------------------------------------------------------------------------------------
# The URDF as XML: joint order, mimic tags, inertias.

def floats(text, n, default=0.0):
    if text is None:
        return np.full(n, default)
    vals = [float(x) for x in text.split()]
    assert len(vals) == n, text
    return np.array(vals)


def rpy_matrix(rpy):
    """URDF's fixed-axis roll-pitch-yaw: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    Rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    Ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    Rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


def origin(el):
    o = el.find('origin') if el is not None else None
    if o is None:
        return np.zeros(3), np.eye(3)
    return floats(o.get('xyz'), 3), rpy_matrix(floats(o.get('rpy'), 3))


class Urdf:
    def __init__(self, path):
        self.root = ET.parse(path).getroot()
        self.joints = self.root.findall('joint')
        self.links = {l.get('name'): l for l in self.root.findall('link')}
        self.children = {}
        self.parent_joint = {}
        for j in self.joints:
            self.children.setdefault(j.find('parent').get('link'), []).append(j)
            self.parent_joint[j.find('child').get('link')] = j
        roots = [n for n in self.links if n not in self.parent_joint]
        assert len(roots) == 1, roots
        self.root_link = roots[0]

    def document_order(self):
        """The movable joints, depth first from the root, children in document order."""
        order = []

        def visit(link):
            for j in self.children.get(link, []):
                if j.get('type') != 'fixed':
                    order.append(j)
                visit(j.find('child').get('link'))
        visit(self.root_link)
        return order

    @staticmethod
    def mimic_of(j):
        m = j.find('mimic')
        if m is None:
            return None
        return dict(joint=m.get('joint'), multiplier=float(m.get('multiplier', 1.0)),
                    offset=float(m.get('offset', 0.0)))

    def inertial(self, link):
        """(mass, com, I about the com in the link frame) or None without <inertial>."""
        el = self.links[link].find('inertial')
        if el is None:
            return None
        c, R = origin(el)
        m = float(el.find('mass').get('value'))
        i = el.find('inertia')
        g = lambda k: float(i.get(k, 0.0))
        I = np.array([[g('ixx'), g('ixy'), g('ixz')], [g('ixy'), g('iyy'), g('iyz')],
                      [g('ixz'), g('iyz'), g('izz')]])
        return m, c, R @ I @ R.T

    def body_of(self, link):
        """The top link of the rigid body `link` belongs to (follow fixed joints up)."""
        while link in self.parent_joint and self.parent_joint[link].get('type') == 'fixed':
            link = self.parent_joint[link].find('parent').get('link')
        return link

    def merged(self, body):
        """(mass, com, I about the com) of `body` and every link welded to it, in `body`'s frame."""
        parts = []

        def visit(link, p, R):
            inert = self.inertial(link)
            if inert is not None:
                m, c, I = inert
                parts.append((m, p + R @ c, R @ I @ R.T))
            for j in self.children.get(link, []):
                if j.get('type') == 'fixed':
                    xyz, Rj = origin(j)
                    visit(j.find('child').get('link'), p + R @ xyz, R @ Rj)
        visit(body, np.zeros(3), np.eye(3))
        mass = sum(m for m, _, _ in parts)
        com = sum(m * c for m, c, _ in parts) / mass if mass > 0 else np.zeros(3)
        I = np.zeros((3, 3))
        for m, c, Ic in parts:  # parallel-axis theorem, about the merged centre of mass
            d = c - com
            I += Ic + m * (d @ d * np.eye(3) - np.outer(d, d))
        return mass, com, I


REL = 1e-12  # eigenvalues within REL * max|λ| of zero are the eigen-solver's rounding


def principal(I):
    """Ascending eigenvalues, λmin/λmax and the triangle deficit (λmax - λmid - λmin)/λmax."""
    lam = np.linalg.eigvalsh(0.5 * (I + I.T))
    top = lam[-1]
    ratio = float(lam[0] / top) if top > 0 else None
    deficit = float((lam[2] - lam[1] - lam[0]) / top) if top > 0 else None
    return lam, ratio, deficit


def inertia_problems(m, lam, deficit):
    scale = np.abs(lam).max()
    problems = []
    if m == 0:
        problems.append('zero_mass' if scale == 0 else 'zero_mass_nonzero_inertia')
    if m < 0:
        problems.append('negative_mass')
    if scale > 0 and lam[0] < -REL * scale:
        problems.append('negative_principal_moment')
    elif scale > 0 and lam[0] <= REL * scale:
        problems.append('singular_inertia')
    if deficit is not None and deficit > REL:
        problems.append('triangle_inequality')
    if m > 0 and 0 < scale < 1e-12:
        problems.append('negligible_inertia')
    return problems


def quirks(urdf, nv):
    out = {'nv_zero': nv == 0,
           'mimic_on_fixed_joints': [j.get('name') for j in urdf.joints
                                     if j.get('type') == 'fixed' and j.find('mimic') is not None]}
    movable = {j.get('name') for j in urdf.joints if j.get('type') != 'fixed'}
    out['mimic_of_unknown_joint'] = [j.get('name') for j in urdf.joints if j.get('type') != 'fixed'
                                     and j.find('mimic') is not None
                                     and j.find('mimic').get('joint') not in movable]
    empty, nonstd, nonfinite = {}, {}, []

    def walk(e, path):
        p = f'{path}/{e.tag}' if path else e.tag
        for k, v in e.attrib.items():
            if any(w in ('nan', 'inf', '-inf', '+inf', 'infinity', '-infinity') for w in v.lower().split()):
                nonfinite.append(f'{p}@{k}={v}')
        if path and not e.attrib and len(e) == 0 and not (e.text or '').strip():
            empty[p] = empty.get(p, 0) + 1
        for c in e:
            walk(c, p)
    for el in urdf.root:
        if el.tag in ('link', 'joint', 'material'):
            walk(el, '')
        if el.tag == 'link':
            for c in el:
                if c.tag not in ('inertial', 'visual', 'collision'):
                    nonstd[c.tag] = nonstd.get(c.tag, 0) + 1
    out['empty_elements'] = dict(sorted(empty.items()))
    out['nonstandard_link_children'] = dict(sorted(nonstd.items()))
    out['nonfinite'] = nonfinite
    links = []
    for name in urdf.links:
        inert = urdf.inertial(name)
        if inert is None:
            continue
        m, c, I = inert
        lam, ratio, deficit = principal(I)
        problems = inertia_problems(m, lam, deficit)
        if not problems:
            continue
        body = urdf.body_of(name)
        bm, _, bI = urdf.merged(body)
        blam, bratio, bdeficit = principal(bI)
        bscale = np.abs(blam).max()
        links.append(dict(
            link=name, mass=m, problems=problems, principal_moments=lam.tolist(),
            min_over_max=ratio, triangle_deficit=deficit if deficit is not None and deficit > REL else None,
            fixed_to_parent=name in urdf.parent_joint and urdf.parent_joint[name].get('type') == 'fixed',
            body=body, body_is_root=body == urdf.root_link, merged_mass=bm,
            merged_principal_moments=blam.tolist(), merged_min_over_max=bratio,
            merged_psd=bool(blam[0] >= -REL * bscale),
            merged_triangle_deficit=bdeficit if bdeficit is not None and bdeficit > REL else None))
    out['links'] = links
    return out


# ---------------------------------------------------------------------------------------------
# Pinocchio.

def euler_base():
    """Our Euler floating base, as in tests/data/pinocchio/make_reference.py."""
    root = pin.JointModelComposite(2)
    root.addJoint(pin.JointModelTranslation())
    root.addJoint(pin.JointModelSphericalZYX())
    return root


def load(path, floating, mimic):
    if floating:
        return pin.buildModelFromUrdf(path, euler_base(), mimic=mimic)
    return pin.buildModelFromUrdf(path, mimic=mimic)


def layout(model, order, base):
    """For OUR coordinates: (Pinocchio idx_q, nq, idx_v) of each; the base's six first."""
    coords = [(i, 1, i) for i in range(base)]
    for j in order:
        jm = model.joints[model.getJointId(j.get('name'))]
        if jm.nv == 0:  # a mimic joint: no coordinate of its own
            continue
        assert jm.nv == 1 and jm.nq in (1, 2), (j.get('name'), jm.shortname())
        coords.append((jm.idx_q, jm.nq, jm.idx_v))
    assert sorted(c[2] for c in coords) == list(range(model.nv)), 'every velocity once'
    assert sum(c[1] for c in coords) == model.nq
    return coords


def to_pinocchio(model, coords, q, v, a):
    qp, vp, ap = np.zeros(model.nq), np.zeros(model.nv), np.zeros(model.nv)
    for k, (iq, nq, iv) in enumerate(coords):
        if nq == 1:
            qp[iq] = q[k]
        else:  # continuous: (cos θ, sin θ)
            qp[iq:iq + 2] = math.cos(q[k]), math.sin(q[k])
        vp[iv], ap[iv] = v[k], a[k]
    return qp, vp, ap


def rel(x, y):
    return float(np.abs(np.asarray(x) - np.asarray(y)).max(initial=0.0) / max(1.0, np.abs(y).max(initial=0.0)))


def evaluate(model, coords, q, v, a):
    """Pinocchio's values at our (q, v, a), back in our order; each call on a fresh Data."""
    qp, vp, ap = to_pinocchio(model, coords, q, v, a)
    fresh = model.createData
    perm = np.array([c[2] for c in coords], dtype=int)
    M = symmetric(pin.crba(model, fresh(), qp))[np.ix_(perm, perm)]
    nle = np.array(pin.nonLinearEffects(model, fresh(), qp, vp))[perm]
    g = np.array(pin.computeGeneralizedGravity(model, fresh(), qp))[perm]
    tau = np.array(pin.rnea(model, fresh(), qp, vp, ap))[perm]
    g0 = np.array(pin.nonLinearEffects(model, fresh(), qp, np.zeros(model.nv)))[perm]
    assert rel(M @ a + nle, tau) < TOL, rel(M @ a + nle, tau)
    assert rel(g0, g) < TOL
    return M, nle, g, tau


def mimic_check(path, urdf, floating, model_values, q, v, a):
    """M = G^T M_full G and tau = G^T tau_full(G q + o, G v, G a) against mimic=False."""
    full = load(path, floating, False)
    order = urdf.document_order()
    base = 6 if floating else 0
    reduced = [j.get('name') for j in order if urdf.mimic_of(j) is None]
    col = {n: base + k for k, n in enumerate(reduced)}
    G = np.zeros((base + len(order), base + len(reduced)))
    o = np.zeros(base + len(order))
    for i in range(base):
        G[i, i] = 1
    for r, j in enumerate(order):
        m = urdf.mimic_of(j)
        if m is None:
            G[base + r, col[j.get('name')]] = 1
        else:
            G[base + r, col[m['joint']]] = m['multiplier']
            o[base + r] = m['offset']
    M, _, _, tau = model_values
    Mf, _, _, tauf = evaluate(full, layout(full, order, base), G @ q + o, G @ v, G @ a)
    assert rel(G.T @ Mf @ G, M) < TOL, rel(G.T @ Mf @ G, M)
    assert rel(G.T @ tauf, tau) < TOL, rel(G.T @ tauf, tau)


def configuration(path, urdf, rel_path, floating, mimic, link_mass):
    model = load(path, floating, mimic)
    base = 6 if floating else 0
    order = urdf.document_order()
    coords = layout(model, order, base)
    assert len(coords) == model.nv
    if floating:
        assert model.joints[1].shortname() == 'JointModelComposite' and model.joints[1].nq == 6
        assert abs(pin.computeTotalMass(model) - link_mass) <= 1e-12 * max(1, link_mass)
    assert np.array_equal(model.gravity.linear, [0, 0, -9.81])
    rng = np.random.default_rng([SEED, zlib.crc32(rel_path.encode()), int(floating)])
    q = rng.uniform(-1.2, 1.2, model.nv)
    v = rng.uniform(-2, 2, model.nv)
    a = rng.uniform(-3, 3, model.nv)
    values = evaluate(model, coords, q, v, a)
    if mimic:
        mimic_check(path, urdf, floating, values, q, v, a)
    M, nle, g, tau = values
    names = BASE_NAMES[:base] + [j.get('name') for j in order
                                 if model.joints[model.getJointId(j.get('name'))].nv == 1]
    diag = np.diag(M)
    massless = [n for n, m in zip(names, diag) if m <= 1e-12 * diag.max(initial=0.0)]
    if LOWER_TRIANGLE:
        M = [row[:i + 1] for i, row in enumerate(M.tolist())]
    else:
        M = M.tolist()
    return model, dict(nq=model.nq, nv=model.nv, total_mass=pin.computeTotalMass(model),
                       q=q.tolist(), v=v.tolist(), a=a.tolist(), mass_matrix=M,
                       nonlinear_effects=nle.tolist(), gravity=g.tolist(), tau_out=tau.tolist(),
                       massless_coordinates=massless)


def error_text(e, robots=None):
    text = f'{type(e).__name__}: {e}'
    return text.replace(robots + os.sep, '') if robots else text


def with_stderr(fn):
    """(fn's result or None, its exception or None, what C++ wrote to stderr meanwhile)."""
    sys.stderr.flush()
    saved = os.dup(2)
    with tempfile.TemporaryFile() as tmp:
        os.dup2(tmp.fileno(), 2)
        try:
            result, exc = fn(), None
        except Exception as e:  # noqa: BLE001 -- Pinocchio raises ValueError / RuntimeError
            result, exc = None, e
        finally:
            os.dup2(saved, 2)
            os.close(saved)
        tmp.seek(0)
        text = tmp.read().decode(errors='replace')
    return result, exc, text


def main():
    robots = find_robots(sys.argv)
    version = package_version(robots)
    assert version == VERSION, version
    paths = sorted(os.path.relpath(p, robots).replace(os.sep, '/')
                   for p in glob.glob(os.path.join(robots, '**', '*.urdf'), recursive=True))
    copies = os.path.join(here, 'urdf')
    if os.path.isdir(copies):
        shutil.rmtree(copies)
    os.makedirs(copies)
    models = {}
    copied_dirs = set()
    for rel_path in paths:
        path = os.path.join(robots, rel_path)
        with open(path, 'rb') as f:
            entry = dict(sha256=hashlib.sha256(f.read()).hexdigest(), urdf=None)
        fixed_model, exc, stderr = with_stderr(lambda: load(path, False, False))
        if exc is None:
            entry.update(loads=True, error=None)
        else:
            # urdfdom says why on stderr ("Error:   No name given for the robot."): kept.
            said = ' '.join(' '.join(l.split()) for l in stderr.splitlines() if l.startswith('Error:'))
            entry.update(loads=False, error=error_text(exc, robots) + (f' (urdfdom: {said})' if said else ''))
            models[rel_path] = entry
            print(f'{rel_path}: does not load ({entry["error"]})')
            continue
        urdf = Urdf(path)
        order = urdf.document_order()
        assert sorted(j.get('name') for j in order) == sorted(list(fixed_model.names)[1:])
        mimics = [dict(name=j.get('name'), **urdf.mimic_of(j)) for j in order if urdf.mimic_of(j)]
        entry['mimic_joints'] = mimics
        entry['mimic_loads'] = entry['mimic_error'] = None
        uses_mimic = False
        if mimics:
            try:
                load(path, False, True)
                entry['mimic_loads'] = uses_mimic = True
            except Exception as e:  # noqa: BLE001
                entry['mimic_loads'], entry['mimic_error'] = False, error_text(e, robots)
        entry['uses_mimic'] = uses_mimic
        entry['root_link'] = urdf.root_link
        link_mass = sum(urdf.inertial(l)[0] for l in urdf.links if urdf.inertial(l) is not None)

        model, entry['fixed'] = configuration(path, urdf, rel_path, False, uses_mimic, link_mass)
        joints = []
        for j in order:
            jm = model.joints[model.getJointId(j.get('name'))]
            joints.append(dict(name=j.get('name'), type=j.get('type'), pinocchio_type=jm.shortname(),
                               nq=jm.nq, nv=jm.nv,
                               mimic=urdf.mimic_of(j) if uses_mimic else None))
        entry['joints'] = joints
        entry['quirks'] = quirks(urdf, entry['fixed']['nv'])
        try:
            entry['floating'] = configuration(path, urdf, rel_path, True, uses_mimic, link_mass)[1]
        except Exception as e:  # noqa: BLE001
            entry['floating'] = dict(error=error_text(e, robots))
        else:
            assert entry['floating']['nv'] == entry['fixed']['nv'] + 6

        # The path of the copy either way (the test reads it); the file itself only where its
        # licence lets a repository that allows commercial use hold it.
        entry['urdf'] = 'urdf/' + rel_path
        if rel_path.split('/')[0] not in NOT_COPIED:
            dest = os.path.join(copies, rel_path)
            os.makedirs(os.path.dirname(dest), exist_ok=True)
            shutil.copyfile(path, dest)
            copied_dirs.add(rel_path.split('/')[0])
        models[rel_path] = entry
        fl = entry['floating']
        print(f'{rel_path}: nq {model.nq} nv {model.nv}, mass {entry["fixed"]["total_mass"]:.4f}'
              f'{", mimic" if uses_mimic else ""}{", floating failed" if "error" in fl else ""}'
              f', {len(entry["quirks"]["links"])} inertia quirks')

    # The licences: the package's, its package.xml (the licence of each robot folder), and each
    # copied robot folder's README.md (upstream, licence) and LICENSE where it has them.
    shutil.copyfile(os.path.join(robots, '..', 'package.xml'), os.path.join(copies, 'package.xml'))
    # The dist-info sits beside cmeel.prefix, in the unzipped wheel as in site-packages.
    licence = os.path.join(robots, '..', '..', '..', '..', f'example_robot_data-{version}.dist-info',
                           'licenses', 'LICENSE')
    shutil.copyfile(licence, os.path.join(copies, 'LICENSE'))
    for d in sorted(copied_dirs):
        for name in ('README.md', 'LICENSE'):
            src = os.path.join(robots, d, name)
            if os.path.isfile(src):
                shutil.copyfile(src, os.path.join(copies, d, name))

    out = {
        "generator": f"Pinocchio {pin.__version__} (pip package `pin`), "
                     "tests/data/real_robots/make_real_robots.py",
        "package": f"example-robot-data {version} (PyPI wheel example_robot_data-{version}-0-py3-none-any.whl, "
                   "files under cmeel.prefix/share/example-robot-data/robots/)",
        "seed": SEED,
        "lower_triangle": LOWER_TRIANGLE,
        "conventions": __doc__,
        "models": models,
    }
    path = os.path.join(here, 'pinocchio-real-robots.json')
    write_json(path, out)
    loaded = sum(e['loads'] for e in models.values())
    print(f'{path}: {len(models)} URDFs, {loaded} load, {os.path.getsize(path)} bytes')


if __name__ == '__main__':
    main()
