//! Spatial algebra over a generic [`Scalar`] (Featherstone 2008, RBDA ch. 2).
//!
//! # Ordering: angular first
//! Every 6-vector here is **angular first**, as in Featherstone's book:
//! a [`Motion`] is `[ω; v]` (angular velocity, then the linear velocity of the body-fixed point
//! at the frame origin) and a [`Force`] is `[n; f]` (the couple about the frame origin, then the
//! force). Pinocchio stores them linear first: swap the halves when comparing.
//!
//! # Rotations
//! [`Mat3::rot_x`], [`Mat3::rot_y`], [`Mat3::rot_z`], [`Mat3::rot_axis`], [`Mat3::rpy`] and
//! [`Mat3::quaternion`] return the **active** rotation `R` whose columns are the rotated frame's
//! axes written in the original frame (so `p_parent = R·p_child`). A [`Transform`] stores
//! Featherstone's coordinate transform `E = Rᵀ` instead.
//!
//! Nothing here branches on or compares a scalar value, allocates, or needs `std`: the generator
//! traces this same code over a symbolic scalar.

use core::ops::{Add, Mul, Neg, Sub};

use crate::scalar::Scalar;

/// How far from 1 the norm of a quaternion in `q` may be: within it the quaternion is
/// normalized (so a state printed to a few digits, or integrated for long, is taken as meant);
/// beyond it the state is refused (`reference::Error::NotUnitQuaternion`, and the runtime's
/// integrators' `Cause::NotUnitQuaternion`). A quaternion that far off unit is a mistake: a
/// vector of zeros, a quaternion scaled by hand, or the four numbers of another layout.
pub const QUATERNION_NORM_TOLERANCE: f64 = 1e-3;

/// A 3-vector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vec3<T>(pub [T; 3]);

/// The names of the three axes, for labels.
const AXES: [&str; 3] = ["x", "y", "z"];

impl<T: Scalar> Vec3<T> {
    /// Labels the components `{stem}_x`, `{stem}_y`, `{stem}_z` ([`Scalar::label`]).
    #[inline(always)]
    pub fn label(self, stem: core::fmt::Arguments<'_>) -> Self {
        Vec3([0, 1, 2].map(|k| self.0[k].label(format_args!("{stem}_{}", AXES[k]))))
    }
    /// `[x, y, z]`.
    pub fn new(x: T, y: T, z: T) -> Self {
        Vec3([x, y, z])
    }
    /// The zero vector.
    pub fn zero() -> Self {
        Vec3([T::zero(); 3])
    }
    /// A constant vector.
    pub fn from_f64(a: [f64; 3]) -> Self {
        Vec3([T::from_f64(a[0]), T::from_f64(a[1]), T::from_f64(a[2])])
    }
    /// Dot product.
    pub fn dot(self, o: Self) -> T {
        self.0[0] * o.0[0] + self.0[1] * o.0[1] + self.0[2] * o.0[2]
    }
    /// Cross product `self × o`.
    pub fn cross(self, o: Self) -> Self {
        let [a0, a1, a2] = self.0;
        let [b0, b1, b2] = o.0;
        Vec3([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])
    }
    /// `s·self`.
    pub fn scale(self, s: T) -> Self {
        Vec3([self.0[0] * s, self.0[1] * s, self.0[2] * s])
    }
}

impl<T: Scalar> Add for Vec3<T> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Vec3([self.0[0] + o.0[0], self.0[1] + o.0[1], self.0[2] + o.0[2]])
    }
}

impl<T: Scalar> Sub for Vec3<T> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Vec3([self.0[0] - o.0[0], self.0[1] - o.0[1], self.0[2] - o.0[2]])
    }
}

impl<T: Scalar> Neg for Vec3<T> {
    type Output = Self;
    fn neg(self) -> Self {
        Vec3([-self.0[0], -self.0[1], -self.0[2]])
    }
}

/// A 3×3 matrix, stored by rows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mat3<T>(pub [[T; 3]; 3]);

