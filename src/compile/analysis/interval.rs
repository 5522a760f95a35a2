//! Interval evaluation of a compiled graph and of its forward-mode tangents:
//! every operation's value and its derivative by one state enclosed over a box
//! of inputs (parameters, time, states, mode values). From it, an enclosure of
//! every entry of the derivative's Jacobian `∂(dy/dt)_i/∂y_j` over the box, and
//! a bound on the Jacobian's spectral radius that the RK4 step guard uses
//! ([`spectral_bound`]), so any rig gets its stability bound from its graph.
//!
//! Rounding: every result's ends are moved outward by one ulp
//! ([`Interval::widen`]), which covers the correctly rounded `+ − × ÷` and the
//! evaluators' `exp`/`expm1`/`ln`/`sin`/`cos` ([`crate::compile::math`],
//! held within 1–4 ulp of the C library by its tests, which is itself within
//! an ulp or so on the targets we run: a documented small widening, not a
//! proof for a libm worse than that). Conventions: `0 · (±∞) = 0` (a zero tangent times an unbounded
//! value stays zero), a division by an interval holding 0 is the whole line,
//! `ln` of a non-positive part is `−∞`.

use crate::compile::ir::{Id, Input, Op};
use crate::compile::program::Program;

/// A closed interval `[lo, hi]` of reals (ends may be infinite).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interval {
    /// Lower end.
    pub lo: f64,
    /// Upper end.
    pub hi: f64,
}

impl Interval {
    /// The whole line.
    pub const ENTIRE: Self = Self {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
    };

    /// `[v, v]`.
    pub fn point(v: f64) -> Self {
        Self { lo: v, hi: v }
    }

    /// `[min(a, b), max(a, b)]`; the whole line if either is NaN.
    pub fn new(a: f64, b: f64) -> Self {
        if a.is_nan() || b.is_nan() {
            return Self::ENTIRE;
        }
        Self {
            lo: a.min(b),
            hi: a.max(b),
        }
    }

    /// Outward by one ulp at each finite end.
    pub fn widen(self) -> Self {
        if self.lo.is_nan() || self.hi.is_nan() {
            return Self::ENTIRE;
        }
        Self {
            lo: if self.lo.is_finite() {
                step_out(self.lo, false)
            } else {
                self.lo
            },
            hi: if self.hi.is_finite() {
                step_out(self.hi, true)
            } else {
                self.hi
            },
        }
    }

    /// Smallest interval holding both.
    pub fn hull(self, o: Self) -> Self {
        Self {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
        }
    }

    /// Whether `v` lies in it.
    pub fn contains(self, v: f64) -> bool {
        self.lo <= v && v <= self.hi
    }

    /// Largest `|x|` over it.
    pub fn mag(self) -> f64 {
        self.lo.abs().max(self.hi.abs())
    }

    fn add(self, o: Self) -> Self {
        Self::new(self.lo + o.lo, self.hi + o.hi).widen()
    }

    fn sub(self, o: Self) -> Self {
        Self::new(self.lo - o.hi, self.hi - o.lo).widen()
    }

    fn neg(self) -> Self {
        Self {
            lo: -self.hi,
            hi: -self.lo,
        }
    }

    fn mul(self, o: Self) -> Self {
        if self == Self::point(0.0) || o == Self::point(0.0) {
            return Self::point(0.0);
        }
        let m = |a: f64, b: f64| if a == 0.0 || b == 0.0 { 0.0 } else { a * b };
        let p = [
            m(self.lo, o.lo),
            m(self.lo, o.hi),
            m(self.hi, o.lo),
            m(self.hi, o.hi),
        ];
        if p.iter().any(|x| x.is_nan()) {
            return Self::ENTIRE;
        }
        Self {
            lo: p.iter().copied().fold(f64::INFINITY, f64::min),
            hi: p.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        }
        .widen()
    }

    fn div(self, o: Self) -> Self {
        if o.contains(0.0) {
            return if self == Self::point(0.0) && o != Self::point(0.0) {
                // 0 / b is 0 wherever it is defined.
                Self::point(0.0)
            } else {
                Self::ENTIRE
            };
        }
        let inv = Self::new(1.0 / o.lo, 1.0 / o.hi).widen();
        self.mul(inv)
    }

    fn abs(self) -> Self {
        if self.lo >= 0.0 {
            self
        } else if self.hi <= 0.0 {
            self.neg()
        } else {
            Self {
                lo: 0.0,
                hi: self.mag(),
            }
        }
    }

