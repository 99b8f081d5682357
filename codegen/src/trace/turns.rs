//! A revolute joint's placement turned about the joint's own axis, folded into its angle.
//!
//! A revolute node's child frame is placed by the fixed rotation of its placement, then by the
//! joint's: `R_T·Rot(u, q)` (poses, parent to child). When `R_T = P·Rot(u, θ₀)` with `P` a
//! signed permutation (often the identity), the two rotations about `u` merge:
//! `R_T·Rot(u, q) = P·Rot(u, q + θ₀)`. Traced that way, the turn by `θ₀` costs one addition in
//! the angle, and `P` costs nothing (its entries are 0 and ±1, which fold away), where `R_T`
//! cost the products that carry every quantity of the subtree through it: about 40 of the 395
//! operations of `arm7`'s mass matrix (its flange is turned by −π/4 about the last joint's
//! axis), 8 of its inverse dynamics and 40 of its forward dynamics.
//!
//! The frames do not change (`P·Rot(u, q + θ₀)` is the same child frame), so neither does any
//! output: only the intermediate joint frame, which no output is expressed in, is skipped. The
//! angle's sine and cosine are then those of `q + θ₀`, which the emitted `f64` code still
//! computes in its one `sincos_array` call ([`crate::emit`]).

use articulated_dynamics::reference::{NodeJoint, Tree};
use articulated_dynamics::spatial::{Mat3, Vec3};
use articulated_dynamics::Scalar;

use crate::sym::Sym;

/// How far a rotation may be from `P·Rot(u, θ₀)` (largest entry) and still be folded: the
/// rounding of a placement's `rpy` (a few units of `f64`'s epsilon), not a real difference.
const TOLERANCE: f64 = 1e-15;

/// One fold: the tree's angle `q[q_at]` is turned by `angle`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Turn {
    /// The tree coordinate of the revolute node.
    pub q_at: usize,
    /// `θ₀`, added to the angle.
    pub angle: f64,
    /// The node's name, for the angle's label.
    name: String,
}

/// Folds every revolute node's turn about its axis into its angle: the placement's rotation
/// becomes the signed permutation `P` (see the [module docs](self)), and the turns returned
/// are to be added to the angles by [`turned`]. Nodes whose placement or axis is not a
/// constant (parameters), or whose rotation has no such factor, or is already a signed
/// permutation, are left as they are.
pub(crate) fn fold(tree: &mut Tree<Sym>) -> Vec<Turn> {
    let mut turns = Vec::new();
    for node in &mut tree.nodes {
        let NodeJoint::Revolute(u) = node.joint else {
            continue;
        };
        let (Some(e), Some(u)) = (constant_mat(&node.x_tree.e), constant_vec(&u)) else {
            continue;
        };
        // `E = R_Tᵀ` (`Transform::from_pose`).
        let r_t = e.transpose();
        if signed_permutation(&r_t) {
            continue;
        }
        let Some((p, angle)) = split(&r_t, &u) else {
            continue;
        };
        node.x_tree.e = Mat3(p.transpose().0.map(|row| row.map(Sym::from_f64)));
        turns.push(Turn {
            q_at: node.q_at,
            angle,
            name: node.name.clone(),
        });
    }
    turns
}

/// The tree's angles with the `turns` added (each labelled `{node}_angle`).
pub(crate) fn turned(mut q: Vec<Sym>, turns: &[Turn]) -> Vec<Sym> {
    for t in turns {
        q[t.q_at] = (q[t.q_at] + Sym::from_f64(t.angle)).label(format_args!("{}_angle", t.name));
    }
    q
}

