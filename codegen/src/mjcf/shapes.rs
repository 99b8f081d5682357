//! MuJoCo's compiler rules for poses and mass, as its `user_objects.cc` and `user_util.cc`
//! write them: the five orientation forms ([`orientation`]), geoms' volumes and inertias
//! ([`geom_mass`], solid or shell) and `fromto`, and the bounds put on a body's principal
//! moments ([`bound_inertia`]).

use articulated_dynamics::spatial::{Mat3, Vec3};

use super::xml::Classed;
use super::Compiler;
use crate::import::frames::{rotate_inertia, MassProps, Transform};
use crate::import::ImportError;

/// MuJoCo's `mjEPS`: below it a volume, mass or axis counts as zero.
pub(super) const EPS: f64 = 1e-14;

/// A quaternion `[w, x, y, z]`.
pub(super) type Quat = [f64; 4];

fn mul(a: Quat, b: Quat) -> Quat {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// `v / |v|` and `|v|`.
fn unit<const N: usize>(v: [f64; N]) -> ([f64; N], f64) {
    let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    if n < EPS {
        return (v, n);
    }
    (v.map(|x| x / n), n)
}

/// The rotation taking `z` to `v` about `z × v` (MuJoCo's `mjuu_z2quat`).
pub(super) fn z_to(v: [f64; 3]) -> Quat {
    let c = [-v[1], v[0], 0.0]; // [0, 0, 1] × v
    let (mut axis, s) = unit(c);
    if s < 1e-10 {
        axis = [1.0, 0.0, 0.0];
    }
    let half = s.atan2(v[2]) / 2.0;
    let (sin, cos) = half.sin_cos();
    [cos, axis[0] * sin, axis[1] * sin, axis[2] * sin]
}

/// The rotation whose columns are `x`, `y`, `z` (MuJoCo's `mjuu_frame2quat`).
fn frame_quat(x: [f64; 3], y: [f64; 3], z: [f64; 3]) -> Quat {
    let m = [x, y, z]; // m[column][row]
    let q = if m[0][0] + m[1][1] + m[2][2] > 0.0 {
        let w = 0.5 * (1.0 + m[0][0] + m[1][1] + m[2][2]).sqrt();
        [
            w,
            0.25 * (m[1][2] - m[2][1]) / w,
            0.25 * (m[2][0] - m[0][2]) / w,
            0.25 * (m[0][1] - m[1][0]) / w,
        ]
    } else if m[0][0] > m[1][1] && m[0][0] > m[2][2] {
        let a = 0.5 * (1.0 + m[0][0] - m[1][1] - m[2][2]).sqrt();
        [
            0.25 * (m[1][2] - m[2][1]) / a,
            a,
            0.25 * (m[1][0] + m[0][1]) / a,
            0.25 * (m[2][0] + m[0][2]) / a,
        ]
    } else if m[1][1] > m[2][2] {
        let b = 0.5 * (1.0 - m[0][0] + m[1][1] - m[2][2]).sqrt();
        [
            0.25 * (m[2][0] - m[0][2]) / b,
            0.25 * (m[1][0] + m[0][1]) / b,
            b,
            0.25 * (m[2][1] + m[1][2]) / b,
        ]
    } else {
        let c = 0.5 * (1.0 - m[0][0] - m[1][1] + m[2][2]).sqrt();
        [
            0.25 * (m[0][1] - m[1][0]) / c,
            0.25 * (m[2][0] + m[0][2]) / c,
            0.25 * (m[2][1] + m[1][2]) / c,
            c,
        ]
    };
    unit(q).0
}

/// The quaternion of a rotation matrix (MuJoCo's conversion, on its columns).
pub(super) fn matrix_quat(r: &Mat3<f64>) -> Quat {
    let m = r.0;
    frame_quat(
        [m[0][0], m[1][0], m[2][0]],
        [m[0][1], m[1][1], m[2][1]],
        [m[0][2], m[1][2], m[2][2]],
    )
}

/// The element's orientation from whichever of `quat`, `axisangle`, `xyaxes`, `zaxis` and
/// `euler` it gives (more than one is an error), `None` where it gives none. Angles are in the
/// compiler's unit; Euler angles follow its `eulerseq` (lower case: axes that move with the
/// frame, post-multiplied; upper case: fixed axes, pre-multiplied).
pub(super) fn orientation(c: &Classed, compiler: &Compiler) -> Result<Option<Quat>, ImportError> {
    let given: Vec<&str> = ["quat", "axisangle", "xyaxes", "zaxis", "euler"]
        .into_iter()
        .filter(|k| c.el.own(k).is_some())
        .collect();
    if given.len() > 1 {
        return Err(c.el.error(format!(
            "`<{}>` gives its orientation twice: {}",
            c.el.tag,
            given
                .iter()
                .map(|k| format!("`{k}`"))
                .collect::<Vec<_>>()
                .join(" and ")
        )));
    }
    let angle = |a: f64| if compiler.degree { a.to_radians() } else { a };
    let too_small = |what: &str| c.el.error(format!("`<{} {what}>` is too small", c.el.tag));
    if let Some(q) = c.array::<4>("quat")? {
        let (q, n) = unit(q);
        return if n < EPS {
            Err(too_small("quat"))
        } else {
            Ok(Some(q))
        };
    }
    if let Some([x, y, z, a]) = c.array::<4>("axisangle")? {
        let (axis, n) = unit([x, y, z]);
        if n < EPS {
            return Err(too_small("axisangle"));
        }
        let (s, co) = (angle(a) / 2.0).sin_cos();
        return Ok(Some([co, s * axis[0], s * axis[1], s * axis[2]]));
    }
    if let Some(v) = c.array::<6>("xyaxes")? {
        let (x, n) = unit([v[0], v[1], v[2]]);
        let d = x[0] * v[3] + x[1] * v[4] + x[2] * v[5];
        let (y, m) = unit([v[3] - x[0] * d, v[4] - x[1] * d, v[5] - x[2] * d]);
        let z = Vec3(x).cross(Vec3(y)).0;
        if n < EPS || m < EPS {
            return Err(too_small("xyaxes"));
        }
        return Ok(Some(frame_quat(x, y, z)));
    }
    if let Some(z) = c.array::<3>("zaxis")? {
        let (z, n) = unit(z);
        return if n < EPS {
            Err(too_small("zaxis"))
        } else {
            Ok(Some(z_to(z)))
        };
    }
    if let Some(e) = c.array::<3>("euler")? {
        let mut q = [1.0, 0.0, 0.0, 0.0];
        for (axis, a) in compiler.eulerseq.iter().zip(e) {
            let (s, co) = (angle(a) / 2.0).sin_cos();
            let mut r = [co, 0.0, 0.0, 0.0];
            r[1 + (axis.to_ascii_lowercase() - b'x') as usize] = s;
            q = if axis.is_ascii_lowercase() {
                mul(q, r)
            } else {
                mul(r, q)
            };
        }
        return Ok(Some(unit(q).0));
    }
    Ok(None)
}

/// The pose `fromto` gives a geom or a site: centred between the two points, its `z` axis along
/// `from − to`; and half the distance between the points (`None` where they are too close).
pub(super) fn from_to(ft: [f64; 6]) -> Option<(Transform, f64)> {
    let d = [ft[0] - ft[3], ft[1] - ft[4], ft[2] - ft[5]];
    let (dir, len) = unit(d);
    if len / 2.0 < EPS {
        return None;
    }
    let mid = [
        (ft[0] + ft[3]) / 2.0,
        (ft[1] + ft[4]) / 2.0,
        (ft[2] + ft[5]) / 2.0,
    ];
    Some((transform(mid, Some(z_to(dir))), len / 2.0))
}

/// The element's `pos` and orientation as a transform (the identity where it gives neither).
pub(super) fn pose(c: &Classed, compiler: &Compiler) -> Result<Transform, ImportError> {
    let pos = c.array::<3>("pos")?;
    let quat = orientation(c, compiler)?;
    Ok(transform(pos.unwrap_or([0.0; 3]), quat))
}

/// The transform of a position and an orientation.
pub(super) fn transform(pos: [f64; 3], quat: Option<Quat>) -> Transform {
    match quat {
        None if pos == [0.0; 3] => Transform::IDENTITY,
        _ => Transform {
            r: quat.map_or(Mat3::identity(), Mat3::quaternion),
            p: Vec3(pos),
            identity: false,
        },
    }
}

/// A geom's shape: what its volume and inertia follow.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum Shape {
    Sphere,
    Capsule,
    Cylinder,
    Ellipsoid,
    Box,
    /// Planes, height fields' outlines aside: no volume.
    Massless,
}

