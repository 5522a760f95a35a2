//! The compiled form of a rig: one SSA list of scalar operations.
//!
//! Every element law lowers to these few operations; the CPU reference ([`super::exec::tape`])
//! and the WGSL emitter ([`super::back::wgsl`]) walk the same list in the same order, so
//! the two paths compute the same arithmetic. Values are `f64` here; the emitter
//! writes them in the kernel's precision.

use std::collections::HashMap;

/// Largest constant whole exponent [`Graph::signed_pow`] takes as a product.
pub const SIGNED_POW_PRODUCT_UP_TO: f64 = 8.0;

/// Index of a value in a [`Graph`].
pub type Id = u32;

/// Which value an input operation reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Input {
    /// Model time (s).
    Time,
    /// Packed per-run value `i` (a parameter or a host-derived constant).
    Slot(u32),
    /// Continuous state `i`.
    State(u32),
    /// Discrete regime variable `i`, as a number (0, 1, 2, …).
    Regime(u32),
    /// Piecewise-linear table `i` at model time (0 for `t < 0` where the table says so).
    Table(u32),
    /// Discrete (controller) state `i`: the value set at its last sample
    /// instant, held until the next.
    Held(u32),
}

/// One operation. Operands are earlier ids.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Op {
    /// A literal.
    Const(f64),
    /// An input.
    In(Input),
    /// `a + b`.
    Add(Id, Id),
    /// `a − b`.
    Sub(Id, Id),
    /// `a · b`.
    Mul(Id, Id),
    /// `a / b`.
    Div(Id, Id),
    /// `−a`.
    Neg(Id),
    /// `|a|`.
    Abs(Id),
    /// `min(a, b)`.
    Min(Id, Id),
    /// `max(a, b)`.
    Max(Id, Id),
    /// `eᵃ`.
    Exp(Id),
    /// `eᵃ − 1`.
    Expm1(Id),
    /// `ln a` (`a > 0`).
    Ln(Id),
    /// `sin a` (radians).
    Sin(Id),
    /// `cos a` (radians).
    Cos(Id),
    /// `1` if `a ≤ b`, else `0`.
    Le(Id, Id),
    /// `1` if `a == b`, else `0`.
    Eq(Id, Id),
    /// `c ≠ 0 ? a : b`.
    Select(Id, Id, Id),
}

/// Hashable key of an operation, for common-subexpression elimination.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Key {
    Const(u64),
    In(Input),
    Bin(u8, Id, Id),
    Un(u8, Id),
    Sel(Id, Id, Id),
}

fn key(op: &Op) -> Key {
    match *op {
        Op::Const(v) => Key::Const(v.to_bits()),
        Op::In(i) => Key::In(i),
        Op::Add(a, b) => Key::Bin(0, a, b),
        Op::Sub(a, b) => Key::Bin(1, a, b),
        Op::Mul(a, b) => Key::Bin(2, a, b),
        Op::Div(a, b) => Key::Bin(3, a, b),
        Op::Min(a, b) => Key::Bin(4, a, b),
        Op::Max(a, b) => Key::Bin(5, a, b),
        Op::Le(a, b) => Key::Bin(6, a, b),
        Op::Eq(a, b) => Key::Bin(7, a, b),
        Op::Neg(a) => Key::Un(0, a),
        Op::Abs(a) => Key::Un(1, a),
        Op::Exp(a) => Key::Un(2, a),
        Op::Expm1(a) => Key::Un(3, a),
        Op::Ln(a) => Key::Un(4, a),
        Op::Sin(a) => Key::Un(5, a),
        Op::Cos(a) => Key::Un(6, a),
        Op::Select(c, a, b) => Key::Sel(c, a, b),
    }
}

/// An SSA list of operations with named roots, built with constant folding and
/// common-subexpression elimination.
#[derive(Debug, Clone, Default)]
pub struct Graph {
    /// The operations, in evaluation order.
    pub ops: Vec<Op>,
    seen: HashMap<Key, Id>,
}

impl Graph {
    /// An empty graph.
    pub fn new() -> Self {
        Self::default()
    }

    fn constant(&self, id: Id) -> Option<f64> {
        match self.ops[id as usize] {
            Op::Const(v) => Some(v),
            _ => None,
        }
    }

