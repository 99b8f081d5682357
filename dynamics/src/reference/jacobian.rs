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
    let world = Frame {
        r: Matrix3::identity(),
        o: Vector3::zeros(),
        w: Vector3::zeros(),
        o_dot: Vector3::zeros(),
        columns: Vec::new(),
    };
    let mut frames: Vec<Frame> = Vec::with_capacity(model.nb());
    let mut out = Vec::with_capacity(model.nb());
    let (mut qa, mut va) = (0, 0);
    for (joint, body) in model.joints.iter().zip(&model.bodies) {
        let parent = joint.parent.map_or(&world, |b| &frames[b]);
        let frame = joint_frame(parent, &joint.placement, params);
        let frame = match joint.mimic {
            // A mimic joint turns by `m·q_j + o` at `m·v_j`, and its column, `m` times the
            // column of its own motion, adds to the followed joint's column `j`.
            Some(m) => {
                let (qj, vj) = (model.q_offset(m.joint), model.v_offset(m.joint));
                let angle = m.multiplier * q[qj] + m.offset;
                let rate = m.multiplier * v[vj];
                frame.moved(joint.kind, &[angle], &[rate], vj, m.multiplier)
            }
            None => {
                let qj = &q[qa..qa + joint.kind.nq()];
                let vj = &v[va..va + joint.kind.nv()];
                frame.moved(joint.kind, qj, vj, va, 1.0)
            }
        };
        qa += joint.nq();
        va += joint.nv();
        out.push(frame.jacobians(body, model.nv(), params));
        frames.push(frame);
    }
    Ok(out)
}

/// The joint frame: the parent's frame moved by the placement, fixed in the parent.
fn joint_frame(p: &Frame, placement: &crate::model::Placement, params: &[f64]) -> Frame {
    let rpy = placement.rpy.map(|x| x.get(params));
    let r_place = rot(unit(2), rpy[2]) * rot(unit(1), rpy[1]) * rot(unit(0), rpy[0]);
    let xyz = Vector3::from(placement.xyz.map(|x| x.get(params)));
    let o = p.o + p.r * xyz;
    Frame {
        r: p.r * r_place,
        o,
        w: p.w,
        o_dot: p.o_dot + p.w.cross(&(o - p.o)),
        columns: p.columns.clone(),
    }
}

impl Frame {
    /// Adds the column of a motion about or along `u` (world), carried by a frame turning at
    /// `w`, about the pivot `(o, ȯ)` for a rotation.
    fn push(&mut self, index: usize, u: Vector3<f64>, w: Vector3<f64>, pivot: bool) {
        self.columns.push(Column {
            index,
            u,
            u_dot: w.cross(&u),
            pivot: pivot.then_some((self.o, self.o_dot)),
        });
    }

    /// Turns through Euler angles about the moving axes: each axis is carried by the frame
    /// before its turn.
    fn euler(
        &mut self,
        axes: [crate::model::Axis; 3],
        angles: &[f64],
        rates: &[f64],
        first: usize,
    ) {
        for k in 0..3 {
            let a = Vector3::from(axes[k].unit());
            let u = self.r * a;
            self.push(first + k, u, self.w, true);
            self.r *= rot(a, angles[k]);
            self.w += u * rates[k];
        }
    }

    /// Translates by `d` (world) at the rate `d_dot` relative to the frame's own turning.
    fn translate(&mut self, d: Vector3<f64>, d_dot: Vector3<f64>) {
        self.o += d;
        self.o_dot += self.w.cross(&d) + d_dot;
    }

    /// Turns by the quaternion `[w, x, y, z]` with the body angular velocity `omega`.
    fn turn(&mut self, quaternion: &[f64], omega: &[f64]) {
        let rq = UnitQuaternion::from_quaternion(Quaternion::new(
            quaternion[0],
            quaternion[1],
            quaternion[2],
            quaternion[3],
        ));
        self.r *= rq.to_rotation_matrix().into_inner();
        self.w += self.r * Vector3::new(omega[0], omega[1], omega[2]);
    }