/// How many of a shape's `size` numbers it reads.
pub(super) fn sizes_needed(shape: Shape) -> usize {
    match shape {
        Shape::Sphere => 1,
        Shape::Capsule | Shape::Cylinder => 2,
        Shape::Ellipsoid | Shape::Box => 3,
        Shape::Massless => 0,
    }
}

/// The shape's volume (or area, for a shell), MuJoCo's `mjCGeom::GetVolume`.
pub(super) fn volume(shape: Shape, s: [f64; 3], shell: bool) -> f64 {
    use std::f64::consts::PI;
    let (r, h) = (s[0], 2.0 * s[1]);
    match (shape, shell) {
        (Shape::Sphere, false) => 4.0 * PI * r * r * r / 3.0,
        (Shape::Sphere, true) => 4.0 * PI * r * r,
        (Shape::Capsule, false) => PI * (r * r * h + 4.0 * r * r * r / 3.0),
        (Shape::Capsule, true) => 4.0 * PI * r * r + 2.0 * PI * r * h,
        (Shape::Cylinder, false) => PI * r * r * h,
        (Shape::Cylinder, true) => 2.0 * PI * r * r + 2.0 * PI * r * h,
        (Shape::Ellipsoid, false) => 4.0 * PI * s[0] * s[1] * s[2] / 3.0,
        (Shape::Ellipsoid, true) => {
            // Thomsen's approximation of the surface, as MuJoCo.
            let p = 1.6075;
            let t = (s[0] * s[1]).powf(p) + (s[1] * s[2]).powf(p) + (s[2] * s[0]).powf(p);
            4.0 * PI * (t / 3.0).powf(1.0 / p)
        }
        (Shape::Box, false) => 8.0 * s[0] * s[1] * s[2],
        (Shape::Box, true) => 8.0 * (s[0] * s[1] + s[1] * s[2] + s[2] * s[0]),
        (Shape::Massless, _) => 0.0,
    }
}