    /// Appends `op` (or returns the id of an equal earlier one), folding
    /// operations whose operands are all constants and the identities `x + 0`,
    /// `x·1`, `x·0` (the laws multiply by zero coefficients often), `select` on a
    /// constant condition.
    pub fn push(&mut self, op: Op) -> Id {
        if let Some(v) = self.fold(&op) {
            return self.push_raw(Op::Const(v));
        }
        // `(0 − x) + b` is `b − x` (the same rounding of the same difference;
        // only the sign of a zero result can differ): a node's net force whose
        // first element pulls on it, one operation fewer per evaluation.
        if let Op::Add(a, b) = op {
            if let Some(x) = self.negation(a) {
                return self.push(Op::Sub(b, x));
            }
            if let Some(x) = self.negation(b) {
                return self.push(Op::Sub(a, x));
            }
        }
        match op {
            Op::Add(a, b) if self.constant(b) == Some(0.0) => return a,
            Op::Add(a, b) if self.constant(a) == Some(0.0) => return b,
            Op::Sub(a, b) if self.constant(b) == Some(0.0) => return a,
            Op::Mul(a, b) if self.constant(b) == Some(1.0) => return a,
            Op::Mul(a, b) if self.constant(a) == Some(1.0) => return b,
            Op::Mul(a, b) if self.constant(a) == Some(0.0) || self.constant(b) == Some(0.0) => {
                return self.push_raw(Op::Const(0.0));
            }
            Op::Div(a, b) if self.constant(b) == Some(1.0) => return a,
            Op::Select(c, a, b) => {
                if let Some(cv) = self.constant(c) {
                    return if cv != 0.0 { a } else { b };
                }
                if a == b {
                    return a;
                }
            }
            _ => {}
        }
        self.push_raw(op)
    }

    /// `x` where `id` is `0 − x` or `−x`.
    fn negation(&self, id: Id) -> Option<Id> {
        match self.ops[id as usize] {
            Op::Sub(z, x) if self.constant(z) == Some(0.0) => Some(x),
            Op::Neg(x) => Some(x),
            _ => None,
        }
    }

    fn push_raw(&mut self, op: Op) -> Id {
        let k = key(&op);
        if let Some(&id) = self.seen.get(&k) {
            return id;
        }
        let id = self.ops.len() as Id;
        self.ops.push(op);
        self.seen.insert(k, id);
        id
    }

    fn fold(&self, op: &Op) -> Option<f64> {
        let c = |id: Id| self.constant(id);
        Some(match *op {
            Op::Add(a, b) => c(a)? + c(b)?,
            Op::Sub(a, b) => c(a)? - c(b)?,
            Op::Mul(a, b) => c(a)? * c(b)?,
            Op::Div(a, b) => c(a)? / c(b)?,
            Op::Neg(a) => -c(a)?,
            Op::Abs(a) => c(a)?.abs(),
            Op::Min(a, b) => c(a)?.min(c(b)?),
            Op::Max(a, b) => c(a)?.max(c(b)?),
            Op::Exp(a) => super::math::exp(c(a)?),
            Op::Expm1(a) => super::math::expm1(c(a)?),
            Op::Ln(a) => super::math::ln(c(a)?),
            Op::Sin(a) => super::math::sin(c(a)?),
            Op::Cos(a) => super::math::cos(c(a)?),
            Op::Le(a, b) => f64::from(u8::from(c(a)? <= c(b)?)),
            Op::Eq(a, b) => f64::from(u8::from(c(a)? == c(b)?)),
            Op::Select(..) | Op::Const(_) | Op::In(_) => return None,
        })
    }

    // Short builders, so lowerings read like the equations.

    /// A literal.
    pub fn c(&mut self, v: f64) -> Id {
        self.push(Op::Const(v))
    }
    /// An input.
    pub fn input(&mut self, i: Input) -> Id {
        self.push(Op::In(i))
    }
    /// `a + b`.
    pub fn add(&mut self, a: Id, b: Id) -> Id {
        self.push(Op::Add(a, b))
    }
    /// `a − b`.
    pub fn sub(&mut self, a: Id, b: Id) -> Id {
        self.push(Op::Sub(a, b))
    }
    /// `a · b`.
    pub fn mul(&mut self, a: Id, b: Id) -> Id {
        self.push(Op::Mul(a, b))
    }
    /// `a / b`.
    pub fn div(&mut self, a: Id, b: Id) -> Id {
        self.push(Op::Div(a, b))
    }
    /// `−a`.
    pub fn neg(&mut self, a: Id) -> Id {
        self.push(Op::Neg(a))
    }
    /// `c ≠ 0 ? a : b`.
    pub fn select(&mut self, c: Id, a: Id, b: Id) -> Id {
        self.push(Op::Select(c, a, b))
    }
    /// `1` if `a ≤ b`.
    pub fn le(&mut self, a: Id, b: Id) -> Id {
        self.push(Op::Le(a, b))
    }
    /// `1` if `a == b`.
    pub fn eq(&mut self, a: Id, b: Id) -> Id {
        self.push(Op::Eq(a, b))
    }

