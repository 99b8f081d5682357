//! Frames and mass properties for the importers (URDF, MJCF): a link's frame placed in another
//! ([`Transform`], composed through fixed joints), a link's mass properties seen from another
//! frame and two links welded into one body ([`MassProps`], by the parallel-axis theorem), and the
//! roll-pitch-yaw of a composed rotation ([`matrix_rpy`]). The 3×3 algebra is the workspace's own
//! [`Mat3`] and [`Vec3`] on `f64`.

use articulated_dynamics::model::{Body, Value};
use articulated_dynamics::spatial::{Mat3, Vec3};

/// A rigid transform: a frame's origin `p` and axes `r` (active: `x_outer = r·x_inner + p`) in
/// another frame. Unlike [`articulated_dynamics::spatial::Transform`], which stores `E = rᵀ` for
/// the recursions, this is the pose URDF writes.
#[derive(Clone, Copy)]
pub(crate) struct Transform {
    pub(crate) r: Mat3<f64>,
    pub(crate) p: Vec3<f64>,
    /// Known to be the identity: composing with it is exact.
    pub(crate) identity: bool,
}

impl Transform {
    /// The identity.
    pub(crate) const IDENTITY: Transform = Transform {
        r: Mat3([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
        p: Vec3([0.0; 3]),
        identity: true,
    };

    /// A URDF `origin`: `xyz`, then `R = Rz(yaw)·Ry(pitch)·Rx(roll)`.
    pub(crate) fn from_pose(pose: &urdf_rs::Pose) -> Self {
        let [roll, pitch, yaw] = *pose.rpy;
        Transform {
            r: Mat3::rpy(roll, pitch, yaw),
            p: Vec3(*pose.xyz),
            identity: false,
        }
    }

    /// `self ∘ other`: `other` given in the frame `self` describes.
    pub(crate) fn then(&self, other: &Transform) -> Transform {
        if self.identity {
            return *other;
        }
        if other.identity {
            return *self;
        }
        Transform {
            r: self.r.mul_mat(&other.r),
            p: self.p + self.r.mul_vec(other.p),
            identity: false,
        }
    }
}

/// Roll, pitch, yaw of a rotation matrix, accurate to rounding everywhere (also near pitch =
/// ±π/2): yaw is taken from the first column, then `Rz(−yaw)·R = Ry(pitch)·Rx(roll)` gives the
/// other two from well-conditioned entries.
pub(crate) fn matrix_rpy(r: &Mat3<f64>) -> [f64; 3] {
    let yaw = r.0[1][0].atan2(r.0[0][0]);
    let rt = Mat3::rot_z(yaw).transpose().mul_mat(r).0;
    let pitch = (-rt[2][0]).atan2(rt[0][0]);
    let roll = (-rt[1][2]).atan2(rt[1][1]);
    [roll, pitch, yaw]
}

/// `R·I·Rᵀ`, symmetrized: the inertia `i` given in a frame rotated by `r`, in the outer frame.
pub(crate) fn rotate_inertia(r: &Mat3<f64>, i: &Mat3<f64>) -> Mat3<f64> {
    let mut out = r.mul_mat(i).mul_mat(&r.transpose());
    for (a, b) in [(0, 1), (0, 2), (1, 2)] {
        let s = 0.5 * (out.0[a][b] + out.0[b][a]);
        out.0[a][b] = s;
        out.0[b][a] = s;
    }
    out
}

/// Mass properties in some frame: mass, centre of mass, inertia about the centre of mass.
#[derive(Clone, Copy)]
pub(crate) struct MassProps {
    pub(crate) m: f64,
    pub(crate) c: Vec3<f64>,
    pub(crate) i: Mat3<f64>,
}

impl MassProps {
    /// No mass: a frame.
    pub(crate) const ZERO: MassProps = MassProps {
        m: 0.0,
        c: Vec3([0.0; 3]),
        i: Mat3([[0.0; 3]; 3]),
    };

    /// The model body `name` with these properties (constants).
    pub(crate) fn into_body(self, name: String) -> Body {
        Body {
            name,
            mass: Value::Const(self.m),
            com: self.c.0.map(Value::Const),
            inertia: self.i.0.map(|row| row.map(Value::Const)),
        }
    }

    /// The same properties seen from the frame in which `t` describes their frame.
    pub(crate) fn transformed(&self, t: &Transform) -> MassProps {
        if t.identity {
            return *self;
        }
        MassProps {
            m: self.m,
            c: t.p + t.r.mul_vec(self.c),
            i: rotate_inertia(&t.r, &self.i),
        }
    }

    /// Both bodies as one rigid body (both given in the same frame): the parallel-axis theorem
    /// moves each inertia to the common centre of mass.
    pub(crate) fn merged(&self, o: &MassProps) -> MassProps {
        let m = self.m + o.m;
        let c = if m > 0.0 {
            Vec3((self.c.scale(self.m) + o.c.scale(o.m)).0.map(|x| x / m))
        } else {
            Vec3::zero()
        };
        let mut i = self.i.add(&o.i);
        for part in [self, o] {
            let d = part.c - c;
            let d2 = d.dot(d);
            for (a, row) in i.0.iter_mut().enumerate() {
                for (b, x) in row.iter_mut().enumerate() {
                    let delta = if a == b { d2 } else { 0.0 };
                    *x += part.m * (delta - d.0[a] * d.0[b]);
                }
            }
        }
        MassProps { m, c, i }
    }
}
