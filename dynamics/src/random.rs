//! Deterministic random models and states for tests (this crate's, the generator's and the
//! cross-crate ones). No dependency: a splitmix64 generator seeded by the caller, so a seed names
//! the same model on every machine.
//!
//! [`random_model`] uses every [`JointKind`]: revolute and prismatic about random unit axes,
//! spherical Euler with random valid sequences, spherical quaternion, fixed, and a free base
//! (Euler or quaternion) only as the root joint. Placements are random, masses lie in
//! `[0.5, 5]` kg, inertia tensors are full, symmetric positive definite and satisfy the triangle
//! inequality. [`random_state`] gives unit quaternions and keeps Euler angles away from gimbal
//! lock, so the mass matrix is comfortably invertible.

// Index loops mirror the matrix formulas they implement.
#![allow(clippy::needless_range_loop)]

use alloc::format;
use alloc::vec::Vec;
use core::f64::consts::PI;

use crate::model::{Axis, Body, Drive, EulerSeq, Joint, JointKind, Model, Placement, Value};
use crate::spatial::Mat3;

/// SplitMix64 (Steele, Lea & Flood 2014): a seeded, reproducible stream, enough randomness for
/// test and benchmark inputs without a dependency. The trees and states here, the benchmarks'
/// inputs and the sine/cosine tests all draw from it.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator started at `seed`.
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// Uniform in `[-r, r)`.
    pub fn symmetric(&mut self, r: f64) -> f64 {
        r * (2.0 * self.unit() - 1.0)
    }
    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    /// Uniform in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
    /// A uniformly random unit vector (normalized Gaussian-free: rejection in the cube).
    fn unit_vector(&mut self) -> [f64; 3] {
        self.on_sphere()
    }
    /// A uniformly random unit quaternion `[w, x, y, z]` (rejection in the 4-cube).
    fn quaternion(&mut self) -> [f64; 4] {
        self.on_sphere()
    }
    /// A uniformly random point of the unit sphere in `N` dimensions: a point of the cube
    /// `[-1, 1)ᴺ`, drawn again until it lies in the unit ball (and not within 0.1 of the
    /// centre), normalized.
    fn on_sphere<const N: usize>(&mut self) -> [f64; N] {
        loop {
            let v: [f64; N] = core::array::from_fn(|_| self.range(-1.0, 1.0));
            let n2: f64 = v.iter().map(|x| x * x).sum();
            if n2 > 0.01 && n2 <= 1.0 {
                let n = libm::sqrt(n2);
                return v.map(|x| x / n);
            }
        }
    }
    fn axis(&mut self) -> Axis {
        [Axis::X, Axis::Y, Axis::Z][self.below(3)]
    }
    /// One of the twelve valid Euler sequences.
    fn euler_seq(&mut self) -> EulerSeq {
        let a = self.axis();
        let b = loop {
            let b = self.axis();
            if b != a {
                break b;
            }
        };
        let c = loop {
            let c = self.axis();
            if c != b {
                break c;
            }
        };
        EulerSeq([a, b, c])
    }
}

fn c(x: f64) -> Value {
    Value::Const(x)
}

/// `R·diag(d)·Rᵀ` for the rotation of the unit quaternion `q`.
fn rotate_diag(q: [f64; 4], d: [f64; 3]) -> [[f64; 3]; 3] {
    let r = Mat3::quaternion(q).0;
    let mut out = [[0.0; 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, o) in row.iter_mut().enumerate() {
            *o = (0..3).map(|k| r[i][k] * d[k] * r[j][k]).sum();
        }
    }
    // Exactly symmetric.
    for i in 0..3 {
        for j in 0..i {
            let m = 0.5 * (out[i][j] + out[j][i]);
            out[i][j] = m;
            out[j][i] = m;
        }
    }
    out
}