    /// `sign(a)·|a|^p` for `p > 0`, as `exp(p·ln|a|)` with a select at 0, so
    /// neither path evaluates `pow` of a negative base or of zero; for a
    /// constant whole `p` up to [`SIGNED_POW_PRODUCT_UP_TO`], as the product
    /// `a·|a|^(p−1)` (a cubic damper's `alpha: 3`: exact to two roundings, and
    /// an `exp` and a `ln` fewer on every path).
    pub fn signed_pow(&mut self, a: Id, p: Id) -> Id {
        if let Some(n) = self.constant(p)
            && n.fract() == 0.0
            && (1.0..=SIGNED_POW_PRODUCT_UP_TO).contains(&n)
        {
            let abs = self.push(Op::Abs(a));
            let mut r = a;
            for _ in 1..n as u32 {
                r = self.mul(r, abs);
            }
            return r;
        }
        let zero = self.c(0.0);
        let one = self.c(1.0);
        let abs = self.push(Op::Abs(a));
        let is_zero = self.le(abs, zero);
        let safe = self.select(is_zero, one, abs);
        let ln = self.push(Op::Ln(safe));
        let e = self.mul(p, ln);
        let mag = self.push(Op::Exp(e));
        let mag = self.select(is_zero, zero, mag);
        let neg = self.le(a, zero);
        let minus = self.neg(mag);
        self.select(neg, minus, mag)
    }

    /// `Σ coeffs[i]·aⁱ` by Horner's rule.
    pub fn poly(&mut self, a: Id, coeffs: &[Id]) -> Id {
        let mut s = *coeffs.last().expect("a polynomial has a coefficient");
        for &c in coeffs.iter().rev().skip(1) {
            let m = self.mul(s, a);
            s = self.add(m, c);
        }
        s
    }

    /// Ids reachable from `roots` (so an emitter can drop dead operations).
    pub fn live(&self, roots: &[Id]) -> Vec<bool> {
        let mut live = vec![false; self.ops.len()];
        for &r in roots {
            live[r as usize] = true;
        }
        for i in (0..self.ops.len()).rev() {
            if !live[i] {
                continue;
            }
            for o in operands(&self.ops[i]) {
                live[o as usize] = true;
            }
        }
        live
    }
}

/// The operand ids of `op`.
pub fn operands(op: &Op) -> Vec<Id> {
    match *op {
        Op::Const(_) | Op::In(_) => vec![],
        Op::Neg(a)
        | Op::Abs(a)
        | Op::Exp(a)
        | Op::Expm1(a)
        | Op::Ln(a)
        | Op::Sin(a)
        | Op::Cos(a) => vec![a],
        Op::Add(a, b)
        | Op::Sub(a, b)
        | Op::Mul(a, b)
        | Op::Div(a, b)
        | Op::Min(a, b)
        | Op::Max(a, b)
        | Op::Le(a, b)
        | Op::Eq(a, b) => vec![a, b],
        Op::Select(c, a, b) => vec![c, a, b],
    }
}

/// `op` with each operand id `o` replaced by `f(o)` (constants and inputs as
/// they are).
pub fn map_operands(op: Op, f: impl Fn(Id) -> Id) -> Op {
    match op {
        Op::Const(_) | Op::In(_) => op,
        Op::Add(a, b) => Op::Add(f(a), f(b)),
        Op::Sub(a, b) => Op::Sub(f(a), f(b)),
        Op::Mul(a, b) => Op::Mul(f(a), f(b)),
        Op::Div(a, b) => Op::Div(f(a), f(b)),
        Op::Min(a, b) => Op::Min(f(a), f(b)),
        Op::Max(a, b) => Op::Max(f(a), f(b)),
        Op::Le(a, b) => Op::Le(f(a), f(b)),
        Op::Eq(a, b) => Op::Eq(f(a), f(b)),
        Op::Neg(a) => Op::Neg(f(a)),
        Op::Abs(a) => Op::Abs(f(a)),
        Op::Exp(a) => Op::Exp(f(a)),
        Op::Expm1(a) => Op::Expm1(f(a)),
        Op::Ln(a) => Op::Ln(f(a)),
        Op::Sin(a) => Op::Sin(f(a)),
        Op::Cos(a) => Op::Cos(f(a)),
        Op::Select(c, a, b) => Op::Select(f(c), f(a), f(b)),
    }
}

