"""Pinocchio reference values for the free-floating quantities -> `tests/data/pinocchio-centroidal.json`.

Runs on our machines, NOT in CI (CI has no Pinocchio): `pip install pin numpy`, then
`python tests/data/make_centroidal_reference.py` from the repository root or anywhere else. The
JSON it writes is committed and read by the tests. Seeded: a rerun reproduces the file byte for
byte. Modelled on `tests/data/make_scale_reference.py` (same helpers, copied here because that
script writes its own file when imported).

Configurations, `models.<model>.<base>`:
- `humanoid.free_flyer`: `models/humanoid.urdf` under Pinocchio's `JointModelFreeFlyer`, which is
  what `models/humanoid.chain` writes as `free(quaternion)`. Stored in OUR convention: q =
  position, then the quaternion as [w, x, y, z] (Pinocchio stores [x, y, z, w]: reordered here);
  v = [linear; angular], both in the pelvis frame, as in Pinocchio.
- `humanoid.floating`, `arm7.floating` (`models/arm7.urdf`), `tree.floating` (`models/tree.urdf`):
  a translation (world frame) then Euler angles z-y-x (R = Rz Ry Rx) under the URDF root (which
  keeps its inertial), v = coordinate rates, these 6 coordinates first: what
  `load_model(<model>.urdf, floating = true)` builds. In Pinocchio, as in the other scripts, a
  `JointModelComposite(Translation, SphericalZYX)`; EXCEPT for `coriolis_matrix`, see there.
Each holds `nq`, `nv`, `total_mass`, `joint_names` (our order of the URDF's movable joints, after
the 6 or 7 base coordinates), `coriolis_check` (below) and 4 random `states`: q uniform in
[-1, 1] (quaternion: a normalized normal draw), v standard normal.

Joint order: every vector and every matrix column (and the rows of the nv x nv matrices) are in OUR
coordinate order, depth first from the root with children in document order. Pinocchio may order
siblings otherwise, so the values are permuted here by joint name.

Fields of a state (besides the inputs `q`, `v`); matrices are lists of rows; gravity (0, 0, -9.81):
- `center_of_mass`: c, the world-frame centre of mass (`centerOfMass(q)`).
- `center_of_mass_velocity`: dc/dt (`centerOfMass(q, v)` -> `data.vcom[0]`).
- `center_of_mass_jacobian`: J_c, 3 x nv, with dc/dt = J_c v (`jacobianCenterOfMass`).
- `centroidal_momentum`: h_G = [k_G; p], ANGULAR FIRST: the angular momentum about the centre of
  mass, world axes, then the linear momentum, world axes (`computeCentroidalMomentum` -> `data.hg`,
  which is linear first: halves swapped here).
- `centroidal_momentum_matrix`: A_G, 6 x nv, with h_G = A_G v; rows ANGULAR FIRST (`ccrba` -> `Ag`,
  linear first: rows 0..3 and 3..6 swapped here).
- `kinetic_energy`: T = 1/2 v^T M v (`computeKineticEnergy`).
- `potential_energy`: U = -sum_k m_k g^T x_k = -m_total g^T c (zero with every CoM at the world
  origin); Pinocchio's `computePotentialEnergy` is the same (asserted).
- `mass_matrix`: M(q), full, symmetrized from crba's upper triangle.
- `coriolis_matrix`: C(q, v) from `computeCoriolisMatrix`, with C v = N(q, v) v (the bias without
  gravity) and M' = C + C^T (M' - 2C skew-symmetric). C is not unique; for the Euler bases this one
  equals the Christoffel-symbol matrix C_ij = sum_k 1/2 (dM_ij/dq_k + dM_ik/dq_j - dM_jk/dq_i) v_k
  (checked here by finite differences, see `coriolis_check`). Pinocchio's C is WRONG with a
  composite joint (issue 2053: C v != nle - g), so for the Euler bases C comes from an equivalent
  model whose base is four separate joints, Translation, RZ, RY, RX (massless links between them),
  asserted to give the same M, nle, g, c and A_G as the composite base to 1e-12.
`coriolis_check` (per configuration, over its states): `skew_symmetric` = whether
|M' - C - C^T| <= 1e-6 max(1, |M'|) (max norms), M' by a central difference of crba along v (step
1e-5; the free flyer's q moved with `pin.integrate`); `max_relative_skew_error`;
`max_relative_christoffel_error` (Euler bases only, null otherwise; same normalization, by central
differences of crba along each q_k; asserted <= 1e-6); `composite_base_max_relative_cv_error` and
`composite_base_max_relative_skew_error` (Euler bases only, null otherwise: how wrong Pinocchio's C
of the composite base is, max |C v - (nle - g)| / max(1, |nle - g|) and the skew error as above).
Asserted besides: h_G = A_G v; p = m_total dc/dt; dc/dt = J_c v; T = 1/2 v^T M v; for the free flyer
A_G = X^* M[0:6, :] (the base rows of M carry the total momentum in the base frame), for the Euler
bases p = M[0:3, :] v; C v = nle - g to 1e-10.
"""
import json
import os

