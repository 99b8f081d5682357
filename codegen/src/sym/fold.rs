//! The folding rules of the graph (see the [module docs](super)): constants computed, identities
//! dropped, signs moved where a sum absorbs them.

use articulated_dynamics::Scalar;

use super::decimal::Decimal;
use super::graph::{Graph, Key};

impl Graph {
    pub(super) fn constant(&mut self, x: f64) -> u32 {
        // One zero: −0 and +0 are the same number to the algebra (and to every rule above).
        let x = if x == 0.0 { 0.0 } else { x };
        self.intern(Key::Const(x.to_bits()))
    }

    /// A number as written ([`Scalar::from_f64`]): a constant, and a decimal if its shortest
    /// digits are few enough ([`Decimal::from_f64`]).
    pub(super) fn literal(&mut self, x: f64) -> u32 {
        let i = self.constant(x);
        if let Some(d) = Decimal::from_f64(x) {
            self.decimals.entry(i).or_insert(d);
        }
        i
    }

    /// The constant nearest to the decimal `d`, which it is known to be; `None` if that is not
    /// finite.
    fn decimal(&mut self, d: Decimal) -> Option<u32> {
        let i = self.constant(d.to_f64()?);
        self.decimals.entry(i).or_insert(d);
        Some(i)
    }

    /// `−x` for the constant `x` (a decimal stays one).
    fn negated_constant(&mut self, bits: u64, i: u32) -> u32 {
        match self.decimals.get(&i) {
            Some(d) => {
                let d = d.neg();
                self.decimal(d)
                    .unwrap_or_else(|| self.constant(-f64::from_bits(bits)))
            }
            None => self.constant(-f64::from_bits(bits)),
        }
    }

    pub(super) fn value(&self, i: u32) -> Option<f64> {
        match self.nodes[i as usize] {
            Key::Const(bits) => Some(f64::from_bits(bits)),
            _ => None,
        }
    }

    fn is(&self, i: u32, x: f64) -> bool {
        self.value(i) == Some(x)
    }

    /// Whether `i` is a negation: a `Neg` node or a negative constant.
    fn is_negation(&self, i: u32) -> bool {
        match self.nodes[i as usize] {
            Key::Neg(_) => true,
            Key::Const(bits) => f64::from_bits(bits) < 0.0,
            _ => false,
        }
    }

    /// `−i` for a negation `i` (see [`Graph::is_negation`]): its operand, or the positive constant.
    fn strip_negation(&mut self, i: u32) -> u32 {
        match self.nodes[i as usize] {
            Key::Neg(a) => a,
            Key::Const(bits) => self.negated_constant(bits, i),
            _ => unreachable!("strip_negation of a node that is not a negation"),
        }
    }

    /// Folds two constants if both are and the result is finite: in exact decimal arithmetic,
    /// rounded once, when both are decimals and `exact` can ([`Decimal`]); in `f64` by `op`
    /// otherwise.
    fn fold2(
        &mut self,
        a: u32,
        b: u32,
        op: fn(f64, f64) -> f64,
        exact: fn(Decimal, Decimal) -> Option<Decimal>,
    ) -> Option<u32> {
        let (x, y) = (self.value(a)?, self.value(b)?);
        let exact = match (self.decimals.get(&a), self.decimals.get(&b)) {
            (Some(&dx), Some(&dy)) => exact(dx, dy),
            _ => None,
        };
        if let Some(i) = exact.and_then(|d| self.decimal(d)) {
            return Some(i);
        }
        let r = op(x, y);
        r.is_finite().then(|| self.constant(r))
    }

    fn fold1(&mut self, a: u32, op: fn(f64) -> f64) -> Option<u32> {
        let r = op(self.value(a)?);
        r.is_finite().then(|| self.constant(r))
    }

    pub(super) fn add(&mut self, a: u32, b: u32) -> u32 {
        if let Some(r) = self.fold2(a, b, |x, y| x + y, Decimal::add) {
            return r;
        }
        if self.is(a, 0.0) {
            return b;
        }
        if self.is(b, 0.0) {
            return a;
        }
        if self.is_negation(b) {
            let y = self.strip_negation(b);
            return self.sub(a, y);
        }
        if self.is_negation(a) {
            let x = self.strip_negation(a);
            return self.sub(b, x);
        }
        self.intern(Key::Add(a.min(b), a.max(b)))
    }