/// The value of `op`, its operands' values read through `a` and its input
/// through `input`: the one scalar meaning of every operation. The CPU tape
/// evaluates through it; the lanes (`lanes.rs`) and the WGSL emitter
/// (`wgsl.rs`) write the same arithmetic in their own forms.
pub fn eval_op(op: Op, a: impl Fn(Id) -> f64, input: impl FnOnce(Input) -> f64) -> f64 {
    match op {
        Op::Const(c) => c,
        Op::In(i) => input(i),
        Op::Add(p, q) => a(p) + a(q),
        Op::Sub(p, q) => a(p) - a(q),
        Op::Mul(p, q) => a(p) * a(q),
        Op::Div(p, q) => a(p) / a(q),
        Op::Neg(p) => -a(p),
        Op::Abs(p) => a(p).abs(),
        Op::Min(p, q) => a(p).min(a(q)),
        Op::Max(p, q) => a(p).max(a(q)),
        Op::Exp(p) => super::math::exp(a(p)),
        Op::Expm1(p) => super::math::expm1(a(p)),
        Op::Ln(p) => super::math::ln(a(p)),
        Op::Sin(p) => super::math::sin(a(p)),
        Op::Cos(p) => super::math::cos(a(p)),
        Op::Le(p, q) => f64::from(u8::from(a(p) <= a(q))),
        Op::Eq(p, q) => f64::from(u8::from(a(p) == a(q))),
        Op::Select(c, p, q) => {
            if a(c) != 0.0 {
                a(p)
            } else {
                a(q)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folds_constants_and_shares_subexpressions() {
        let mut g = Graph::new();
        let x = g.input(Input::State(0));
        let two = g.c(2.0);
        let three = g.c(3.0);
        let six = g.mul(two, three);
        assert_eq!(g.ops[six as usize], Op::Const(6.0));
        let a = g.mul(x, six);
        let b = g.mul(x, six);
        assert_eq!(a, b);
        let zero = g.c(0.0);
        assert_eq!(g.add(a, zero), a);
        let z = g.mul(a, zero);
        assert_eq!(g.ops[z as usize], Op::Const(0.0));
    }

    #[test]
    fn a_negated_term_added_becomes_a_difference() {
        let mut g = Graph::new();
        let (a, b) = (g.input(Input::State(0)), g.input(Input::State(1)));
        let zero = g.c(0.0);
        let minus_a = g.sub(zero, a);
        let sum = g.add(minus_a, b);
        assert_eq!(g.ops[sum as usize], Op::Sub(b, a));
        let neg_b = g.neg(b);
        let sum = g.add(a, neg_b);
        assert_eq!(g.ops[sum as usize], Op::Sub(a, b));
    }

    /// Every value of `g` at state 0 = `x`, in order.
    fn values(g: &Graph, x: f64) -> Vec<f64> {
        let mut v: Vec<f64> = Vec::with_capacity(g.ops.len());
        for &op in &g.ops {
            let r = eval_op(op, |i| v[i as usize], |_| x);
            v.push(r);
        }
        v
    }

    #[test]
    fn a_constant_whole_exponent_is_a_product_and_any_other_goes_through_ln() {
        let mut g = Graph::new();
        let x = g.input(Input::State(0));
        let three = g.c(3.0);
        let cube = g.signed_pow(x, three);
        let cube_ops = g.ops.len();
        let other = g.c(1.81);
        let p = g.signed_pow(x, other);
        assert!(
            !g.ops[..cube_ops]
                .iter()
                .any(|op| matches!(op, Op::Exp(_) | Op::Ln(_))),
            "{:?}",
            &g.ops[..cube_ops]
        );
        assert!(g.ops[cube_ops..].iter().any(|op| matches!(op, Op::Ln(_))));
        for x in [-2.5, -1e-3, 0.0, 1e-3, 0.7, 4.0] {
            let v = values(&g, x);
            let want = x.signum() * x.abs().powi(3);
            assert!((v[cube as usize] - want).abs() <= 1e-15 * want.abs(), "{x}");
            let want = x.signum() * x.abs().powf(1.81);
            assert!((v[p as usize] - want).abs() <= 1e-14 * want.abs(), "{x}");
        }
    }
}
