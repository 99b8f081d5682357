"""Pinocchio's analytical derivatives of the dynamics -> `tests/data/pinocchio-derivatives.json`.

Runs on our machines, NOT in CI (CI has no Pinocchio): `pip install pin numpy`, then
`python tests/data/make_derivatives_reference.py` from the repository root or anywhere else. The
JSON it writes is committed and read by the tests of the generated derivative code. Seeded: a
rerun reproduces the file byte for byte. Modelled on `tests/data/make_centroidal_reference.py`,
whose `euler_base`, `serial_euler` and `rel` it imports.

Configurations, `models.<model>.<base>`:
- `arm7.fixed`: `models/arm7.urdf`, fixed base (7 revolute joints).
- `humanoid.free_flyer`: `models/humanoid.urdf` under Pinocchio's `JointModelFreeFlyer`, which is
  what `models/humanoid.chain` writes as `free(quaternion)`. Stored in OUR convention: q =
  position, then the quaternion as [w, x, y, z] (Pinocchio stores [x, y, z, w]: reordered here);
  v = [linear; angular], both in the pelvis frame, as in Pinocchio. nq = 38, nv = 37.
- `arm7.floating`: `models/arm7.urdf` under a translation (world frame) then Euler angles z-y-x
  (R = Rz Ry Rx), the URDF root keeping its inertial, v = coordinate rates, these 6 coordinates
  first: what `load_model(arm7.urdf, floating = true)` builds. Built, as in the other scripts, as
  a `JointModelComposite(Translation, SphericalZYX)`; but Pinocchio's RNEA and ABA derivatives of
  that composite base are WRONG (off by O(1), see `checks.composite_base_*`, cf. issue 2053 on its
  Coriolis matrix), so every value here comes from an equivalent model whose base is four separate
  joints, Translation, RZ, RY, RX (massless links between them), asserted to give the same rnea,
  aba, crba and computeMinverse as the composite base to 1e-12.
Each holds `nq`, `nv`, `joint_names` (our order of the URDF's movable joints, after the 6 or 7
base coordinates), `checks` (below) and 4 random `states`: q uniform in [-1, 1] (quaternion: a
normalized normal draw), v and a standard normal, tau standard normal times 10.

Joint order: every vector and every matrix (rows and columns) are in OUR coordinate order, depth
first from the root with children in document order. Pinocchio may order siblings otherwise, so
the values are permuted here by joint name (`document_order` and `permutation` of
`tests/data/make_scale_reference.py`).

Derivatives with respect to q: every matrix is nv x nv. For the fixed and Euler bases q is
Euclidean (nq = nv) and column k is the plain partial derivative along q + h e_k. For the free
flyer, as in Pinocchio, column k is the derivative along the TANGENT-SPACE increment,
d/dh f(q (+) h e_k) at h = 0 with q (+) delta = `pin.integrate(model, q, delta)`: delta in
velocity coordinates, its base part [linear; angular] in the BASE (pelvis, local) frame. To first
order, columns 0..3 move the base position by R e_k (R the base rotation: along the base's own
axes), columns 3..6 rotate it as R <- R exp(h [e_k]x) (about its own axes, its position fixed),
and the joint columns are plain partials. Asserted: a central difference of rnea along
`pin.integrate(model, q, +-h e_k)` matches column k of dtau_dq (`checks.dtau_dq_fd`, <= 1e-8).

Fields of a state (besides the inputs `q`, `v`, `a`, `tau`); matrices are lists of rows; gravity
(0, 0, -9.81):
- `rnea`: tau(q, v, a) = M(q) a + N(q, v) v + g(q) (`rnea`).
- `dtau_dq`, `dtau_dv`: d rnea / dq and d rnea / dv at (q, v, a) (`computeRNEADerivatives`).
- `ddq`: qdd(q, v, tau) = M^-1 (tau - N v - g) (`aba`).
- `ddq_dq`, `ddq_dv`: d aba / dq and d aba / dv at (q, v, tau) (`computeABADerivatives`,
  `data.ddq_dq`, `data.ddq_dv`).
- `minv`: M(q)^-1 as `computeABADerivatives` leaves it in `data.Minv`, symmetrized from its upper
  triangle.
- `mass_matrix_inverse`: M(q)^-1 from `computeMinverse`, symmetrized from its upper triangle.

`checks` (per configuration, the largest over its states, each a relative error max |x - y| /
max(1, max |y|) with y the stored value), all asserted <= 1e-8 unless stated:
- `dtau_dq_fd`, `dtau_dv_fd`: against central differences of rnea (step 1e-6; the free flyer's q
  through `pin.integrate`, as above).
- `ddq_dq_identity`, `ddq_dv_identity`: ddq_dq = -Minv dtau_dq and ddq_dv = -Minv dtau_dv, with
  the RNEA derivatives taken at a = ddq.
- `ddq_dq_fd`, `ddq_dv_fd`: against central differences of aba (step 1e-6; asserted <= 1e-6 only:
  the difference quotient's rounding, ~1e-16 max |ddq| / 1e-6 with |ddq| up to 2e4, dominates).
- `minv_identity`: Minv M = I, M from crba (symmetrized).
- `minv_crba`: `mass_matrix_inverse` against inv(crba); `minv_aba`: `minv` against
  `mass_matrix_inverse`.
- `composite_base_dtau_dq`, `composite_base_dtau_dv`, `composite_base_ddq_dq`,
  `composite_base_ddq_dv` (`arm7.floating` only, not asserted): how far Pinocchio's derivatives
  of the composite base are from the stored ones.
"""
import json
import os

