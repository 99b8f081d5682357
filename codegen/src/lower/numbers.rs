//! Numbers: constant folding of the description's number expressions (`+ - * /`, parentheses,
//! `pi`), parameters (declared once, never named `pi`, standing alone wherever a value may be a
//! parameter, never inside an expression, an axis or another default), `[x, y, z]` vectors, and
//! the values at the parameters' defaults that the mass checks use. Every number is finite and
//! written without a type suffix.

use proc_macro2::Ident;
use syn::Lit;

use super::Lower;
use crate::check::num;
use crate::model::{Param, Value};
use crate::options::one_of;
use crate::parse::{BinOp, Expr};

/// Where a number stands, for the messages about parameters.
#[derive(Clone, Copy)]
pub(super) enum NumCtx<'a> {
    /// Anywhere a parameter may stand alone.
    Value,
    /// A joint axis: constants only.
    Axis,
    /// The default of the named parameter: constants only.
    Default(&'a Ident),
    /// The named drive field of a joint (`armature`, `lower`, …): constants only.
    Drive(&'a str),
}

impl Lower {
    /// Declares the parameter `name` with its `default` (a constant), once and never as `pi`.
    pub(super) fn param(&mut self, name: &Ident, default: &Expr) {
        let key = name.to_string();
        let value = self.constant(default, NumCtx::Default(name));
        if key == "pi" {
            self.cx.error(
                name,
                "`pi` is the constant π and cannot name a parameter: expected another name",
            );
        } else if self.param_index.contains_key(&key) {
            self.cx
                .error(name, format!("parameter `{key}` is declared twice"));
        } else {
            self.param_index.insert(key.clone(), self.params.len());
            self.params.push(Param {
                name: key,
                default: value.unwrap_or(0.0),
            });
            self.param_ok.push(value.is_some());
        }
    }

    /// `[x, y, z]` of numbers (parameters allowed). `what` names the field; `alt` lists other
    /// accepted forms for the message.
    pub(super) fn vec3(&mut self, e: &Expr, what: &str, alt: &str) -> Option<[Value; 3]> {
        match e {
            Expr::List(_, elems) if elems.len() == 3 => {
                let v: Vec<Option<Value>> = elems.iter().map(|x| self.value(x)).collect();
                Some([v[0]?, v[1]?, v[2]?])
            }
            _ => {
                self.cx.error(
                    e,
                    format!(
                        "expected {alt}a list of 3 numbers `[x, y, z]` for {what}, found `{e}`"
                    ),
                );
                None
            }
        }
    }

    /// A number where a parameter may stand alone.
    pub(super) fn value(&mut self, e: &Expr) -> Option<Value> {
        if let Expr::Name(n) = e {
            if let Some(&i) = self.param_index.get(&n.to_string()) {
                return Some(Value::Param(i));
            }
        }
        self.constant(e, NumCtx::Value).map(Value::Const)
    }

    /// A constant number expression, folded; must be finite.
    pub(super) fn constant(&mut self, e: &Expr, ctx: NumCtx) -> Option<f64> {
        let x = self.fold(e, ctx)?;
        if x.is_finite() {
            Some(x)
        } else {
            self.cx.error(
                e,
                format!(
                    "`{e}` is not a finite number: it evaluates to {x}; expected a finite value"
                ),
            );
            None
        }
    }

    /// Folds a number expression. Reports every bad operand, not just the first.
    pub(super) fn fold(&mut self, e: &Expr, ctx: NumCtx) -> Option<f64> {
        match e {
            Expr::Number(lit) => {
                let (x, suffix) = match lit {
                    Lit::Float(f) => (f.base10_digits().parse::<f64>().ok(), f.suffix()),
                    Lit::Int(i) => (i.base10_digits().parse::<f64>().ok(), i.suffix()),
                    _ => (None, ""),
                };
                if !suffix.is_empty() {
                    self.cx.error(
                        lit,
                        format!(
                            "unexpected suffix `{suffix}` on `{e}`: expected a plain number \
                             (the scalar is chosen by the `scalar` setting)"
                        ),
                    );
                    return None;
                }
                match x {
                    Some(x) if x.is_finite() => Some(x),
                    _ => {
                        self.cx.error(
                            lit,
                            format!("`{e}` is not a finite number: it overflows f64; expected a finite value"),
                        );
                        None
                    }
                }
            }
            Expr::Name(n) if n == "pi" => Some(std::f64::consts::PI),
            Expr::Name(n) => {
                let msg = self.name_message(n, ctx);
                self.cx.error(n, msg);
                None
            }
            Expr::Neg(_, inner) => self.fold(inner, ctx).map(|x| -x),
            Expr::Binary(l, op, r) => {
                let (l, r) = (self.fold(l, ctx), self.fold(r, ctx));
                let (l, r) = (l?, r?);
                Some(match op {
                    BinOp::Add(_) => l + r,
                    BinOp::Sub(_) => l - r,
                    BinOp::Mul(_) => l * r,
                    BinOp::Div(_) => l / r,
                })
            }
            Expr::Paren(_, inner) => self.fold(inner, ctx),
            Expr::List(..) | Expr::Call(..) | Expr::Labeled(..) => {
                self.cx.error(e, format!("expected a number, found `{e}`"));
                None
            }
        }
    }

    /// Why the name `n` cannot stand where a number of context `ctx` is folded: a parameter in
    /// an expression, an axis or a default, or an unknown name (the declared parameters listed).
    fn name_message(&self, n: &Ident, ctx: NumCtx) -> String {
        let is_param = self.param_index.contains_key(&n.to_string());
        match (is_param, ctx) {
            (true, NumCtx::Value) => format!(
                "parameter `{n}` cannot be used inside an expression: expected a \
                     parameter standing alone (such as `mass: {n}`) or a constant expression"
            ),
            (true, NumCtx::Axis) => {
                format!("parameter `{n}` cannot be used in a joint axis: expected a constant")
            }
            (true, NumCtx::Drive(field)) => format!(
                "parameter `{n}` cannot be used in a joint's `{field}`: expected a constant"
            ),
            (true, NumCtx::Default(p)) => format!(
                "parameter `{n}` cannot be used in the default of parameter `{p}`: \
                     expected a constant"
            ),
            (false, _) => {
                let names: Vec<&str> = self.params.iter().map(|p| p.name.as_str()).collect();
                if names.is_empty() {
                    format!(
                        "unknown parameter `{n}`: expected a number or `pi` (no \
                             parameters are declared)"
                    )
                } else {
                    format!(
                        "unknown parameter `{n}`: expected a number, `pi` or a \
                             parameter: {}",
                        one_of(&names)
                    )
                }
            }
        }
    }

    /// The value of `v` at the parameters' defaults (`None` if a default was invalid).
    pub(super) fn at_default(&self, v: Value) -> Option<f64> {
        match v {
            Value::Const(x) => Some(x),
            Value::Param(i) => self.param_ok[i].then(|| self.params[i].default),
        }
    }

    /// `v` for a message: the number, or the parameter as written with its default.
    pub(super) fn describe(&self, v: Value, e: &Expr) -> String {
        match v {
            Value::Param(i) => format!("`{e}` = {} (its default)", num(self.params[i].default)),
            Value::Const(x) => num(x),
        }
    }
}