import numpy as np
import pinocchio as pin

# The joint order and its permutation are the scale script's (importing it runs nothing).
from make_scale_reference import document_order, permutation

here = os.path.dirname(os.path.abspath(__file__))
models_dir = os.path.join(here, '..', '..', 'models')
rng = np.random.default_rng(20261125)
GRAVITY = np.array([0.0, 0.0, -9.81])
FD_STEP = 1e-5
SKEW_TOL = 1e-6


def euler_base():
    """Our Euler floating base as in the other scripts: translation (world), then z-y-x angles."""
    euler = pin.JointModelComposite(2)
    euler.addJoint(pin.JointModelTranslation())
    euler.addJoint(pin.JointModelSphericalZYX())
    return euler


def serial_euler(model):
    """`model` (built with `euler_base()`) with its base split into Translation, RZ, RY, RX joints.

    Same coordinates, same velocities (rates), same dynamics; but no composite joint, which
    Pinocchio's computeCoriolisMatrix gets wrong (issue 2053)."""
    assert model.joints[1].shortname() == 'JointModelComposite' and model.joints[1].nq == 6
    out = pin.Model()
    out.name = model.name
    out.gravity = model.gravity
    I = pin.SE3.Identity()
    parent = 0
    for name, joint in (('root_translation', pin.JointModelTranslation()),
                        ('root_z', pin.JointModelRZ()), ('root_y', pin.JointModelRY())):
        parent = out.addJoint(parent, joint, I, name)
    ids = {0: 0}
    for i in range(1, model.njoints):
        if i == 1:
            joint, p = pin.JointModelRX(), parent
        else:
            joint, p = model.joints[i], ids[model.parents[i]]
        ids[i] = out.addJoint(p, joint, model.jointPlacements[i], model.names[i])
        out.appendBodyToJoint(ids[i], model.inertias[i], I)
    for i in range(2, model.njoints):
        assert out.joints[ids[i]].idx_q == model.joints[i].idx_q, model.names[i]
        assert out.joints[ids[i]].idx_v == model.joints[i].idx_v, model.names[i]
    assert (out.nq, out.nv) == (model.nq, model.nv)
    return out


def mass_matrix(model, d, q):
    M = pin.crba(model, d, q)
    return np.triu(M) + np.triu(M, 1).T