    fn monotone(self, f: impl Fn(f64) -> f64) -> Self {
        Self::new(f(self.lo), f(self.hi)).widen()
    }

    fn ln(self) -> Self {
        if self.hi <= 0.0 {
            // ln of a non-positive number: NaN on the evaluators.
            return Self::ENTIRE;
        }
        Self::new(
            if self.lo <= 0.0 {
                f64::NEG_INFINITY
            } else {
                crate::compile::math::ln(self.lo)
            },
            crate::compile::math::ln(self.hi),
        )
        .widen()
    }

    /// `sin` (or `cos`) over it: both ends plus every extremum inside
    /// (`sin` at π/2 + kπ, `cos` at kπ, value `(−1)^k`).
    fn trig(self, cos: bool) -> Self {
        use std::f64::consts::{FRAC_PI_2, PI};
        if !(self.lo.is_finite() && self.hi.is_finite()) || self.hi - self.lo >= 2.0 * PI {
            return Self { lo: -1.0, hi: 1.0 };
        }
        let f = |x: f64| {
            use crate::compile::math;
            if cos { math::cos(x) } else { math::sin(x) }
        };
        let base = if cos { 0.0 } else { FRAC_PI_2 };
        let (a, b) = (self.lo, self.hi);
        let mut r = Self::new(f(a), f(b));
        // Extremum base + kπ inside [a, b], tested with slack so a rounding
        // never drops one (an extra one only widens).
        let k0 = ((a - base) / PI).floor() as i64 - 1;
        let k1 = ((b - base) / PI).ceil() as i64 + 1;
        for k in k0..=k1 {
            let x = base + k as f64 * PI;
            if x >= a - 1e-12 * a.abs().max(1.0) && x <= b + 1e-12 * b.abs().max(1.0) {
                r = r.hull(Self::point(if k.rem_euclid(2) == 0 { 1.0 } else { -1.0 }));
            }
        }
        let w = r.widen().widen();
        Self {
            lo: w.lo.max(-1.0),
            hi: w.hi.min(1.0),
        }
    }

    fn min(self, o: Self) -> Self {
        Self {
            lo: self.lo.min(o.lo),
            hi: self.hi.min(o.hi),
        }
    }

    fn max(self, o: Self) -> Self {
        Self {
            lo: self.lo.max(o.lo),
            hi: self.hi.max(o.hi),
        }
    }
}

/// The next float above (`up`) or below a finite `x` (the crate's MSRV
/// predates `f64::next_up`).
fn step_out(x: f64, up: bool) -> f64 {
    if x == 0.0 {
        let tiny = f64::from_bits(1);
        return if up { tiny } else { -tiny };
    }
    let bits = x.to_bits();
    // Away from zero is +1 on the magnitude's bits, towards zero −1.
    let away = (x > 0.0) == up;
    f64::from_bits(if away { bits + 1 } else { bits - 1 })
}

/// Which case a condition interval decides: `Some(true)` (every value non-zero),
/// `Some(false)` (it is exactly 0), `None` (undecided).
fn decided(c: Interval) -> Option<bool> {
    if !c.contains(0.0) {
        Some(true)
    } else if c == Interval::point(0.0) {
        Some(false)
    } else {
        None
    }
}

const ZERO_ONE: Interval = Interval { lo: 0.0, hi: 1.0 };

/// The value of one operation over intervals: the enclosure of
/// [`crate::compile::ir::eval_op`]'s result for every choice of operands in theirs.
pub fn interval_op(
    op: Op,
    a: impl Fn(Id) -> Interval,
    input: impl FnOnce(Input) -> Interval,
) -> Interval {
    match op {
        Op::Const(c) => Interval::point(c),
        Op::In(i) => input(i),
        Op::Add(p, q) => a(p).add(a(q)),
        Op::Sub(p, q) => a(p).sub(a(q)),
        Op::Mul(p, q) => a(p).mul(a(q)),
        Op::Div(p, q) => a(p).div(a(q)),
        Op::Neg(p) => a(p).neg(),
        Op::Abs(p) => a(p).abs(),
        Op::Min(p, q) => a(p).min(a(q)),
        Op::Max(p, q) => a(p).max(a(q)),
        Op::Exp(p) => a(p).monotone(crate::compile::math::exp),
        Op::Expm1(p) => a(p).monotone(crate::compile::math::expm1),
        Op::Ln(p) => a(p).ln(),
        Op::Sin(p) => a(p).trig(false),
        Op::Cos(p) => a(p).trig(true),
        Op::Le(p, q) => {
            let (x, y) = (a(p), a(q));
            if x.hi <= y.lo {
                Interval::point(1.0)
            } else if x.lo > y.hi {
                Interval::point(0.0)
            } else {
                ZERO_ONE
            }
        }
        Op::Eq(p, q) => {
            let (x, y) = (a(p), a(q));
            if x.lo == x.hi && x == y {
                Interval::point(1.0)
            } else if x.hi < y.lo || y.hi < x.lo {
                Interval::point(0.0)
            } else {
                ZERO_ONE
            }
        }
        Op::Select(c, p, q) => match decided(a(c)) {
            Some(true) => a(p),
            Some(false) => a(q),
            None => a(p).hull(a(q)),
        },
    }
}