    pub(super) fn sub(&mut self, a: u32, b: u32) -> u32 {
        if let Some(r) = self.fold2(a, b, |x, y| x - y, |x, y| x.add(y.neg())) {
            return r;
        }
        if self.is(b, 0.0) {
            return a;
        }
        if self.is(a, 0.0) {
            return self.neg(b);
        }
        if a == b {
            return self.constant(0.0);
        }
        if self.is_negation(b) {
            let y = self.strip_negation(b);
            return self.add(a, y);
        }
        // `(−x) − y = −(x + y)`: one negation, which an enclosing sum can absorb.
        if let Key::Neg(x) = self.nodes[a as usize] {
            let t = self.add(x, b);
            return self.neg(t);
        }
        self.intern(Key::Sub(a, b))
    }

    pub(super) fn mul(&mut self, a: u32, b: u32) -> u32 {
        if let Some(r) = self.fold2(a, b, |x, y| x * y, Decimal::mul) {
            return r;
        }
        if self.is(a, 0.0) || self.is(b, 0.0) {
            return self.constant(0.0);
        }
        if self.is(a, 1.0) {
            return b;
        }
        if self.is(b, 1.0) {
            return a;
        }
        if self.is(a, -1.0) {
            return self.neg(b);
        }
        if self.is(b, -1.0) {
            return self.neg(a);
        }
        if self.is_negation(a) && self.is_negation(b) {
            let (x, y) = (self.strip_negation(a), self.strip_negation(b));
            return self.mul(x, y);
        }
        // The sign of a negated (non-constant) factor moves out, where a sum or difference
        // absorbs it: `x·(−y) = −(x·y)`.
        if let Key::Neg(y) = self.nodes[b as usize] {
            let p = self.mul(a, y);
            return self.neg(p);
        }
        if let Key::Neg(x) = self.nodes[a as usize] {
            let p = self.mul(x, b);
            return self.neg(p);
        }
        self.intern(Key::Mul(a.min(b), a.max(b)))
    }

    pub(super) fn div(&mut self, a: u32, b: u32) -> u32 {
        if let Some(r) = self.fold2(a, b, |x, y| x / y, |_, _| None) {
            return r;
        }
        if self.is(a, 0.0) {
            return self.constant(0.0);
        }
        if self.is(b, 1.0) {
            return a;
        }
        if self.is(b, -1.0) {
            return self.neg(a);
        }
        if a == b {
            return self.constant(1.0);
        }
        if self.is_negation(a) && self.is_negation(b) {
            let (x, y) = (self.strip_negation(a), self.strip_negation(b));
            return self.div(x, y);
        }
        self.intern(Key::Div(a, b))
    }

    pub(super) fn neg(&mut self, a: u32) -> u32 {
        match self.nodes[a as usize] {
            Key::Const(bits) => self.negated_constant(bits, a),
            Key::Neg(x) => x,
            Key::Sub(x, y) => self.sub(y, x),
            _ => self.intern(Key::Neg(a)),
        }
    }

    pub(super) fn sin(&mut self, a: u32) -> u32 {
        if let Some(r) = self.fold1(a, |x| snap_unit(Scalar::sin_cos(x).0)) {
            return r;
        }
        if let Key::Neg(x) = self.nodes[a as usize] {
            let s = self.sin(x);
            return self.neg(s);
        }
        self.intern(Key::Sin(a))
    }

    pub(super) fn cos(&mut self, a: u32) -> u32 {
        if let Some(r) = self.fold1(a, |x| snap_unit(Scalar::sin_cos(x).1)) {
            return r;
        }
        if let Key::Neg(x) = self.nodes[a as usize] {
            return self.cos(x);
        }
        self.intern(Key::Cos(a))
    }

    pub(super) fn sqrt(&mut self, a: u32) -> u32 {
        if let Some(r) = self.fold1(a, <f64 as Scalar>::sqrt) {
            return r;
        }
        self.intern(Key::Sqrt(a))
    }
}

/// The sine or cosine of a constant angle, with values within 1e-15 of 0 or ±1 made exact.
/// Constant angles come from placements written in decimal (`rpy="1.5707963267948966 0 0"`),
/// where a quarter turn is meant: `cos(fl(π/2)) = 6.1e-17` kept as it is makes every rotation
/// through such a frame dense, while an exact 0 lets the products with it fold away. The change
/// (≤ 1e-15) is far below every tolerance the outputs are held to.
fn snap_unit(x: f64) -> f64 {
    const EPS: f64 = 1e-15;
    if x.abs() < EPS {
        0.0
    } else if (x - 1.0).abs() < EPS {
        1.0
    } else if (x + 1.0).abs() < EPS {
        -1.0
    } else {
        x
    }
}