def rel(x, y, scale=None):
    """max |x - y| / max(1, max |scale|) (scale defaults to y)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    s = y if scale is None else np.asarray(scale, float)
    return float(np.abs(x - y).max() / max(1.0, np.abs(s).max()))


def swap(x):
    """Linear-first <-> angular-first: swap the halves (rows 0..3 and 3..6)."""
    return np.concatenate([x[3:6], x[0:3]])


def coriolis_checks(model, d, q, v, C, euler):
    """Relative errors of M' = C + C^T and (Euler bases) of C = Christoffel, by central differences."""
    step = lambda dq: pin.integrate(model, q, dq)
    Mdot = (mass_matrix(model, d, step(FD_STEP * v)) - mass_matrix(model, d, step(-FD_STEP * v))) / (2 * FD_STEP)
    skew = rel(Mdot, C + C.T, Mdot)
    if not euler:
        return skew, None
    dM = np.empty((model.nv, model.nv, model.nv))  # dM[i, j, k] = dM_ij / dq_k
    for k in range(model.nv):
        e = np.zeros(model.nq)
        e[k] = FD_STEP
        dM[:, :, k] = (mass_matrix(model, d, q + e) - mass_matrix(model, d, q - e)) / (2 * FD_STEP)
    christoffel = 0.5 * (np.einsum('ijk,k->ij', dM, v) + np.einsum('ikj,k->ij', dM, v)
                         - np.einsum('jki,k->ij', dM, v))
    return skew, rel(C, christoffel, christoffel)


def states(model, names, kind, count):
    base = {'floating': (6, 6), 'free_flyer': (7, 6)}[kind]
    pq, pv = permutation(model, names, base)
    euler = kind == 'floating'
    d = model.createData()
    cmodel = serial_euler(model) if euler else model  # the model computeCoriolisMatrix gets right
    cd = cmodel.createData()
    total_mass = pin.computeTotalMass(model)
    assert np.array_equal(model.gravity.linear, GRAVITY)
    out = []
    skews, christoffels, composite_cv, composite_skew = [], [], [], []
    for _ in range(count):
        q = rng.uniform(-1.0, 1.0, model.nq)
        if kind == 'free_flyer':
            quat = rng.normal(size=4)
            q[3:7] = quat / np.linalg.norm(quat)  # Pinocchio's [x, y, z, w]
        v = rng.normal(size=model.nv)

        com = pin.centerOfMass(model, d, q).copy()
        pin.centerOfMass(model, d, q, v)
        vcom = d.vcom[0].copy()
        Jcom = pin.jacobianCenterOfMass(model, d, q).copy()
        hg = pin.computeCentroidalMomentum(model, d, q, v)
        h = swap(np.array(hg.vector))  # [k_G; p]
        Ag = np.array(pin.ccrba(model, d, q, v))
        A = np.concatenate([Ag[3:6], Ag[0:3]])  # rows angular first
        kinetic = pin.computeKineticEnergy(model, d, q, v)
        potential_pin = pin.computePotentialEnergy(model, d, q)
        potential = float(-total_mass * GRAVITY @ com)
        M = mass_matrix(model, d, q)
        nle = pin.nonLinearEffects(model, d, q, v).copy()
        g = pin.computeGeneralizedGravity(model, d, q).copy()
        C = np.array(pin.computeCoriolisMatrix(cmodel, cd, q, v))

        # Self-checks: a wrong convention fails loudly.
        assert rel(A @ v, h) < 1e-12, (kind, 'h_G = A_G v', rel(A @ v, h))
        assert rel(h[3:6], total_mass * vcom) < 1e-12, (kind, 'p = m vcom')
        assert rel(Jcom @ v, vcom) < 1e-12, (kind, 'vcom = Jcom v')
        assert abs(kinetic - 0.5 * v @ M @ v) / max(1, abs(kinetic)) < 1e-12, (kind, 'T')
        assert abs(potential_pin - potential) / max(1, abs(potential)) < 1e-12, (kind, 'U', potential_pin, potential)
        assert rel(C @ v, nle - g) < 1e-10, (kind, 'C v = nle - g', rel(C @ v, nle - g))
        if euler:
            # p in world axes = the translation rows of M (translation rates are world-frame).
            assert rel(M[0:3] @ v, h[3:6]) < 1e-12, (kind, 'p = M[0:3] v')
            # The split base changes nothing but C.
            assert rel(mass_matrix(cmodel, cd, q), M) < 1e-12, kind
            assert rel(pin.nonLinearEffects(cmodel, cd, q, v), nle) < 1e-12, kind
            assert rel(pin.computeGeneralizedGravity(cmodel, cd, q), g) < 1e-12, kind
            assert rel(pin.centerOfMass(cmodel, cd, q), com) < 1e-12, kind
            assert rel(pin.ccrba(cmodel, cd, q, v), Ag) < 1e-12, kind
            Cc = np.array(pin.computeCoriolisMatrix(model, d, q, v))
            composite_cv.append(rel(Cc @ v, nle - g))
            composite_skew.append(coriolis_checks(model, d, q, v, Cc, False)[0])
        else:
            # The base rows of M give the total momentum in the base frame, about its origin,
            # [f; n]; moved to the CoM in world axes it is h_G.
            pin.forwardKinematics(model, d, q)
            X = d.oMi[1]
            lin = X.rotation @ M[0:3]
            ang = X.rotation @ M[3:6] + np.cross((X.translation - com)[:, None], lin, axis=0)
            assert rel(np.concatenate([ang, lin]), A) < 1e-12, (kind, 'A_G = X* M[0:6]')
        skew, christoffel = coriolis_checks(cmodel, cd, q, v, C, euler)
        assert christoffel is None or christoffel < SKEW_TOL, (kind, 'C = Christoffel', christoffel)
        skews.append(skew)
        christoffels.append(christoffel)

        ours_q = q[pq]
        if kind == 'free_flyer':
            ours_q[3:7] = [q[6], q[3], q[4], q[5]]  # [w, x, y, z]
        vec = lambda x: x[pv].tolist()
        cols = lambda X: X[:, pv].tolist()
        square = lambda X: X[np.ix_(pv, pv)].tolist()
        out.append(dict(
            q=ours_q.tolist(), v=vec(v), center_of_mass=com.tolist(),
            center_of_mass_velocity=vcom.tolist(), center_of_mass_jacobian=cols(Jcom),
            centroidal_momentum=h.tolist(), centroidal_momentum_matrix=cols(A),
            kinetic_energy=float(kinetic), potential_energy=potential,
            mass_matrix=square(M), coriolis_matrix=square(C)))
    check = dict(
        skew_symmetric=max(skews) <= SKEW_TOL, max_relative_skew_error=max(skews),
        max_relative_christoffel_error=max(christoffels) if euler else None,
        composite_base_max_relative_cv_error=max(composite_cv) if euler else None,
        composite_base_max_relative_skew_error=max(composite_skew) if euler else None)
    return dict(nq=model.nq, nv=model.nv, total_mass=total_mass, joint_names=names,
                coriolis_check=check, states=out)