impl<T: Scalar> Mat3<T> {
    /// Labels every entry `{stem}_xx`, `{stem}_xy`, … ([`Scalar::label`]).
    #[inline(always)]
    pub fn label(self, stem: core::fmt::Arguments<'_>) -> Self {
        Mat3([0, 1, 2].map(|r| {
            [0, 1, 2].map(|c| self.0[r][c].label(format_args!("{stem}_{}{}", AXES[r], AXES[c])))
        }))
    }
    /// Labels the upper triangle `{stem}_xx`, `{stem}_xy`, … of a symmetric matrix (the lower
    /// triangle is the same values).
    #[inline(always)]
    pub fn label_symmetric(self, stem: core::fmt::Arguments<'_>) -> Self {
        let mut m = self;
        for (r, row_axis) in AXES.iter().enumerate() {
            for (c, col_axis) in AXES.iter().enumerate().skip(r) {
                m.0[r][c] = self.0[r][c].label(format_args!("{stem}_{row_axis}{col_axis}"));
            }
        }
        m
    }
    /// The zero matrix.
    pub fn zero() -> Self {
        Mat3([[T::zero(); 3]; 3])
    }
    /// The identity.
    pub fn identity() -> Self {
        let (o, z) = (T::one(), T::zero());
        Mat3([[o, z, z], [z, o, z], [z, z, o]])
    }
    /// A constant matrix (rows).
    pub fn from_f64(a: [[f64; 3]; 3]) -> Self {
        Mat3(a.map(|r| r.map(T::from_f64)))
    }
    /// The skew matrix `v×` with `(v×)·u = v × u` (Featherstone 2008, RBDA eq. 2.23).
    pub fn skew(v: Vec3<T>) -> Self {
        let z = T::zero();
        let [x, y, w] = v.0;
        Mat3([[z, -w, y], [w, z, -x], [-y, x, z]])
    }
    /// Transpose.
    pub fn transpose(self) -> Self {
        let a = self.0;
        Mat3([
            [a[0][0], a[1][0], a[2][0]],
            [a[0][1], a[1][1], a[2][1]],
            [a[0][2], a[1][2], a[2][2]],
        ])
    }
    /// `self·v`.
    pub fn mul_vec(&self, v: Vec3<T>) -> Vec3<T> {
        let a = &self.0;
        Vec3([
            a[0][0] * v.0[0] + a[0][1] * v.0[1] + a[0][2] * v.0[2],
            a[1][0] * v.0[0] + a[1][1] * v.0[1] + a[1][2] * v.0[2],
            a[2][0] * v.0[0] + a[2][1] * v.0[1] + a[2][2] * v.0[2],
        ])
    }
    /// `selfᵀ·v`.
    pub fn tr_mul_vec(&self, v: Vec3<T>) -> Vec3<T> {
        let a = &self.0;
        Vec3([
            a[0][0] * v.0[0] + a[1][0] * v.0[1] + a[2][0] * v.0[2],
            a[0][1] * v.0[0] + a[1][1] * v.0[1] + a[2][1] * v.0[2],
            a[0][2] * v.0[0] + a[1][2] * v.0[1] + a[2][2] * v.0[2],
        ])
    }
    /// `self·b`.
    pub fn mul_mat(&self, b: &Self) -> Self {
        let mut out = Self::zero();
        for i in 0..3 {
            for j in 0..3 {
                out.0[i][j] =
                    self.0[i][0] * b.0[0][j] + self.0[i][1] * b.0[1][j] + self.0[i][2] * b.0[2][j];
            }
        }
        out
    }
    /// `self + b`.
    pub fn add(&self, b: &Self) -> Self {
        let mut out = *self;
        for i in 0..3 {
            for j in 0..3 {
                out.0[i][j] = self.0[i][j] + b.0[i][j];
            }
        }
        out
    }
    /// `self − b`.
    pub fn sub(&self, b: &Self) -> Self {
        let mut out = *self;
        for i in 0..3 {
            for j in 0..3 {
                out.0[i][j] = self.0[i][j] - b.0[i][j];
            }
        }
        out
    }
    /// Rotation by `angle` about x: `[[1, 0, 0], [0, c, −s], [0, s, c]]`.
    pub fn rot_x(angle: T) -> Self {
        let (s, c) = angle.sin_cos();
        let (o, z) = (T::one(), T::zero());
        Mat3([[o, z, z], [z, c, -s], [z, s, c]])
    }
    /// Rotation by `angle` about y: `[[c, 0, s], [0, 1, 0], [−s, 0, c]]`.
    pub fn rot_y(angle: T) -> Self {
        let (s, c) = angle.sin_cos();
        let (o, z) = (T::one(), T::zero());
        Mat3([[c, z, s], [z, o, z], [-s, z, c]])
    }
    /// Rotation by `angle` about z: `[[c, −s, 0], [s, c, 0], [0, 0, 1]]`.
    pub fn rot_z(angle: T) -> Self {
        let (s, c) = angle.sin_cos();
        let (o, z) = (T::one(), T::zero());
        Mat3([[c, -s, z], [s, c, z], [z, z, o]])
    }
    /// Rotation by `angle` about the unit vector `u` (Rodrigues):
    /// `R = 1 + sin·(u×) + (1 − cos)·(u×)²`.
    pub fn rot_axis(u: Vec3<T>, angle: T) -> Self {
        let (s, c) = angle.sin_cos();
        let k = Self::skew(u);
        let one_c = T::one() - c;
        let mut out = Self::identity();
        for i in 0..3 {
            for j in 0..3 {
                out.0[i][j] = if i == j {
                    // u_i² + c·(1 − u_i²), equal to c + (1 − c)·u_i², but written so that a
                    // coordinate axis folds to exactly 1 or c when traced symbolically.
                    let uu = u.0[i] * u.0[i];
                    uu + c * (T::one() - uu)
                } else {
                    one_c * u.0[i] * u.0[j] + s * k.0[i][j]
                };
            }
        }
        out
    }
    /// Roll, pitch, yaw about fixed axes (URDF): `R = Rz(yaw)·Ry(pitch)·Rx(roll)`.
    pub fn rpy(roll: T, pitch: T, yaw: T) -> Self {
        Self::rot_z(yaw)
            .mul_mat(&Self::rot_y(pitch))
            .mul_mat(&Self::rot_x(roll))
    }
    /// The rotation of the quaternion `[w, x, y, z]`, divided by `|q|²` so that a non-unit
    /// quaternion is normalized (`R = 1 + (2/|q|²)·(w·(u×) + (u×)²)` with `u = [x, y, z]`).
    /// The zero quaternion gives NaN: callers check it first.
    pub fn quaternion(q: [T; 4]) -> Self {
        let [w, x, y, z] = q;
        let s = T::from_f64(2.0) / (w * w + x * x + y * y + z * z);
        let o = T::one();
        Mat3([
            [
                o - s * (y * y + z * z),
                s * (x * y - w * z),
                s * (x * z + w * y),
            ],
            [
                s * (x * y + w * z),
                o - s * (x * x + z * z),
                s * (y * z - w * x),
            ],
            [
                s * (x * z - w * y),
                s * (y * z + w * x),
                o - s * (x * x + y * y),
            ],
        ])
    }
}