    /// The joint frame moved by joint `kind` through `(qj, vj)` (its velocities from index
    /// `va`): the child's frame, its columns added, scaled by `scale` (a mimic joint's
    /// multiplier: the rate of its coordinate per unit of the coordinate `va`).
    fn moved(mut self, kind: JointKind, qj: &[f64], vj: &[f64], va: usize, scale: f64) -> Frame {
        let parent_w = self.w;
        match kind {
            JointKind::Revolute { axis } => {
                let u = self.r * Vector3::from(axis);
                self.push(va, u * scale, parent_w, true);
                self.r *= rot(Vector3::from(axis), qj[0]);
                self.w += u * vj[0];
            }
            JointKind::Prismatic { axis } => {
                let u = self.r * Vector3::from(axis);
                self.push(va, u * scale, parent_w, false);
                self.translate(u * qj[0], u * vj[0]);
            }
            JointKind::SphericalEuler { seq } => self.euler(seq.0, qj, vj, va),
            JointKind::SphericalQuaternion => {
                self.turn(qj, vj);
                for k in 0..3 {
                    self.push(va + k, self.r * unit(k), self.w, true);
                }
            }
            JointKind::FreeEuler { seq } => {
                let r_j = self.r;
                self.translate(
                    r_j * Vector3::new(qj[0], qj[1], qj[2]),
                    r_j * Vector3::new(vj[0], vj[1], vj[2]),
                );
                for k in 0..3 {
                    self.push(va + k, r_j * unit(k), parent_w, false);
                }
                self.euler(seq.0, &qj[3..], &vj[3..], va + 3);
            }
            JointKind::FreeQuaternion => {
                // The position is in the joint frame, the linear velocity in the child's.
                let d = self.r * Vector3::new(qj[0], qj[1], qj[2]);
                self.translate(d, Vector3::zeros());
                self.turn(&qj[3..], &vj[3..]);
                self.o_dot += self.r * Vector3::new(vj[0], vj[1], vj[2]);
                for (k, pivot) in (0..6).map(|k| (k, k >= 3)) {
                    self.push(va + k, self.r * unit(k % 3), self.w, pivot);
                }
            }
            JointKind::Fixed => {}
        }
        self
    }

    /// A body's centre of mass and its Jacobians in this frame.
    fn jacobians(&self, body: &crate::model::Body, nv: usize, params: &[f64]) -> BodyJacobians {
        let val = |x: &crate::model::Value| x.get(params);
        let (r, o, w) = (self.r, self.o, self.w);
        let c = r * Vector3::from(body.com.map(|x| val(&x)));
        let x = o + c;
        let x_dot = self.o_dot + w.cross(&c);
        let mut jt = DMatrix::zeros(3, nv);
        let mut jr = DMatrix::zeros(3, nv);
        let mut jt_dot = DMatrix::zeros(3, nv);
        let mut jr_dot = DMatrix::zeros(3, nv);
        for col in &self.columns {
            let (t, t_dot, a, a_dot) = match col.pivot {
                Some((po, po_dot)) => (
                    col.u.cross(&(x - po)),
                    col.u_dot.cross(&(x - po)) + col.u.cross(&(x_dot - po_dot)),
                    r.transpose() * col.u,
                    r.transpose() * (col.u_dot - w.cross(&col.u)),
                ),
                None => (col.u, col.u_dot, Vector3::zeros(), Vector3::zeros()),
            };
            // Added, not set: a mimic joint's column adds to the one of the joint it follows.
            for (j, x) in [
                (&mut jt, t),
                (&mut jt_dot, t_dot),
                (&mut jr, a),
                (&mut jr_dot, a_dot),
            ] {
                let mut column = j.column_mut(col.index);
                column += x;
            }
        }
        BodyJacobians {
            jt,
            jr,
            jt_dot,
            jr_dot,
            com: x,
            origin: o,
            rotation: r,
            mass: val(&body.mass),
            inertia: Matrix3::from_fn(|i, j| val(&body.inertia[i][j])),
        }
    }
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
