//! Joint kinds: `revolute(axis)` and `prismatic(axis)` (a coordinate axis, possibly negated, or
//! a nonzero constant vector, normalized), `spherical(quaternion | SEQ)`, `free`,
//! `free(quaternion | SEQ)` (`free` alone is `free(zyx)`) and `fixed`, with SEQ one of the twelve
//! valid Euler sequences.

use super::numbers::NumCtx;
use super::Lower;
use crate::model::{EulerSeq, JointKind};
use crate::parse::{Expr, KindDef};

/// The twelve valid Euler sequences, for messages.
const EULER_SEQS: &str =
    "`xyz`, `xzy`, `yxz`, `yzx`, `zxy`, `zyx`, `xyx`, `xzx`, `yxy`, `yzy`, `zxz`, `zyz`";

impl Lower {
    /// The kind of the joint `owner`, checked.
    pub(super) fn kind(&mut self, k: &KindDef, owner: &str) -> Option<JointKind> {
        let name = k.name.to_string();
        let args: Vec<&Expr> = k.args.iter().flat_map(|(_, a)| a.iter()).collect();
        match name.as_str() {
            "revolute" | "prismatic" => {
                let [arg] = args[..] else {
                    self.cx.error(
                        k,
                        format!(
                            "`{name}` takes one axis: expected `{name}(x)`, `{name}(y)`, \
                             `{name}(z)` or `{name}([ax, ay, az])`, found `{k}`"
                        ),
                    );
                    return None;
                };
                let axis = self.axis(arg, owner)?;
                Some(if name == "revolute" {
                    JointKind::Revolute { axis }
                } else {
                    JointKind::Prismatic { axis }
                })
            }
            "spherical" => {
                let [arg] = args[..] else {
                    self.cx.error(
                        k,
                        format!(
                            "`spherical` takes one rotation: expected `spherical(quaternion)` \
                             or `spherical(SEQ)` with an Euler sequence SEQ ({EULER_SEQS}), \
                             found `{k}`"
                        ),
                    );
                    return None;
                };
                match self.rotation(arg)? {
                    None => Some(JointKind::SphericalQuaternion),
                    Some(seq) => Some(JointKind::SphericalEuler { seq }),
                }
            }
            "free" => match args[..] {
                [] => Some(JointKind::FreeEuler { seq: EulerSeq::ZYX }),
                [arg] => match self.rotation(arg)? {
                    None => Some(JointKind::FreeQuaternion),
                    Some(seq) => Some(JointKind::FreeEuler { seq }),
                },
                _ => {
                    self.cx.error(
                        k,
                        format!(
                            "`free` takes at most one rotation: expected `free`, \
                             `free(quaternion)` or `free(SEQ)` with an Euler sequence SEQ \
                             ({EULER_SEQS}), found `{k}`"
                        ),
                    );
                    None
                }
            },
            "fixed" => {
                if k.args.is_some() {
                    self.cx.error(
                        k,
                        format!("`fixed` takes no arguments: expected `fixed`, found `{k}`"),
                    );
                    return None;
                }
                Some(JointKind::Fixed)
            }
            _ => {
                self.cx.error(
                    &k.name,
                    format!(
                        "unknown joint kind `{name}`: expected `revolute`, `prismatic`, \
                         `spherical`, `free` or `fixed`"
                    ),
                );
                None
            }
        }
    }

    /// `quaternion` (→ `Some(None)`) or an Euler sequence (→ `Some(Some(seq))`).
    fn rotation(&mut self, arg: &Expr) -> Option<Option<EulerSeq>> {
        if let Expr::Name(n) = arg {
            let s = n.to_string();
            if s == "quaternion" {
                return Some(None);
            }
            if let Some(seq) = EulerSeq::parse(&s) {
                return Some(Some(seq));
            }
        }
        self.cx.error(
            arg,
            format!(
                "invalid Euler sequence `{arg}`: expected `quaternion` or one of the 12 valid \
                 sequences {EULER_SEQS}"
            ),
        );
        None
    }

    /// A joint axis, normalized: `x`, `y`, `z`, their negatives or a constant vector.
    fn axis(&mut self, arg: &Expr, owner: &str) -> Option<[f64; 3]> {
        match arg {
            Expr::Name(n) if n == "x" => Some([1.0, 0.0, 0.0]),
            Expr::Name(n) if n == "y" => Some([0.0, 1.0, 0.0]),
            Expr::Name(n) if n == "z" => Some([0.0, 0.0, 1.0]),
            Expr::Neg(_, inner) if matches!(&**inner, Expr::Name(n) if n == "x" || n == "y" || n == "z") => {
                self.axis(inner, owner).map(|a| a.map(|x| -x))
            }
            Expr::List(_, elems) if elems.len() == 3 => {
                let v: Vec<Option<f64>> = elems
                    .iter()
                    .map(|e| self.constant(e, NumCtx::Axis))
                    .collect();
                let (Some(x), Some(y), Some(z)) = (v[0], v[1], v[2]) else {
                    return None;
                };
                let n = (x * x + y * y + z * z).sqrt();
                if n == 0.0 || !n.is_finite() {
                    self.cx.error(
                        arg,
                        format!(
                            "the axis of {owner} is zero: expected a nonzero vector, found \
                             `{arg}`"
                        ),
                    );
                    return None;
                }
                Some([x / n, y / n, z / n])
            }
            _ => {
                self.cx.error(
                    arg,
                    format!(
                        "unknown axis `{arg}`: expected `x`, `y`, `z` (or `-x`, `-y`, `-z`) or a vector \
                         `[ax, ay, az]`"
                    ),
                );
                None
            }
        }
    }
}
