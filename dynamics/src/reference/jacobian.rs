//! The cross-check: Wieber's formulation (Wieber 2005, eqs. 5–8) from plain 3D kinematics in the
//! world frame, sharing nothing with the spatial recursions but the [`Model`].
//!
//! For each body `k`, with centre of mass `x_k` (world frame) and angular velocity `ω_k` (body
//! frame):
//! - `ẋ_k = J_tk·q̇` and `ω_k = J_Rk·q̇` (Wieber 2005, eq. 3), built column by column: a rotation
//!   about the unit axis `u` (world) through the point `o` contributes `u × (x_k − o)` to `J_tk`
//!   and `R_kᵀ·u` to `J_Rk`; a translation along `u` contributes `u` to `J_tk` only;
//! - their time derivatives analytically: `u̇ = ω_F × u` for the frame `F` that carries `u`, so
//!   `d/dt (u × (x − o)) = u̇ × (x − o) + u × (ẋ − ȯ)` and
//!   `d/dt (R_kᵀ·u) = R_kᵀ·(u̇ − ω_k^world × u)`;
//! - `M = Σ J_tkᵀ m_k J_tk + J_Rkᵀ 𝕀_k J_Rk` (Wieber 2005, eq. 6),
//!   `N = Σ J_tkᵀ m_k J̇_tk + J_Rkᵀ 𝕀_k J̇_Rk − J_Rkᵀ ((𝕀_k J_Rk q̇)×) J_Rk` (Wieber 2005, eq. 7),
//!   and gravity's generalized force `𝓕_g = Σ J_tkᵀ m_k g` (Wieber 2005, eq. 8 with
//!   `f_k = m_k·g`, `τ_k = 0`). [`super::Reference::gravity`] is `−𝓕_g`.
//!
//! `q̇` here stands for the velocity vector `v` of each joint as documented in
//! [`crate::model::JointKind`] (body angular velocity for quaternion joints); Gauss's principle
//! holds for any velocity coordinates with `ẋ_k = J_tk·v`. `f64` only; it allocates.

// Index loops mirror the matrix formulas they implement.
#![allow(clippy::needless_range_loop)]

use alloc::vec::Vec;

use nalgebra::{DMatrix, DVector, Matrix3, Quaternion, Rotation3, Unit, UnitQuaternion, Vector3};

use super::{check_model, check_q, check_vector, Error};
use crate::model::{JointKind, Model};

/// The Jacobians of one body (Wieber 2005, eqs. 3–4), each `3 × nv`.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyJacobians {
    /// `J_t`: velocity of the centre of mass, world frame.
    pub jt: DMatrix<f64>,
    /// `J_R`: angular velocity, body frame.
    pub jr: DMatrix<f64>,
    /// `J̇_t(q, q̇)`.
    pub jt_dot: DMatrix<f64>,
    /// `J̇_R(q, q̇)`.
    pub jr_dot: DMatrix<f64>,
    /// The centre of mass, world frame.
    pub com: Vector3<f64>,
    /// The body frame's origin, world frame.
    pub origin: Vector3<f64>,
    /// The body's orientation `R` (body → world).
    pub rotation: Matrix3<f64>,
    /// Mass.
    pub mass: f64,
    /// Inertia about the centre of mass, body frame.
    pub inertia: Matrix3<f64>,
}

/// Wieber's `M`, `N` and `𝓕_g` at one state.
#[derive(Clone, Debug, PartialEq)]
pub struct Wieber {
    /// `M(q)` (Wieber 2005, eq. 6).
    pub mass_matrix: DMatrix<f64>,
    /// `N(q, q̇)` (Wieber 2005, eq. 7); the bias is `N·q̇`, and `Ṁ − 2N` is skew-symmetric.
    pub n: DMatrix<f64>,
    /// `𝓕_g`, gravity's generalized force (Wieber 2005, eq. 8); `Reference::gravity = −𝓕_g`.
    pub gravity_force: DVector<f64>,
}

/// One column of the kinematic Jacobians: a unit vector `u` (world) carried by a frame turning
/// at `ω_F`, so `u̇ = ω_F × u`.
#[derive(Clone, Copy, Debug)]
struct Column {
    index: usize,
    u: Vector3<f64>,
    u_dot: Vector3<f64>,
    /// `Some((o, ȯ))` for a rotation about `u` through `o`; `None` for a translation along `u`.
    pivot: Option<(Vector3<f64>, Vector3<f64>)>,
}

/// A body frame's pose and velocity in the world.
#[derive(Clone, Debug)]
struct Frame {
    r: Matrix3<f64>,
    o: Vector3<f64>,
    w: Vector3<f64>,
    o_dot: Vector3<f64>,
    columns: Vec<Column>,
}

