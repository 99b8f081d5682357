//! The contact simulation's scene as written: `grounds: [floor: [nx, ny, nz, d]]`,
//! `spheres: [heel: sphere(frame, [x, y, z], radius)]`, `friction: μ`, `restitution: e`;
//! every malformed item and number out of range reported at its token. Whether a sphere's frame
//! exists is the check stage's ([`crate::check::options`], through the scene's names).

use crate::options::{Options, SceneGround, SceneSphere};
use crate::parse::Expr;

use super::numbers::NumCtx;
use super::Lower;

impl Lower {
    /// `grounds: [name: [nx, ny, nz, d], …]`.
    pub(super) fn ground_list(&mut self, v: &Expr, options: &mut Options) {
        let Expr::List(_, elems) = v else {
            self.cx.error(
                v,
                format!(
                    "expected a list of grounds such as `[floor: [0.0, 0.0, 1.0, 0.0]]` (the \
                     half-space n·x ≥ d), found `{v}`"
                ),
            );
            return;
        };
        for e in elems {
            let (Expr::Labeled(name, _, value), Some(numbers)) = (e, labeled_numbers(e, 4)) else {
                self.cx.error(
                    e,
                    format!(
                        "expected a ground `name: [nx, ny, nz, d]` such as `floor: [0.0, 0.0, \
                         1.0, 0.0]`, found `{e}`"
                    ),
                );
                continue;
            };
            let Some(x) = self.constants(&numbers) else {
                continue;
            };
            let length = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
            if length == 0.0 {
                self.cx.error(
                    value,
                    format!(
                        "ground `{name}`: its normal `[nx, ny, nz]` is zero; expected a direction"
                    ),
                );
                continue;
            }
            options.grounds.push(SceneGround {
                name: name.to_string(),
                normal: [x[0] / length, x[1] / length, x[2] / length],
                offset: x[3],
            });
        }
    }

    /// `spheres: [name: sphere(frame, [x, y, z], radius), …]`.
    pub(super) fn sphere_list(&mut self, v: &Expr, options: &mut Options) {
        let Expr::List(_, elems) = v else {
            self.cx.error(
                v,
                format!(
                    "expected a list of contact spheres such as `[heel: sphere(left_foot, \
                     [-0.06, 0.05, -0.09], 0.0)]`, found `{v}`"
                ),
            );
            return;
        };
        for e in elems {
            let sphere = match e {
                Expr::Labeled(name, _, value) => match &**value {
                    Expr::Call(kind, _, args) if kind == "sphere" && args.len() == 3 => {
                        Some((name, args))
                    }
                    _ => None,
                },
                _ => None,
            };
            let Some((name, args)) = sphere else {
                self.cx.error(
                    e,
                    format!(
                        "expected a contact sphere `name: sphere(frame, [x, y, z], radius)` (its \
                         centre in the frame's axes, its radius; 0 for a point), found `{e}`"
                    ),
                );
                continue;
            };
            let (frame, at, radius) = (&args[0], &args[1], &args[2]);
            let Expr::Name(frame) = frame else {
                self.cx.error(
                    frame,
                    format!("expected the sphere's frame, found `{frame}`"),
                );
                continue;
            };
            let offset = match at {
                Expr::List(_, xs) if xs.len() == 3 => {
                    let xs: Vec<&Expr> = xs.iter().collect();
                    self.constants(&xs)
                }
                _ => {
                    self.cx.error(
                        at,
                        format!(
                            "expected the sphere's centre `[x, y, z]` in its frame, found `{at}`"
                        ),
                    );
                    None
                }
            };
            let r = self.constant(radius, NumCtx::Value);
            if r.is_some_and(|r| r < 0.0) {
                self.cx.error(
                    radius,
                    format!("a sphere's radius is at least 0, found `{radius}`"),
                );
                continue;
            }
            let (Some(offset), Some(radius)) = (offset, r) else {
                continue;
            };
            self.scene_names.insert(frame.to_string(), frame.clone());
            options.spheres.push(SceneSphere {
                name: name.to_string(),
                frame: frame.to_string(),
                offset: [offset[0], offset[1], offset[2]],
                radius,
            });
        }
    }

    /// `friction: μ` (at least 0) or `restitution: e` (within [0, 1]).
    pub(super) fn coefficient(&mut self, key: &str, v: &Expr, options: &mut Options) {
        let Some(x) = self.constant(v, NumCtx::Value) else {
            return;
        };
        if key == "friction" {
            if x < 0.0 {
                self.cx
                    .error(v, format!("`friction` is at least 0, found `{v}`"));
            } else {
                options.friction = Some(x);
            }
        } else if (0.0..=1.0).contains(&x) {
            options.restitution = x;
        } else {
            self.cx
                .error(v, format!("`restitution` is within [0, 1], found `{v}`"));
        }
    }

    /// Constant numbers, each folded; `None` if any is not one.
    fn constants(&mut self, xs: &[&Expr]) -> Option<Vec<f64>> {
        let values: Vec<Option<f64>> = xs.iter().map(|x| self.constant(x, NumCtx::Value)).collect();
        values.into_iter().collect()
    }
}

/// The `n` numbers of `name: [a, b, …]`.
fn labeled_numbers(e: &Expr, n: usize) -> Option<Vec<&Expr>> {
    match e {
        Expr::Labeled(_, _, value) => match &**value {
            Expr::List(_, xs) if xs.len() == n => Some(xs.iter().collect()),
            _ => None,
        },
        _ => None,
    }
}