/// A spatial motion vector `[ω; v]` (angular first), Featherstone 2008, RBDA §2.3.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion<T> {
    /// Angular part `ω`.
    pub ang: Vec3<T>,
    /// Linear part `v`: velocity of the body-fixed point at the frame origin.
    pub lin: Vec3<T>,
}

/// A spatial force vector `[n; f]` (angular first), Featherstone 2008, RBDA §2.4.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Force<T> {
    /// Couple `n` about the frame origin.
    pub ang: Vec3<T>,
    /// Force `f`.
    pub lin: Vec3<T>,
}

impl<T: Scalar> Motion<T> {
    /// Labels the angular part `{ang}_x, …` and the linear part `{lin}_x, …`
    /// ([`Scalar::label`]).
    #[inline(always)]
    pub fn label(self, ang: core::fmt::Arguments<'_>, lin: core::fmt::Arguments<'_>) -> Self {
        Motion::new(self.ang.label(ang), self.lin.label(lin))
    }
    /// `[ang; lin]`.
    pub fn new(ang: Vec3<T>, lin: Vec3<T>) -> Self {
        Motion { ang, lin }
    }
    /// Zero motion.
    pub fn zero() -> Self {
        Motion::new(Vec3::zero(), Vec3::zero())
    }
    /// `s·self`.
    pub fn scale(self, s: T) -> Self {
        Motion::new(self.ang.scale(s), self.lin.scale(s))
    }
    /// Motion cross product `self ×m m` (Featherstone 2008, RBDA eq. 2.31):
    /// `[ω × m_ω; ω × m_v + v × m_ω]`.
    pub fn cross_motion(self, m: Motion<T>) -> Motion<T> {
        Motion::new(
            self.ang.cross(m.ang),
            self.ang.cross(m.lin) + self.lin.cross(m.ang),
        )
    }
    /// Force cross product `self ×f f` (Featherstone 2008, RBDA eq. 2.32):
    /// `[ω × n + v × f; ω × f]`.
    pub fn cross_force(self, f: Force<T>) -> Force<T> {
        Force::new(
            self.ang.cross(f.ang) + self.lin.cross(f.lin),
            self.ang.cross(f.lin),
        )
    }
    /// The scalar product `m·f` (power).
    pub fn dot(self, f: Force<T>) -> T {
        self.ang.dot(f.ang) + self.lin.dot(f.lin)
    }
    /// As a 6-array `[ωx, ωy, ωz, vx, vy, vz]`.
    pub fn to_array(self) -> [T; 6] {
        let (a, l) = (self.ang.0, self.lin.0);
        [a[0], a[1], a[2], l[0], l[1], l[2]]
    }
    /// From a 6-array `[ω; v]`.
    pub fn from_array(a: [T; 6]) -> Self {
        Motion::new(Vec3([a[0], a[1], a[2]]), Vec3([a[3], a[4], a[5]]))
    }
}