/// The principal moments of a shape of mass `m` about its centre, in its own frame
/// (MuJoCo's `mjCGeom::SetInertia`).
pub(super) fn moments(shape: Shape, s: [f64; 3], m: f64, shell: bool) -> [f64; 3] {
    let (r, hh) = (s[0], s[1]);
    let h = 2.0 * hh;
    let (s00, s11, s22) = (s[0] * s[0], s[1] * s[1], s[2] * s[2]);
    match (shape, shell) {
        (Shape::Sphere, false) => [2.0 * m * r * r / 5.0; 3],
        (Shape::Sphere, true) => [2.0 * m * r * r / 3.0; 3],
        (Shape::Capsule, false) => {
            let ms = m * 4.0 * r / (4.0 * r + 3.0 * h);
            let mc = m - ms;
            let side = mc * (3.0 * r * r + h * h) / 12.0
                + 2.0 * ms * r * r / 5.0
                + ms * h * (3.0 * r + 2.0 * h) / 8.0;
            [side, side, mc * r * r / 2.0 + 2.0 * ms * r * r / 5.0]
        }
        (Shape::Capsule, true) => {
            let (a_s, a_c) = (
                4.0 * std::f64::consts::PI * r * r,
                2.0 * std::f64::consts::PI * r * h,
            );
            let ms = m * a_s / (a_s + a_c);
            let mc = m - ms;
            let (com, pos) = (r / 2.0, hh + r / 2.0);
            let side = mc * (6.0 * r * r + h * h) / 12.0
                + 2.0 * ms * r * r / 3.0
                + ms * (pos * pos - com * com);
            [side, side, mc * r * r + 2.0 * ms * r * r / 3.0]
        }
        (Shape::Cylinder, false) => {
            let side = m * (3.0 * r * r + h * h) / 12.0;
            [side, side, m * r * r / 2.0]
        }
        (Shape::Cylinder, true) => {
            let a_d = std::f64::consts::PI * r * r;
            let a_c = 2.0 * std::f64::consts::PI * r * h;
            let md = m * a_d / (2.0 * a_d + a_c);
            let mc = m - 2.0 * md;
            let side = mc * (6.0 * r * r + h * h) / 12.0 + 2.0 * (md * r * r / 4.0 + md * hh * hh);
            [side, side, mc * r * r + md * r * r]
        }
        (Shape::Ellipsoid, false) => [
            m * (s11 + s22) / 5.0,
            m * (s00 + s22) / 5.0,
            m * (s00 + s11) / 5.0,
        ],
        (Shape::Ellipsoid, true) => {
            // The solid grown by 1e-6 less the solid, at the shell's density (MuJoCo's).
            let eps = 1e-6;
            let va = 4.0 * std::f64::consts::PI * s[0] * s[1] * s[2] / 3.0;
            let e = s.map(|x| x + eps);
            let vb = 4.0 * std::f64::consts::PI * e[0] * e[1] * e[2] / 3.0;
            let rho = m / (vb - va);
            let (ma, mb) = (va * rho, vb * rho);
            [
                mb * (e[1] * e[1] + e[2] * e[2]) / 5.0 - ma * (s11 + s22) / 5.0,
                mb * (e[0] * e[0] + e[2] * e[2]) / 5.0 - ma * (s00 + s22) / 5.0,
                mb * (e[0] * e[0] + e[1] * e[1]) / 5.0 - ma * (s00 + s11) / 5.0,
            ]
        }
        (Shape::Box, false) => [
            m * (s11 + s22) / 3.0,
            m * (s00 + s22) / 3.0,
            m * (s00 + s11) / 3.0,
        ],
        (Shape::Box, true) => box_shell(s, m),
        (Shape::Massless, _) => [0.0; 3],
    }
}