/// A deterministic random tree of `n_bodies` bodies (see the module docs). Body 0 is the only
/// root; each later body hangs from a random body on the current depth-first path, so the tree
/// branches at random and stays in depth-first order. Gravity is the default `[0, 0, −9.81]`; no
/// runtime parameters.
pub fn random_model(seed: u64, n_bodies: usize) -> Model {
    let mut rng = Rng(seed ^ 0x5EED_0FA7_71C0_1A7E);
    let mut bodies = Vec::with_capacity(n_bodies);
    let mut joints = Vec::with_capacity(n_bodies);
    let mut path: Vec<usize> = Vec::new();
    for i in 0..n_bodies {
        let parent = if i == 0 {
            None
        } else {
            // Prefer the deepest body (chains), branch off an earlier one a third of the time.
            let k = if rng.below(3) == 0 {
                rng.below(path.len())
            } else {
                path.len() - 1
            };
            path.truncate(k + 1);
            Some(path[k])
        };
        path.push(i);
        let kind = match (parent, rng.below(if i == 0 { 8 } else { 6 })) {
            (_, 0) => JointKind::Revolute {
                axis: rng.unit_vector(),
            },
            (_, 1) => JointKind::Prismatic {
                axis: rng.unit_vector(),
            },
            (_, 2) => JointKind::SphericalEuler {
                seq: rng.euler_seq(),
            },
            (_, 3) => JointKind::SphericalQuaternion,
            (_, 4) => JointKind::Fixed,
            (_, 5) => JointKind::Revolute {
                axis: rng.unit_vector(),
            },
            (_, 6) => JointKind::FreeEuler {
                seq: rng.euler_seq(),
            },
            _ => JointKind::FreeQuaternion,
        };
        let placement = Placement {
            xyz: [0; 3].map(|_| c(rng.range(-0.5, 0.5))),
            rpy: [0; 3].map(|_| c(rng.range(-PI, PI))),
        };
        let mass = rng.range(0.5, 5.0);
        // Second moments of the mass distribution along principal axes: the principal moments
        // I1 = s2 + s3, I2 = s1 + s3, I3 = s1 + s2 then satisfy the triangle inequality strictly.
        let s = [0; 3].map(|_| mass * rng.range(0.002, 0.05));
        let principal = [s[1] + s[2], s[0] + s[2], s[0] + s[1]];
        let inertia = rotate_diag(rng.quaternion(), principal).map(|r| r.map(c));
        bodies.push(Body {
            name: format!("body{i}"),
            mass: c(mass),
            com: [0; 3].map(|_| c(rng.range(-0.3, 0.3))),
            inertia,
        });
        joints.push(Joint {
            name: format!("joint{i}"),
            kind,
            parent,
            placement,
            drive: Drive::FREE,
            mimic: None,
        });
    }
    Model::new("Random", bodies, joints)
}

/// Whether an Euler sequence is proper (`zxz`-like: first and last axes equal).
fn proper(seq: &EulerSeq) -> bool {
    seq.0[0] == seq.0[2]
}

/// Three Euler angles away from gimbal lock: the middle angle in `(−π/2, π/2)` shrunk by 0.3 rad
/// for Tait–Bryan sequences, in `(0, π)` shrunk by 0.3 rad for proper ones.
fn euler_angles(rng: &mut Rng, seq: &EulerSeq) -> [f64; 3] {
    let mid = if proper(seq) {
        rng.range(0.3, PI - 0.3)
    } else {
        rng.range(-PI / 2.0 + 0.3, PI / 2.0 - 0.3)
    };
    [rng.range(-PI, PI), mid, rng.range(-PI, PI)]
}

/// A deterministic random state `(q, v, a)` for `model`: angles in `[−π, π]` (Euler middle angles
/// away from gimbal lock), prismatic and free-base positions in `[−1, 1]`, unit quaternions,
/// velocities and accelerations in `[−1, 1]`.
pub fn random_state(model: &Model, seed: u64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut rng = Rng(seed ^ 0x57A7_E000_0000_0001);
    let mut q = Vec::with_capacity(model.nq());
    // A mimic joint has no coordinate of its own.
    for j in model.joints.iter().filter(|j| j.mimic.is_none()) {
        match j.kind {
            JointKind::Revolute { .. } => q.push(rng.range(-PI, PI)),
            JointKind::Prismatic { .. } => q.push(rng.range(-1.0, 1.0)),
            JointKind::SphericalEuler { seq } => q.extend(euler_angles(&mut rng, &seq)),
            JointKind::SphericalQuaternion => q.extend(rng.quaternion()),
            JointKind::FreeEuler { seq } => {
                q.extend([0; 3].map(|_| rng.range(-1.0, 1.0)));
                q.extend(euler_angles(&mut rng, &seq));
            }
            JointKind::FreeQuaternion => {
                q.extend([0; 3].map(|_| rng.range(-1.0, 1.0)));
                q.extend(rng.quaternion());
            }
            JointKind::Fixed => {}
        }
    }
    let nv = model.nv();
    let v = (0..nv).map(|_| rng.range(-1.0, 1.0)).collect();
    let a = (0..nv).map(|_| rng.range(-1.0, 1.0)).collect();
    (q, v, a)
}