fn rot(axis: Vector3<f64>, angle: f64) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&Unit::new_normalize(axis), angle).into_inner()
}

fn unit(k: usize) -> Vector3<f64> {
    let mut e = Vector3::zeros();
    e[k] = 1.0;
    e
}

/// The Jacobians of every body at `(q, v)`.
pub fn body_jacobians(
    model: &Model,
    params: &[f64],
    q: &[f64],
    v: &[f64],
) -> Result<Vec<BodyJacobians>, Error> {
    check_model(model, params)?;
    check_q(model, q)?;
    check_vector("v", v, model.nv())?;
    let nv = model.nv();
    let val = |x: &crate::model::Value| x.get(params);
    let mut frames: Vec<Frame> = Vec::with_capacity(model.nb());
    let mut out = Vec::with_capacity(model.nb());
    let (mut qa, mut va) = (0, 0);
    for (joint, body) in model.joints.iter().zip(&model.bodies) {
        let world = Frame {
            r: Matrix3::identity(),
            o: Vector3::zeros(),
            w: Vector3::zeros(),
            o_dot: Vector3::zeros(),
            columns: Vec::new(),
        };
        let p = match joint.parent {
            Some(b) => &frames[b],
            None => &world,
        };
        let pl = &joint.placement;
        let rpy = pl.rpy.map(|x| val(&x));
        let r_place = rot(unit(2), rpy[2]) * rot(unit(1), rpy[1]) * rot(unit(0), rpy[0]);
        let xyz = Vector3::from(pl.xyz.map(|x| val(&x)));
        // The joint frame: fixed in the parent.
        let r_j = p.r * r_place;
        let o_j = p.o + p.r * xyz;
        let o_j_dot = p.o_dot + p.w.cross(&(o_j - p.o));
        let mut columns = p.columns.clone();
        let qj = &q[qa..qa + joint.kind.nq()];
        let vj = &v[va..va + joint.kind.nv()];
        // Euler angles about the moving axes: each axis is carried by the frame before its turn.
        let euler = |axes: [crate::model::Axis; 3],
                     angles: &[f64],
                     rates: &[f64],
                     first: usize,
                     mut r: Matrix3<f64>,
                     mut w: Vector3<f64>,
                     pivot: (Vector3<f64>, Vector3<f64>),
                     columns: &mut Vec<Column>| {
            for k in 0..3 {
                let a = Vector3::from(axes[k].unit());
                let u = r * a;
                columns.push(Column {
                    index: first + k,
                    u,
                    u_dot: w.cross(&u),
                    pivot: Some(pivot),
                });
                r *= rot(a, angles[k]);
                w += u * rates[k];
            }
            (r, w)
        };
        let (r, o, w, o_dot) = match joint.kind {
            JointKind::Revolute { axis } => {
                let u = r_j * Vector3::from(axis);
                columns.push(Column {
                    index: va,
                    u,
                    u_dot: p.w.cross(&u),
                    pivot: Some((o_j, o_j_dot)),
                });
                (
                    r_j * rot(Vector3::from(axis), qj[0]),
                    o_j,
                    p.w + u * vj[0],
                    o_j_dot,
                )
            }
            JointKind::Prismatic { axis } => {
                let u = r_j * Vector3::from(axis);
                columns.push(Column {
                    index: va,
                    u,
                    u_dot: p.w.cross(&u),
                    pivot: None,
                });
                let d = u * qj[0];
                (r_j, o_j + d, p.w, o_j_dot + p.w.cross(&d) + u * vj[0])
            }
            JointKind::SphericalEuler { seq } => {
                let (r, w) = euler(seq.0, qj, vj, va, r_j, p.w, (o_j, o_j_dot), &mut columns);
                (r, o_j, w, o_j_dot)
            }
            JointKind::SphericalQuaternion => {
                let rq =
                    UnitQuaternion::from_quaternion(Quaternion::new(qj[0], qj[1], qj[2], qj[3]));
                let r = r_j * rq.to_rotation_matrix().into_inner();
                let w = p.w + r * Vector3::new(vj[0], vj[1], vj[2]);
                for k in 0..3 {
                    let u = r * unit(k);
                    columns.push(Column {
                        index: va + k,
                        u,
                        u_dot: w.cross(&u),
                        pivot: Some((o_j, o_j_dot)),
                    });
                }
                (r, o_j, w, o_j_dot)
            }
            JointKind::FreeEuler { seq } => {
                let d = r_j * Vector3::new(qj[0], qj[1], qj[2]);
                let o = o_j + d;
                let mut o_dot = o_j_dot + p.w.cross(&d);
                for k in 0..3 {
                    let u = r_j * unit(k);
                    o_dot += u * vj[k];
                    columns.push(Column {
                        index: va + k,
                        u,
                        u_dot: p.w.cross(&u),
                        pivot: None,
                    });
                }
                let (r, w) = euler(
                    seq.0,
                    &qj[3..],
                    &vj[3..],
                    va + 3,
                    r_j,
                    p.w,
                    (o, o_dot),
                    &mut columns,
                );
                (r, o, w, o_dot)
            }
            JointKind::FreeQuaternion => {
                let d = r_j * Vector3::new(qj[0], qj[1], qj[2]);
                let o = o_j + d;
                let rq =
                    UnitQuaternion::from_quaternion(Quaternion::new(qj[3], qj[4], qj[5], qj[6]));
                let r = r_j * rq.to_rotation_matrix().into_inner();
                let w = p.w + r * Vector3::new(vj[3], vj[4], vj[5]);
                let o_dot = o_j_dot + p.w.cross(&d) + r * Vector3::new(vj[0], vj[1], vj[2]);
                for k in 0..3 {
                    let u = r * unit(k);
                    columns.push(Column {
                        index: va + k,
                        u,
                        u_dot: w.cross(&u),
                        pivot: None,
                    });
                }
                for k in 0..3 {
                    let u = r * unit(k);
                    columns.push(Column {
                        index: va + 3 + k,
                        u,
                        u_dot: w.cross(&u),
                        pivot: Some((o, o_dot)),
                    });
                }
                (r, o, w, o_dot)
            }
            JointKind::Fixed => (r_j, o_j, p.w, o_j_dot),
        };
        qa += joint.kind.nq();
        va += joint.kind.nv();

        // The body's centre of mass and its Jacobians.
        let c = r * Vector3::from(body.com.map(|x| val(&x)));
        let x = o + c;
        let x_dot = o_dot + w.cross(&c);
        let mut jt = DMatrix::zeros(3, nv);
        let mut jr = DMatrix::zeros(3, nv);
        let mut jt_dot = DMatrix::zeros(3, nv);
        let mut jr_dot = DMatrix::zeros(3, nv);
        for col in &columns {
            let (t, t_dot, a, a_dot) = match col.pivot {
                Some((po, po_dot)) => (
                    col.u.cross(&(x - po)),
                    col.u_dot.cross(&(x - po)) + col.u.cross(&(x_dot - po_dot)),
                    r.transpose() * col.u,
                    r.transpose() * (col.u_dot - w.cross(&col.u)),
                ),
                None => (col.u, col.u_dot, Vector3::zeros(), Vector3::zeros()),
            };
            jt.set_column(col.index, &t);
            jt_dot.set_column(col.index, &t_dot);
            jr.set_column(col.index, &a);
            jr_dot.set_column(col.index, &a_dot);
        }
        out.push(BodyJacobians {
            jt,
            jr,
            jt_dot,
            jr_dot,
            com: x,
            origin: o,
            rotation: r,
            mass: val(&body.mass),
            inertia: Matrix3::from_fn(|i, j| val(&body.inertia[i][j])),
        });
        frames.push(Frame {
            r,
            o,
            w,
            o_dot,
            columns,
        });
    }
    Ok(out)
}