import numpy as np
import pinocchio as pin

# The joint order and its permutation are the scale script's (importing it runs nothing).
from make_scale_reference import document_order, permutation
from make_centroidal_reference import euler_base, rel, serial_euler

here = os.path.dirname(os.path.abspath(__file__))
models_dir = os.path.join(here, '..', '..', 'models')
rng = np.random.default_rng(20261126)
GRAVITY = np.array([0.0, 0.0, -9.81])
FD_STEP = 1e-6
TOL = 1e-8
ABA_FD_TOL = 1e-6


def symmetric(X):
    """X symmetrized from its upper triangle."""
    X = np.array(X)
    return np.triu(X) + np.triu(X, 1).T


def central_differences(model, f, x, tangent):
    """Columns (f(x + h e_k) - f(x - h e_k)) / 2h, k < nv; along `pin.integrate` if `tangent`."""
    cols = []
    for k in range(model.nv):
        e = np.zeros(model.nv)
        e[k] = FD_STEP
        if tangent:
            plus, minus = pin.integrate(model, x, e), pin.integrate(model, x, -e)
        else:
            plus, minus = x + e, x - e
        cols.append((f(plus) - f(minus)) / (2 * FD_STEP))
    return np.array(cols).T


def derivatives(model, d, q, v, a, tau):
    """Pinocchio's RNEA and ABA derivatives (copies: Pinocchio returns views into `d`)."""
    dtau_dq, dtau_dv, _ = (np.array(X) for X in pin.computeRNEADerivatives(model, d, q, v, a))
    ddq_dq, ddq_dv, minv = (np.array(X) for X in pin.computeABADerivatives(model, d, q, v, tau))
    return dtau_dq, dtau_dv, ddq_dq, ddq_dv, symmetric(minv)