/// The box the graph is enclosed over: one interval per parameter slot, the
/// time span, each state, each regime variable (integers `0..=max`, as an
/// interval), and each table (the hull of its values; the experiment's force
/// table is `force`'s values where given, else the whole line).
#[derive(Debug, Clone)]
pub struct InputBox {
    /// Per parameter slot.
    pub slots: Vec<Interval>,
    /// Model time.
    pub t: Interval,
    /// Continuous states.
    pub y: Vec<Interval>,
    /// Regime variables.
    pub regimes: Vec<Interval>,
    /// Hull of the experiment's force table and 0 (`None`: unknown).
    pub force: Option<Interval>,
}

impl InputBox {
    fn input(&self, prog: &Program, i: Input) -> Interval {
        let get = |v: &[Interval], k: u32| v.get(k as usize).copied().unwrap_or(Interval::ENTIRE);
        match i {
            Input::Time => self.t,
            Input::Slot(s) => get(&self.slots, s),
            Input::State(s) => get(&self.y, s),
            Input::Regime(m) => get(&self.regimes, m),
            Input::Table(k) => match &prog.tables[k as usize] {
                Some(tab) => table_hull(tab),
                None => self.force.unwrap_or(Interval::ENTIRE),
            },
            // A controller's held value: whatever its law gives (constant
            // over a step, so it adds nothing to the Jacobian).
            Input::Held(_) => Interval::ENTIRE,
        }
    }
}

/// The hull of a table's values and 0 (its value before `t = 0`).
pub fn table_hull(tab: &crate::base::PiecewiseLinear) -> Interval {
    tab.value
        .iter()
        .fold(Interval::point(0.0), |r, &v| r.hull(Interval::point(v)))
}

/// Every regime variable of `prog` over all the values its transitions use.
pub fn all_regimes(prog: &Program) -> Vec<Interval> {
    (0..prog.mode_count())
        .map(|v| {
            let top = prog
                .transitions
                .iter()
                .filter(|t| t.var as usize == v)
                .map(|t| t.from.max(t.to))
                .max()
                .unwrap_or(0);
            Interval::new(0.0, f64::from(top))
        })
        .collect()
}