impl<T: Scalar> Force<T> {
    /// Labels the couple `{ang}_x, …` and the force `{lin}_x, …` ([`Scalar::label`]).
    #[inline(always)]
    pub fn label(self, ang: core::fmt::Arguments<'_>, lin: core::fmt::Arguments<'_>) -> Self {
        Force::new(self.ang.label(ang), self.lin.label(lin))
    }
    /// `[ang; lin]`.
    pub fn new(ang: Vec3<T>, lin: Vec3<T>) -> Self {
        Force { ang, lin }
    }
    /// Zero force.
    pub fn zero() -> Self {
        Force::new(Vec3::zero(), Vec3::zero())
    }
    /// `s·self`.
    pub fn scale(self, s: T) -> Self {
        Force::new(self.ang.scale(s), self.lin.scale(s))
    }
    /// As a 6-array `[n; f]`.
    pub fn to_array(self) -> [T; 6] {
        let (a, l) = (self.ang.0, self.lin.0);
        [a[0], a[1], a[2], l[0], l[1], l[2]]
    }
    /// From a 6-array `[n; f]`.
    pub fn from_array(a: [T; 6]) -> Self {
        Force::new(Vec3([a[0], a[1], a[2]]), Vec3([a[3], a[4], a[5]]))
    }
}

impl<T: Scalar> Add for Motion<T> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Motion::new(self.ang + o.ang, self.lin + o.lin)
    }
}

impl<T: Scalar> Sub for Motion<T> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Motion::new(self.ang - o.ang, self.lin - o.lin)
    }
}

impl<T: Scalar> Neg for Motion<T> {
    type Output = Self;
    fn neg(self) -> Self {
        Motion::new(-self.ang, -self.lin)
    }
}

impl<T: Scalar> Add for Force<T> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Force::new(self.ang + o.ang, self.lin + o.lin)
    }
}

impl<T: Scalar> Sub for Force<T> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Force::new(self.ang - o.ang, self.lin - o.lin)
    }
}

impl<T: Scalar> Neg for Force<T> {
    type Output = Self;
    fn neg(self) -> Self {
        Force::new(-self.ang, -self.lin)
    }
}

/// A rigid coordinate transform `X` from frame A to frame B in Featherstone's `(E, r)` form
/// (RBDA §2.8): `E` turns A coordinates into B coordinates (`E = Rᵀ` where `R` is B's orientation
/// in A) and `r` is B's origin in A coordinates. As a 6×6 motion transform,
/// `X = [E 0; −E·(r×) E]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform<T> {
    /// Rotation from A coordinates to B coordinates.
    pub e: Mat3<T>,
    /// B's origin, in A coordinates.
    pub r: Vec3<T>,
}

