//! The lane interpreter: register code ([`crate::compile::exec::lane_code`]) applied
//! to every lane in blocks of [`W`] lanes (structure of arrays), so the compiler
//! turns each instruction into a few vector instructions; RK4's stage sums and the
//! event marks, lane by lane. `exp`/`expm1`/`ln` are
//! [`crate::compile::math`]'s branch-free forms, which vectorise too;
//! `sin`/`cos` are its scalar forms, lane by lane.
//!
//! These loops are written once; [`super::isa`] builds them for each vector
//! instruction set and picks one at run time.

#![expect(
    clippy::needless_range_loop,
    reason = "lane loops index several arrays in step, the shape the vectoriser wants"
)]

use crate::compile::exec::lane_code::{Ins, List};
use crate::compile::exec::lanes::{BLOCKS, Reg, W};
use crate::compile::ir::{Id, Op, operands};

/// `d = f(a, b)`, block by block (operands copied in, so `d` may be `a`).
#[inline(always)]
fn bin(r: &mut [Reg], nb: usize, d: usize, a: Id, b: Id, f: impl Fn(f64, f64) -> f64) {
    for k in 0..nb {
        let (x, y) = (r[a as usize][k], r[b as usize][k]);
        let mut o = [0.0; W];
        for l in 0..W {
            o[l] = f(x[l], y[l]);
        }
        r[d][k] = o;
    }
}

/// `d = f(a)`, block by block.
#[inline(always)]
fn un(r: &mut [Reg], nb: usize, d: usize, a: Id, f: impl Fn(f64) -> f64) {
    for k in 0..nb {
        let x = r[a as usize][k];
        let mut o = [0.0; W];
        for l in 0..W {
            o[l] = f(x[l]);
        }
        r[d][k] = o;
    }
}

/// Which blocks an instruction computes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Span {
    /// Every active block.
    Lanes,
    /// Block 0 alone: a value every lane shares that only instructions of
    /// the same kind read (in block 0).
    One,
    /// Block 0, then copied to the others, where a later instruction that
    /// runs over every block, or the caller (a root), reads it.
    OneCopied,
}

impl Span {
    /// Each instruction's span in `list`, given which give every lane the
    /// same value ([`List::uniform`]).
    pub(super) fn of(list: &List, uniform: &[bool]) -> Vec<Self> {
        let code = &list.code;
        (0..code.len())
            .map(|j| {
                if !uniform[j] {
                    return Self::Lanes;
                }
                let d = code[j].dest;
                for (later, &u) in code[j + 1..].iter().zip(&uniform[j + 1..]) {
                    if !u && operands(&later.op).contains(&Id::from(d)) {
                        return Self::OneCopied;
                    }
                    if later.dest == d {
                        return Self::One;
                    }
                }
                if list.roots.contains(&d) {
                    Self::OneCopied
                } else {
                    Self::One
                }
            })
            .collect()
    }
}