def states(model, names, kind, count):
    base = {'fixed': (0, 0), 'floating': (6, 6), 'free_flyer': (7, 6)}[kind]
    pq, pv = permutation(model, names, base)
    free_flyer, euler = kind == 'free_flyer', kind == 'floating'
    assert free_flyer or model.nq == model.nv
    assert np.array_equal(model.gravity.linear, GRAVITY)
    cmodel, cd = model, model.createData()  # as built; for the Euler base, the composite
    if euler:
        model = serial_euler(model)  # the model whose derivatives Pinocchio gets right
    d = model.createData()
    rnea = lambda q, v, a: pin.rnea(model, d, q, v, a).copy()
    aba = lambda q, v, tau: pin.aba(model, d, q, v, tau).copy()
    out = []
    checks = {}
    for _ in range(count):
        q = rng.uniform(-1.0, 1.0, model.nq)
        if free_flyer:
            quat = rng.normal(size=4)
            q[3:7] = quat / np.linalg.norm(quat)  # Pinocchio's [x, y, z, w]
        v = rng.normal(size=model.nv)
        a = rng.normal(size=model.nv)
        tau = 10 * rng.normal(size=model.nv)

        dtau_dq, dtau_dv, ddq_dq, ddq_dv, minv = derivatives(model, d, q, v, a, tau)
        tau_rnea = rnea(q, v, a)
        ddq = aba(q, v, tau)
        mass_matrix_inverse = symmetric(pin.computeMinverse(model, d, q))
        M = symmetric(pin.crba(model, d, q))
        # The RNEA derivatives at a = ddq, for ddq_dq = -Minv dtau_dq.
        at_ddq = derivatives(model, d, q, v, ddq, tau)

        errors = dict(
            dtau_dq_fd=rel(central_differences(model, lambda x: rnea(x, v, a), q, free_flyer), dtau_dq),
            dtau_dv_fd=rel(central_differences(model, lambda x: rnea(q, x, a), v, False), dtau_dv),
            ddq_dq_identity=rel(-minv @ at_ddq[0], ddq_dq),
            ddq_dv_identity=rel(-minv @ at_ddq[1], ddq_dv),
            ddq_dq_fd=rel(central_differences(model, lambda x: aba(x, v, tau), q, free_flyer), ddq_dq),
            ddq_dv_fd=rel(central_differences(model, lambda x: aba(q, x, tau), v, False), ddq_dv),
            minv_identity=rel(minv @ M, np.eye(model.nv)),
            minv_crba=rel(mass_matrix_inverse, np.linalg.inv(M)),
            minv_aba=rel(minv, mass_matrix_inverse))
        if euler:
            # The split base changes no value, but Pinocchio's derivatives of the composite are wrong.
            assert rel(pin.rnea(cmodel, cd, q, v, a), tau_rnea) < 1e-12, kind
            assert rel(pin.aba(cmodel, cd, q, v, tau), ddq) < 1e-12, kind
            assert rel(symmetric(pin.crba(cmodel, cd, q)), M) < 1e-12, kind
            assert rel(symmetric(pin.computeMinverse(cmodel, cd, q)), mass_matrix_inverse) < 1e-12, kind
            composite = derivatives(cmodel, cd, q, v, a, tau)
            for name, x, y in zip(('dtau_dq', 'dtau_dv', 'ddq_dq', 'ddq_dv'), composite,
                                  (dtau_dq, dtau_dv, ddq_dq, ddq_dv)):
                checks[f'composite_base_{name}'] = max(checks.get(f'composite_base_{name}', 0.0), rel(x, y))
        for name, err in errors.items():
            tol = ABA_FD_TOL if name.startswith('ddq_') and name.endswith('_fd') else TOL
            assert err <= tol, (kind, name, err)
            checks[name] = max(checks.get(name, 0.0), err)

        ours_q = q[pq]
        if free_flyer:
            ours_q[3:7] = [q[6], q[3], q[4], q[5]]  # [w, x, y, z]
        vec = lambda x: x[pv].tolist()
        square = lambda X: X[np.ix_(pv, pv)].tolist()
        out.append(dict(
            q=ours_q.tolist(), v=vec(v), a=vec(a), tau=vec(tau),
            rnea=vec(tau_rnea), dtau_dq=square(dtau_dq), dtau_dv=square(dtau_dv),
            ddq=vec(ddq), ddq_dq=square(ddq_dq), ddq_dv=square(ddq_dv),
            minv=square(minv), mass_matrix_inverse=square(mass_matrix_inverse)))
    return dict(nq=model.nq, nv=model.nv, joint_names=names, checks=checks, states=out)


def main():
    out = {
        "generator": f"Pinocchio {pin.__version__} (pip package `pin`), tests/data/make_derivatives_reference.py",
        "conventions": __doc__,
        "models": {},
    }

    arm7 = os.path.join(models_dir, 'arm7.urdf')
    out['models']['arm7'] = {
        'fixed': states(pin.buildModelFromUrdf(arm7), document_order(arm7), 'fixed', 4),
    }
    humanoid = os.path.join(models_dir, 'humanoid.urdf')
    out['models']['humanoid'] = {
        'free_flyer': states(pin.buildModelFromUrdf(humanoid, pin.JointModelFreeFlyer()),
                             document_order(humanoid), 'free_flyer', 4),
    }
    # Last, so that the random states of the two above are those of the first version of this file.
    out['models']['arm7']['floating'] = states(pin.buildModelFromUrdf(arm7, euler_base()),
                                               document_order(arm7), 'floating', 4)

    path = os.path.join(here, 'pinocchio-derivatives.json')
    with open(path + '.tmp', 'w') as f:
        json.dump(out, f, indent=None, separators=(',', ':'))
    os.replace(path + '.tmp', path)
    print(path, {m: {k: (v['nq'], v['nv'], v['checks']) for k, v in e.items()}
                 for m, e in out['models'].items()})


if __name__ == '__main__':
    main()