impl<T: Scalar> Transform<T> {
    /// The identity transform.
    pub fn identity() -> Self {
        Transform {
            e: Mat3::identity(),
            r: Vec3::zero(),
        }
    }
    /// The transform to a frame B whose orientation in A is `rot` (active) and whose origin is at
    /// `origin` (A coordinates): `E = rotᵀ`, `r = origin`.
    pub fn from_pose(rot: Mat3<T>, origin: Vec3<T>) -> Self {
        Transform {
            e: rot.transpose(),
            r: origin,
        }
    }
    /// `X·m`: a motion in A coordinates to B coordinates, `[E·ω; E·(v − r × ω)]`.
    pub fn apply_motion(&self, m: Motion<T>) -> Motion<T> {
        Motion::new(
            self.e.mul_vec(m.ang),
            self.e.mul_vec(m.lin - self.r.cross(m.ang)),
        )
    }
    /// `X⁻¹·m`: a motion in B coordinates to A coordinates, `[Eᵀω; Eᵀv + r × Eᵀω]`.
    pub fn inv_apply_motion(&self, m: Motion<T>) -> Motion<T> {
        let w = self.e.tr_mul_vec(m.ang);
        Motion::new(w, self.e.tr_mul_vec(m.lin) + self.r.cross(w))
    }
    /// `X*·f`: a force in A coordinates to B coordinates, `[E·(n − r × f); E·f]`.
    pub fn apply_force(&self, f: Force<T>) -> Force<T> {
        Force::new(
            self.e.mul_vec(f.ang - self.r.cross(f.lin)),
            self.e.mul_vec(f.lin),
        )
    }
    /// `Xᵀ·f = (X*)⁻¹·f`: a force in B coordinates to A coordinates,
    /// `[Eᵀn + r × Eᵀf; Eᵀf]`.
    pub fn inv_apply_force(&self, f: Force<T>) -> Force<T> {
        let lin = self.e.tr_mul_vec(f.lin);
        Force::new(self.e.tr_mul_vec(f.ang) + self.r.cross(lin), lin)
    }
    /// The composition `self ∘ first`: first A → B (`first`), then B → C (`self`); the result
    /// maps A to C with `E = E_bc·E_ab` and `r = r_ab + E_abᵀ·r_bc`.
    pub fn after(&self, first: &Transform<T>) -> Transform<T> {
        Transform {
            e: self.e.mul_mat(&first.e),
            r: first.r + first.e.tr_mul_vec(self.r),
        }
    }
    /// The 6×6 motion transform `[E 0; −E·(r×) E]`.
    pub fn to_mat6(&self) -> Mat6<T> {
        let mut out = Mat6::zero();
        let erx = self.e.mul_mat(&Mat3::skew(self.r));
        for i in 0..3 {
            for j in 0..3 {
                out.0[i][j] = self.e.0[i][j];
                out.0[i + 3][j + 3] = self.e.0[i][j];
                out.0[i + 3][j] = -erx.0[i][j];
            }
        }
        out
    }
}

/// A rigid-body inertia about a frame origin (Featherstone 2008, RBDA eq. 2.63): mass `m`, first
/// moment `h = m·c` (`c` the centre of mass) and `Ī = I_c − m·(c×)(c×)`, the rotational inertia
/// about the origin. A massless frame is all zeros.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inertia<T> {
    /// Mass.
    pub m: T,
    /// First mass moment `m·c`.
    pub h: Vec3<T>,
    /// Rotational inertia about the frame origin.
    pub i: Mat3<T>,
}

impl<T: Scalar> Inertia<T> {
    /// Labels the mass `{stem}_m`, the first moment `{stem}_h_x, …` and the upper triangle of
    /// the rotational inertia `{stem}_i_xx, {stem}_i_xy, …` ([`Scalar::label`]).
    #[inline(always)]
    pub fn label(self, stem: core::fmt::Arguments<'_>) -> Self {
        Inertia {
            m: self.m.label(format_args!("{stem}_m")),
            h: self.h.label(format_args!("{stem}_h")),
            i: self.i.label_symmetric(format_args!("{stem}_i")),
        }
    }
    /// The zero inertia (a massless frame).
    pub fn zero() -> Self {
        Inertia {
            m: T::zero(),
            h: Vec3::zero(),
            i: Mat3::zero(),
        }
    }
    /// From the mass, the centre of mass `c` and the inertia `i_c` about the centre of mass (all
    /// in this frame): `h = m·c`, `Ī = I_c − m·(c×)(c×)` (parallel axes).
    pub fn from_com(m: T, c: Vec3<T>, i_c: Mat3<T>) -> Self {
        let cx = Mat3::skew(c);
        let cc = cx.mul_mat(&cx);
        let mut i = i_c;
        for r in 0..3 {
            for k in 0..3 {
                i.0[r][k] = i_c.0[r][k] - m * cc.0[r][k];
            }
        }
        Inertia {
            m,
            h: c.scale(m),
            i,
        }
    }
    /// `I·m = [Ī·ω + h × v; m·v − h × ω]` (Featherstone 2008, RBDA eq. 2.63).
    pub fn mul_motion(&self, v: Motion<T>) -> Force<T> {
        Force::new(
            self.i.mul_vec(v.ang) + self.h.cross(v.lin),
            v.lin.scale(self.m) - self.h.cross(v.ang),
        )
    }
    /// The sum of two inertias about the same origin.
    pub fn add(&self, o: &Self) -> Self {
        Inertia {
            m: self.m + o.m,
            h: self.h + o.h,
            i: self.i.add(&o.i),
        }
    }
    /// This inertia (given in B coordinates) expressed in A coordinates, `Xᵀ·I·X` for `x` from A
    /// to B (Featherstone 2008, RBDA eq. 2.66 rearranged without dividing by the mass):
    /// `h_A = Eᵀh + m·r`, `Ī_A = Eᵀ·Ī·E − (r×)(Eᵀh)× − (h_A×)(r×)`.
    pub fn to_parent(&self, x: &Transform<T>) -> Self {
        let eth = x.e.tr_mul_vec(self.h);
        let h_a = eth + x.r.scale(self.m);
        let rx = Mat3::skew(x.r);
        let rot = x.e.transpose().mul_mat(&self.i).mul_mat(&x.e);
        let i = rot
            .sub(&rx.mul_mat(&Mat3::skew(eth)))
            .sub(&Mat3::skew(h_a).mul_mat(&rx));
        Inertia {
            m: self.m,
            h: h_a,
            i,
        }
    }
    /// The 6×6 matrix `[Ī h×; −h× m·1]` mapping a motion `[ω; v]` to a force `[n; f]`.
    pub fn to_mat6(&self) -> Mat6<T> {
        let mut out = Mat6::zero();
        let hx = Mat3::skew(self.h);
        for r in 0..3 {
            for k in 0..3 {
                out.0[r][k] = self.i.0[r][k];
                out.0[r][k + 3] = hx.0[r][k];
                out.0[r + 3][k] = -hx.0[r][k];
            }
            out.0[r + 3][r + 3] = self.m;
        }
        out
    }
}