/// `R = P·Rot(u, θ₀)` with `P` one of the 24 signed permutations of determinant 1 and `θ₀` the
/// smallest in size; `None` if no `P` gives a rotation about `u` (within [`TOLERANCE`]).
fn split(r: &Mat3<f64>, u: &Vec3<f64>) -> Option<(Mat3<f64>, f64)> {
    let mut best: Option<(Mat3<f64>, f64)> = None;
    for p in rotations_of_the_cube() {
        // Pᵀ·R should be Rot(u, θ₀) = 1 + sin θ₀·(u×) + (1 − cos θ₀)·(u×)².
        let m = p.transpose().mul_mat(r);
        let a = m.0;
        let cos = (a[0][0] + a[1][1] + a[2][2] - 1.0) / 2.0;
        let w = Vec3([a[2][1] - a[1][2], a[0][2] - a[2][0], a[1][0] - a[0][1]]);
        let sin = w.dot(*u) / 2.0;
        let angle = sin.atan2(cos);
        let rot = Mat3::rot_axis(*u, angle);
        let off = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| (rot.0[i][j] - a[i][j]).abs())
            .fold(0.0f64, f64::max);
        if off <= TOLERANCE && best.as_ref().is_none_or(|b| angle.abs() < b.1.abs()) {
            best = Some((p, angle));
        }
    }
    best
}

/// The 24 rotations that map the coordinate axes onto signed coordinate axes.
fn rotations_of_the_cube() -> impl Iterator<Item = Mat3<f64>> {
    const PERMUTATIONS: [[usize; 3]; 6] = [
        [0, 1, 2],
        [1, 2, 0],
        [2, 0, 1],
        [0, 2, 1],
        [2, 1, 0],
        [1, 0, 2],
    ];
    PERMUTATIONS.into_iter().flat_map(|perm| {
        (0..8).filter_map(move |signs: u32| {
            let mut m = Mat3::<f64>::zero();
            for (row, &col) in perm.iter().enumerate() {
                m.0[row][col] = if signs >> row & 1 == 1 { -1.0 } else { 1.0 };
            }
            (determinant(&m) > 0.0).then_some(m)
        })
    })
}

fn determinant(m: &Mat3<f64>) -> f64 {
    let a = m.0;
    a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
}

/// Whether every entry is 0 or ±1.
fn signed_permutation(m: &Mat3<f64>) -> bool {
    m.0.iter().flatten().all(|&x| x == 0.0 || x.abs() == 1.0)
}

fn constant_mat(m: &Mat3<Sym>) -> Option<Mat3<f64>> {
    let mut out = Mat3::<f64>::zero();
    for i in 0..3 {
        for j in 0..3 {
            out.0[i][j] = m.0[i][j].constant()?;
        }
    }
    Some(out)
}

fn constant_vec(v: &Vec3<Sym>) -> Option<Vec3<f64>> {
    Some(Vec3([
        v.0[0].constant()?,
        v.0[1].constant()?,
        v.0[2].constant()?,
    ]))
}

#[cfg(test)]
mod tests {
    use std::f64::consts::FRAC_PI_2;

    use articulated_dynamics::model::{JointKind, Model, Value};
    use articulated_dynamics::random::{random_model, random_state};
    use articulated_dynamics::reference::Reference;

    use super::*;
    use crate::options::Output;
    use crate::sym::Var;
    use crate::trace::{symbolic_tree, trace};

    /// `model` with every revolute joint turned about its own axis on top of a rotation of the
    /// cube: about x by `rpy = [θ, k·π/2, m·π/2]` (`R = Rz·Ry·Rx(θ)`), about −y by
    /// `[0, θ, m·π/2]`, about z by `[0, 0, θ]`; the angles drawn from the seed. Returns how
    /// many joints were turned.
    fn turned_model(model: &mut Model, seed: u64) -> usize {
        let mut n = 0;
        for (i, joint) in model.joints.iter_mut().enumerate() {
            let JointKind::Revolute { axis } = &mut joint.kind else {
                continue;
            };
            let k = seed as usize * 7 + i * 3;
            let theta = 0.3 + 0.41 * (k % 11) as f64 - 2.0;
            let quarter = |j: usize| FRAC_PI_2 * (j % 4) as f64;
            let rpy = match k % 3 {
                0 => {
                    *axis = [1.0, 0.0, 0.0];
                    [theta, quarter(k / 3), quarter(k / 5)]
                }
                1 => {
                    *axis = [0.0, -1.0, 0.0];
                    [0.0, theta, quarter(k / 3)]
                }
                _ => {
                    *axis = [0.0, 0.0, 1.0];
                    [0.0, 0.0, theta]
                }
            };
            joint.placement.rpy = rpy.map(Value::Const);
            n += 1;
        }
        n
    }