/// `M`, `N` and `𝓕_g` by Wieber 2005, eqs. 6, 7 and 8, at `(q, v)`.
pub fn wieber(model: &Model, params: &[f64], q: &[f64], v: &[f64]) -> Result<Wieber, Error> {
    let bodies = body_jacobians(model, params, q, v)?;
    let nv = model.nv();
    let g = match &model.gravity {
        Some(g) => Vector3::from(g.map(|x| x.get(params))),
        None => Vector3::zeros(),
    };
    let qd = DVector::from_column_slice(v);
    let mut m = DMatrix::zeros(nv, nv);
    let mut n = DMatrix::zeros(nv, nv);
    let mut f_g = DVector::zeros(nv);
    for b in &bodies {
        let i = DMatrix::from_fn(3, 3, |r, c| b.inertia[(r, c)]);
        let jt_t = b.jt.transpose();
        let jr_t = b.jr.transpose();
        m += &jt_t * &b.jt * b.mass + &jr_t * &i * &b.jr;
        let iw = &i * (&b.jr * &qd);
        let iw_x = DMatrix::from_row_slice(
            3,
            3,
            &[0.0, -iw[2], iw[1], iw[2], 0.0, -iw[0], -iw[1], iw[0], 0.0],
        );
        n += &jt_t * &b.jt_dot * b.mass + &jr_t * &i * &b.jr_dot - &jr_t * iw_x * &b.jr;
        f_g += &jt_t * DVector::from_column_slice((g * b.mass).as_slice());
    }
    Ok(Wieber {
        mass_matrix: m,
        n,
        gravity_force: f_g,
    })
}