/// Enclosure of the derivative's Jacobian `∂(dy/dt)_i/∂y_j` over `bx`, row
/// major. Each entry holds the derivative at every point of the box where it
/// exists; at a kink (`|a|` at 0, `min`/`max` with overlapping operands) or an
/// undecided select it holds both one-sided tangents (the hull), so also what
/// [`crate::compile::analysis::tangent::deriv_jacobian`] returns there.
pub fn deriv_jacobian_box(prog: &Program, bx: &InputBox) -> Vec<Interval> {
    let ops = &prog.graph.ops;
    let live = prog.graph.live(&prog.deriv);
    let mut val = vec![Interval::point(0.0); ops.len()];
    for (i, &op) in ops.iter().enumerate() {
        if live[i] {
            val[i] = interval_op(op, |k| val[k as usize], |inp| bx.input(prog, inp));
        }
    }
    let n = prog.deriv.len();
    let mut jac = vec![Interval::point(0.0); n * n];
    let mut dot = vec![Interval::point(0.0); ops.len()];
    let one = Interval::point(1.0);
    let zero = Interval::point(0.0);
    // The tangent by `y_j` is zero outside the operations that read `y_j`
    // (its cone): only those are evaluated, so a sparse rig (a chain) costs
    // its cones, not `n × ops`. A tangent whose operands' tangents are all
    // zero is zero (what the dense sweep computed, less its 1-ulp widening).
    let mut users: Vec<Vec<Id>> = vec![vec![]; ops.len()];
    let mut reads: Vec<Vec<Id>> = vec![vec![]; n];
    for (i, &op) in ops.iter().enumerate() {
        if !live[i] {
            continue;
        }
        if let Op::In(Input::State(s)) = op
            && (s as usize) < n
        {
            reads[s as usize].push(i as Id);
        }
        for a in crate::compile::ir::operands(&op) {
            users[a as usize].push(i as Id);
        }
    }
    let mut in_cone = vec![false; ops.len()];
    for j in 0..n {
        let mut cone: Vec<Id> = reads[j].clone();
        let mut k = 0;
        while k < cone.len() {
            let c = cone[k] as usize;
            if !in_cone[c] {
                in_cone[c] = true;
                for &u in &users[c] {
                    if !in_cone[u as usize] {
                        cone.push(u);
                    }
                }
            }
            k += 1;
        }
        cone.sort_unstable();
        cone.dedup();
        for &ci in &cone {
            let i = ci as usize;
            let op = ops[i];
            if crate::compile::ir::operands(&op)
                .into_iter()
                .all(|a| !in_cone[a as usize])
                && !matches!(op, Op::In(Input::State(_)))
            {
                dot[i] = zero;
                continue;
            }
            let v = |k: Id| val[k as usize];
            let d = |k: Id| dot[k as usize];
            let x = match op {
                Op::In(Input::State(s)) => Interval::point(f64::from(u8::from(s as usize == j))),
                Op::Const(_) | Op::In(_) | Op::Le(..) | Op::Eq(..) => Interval::point(0.0),
                Op::Add(p, q) => d(p).add(d(q)),
                Op::Sub(p, q) => d(p).sub(d(q)),
                Op::Mul(p, q) => d(p).mul(v(q)).add(v(p).mul(d(q))),
                Op::Div(p, q) => d(p).sub(v(i as Id).mul(d(q))).div(v(q)),
                Op::Neg(p) => d(p).neg(),
                Op::Abs(p) => {
                    let s = v(p);
                    if s.lo > 0.0 {
                        d(p)
                    } else if s.hi < 0.0 {
                        d(p).neg()
                    } else {
                        Interval { lo: -1.0, hi: 1.0 }.mul(d(p))
                    }
                }
                Op::Min(p, q) | Op::Max(p, q) => {
                    let (a, b) = (v(p), v(q));
                    let smaller = matches!(op, Op::Min(..));
                    if a.hi < b.lo {
                        if smaller { d(p) } else { d(q) }
                    } else if b.hi < a.lo {
                        if smaller { d(q) } else { d(p) }
                    } else {
                        d(p).hull(d(q))
                    }
                }
                Op::Exp(p) => v(i as Id).mul(d(p)),
                Op::Expm1(p) => v(i as Id).add(one).mul(d(p)),
                Op::Ln(p) => d(p).div(v(p)),
                Op::Sin(p) => v(p).trig(true).mul(d(p)),
                Op::Cos(p) => v(p).trig(false).neg().mul(d(p)),
                Op::Select(c, p, q) => match decided(v(c)) {
                    Some(true) => d(p),
                    Some(false) => d(q),
                    None => d(p).hull(d(q)),
                },
            };
            dot[i] = x;
        }
        for (i, &id) in prog.deriv.iter().enumerate() {
            if in_cone[id as usize] {
                jac[i * n + j] = dot[id as usize];
            }
        }
        for &ci in &cone {
            in_cone[ci as usize] = false;
            dot[ci as usize] = zero;
        }
    }
    jac
}