/// A hollow box's principal moments: its six faces as plates (MuJoCo's).
fn box_shell(s: [f64; 3], m: f64) -> [f64; 3] {
    let (lx, ly, lz) = (2.0 * s[0], 2.0 * s[1], 2.0 * s[2]);
    let (s00, s11, s22) = (s[0] * s[0], s[1] * s[1], s[2] * s[2]);
    let (a0, a1, a2) = (lx * ly, ly * lz, lz * lx);
    let total = 2.0 * (a0 + a1 + a2);
    let (m0, m1, m2) = (m * a0 / total, m * a1 / total, m * a2 / total);
    let (ix0, iy0, iz0) = (
        m0 * ly * ly / 12.0,
        m0 * lx * lx / 12.0,
        m0 * (lx * lx + ly * ly) / 12.0,
    );
    let (ix1, iy1, iz1) = (
        m1 * (ly * ly + lz * lz) / 12.0,
        m1 * lz * lz / 12.0,
        m1 * ly * ly / 12.0,
    );
    let (ix2, iy2, iz2) = (
        m2 * lz * lz / 12.0,
        m2 * (lx * lx + lz * lz) / 12.0,
        m2 * lx * lx / 12.0,
    );
    [
        2.0 * (m0 * s22 + m2 * s11 + ix0 + ix1 + ix2),
        2.0 * (m0 * s22 + m1 * s00 + iy0 + iy1 + iy2),
        2.0 * (m1 * s00 + m2 * s11 + iz0 + iz1 + iz2),
    ]
}

/// Mass properties with principal moments `d` about axes rotated by `r`, centred at `c`.
pub(super) fn principal(m: f64, c: [f64; 3], r: &Mat3<f64>, d: [f64; 3]) -> MassProps {
    let diag = Mat3([[d[0], 0.0, 0.0], [0.0, d[1], 0.0], [0.0, 0.0, d[2]]]);
    MassProps {
        m,
        c: Vec3(c),
        i: rotate_inertia(r, &diag),
    }
}

/// A body's inertia with the compiler's bounds: each principal moment at least `boundinertia`,
/// and, with `balanceinertia`, moments that break the triangle inequality all set to their mean
/// (MuJoCo applies both to the principal moments). `None` where nothing changes.
pub(super) fn bound_inertia(i: &Mat3<f64>, compiler: &Compiler) -> Option<Mat3<f64>> {
    if compiler.boundinertia <= 0.0 && !compiler.balanceinertia {
        return None;
    }
    let m = nalgebra::Matrix3::from_fn(|a, b| i.0[a][b]);
    let eig = nalgebra::SymmetricEigen::new(m);
    let mut d: [f64; 3] = [eig.eigenvalues[0], eig.eigenvalues[1], eig.eigenvalues[2]];
    let before = d;
    for x in &mut d {
        *x = x.max(compiler.boundinertia);
    }
    if compiler.balanceinertia && (d[0] + d[1] < d[2] || d[0] + d[2] < d[1] || d[1] + d[2] < d[0]) {
        d = [(d[0] + d[1] + d[2]) / 3.0; 3];
    }
    if d == before {
        return None;
    }
    let v = eig.eigenvectors;
    let r = Mat3::from_f64([
        [v[(0, 0)], v[(0, 1)], v[(0, 2)]],
        [v[(1, 0)], v[(1, 1)], v[(1, 2)]],
        [v[(2, 0)], v[(2, 1)], v[(2, 2)]],
    ]);
    Some(principal(0.0, [0.0; 3], &r, d).i)
}