def main():
    out = {
        "generator": f"Pinocchio {pin.__version__} (pip package `pin`), tests/data/make_centroidal_reference.py",
        "conventions": __doc__,
        "models": {},
    }

    humanoid = os.path.join(models_dir, 'humanoid.urdf')
    names = document_order(humanoid)
    out['models']['humanoid'] = {
        'free_flyer': states(pin.buildModelFromUrdf(humanoid, pin.JointModelFreeFlyer()), names, 'free_flyer', 4),
        'floating': states(pin.buildModelFromUrdf(humanoid, euler_base()), names, 'floating', 4),
    }
    for name in ('arm7', 'tree'):
        urdf = os.path.join(models_dir, f'{name}.urdf')
        out['models'][name] = {
            'floating': states(pin.buildModelFromUrdf(urdf, euler_base()), document_order(urdf), 'floating', 4),
        }

    path = os.path.join(here, 'pinocchio-centroidal.json')
    with open(path + '.tmp', 'w') as f:
        json.dump(out, f, indent=None, separators=(',', ':'))
    os.replace(path + '.tmp', path)
    print(path, {m: {k: (v['nq'], v['nv'], v['coriolis_check']) for k, v in e.items()}
                 for m, e in out['models'].items()})


if __name__ == '__main__':
    main()