impl<T: Scalar> Mul<Motion<T>> for &Inertia<T> {
    type Output = Force<T>;
    fn mul(self, v: Motion<T>) -> Force<T> {
        self.mul_motion(v)
    }
}

/// A general 6×6 matrix (by rows), used for articulated-body inertias (motion → force) and 6×6
/// motion transforms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mat6<T>(pub [[T; 6]; 6]);

impl<T: Scalar> Mat6<T> {
    /// Labels the upper triangle `{stem}{r}{c}` of a symmetric 6×6 matrix, rows and columns
    /// counted from 0 ([`Scalar::label`]).
    #[inline(always)]
    pub fn label_symmetric(self, stem: core::fmt::Arguments<'_>) -> Self {
        let mut m = self;
        for r in 0..6 {
            for c in r..6 {
                m.0[r][c] = self.0[r][c].label(format_args!("{stem}{r}{c}"));
            }
        }
        m
    }
    /// The zero matrix.
    pub fn zero() -> Self {
        Mat6([[T::zero(); 6]; 6])
    }
    /// `self·x` for a 6-array.
    pub fn mul_array(&self, x: [T; 6]) -> [T; 6] {
        let mut out = [T::zero(); 6];
        for (o, row) in out.iter_mut().zip(&self.0) {
            let mut s = row[0] * x[0];
            for k in 1..6 {
                s = s + row[k] * x[k];
            }
            *o = s;
        }
        out
    }
    /// An articulated inertia times a motion: the force `self·m`.
    pub fn mul_motion(&self, m: Motion<T>) -> Force<T> {
        Force::from_array(self.mul_array(m.to_array()))
    }
    /// `self·b`.
    pub fn mul_mat(&self, b: &Self) -> Self {
        let mut out = Self::zero();
        for i in 0..6 {
            for j in 0..6 {
                let mut s = self.0[i][0] * b.0[0][j];
                for k in 1..6 {
                    s = s + self.0[i][k] * b.0[k][j];
                }
                out.0[i][j] = s;
            }
        }
        out
    }
    /// Transpose.
    pub fn transpose(&self) -> Self {
        let mut out = *self;
        for i in 0..6 {
            for j in 0..6 {
                out.0[i][j] = self.0[j][i];
            }
        }
        out
    }
    /// `self + b`.
    pub fn add(&self, b: &Self) -> Self {
        let mut out = *self;
        for i in 0..6 {
            for j in 0..6 {
                out.0[i][j] = self.0[i][j] + b.0[i][j];
            }
        }
        out
    }
    /// An articulated inertia given in B coordinates, expressed in A coordinates: `Xᵀ·self·X`
    /// for the motion transform `x` from A to B (Featherstone 2008, RBDA eq. 7.40's transform).
    pub fn to_parent(&self, x: &Transform<T>) -> Self {
        let xm = x.to_mat6();
        xm.transpose().mul_mat(&self.mul_mat(&xm))
    }
}