/// An upper bound on the spectral radius of every matrix whose entries lie in
/// `jac` (`n × n`, row major): with `M = |jac|` entrywise (largest magnitude),
/// `ρ(J) ≤ ρ(|J|) ≤ ρ(M) ≤ max_i (M·d)_i / d_i` for any positive `d`
/// (Collatz–Wielandt), with `d` from a power iteration towards `M`'s Perron
/// vector. A row-scaled Gershgorin bound, as tight as the scaling allows; for
/// one mass on a spring and damper it is `c/(2m) + √(c²/(4m²) + k/m)`.
/// Infinite when an entry is unbounded.
pub fn spectral_bound(jac: &[Interval], n: usize) -> f64 {
    // `M` by rows, its zeros left out: a rig's Jacobian is sparse (a chain's
    // is banded), so each product costs its nonzeros, not `n²`. Leaving out
    // a `0·d_j` (a `+0` to a sum of non-negative terms) changes no bit.
    let mut rows: Vec<Vec<(usize, f64)>> = vec![vec![]; n];
    for (k, e) in jac.iter().enumerate() {
        let mag = e.mag();
        if !mag.is_finite() {
            return f64::INFINITY;
        }
        if mag != 0.0 {
            rows[k / n].push((k % n, mag));
        }
    }
    let apply = |d: &[f64]| -> Vec<f64> {
        rows.iter()
            .map(|row| row.iter().map(|&(j, m)| m * d[j]).sum())
            .collect()
    };
    let ratio = |d: &[f64]| -> f64 {
        let md = apply(d);
        (0..n).map(|i| md[i] / d[i]).fold(0.0, f64::max)
    };
    let mut best = ratio(&vec![1.0; n]);
    // Iterating with `M + σI` has the same Perron vector; `M` alone may cycle
    // (a mass on a spring's `[[0, 1], [k/m, 0]]` does), a large σ converges
    // slowly: a few shifts, each from the all-ones vector, keeping the least
    // ratio any of them reaches (every one is a bound).
    for shift in [0.0, 1e-3, 3e-2, 1.0] {
        let sigma = shift * best;
        let mut d = vec![1.0; n];
        for _ in 0..300 {
            let md: Vec<f64> = apply(&d)
                .iter()
                .zip(&d)
                .map(|(a, b)| a + sigma * b)
                .collect();
            let top = md.iter().copied().fold(0.0, f64::max);
            if top <= 0.0 || !top.is_finite() {
                break;
            }
            // Kept strictly positive so the ratio stays a bound.
            d = md.iter().map(|x| (x / top).max(1e-200)).collect();
            best = best.min(ratio(&d));
        }
    }
    // The ratio's own rounding: a few ulps per sum of n terms.
    best * (1.0 + 4.0 * n as f64 * f64::EPSILON)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn iv(a: f64, b: f64) -> Interval {
        Interval::new(a, b)
    }

    /// Every operation's interval holds its value at points sampled in the
    /// operands' intervals.
    #[test]
    fn each_operation_encloses_its_point_values() {
        use crate::compile::ir::eval_op;
        let boxes = [
            iv(-2.0, 3.0),
            iv(0.5, 1.5),
            iv(-4.0, -0.25),
            iv(-7.0, 7.0),
            iv(0.0, 0.0),
            iv(1.0, 1.0),
            iv(2.0, 40.0),
        ];
        let ops = [
            Op::Add(0, 1),
            Op::Sub(0, 1),
            Op::Mul(0, 1),
            Op::Div(0, 1),
            Op::Neg(0),
            Op::Abs(0),
            Op::Min(0, 1),
            Op::Max(0, 1),
            Op::Exp(0),
            Op::Expm1(0),
            Op::Ln(0),
            Op::Sin(0),
            Op::Cos(0),
            Op::Le(0, 1),
            Op::Eq(0, 1),
        ];
        for &a in &boxes {
            for &b in &boxes {
                for &c in &boxes {
                    let ab = [a, b, c];
                    for op in ops.iter().copied().chain([Op::Select(2, 0, 1)]) {
                        let r = interval_op(op, |k| ab[k as usize], |_| Interval::ENTIRE);
                        for s in 0..=16 {
                            for u in 0..=4 {
                                let at = |x: Interval, f: f64| x.lo + (x.hi - x.lo) * f;
                                let xs = [
                                    at(a, s as f64 / 16.0),
                                    at(b, u as f64 / 4.0),
                                    at(c, (s % 3) as f64 / 2.0),
                                ];
                                let x = eval_op(op, |k| xs[k as usize], |_| 0.0);
                                assert!(
                                    x.is_nan() || r.contains(x),
                                    "{op:?} over {ab:?} gave {r:?}, but {x} at {xs:?}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn step_out_moves_one_float_outward() {
        for x in [1.0, -1.0, 0.0, 3.5e-300, -7.25e200, f64::MAX / 2.0] {
            let (d, u) = (step_out(x, false), step_out(x, true));
            assert!(d < x && x < u, "{x}: {d} {u}");
            assert!(
                x == 0.0
                    || (d.to_bits().abs_diff(x.to_bits()) == 1
                        && u.to_bits().abs_diff(x.to_bits()) == 1)
            );
        }
    }

    #[test]
    fn spectral_bound_of_a_single_oscillator() {
        // ẋ = v, v̇ = −(k/m)x − (c/m)v with k/m = 100, c/m = 2.
        let j = [
            Interval::point(0.0),
            Interval::point(1.0),
            Interval::point(-100.0),
            Interval::point(-2.0),
        ];
        let b = spectral_bound(&j, 2);
        let exact = 1.0 + (1.0f64 + 100.0).sqrt();
        assert!(b >= exact && b <= exact * (1.0 + 1e-9), "{b} vs {exact}");
    }
}