/// Runs `code` (instruction by instruction over `span`'s blocks) over the
/// first `nb` blocks of `r`.
#[inline(always)]
pub(super) fn exec(code: &[Ins], span: &[Span], r: &mut [Reg], nb: usize) {
    use crate::compile::math::{cos, exp, expm1, ln, sin};
    for (&ins, &sp) in code.iter().zip(span) {
        // A value every lane shares is computed in one block (and copied
        // where a block of its own lane reads it).
        let nb = if sp == Span::Lanes { nb } else { 1 };
        let d = ins.dest as usize;
        match ins.op {
            Op::Add(a, b) => bin(r, nb, d, a, b, |x, y| x + y),
            Op::Sub(a, b) => bin(r, nb, d, a, b, |x, y| x - y),
            Op::Mul(a, b) => bin(r, nb, d, a, b, |x, y| x * y),
            Op::Div(a, b) => bin(r, nb, d, a, b, |x, y| x / y),
            Op::Min(a, b) => bin(r, nb, d, a, b, f64::min),
            Op::Max(a, b) => bin(r, nb, d, a, b, f64::max),
            Op::Le(a, b) => bin(r, nb, d, a, b, |x, y| if x <= y { 1.0 } else { 0.0 }),
            Op::Eq(a, b) => bin(r, nb, d, a, b, |x, y| if x == y { 1.0 } else { 0.0 }),
            Op::Neg(a) => un(r, nb, d, a, |x| -x),
            Op::Abs(a) => un(r, nb, d, a, f64::abs),
            Op::Exp(a) => un(r, nb, d, a, exp),
            Op::Expm1(a) => un(r, nb, d, a, expm1),
            Op::Ln(a) => un(r, nb, d, a, ln),
            Op::Sin(a) => un(r, nb, d, a, sin),
            Op::Cos(a) => un(r, nb, d, a, cos),
            Op::Select(c, a, b) => {
                for k in 0..nb {
                    let (s, x, y) = (r[c as usize][k], r[a as usize][k], r[b as usize][k]);
                    let mut o = [0.0; W];
                    for l in 0..W {
                        o[l] = if s[l] != 0.0 { x[l] } else { y[l] };
                    }
                    r[d][k] = o;
                }
            }
            Op::Const(_) | Op::In(_) => unreachable!("registers filled before the list runs"),
        }
        if sp == Span::OneCopied {
            let b0 = r[d][0];
            r[d].0[1..].fill(b0);
        }
    }
}

/// After one of RK4's first three derivatives, whose slopes are in the
/// registers `slopes`: `acc = k` (the first) or `acc += 2·k`, and the next
/// stage's input `y + c·k` into the state registers, lane by lane.
#[inline(always)]
pub(super) fn stage(
    r: &mut [Reg],
    nb: usize,
    y: &[Reg],
    acc: &mut [Reg],
    slopes: &[u16],
    c: f64,
    first: bool,
) {
    for i in 0..y.len() {
        let s = slopes[i] as usize;
        for b in 0..nb {
            let (yb, kb, mut a) = (y[i][b], r[s][b], acc[i][b]);
            let mut o = [0.0; W];
            for l in 0..W {
                a[l] = if first { kb[l] } else { a[l] + 2.0 * kb[l] };
                o[l] = yb[l] + c * kb[l];
            }
            acc[i][b] = a;
            r[i][b] = o;
        }
    }
}

/// RK4's last line after its fourth derivative: `y + c·(acc + k)` into the
/// state registers, lane by lane, with `acc = k₀ + 2k₁ + 2k₂` summed in that
/// order by [`stage`], so it rounds as `y + c·(k₀ + 2k₁ + 2k₂ + k₃)` does.
#[inline(always)]
pub(super) fn finish(r: &mut [Reg], nb: usize, y: &[Reg], acc: &[Reg], slopes: &[u16], c: f64) {
    for i in 0..y.len() {
        let s = slopes[i] as usize;
        for b in 0..nb {
            let (yb, kb, a) = (y[i][b], r[s][b], acc[i][b]);
            let mut o = [0.0; W];
            for l in 0..W {
                o[l] = yb[l] + c * (a[l] + kb[l]);
            }
            r[i][b] = o;
        }
    }
}

/// Sets the bit of each lane of the first `nb` blocks whose mode is `from`,
/// whose guard holds (each (register, value) pair of `guard.0`, registers
/// `guard.1`) and whose event function `g` is `past` its switch.
#[inline(always)]
pub(super) fn mark(
    hit: &mut [u8; BLOCKS],
    nb: usize,
    g: &Reg,
    mode: &Reg,
    from: f64,
    guard: (&[(u16, f64)], &[Reg]),
    past: impl Fn(f64) -> bool,
) {
    for b in 0..nb {
        let (gb, mb) = (g[b], mode[b]);
        let mut bits = 0;
        for l in 0..W {
            bits |= u8::from(past(gb[l]) & (mb[l] == from)) << l;
        }
        for &(r, v) in guard.0 {
            let rb = guard.1[usize::from(r)][b];
            for l in 0..W {
                bits &= !(u8::from(rb[l] != v) << l);
            }
        }
        hit[b] |= bits;
    }
}