    /// Every rotation of the cube, times a turn about an axis, splits back into the two.
    #[test]
    fn splits_a_permutation_and_a_turn() {
        let axes = [
            Vec3([0.0, 0.0, 1.0]),
            Vec3([0.0, -1.0, 0.0]),
            Vec3([0.6, 0.0, 0.8]),
        ];
        assert_eq!(rotations_of_the_cube().count(), 24);
        for u in axes {
            for p in rotations_of_the_cube() {
                for angle in [-2.5, -0.785, 0.3, 1.0] {
                    let r = p.mul_mat(&Mat3::rot_axis(u, angle));
                    let (p2, a2) = split(&r, &u).expect("splits");
                    let back = p2.mul_mat(&Mat3::rot_axis(u, a2));
                    for i in 0..3 {
                        for j in 0..3 {
                            assert!((back.0[i][j] - r.0[i][j]).abs() <= TOLERANCE);
                        }
                    }
                    assert!(a2.abs() <= angle.abs() + 1e-12, "{a2} for {angle}");
                }
            }
        }
    }

    /// A rotation about another axis does not split.
    #[test]
    fn leaves_other_rotations() {
        let r = Mat3::rot_axis(Vec3([1.0, 0.0, 0.0]), 0.3);
        assert!(split(&r, &Vec3([0.0, 0.0, 1.0])).is_none());
        let r = Mat3::rot_axis(Vec3([0.6, 0.8, 0.0]), 0.3);
        assert!(split(&r, &Vec3([0.0, 0.0, 1.0])).is_none());
    }

    /// On random trees of every joint kind with their revolute joints turned: the tree folds
    /// every turn, and `M`, inverse and forward dynamics traced with the turns in the angles
    /// (every variant the generator keeps) equal the reference's, which turns the frames by
    /// the placements themselves.
    #[test]
    fn folded_turns_keep_the_dynamics() {
        let mut folded = 0;
        for seed in 0..40u64 {
            let mut model = random_model(seed, 2 + (seed as usize % 8));
            let turned = turned_model(&mut model, seed);
            let (_, turns) = crate::sym::trace(|| symbolic_tree(&model, false).1);
            assert_eq!(turns.len(), turned, "seed {seed}: every turn folds");
            folded += turned;
            let reference = Reference::new(&model).unwrap();
            let (q, v, a) = random_state(&model, seed);
            let tau = reference.inverse_dynamics(&q, &v, &a).unwrap();
            let input = |var: Var| match var {
                Var::Q(i) => q[i],
                Var::V(i) => v[i],
                Var::A(i) => a[i],
                Var::Tau(i) => tau[i],
                other => panic!("unexpected input {other:?}"),
            };
            let m = reference.mass_matrix(&q).unwrap();
            let cases: [(Output, Vec<f64>); 3] = [
                (Output::MassMatrix, m.transpose().iter().copied().collect()),
                (Output::InverseDynamics, tau.iter().copied().collect()),
                (Output::ForwardDynamics, a.to_vec()),
            ];
            for (output, want) in cases {
                let (got, ok) = trace(&model, output).eval(input);
                assert!(ok, "seed {seed} {output:?}: pivots");
                let scale = want.iter().fold(1.0f64, |s, x| s.max(x.abs()));
                for (g, w) in got.iter().zip(&want) {
                    let tol = if output == Output::ForwardDynamics {
                        1e-9
                    } else {
                        1e-12
                    };
                    assert!(
                        (g - w).abs() <= tol * scale,
                        "seed {seed} {output:?}: {g} vs {w}"
                    );
                }
            }
        }
        assert!(folded > 60, "only {folded} turns folded");
    }
}
