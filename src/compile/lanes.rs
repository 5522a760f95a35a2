//! The CPU ensemble of a compiled rig: up to [`LANES`] runs of one experiment
//! (one sample grid) advanced together. The tape's operations are translated
//! once into a register program ([`super::lane_code`]); every instruction is
//! applied to all runs in blocks of [`W`] lanes (structure of arrays), so the
//! compiler turns each into a few vector instructions, and `exp`/`expm1` are
//! [`super::math`]'s branch-free forms, which vectorise too.
//!
//! Plain steps, event checks and reports run over the lanes. A lane whose step
//! ends past a switch is handed to its own [`EventStepper`], which redoes that
//! step from its start with the switch located: the lanes evaluate the same
//! operations in the same order as the scalar reference, so every lane's history
//! is bit-identical to [`EventStepper`]'s (`tests/rig_cpu_ensemble.rs`).

#![expect(
    clippy::needless_range_loop,
    reason = "lane loops index several arrays in step, the shape the vectoriser wants"
)]

use std::ops::ControlFlow;

use super::events::EventStepper;
use super::ir::{Id, Op};
use super::lane_code::{Ins, LaneCode, List};
use super::program::Program;
use super::tape::{Tape, table_value};
use crate::integrate::{SampleGrid, walk_grid};
use crate::model::{PiecewiseLinear, Sample};

/// Lanes in one vector block.
pub const W: usize = 8;
/// Blocks in a register.
const BLOCKS: usize = 8;
/// Runs advanced together, at most.
pub const LANES: usize = W * BLOCKS;

type Blk = [f64; W];
/// One value of every lane, aligned to a cache line so no vector load or
/// store straddles two.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(64))]
pub(crate) struct Reg([Blk; BLOCKS]);

impl std::ops::Index<usize> for Reg {
    type Output = Blk;
    #[inline(always)]
    fn index(&self, b: usize) -> &Blk {
        &self.0[b]
    }
}

impl std::ops::IndexMut<usize> for Reg {
    #[inline(always)]
    fn index_mut(&mut self, b: usize) -> &mut Blk {
        &mut self.0[b]
    }
}

impl Reg {
    /// Every lane `v`.
    const fn splat(v: f64) -> Self {
        Self([[v; W]; BLOCKS])
    }
}

const ZERO: Reg = Reg::splat(0.0);

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

/// Runs `code` over the first `nb` blocks of `r`.
#[inline(always)]
fn exec(code: &[Ins], uniform: &[bool], r: &mut [Reg], nb: usize) {
    use super::math::{exp, expm1};
    for (&ins, &u) in code.iter().zip(uniform) {
        // A value every lane shares is computed in one block and copied.
        let nb = if u { 1 } else { nb };
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
            Op::Ln(a) => un(r, nb, d, a, f64::ln),
            Op::Sin(a) => un(r, nb, d, a, f64::sin),
            Op::Cos(a) => un(r, nb, d, a, f64::cos),
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
        if u {
            let b0 = r[d][0];
            r[d].0[1..].fill(b0);
        }
    }
}

/// `dst = y + c·k`, lane by lane, over every state (an RK4 stage's input).
#[inline(always)]
fn stage(r: &mut [Reg], nb: usize, y: &[Reg], c: f64, k: &[Reg]) {
    for i in 0..y.len() {
        for b in 0..nb {
            let (yb, kb) = (y[i][b], k[i][b]);
            let mut o = [0.0; W];
            for l in 0..W {
                o[l] = yb[l] + c * kb[l];
            }
            r[i][b] = o;
        }
    }
}

/// `y += c·(k₀ + 2k₁ + 2k₂ + k₃)`, lane by lane (RK4's last line).
#[inline(always)]
fn combine(y: &mut [Reg], nb: usize, c: f64, k: &[Vec<Reg>; 4]) {
    for i in 0..y.len() {
        for b in 0..nb {
            let (k0, k1, k2, k3) = (k[0][i][b], k[1][i][b], k[2][i][b], k[3][i][b]);
            let yb = &mut y[i][b];
            for l in 0..W {
                yb[l] += c * (k0[l] + 2.0 * k1[l] + 2.0 * k2[l] + k3[l]);
            }
        }
    }
}

/// The vector instructions the lane loops are compiled for, picked at run
/// time: the same source built three times, for AVX-512, AVX2 and the
/// baseline. None of them fuses a multiply and an add (Rust never contracts
/// floating-point expressions), so all three round exactly as the scalar
/// reference does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Isa {
    /// The target's baseline (SSE2 on x86-64).
    Base,
    /// 256-bit vectors.
    Avx2,
    /// 512-bit vectors.
    Avx512,
}

#[cfg(target_arch = "x86_64")]
mod wide {
    use super::{Ins, Reg, combine, exec, stage};

    #[target_feature(enable = "avx512f")]
    pub fn exec_512(code: &[Ins], uniform: &[bool], r: &mut [Reg], nb: usize) {
        exec(code, uniform, r, nb);
    }
    #[target_feature(enable = "avx2")]
    pub fn exec_256(code: &[Ins], uniform: &[bool], r: &mut [Reg], nb: usize) {
        exec(code, uniform, r, nb);
    }
    #[target_feature(enable = "avx512f")]
    pub fn stage_512(r: &mut [Reg], nb: usize, y: &[Reg], c: f64, k: &[Reg]) {
        stage(r, nb, y, c, k);
    }
    #[target_feature(enable = "avx2")]
    pub fn stage_256(r: &mut [Reg], nb: usize, y: &[Reg], c: f64, k: &[Reg]) {
        stage(r, nb, y, c, k);
    }
    #[target_feature(enable = "avx512f")]
    pub fn combine_512(y: &mut [Reg], nb: usize, c: f64, k: &[Vec<Reg>; 4]) {
        combine(y, nb, c, k);
    }
    #[target_feature(enable = "avx2")]
    pub fn combine_256(y: &mut [Reg], nb: usize, c: f64, k: &[Vec<Reg>; 4]) {
        combine(y, nb, c, k);
    }
}

impl Isa {
    /// The widest this processor runs, or the one `RIGFIT_LANES_ISA`
    /// (`base`, `avx2`, `avx512`) names if the processor has it; decided once
    /// per process.
    pub fn detect() -> Self {
        static PICKED: std::sync::OnceLock<Isa> = std::sync::OnceLock::new();
        *PICKED.get_or_init(|| {
            let best = Self::widest();
            match std::env::var("RIGFIT_LANES_ISA").as_deref() {
                Ok("base") => Self::Base,
                Ok("avx2") if best != Self::Base => Self::Avx2,
                _ => best,
            }
        })
    }

    /// Every one this processor runs, narrowest first.
    pub fn available() -> Vec<Self> {
        let w = Self::widest();
        [Self::Base, Self::Avx2, Self::Avx512]
            .into_iter()
            .filter(|&i| i == Self::Base || i == Self::Avx2 && w != Self::Base || i == w)
            .collect()
    }

    fn widest() -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f") {
                return Self::Avx512;
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                return Self::Avx2;
            }
        }
        Self::Base
    }

    #[expect(
        unsafe_code,
        reason = "calls the loops built for a feature `detect` found"
    )]
    fn exec(self, code: &[Ins], uniform: &[bool], r: &mut [Reg], nb: usize) {
        match self {
            // SAFETY: `detect` returns these only where the processor has them.
            #[cfg(target_arch = "x86_64")]
            Self::Avx512 => unsafe { wide::exec_512(code, uniform, r, nb) },
            #[cfg(target_arch = "x86_64")]
            Self::Avx2 => unsafe { wide::exec_256(code, uniform, r, nb) },
            _ => exec(code, uniform, r, nb),
        }
    }

    #[expect(
        unsafe_code,
        reason = "calls the loops built for a feature `detect` found"
    )]
    fn stage(self, r: &mut [Reg], nb: usize, y: &[Reg], c: f64, k: &[Reg]) {
        match self {
            // SAFETY: as in `exec`.
            #[cfg(target_arch = "x86_64")]
            Self::Avx512 => unsafe { wide::stage_512(r, nb, y, c, k) },
            #[cfg(target_arch = "x86_64")]
            Self::Avx2 => unsafe { wide::stage_256(r, nb, y, c, k) },
            _ => stage(r, nb, y, c, k),
        }
    }

    #[expect(
        unsafe_code,
        reason = "calls the loops built for a feature `detect` found"
    )]
    fn combine(self, y: &mut [Reg], nb: usize, c: f64, k: &[Vec<Reg>; 4]) {
        match self {
            // SAFETY: as in `exec`.
            #[cfg(target_arch = "x86_64")]
            Self::Avx512 => unsafe { wide::combine_512(y, nb, c, k) },
            #[cfg(target_arch = "x86_64")]
            Self::Avx2 => unsafe { wide::combine_256(y, nb, c, k) },
            _ => combine(y, nb, c, k),
        }
    }
}

/// Up to [`LANES`] runs of one program on one grid.
#[derive(Debug)]
pub struct LaneRunner<'p> {
    prog: &'p Program,
    code: &'p LaneCode,
    force: Option<&'p PiecewiseLinear>,
    /// Active blocks.
    nb: usize,
    isa: Isa,
    /// Per list (derivative, events, report): which instructions every lane
    /// shares.
    uniform: [Vec<bool>; 3],
    regs: Vec<Reg>,
    steppers: Vec<EventStepper<'p>>,
    y: Vec<Reg>,
    start: Vec<Reg>,
    k: [Vec<Reg>; 4],
    /// Lanes whose step ended past an armed switch.
    hit: [[bool; W]; BLOCKS],
    /// One lane's state, for a step its stepper redoes.
    lane_y: Vec<f64>,
}

impl<'p> LaneRunner<'p> {
    /// Runs of `prog` (translated to `code`) for each parameter vector of
    /// `params` (at most [`LANES`]).
    pub fn new(
        prog: &'p Program,
        tape: &'p Tape,
        code: &'p LaneCode,
        params: &[&[f64]],
        force: Option<&'p PiecewiseLinear>,
    ) -> Self {
        assert!(!params.is_empty() && params.len() <= LANES);
        let steppers: Vec<EventStepper<'p>> = params
            .iter()
            .map(|p| EventStepper::new(prog, tape, p, force))
            .collect();
        let nb = params.len().div_ceil(W);
        let n = prog.deriv.len();
        let mut regs = vec![ZERO; code.registers];
        // Each run's constants, and the initial state and modes its stepper
        // found; idle lanes repeat lane 0, so they compute something finite.
        let mut y = vec![ZERO; n];
        for l in 0..nb * W {
            let s = steppers.get(l).unwrap_or(&steppers[0]);
            let (b, j) = (l / W, l % W);
            for &(id, reg) in &code.constants {
                regs[reg as usize][b][j] = s.frame.get(id);
            }
            for (i, &v) in s.y0.iter().enumerate() {
                y[i][b][j] = v;
            }
            for (m, &v) in s.modes.iter().enumerate() {
                regs[code.modes[m] as usize][b][j] = f64::from(v);
            }
        }
        // Registers every active lane shares: time, tables and the per-run
        // constants whose values agree (fixed parameters, literals).
        let mut shared = vec![false; code.registers];
        shared[code.time as usize] = true;
        for l in [&code.deriv, &code.events, &code.report] {
            for &(_, reg) in &l.tables {
                shared[reg as usize] = true;
            }
        }
        for &(_, reg) in &code.constants {
            let r = &regs[reg as usize];
            let v0 = r[0][0];
            shared[reg as usize] = (0..nb * W).all(|l| r[l / W][l % W].to_bits() == v0.to_bits());
        }
        let uniform =
            [&code.deriv, &code.events, &code.report].map(|l| l.uniform(&mut shared.clone()));
        Self {
            prog,
            code,
            force,
            nb,
            isa: Isa::detect(),
            uniform,
            regs,
            steppers,
            y,
            start: vec![ZERO; n],
            k: std::array::from_fn(|_| vec![ZERO; n]),
            hit: [[false; W]; BLOCKS],
            lane_y: vec![0.0; n],
        }
    }

    /// The same runs on vector instructions `isa` (one of
    /// [`Isa::available`]) instead of the widest.
    pub fn with_isa(mut self, isa: Isa) -> Self {
        assert!(
            Isa::available().contains(&isa),
            "{isa:?} is not available here"
        );
        self.isa = isa;
        self
    }

    /// Fills the time and table registers for `list` (whose uniform flags
    /// are `self.uniform[which]`) at `t`, then runs it.
    fn eval(&mut self, list: &List, which: usize, t: f64) {
        let nb = self.nb;
        if list.uses_time {
            self.regs[self.code.time as usize].0[..nb].fill([t; W]);
        }
        for &(table, reg) in &list.tables {
            let v = table_value(self.prog, self.force, table, t);
            self.regs[reg as usize].0[..nb].fill([v; W]);
        }
        self.isa
            .exec(&list.code, &self.uniform[which], &mut self.regs, nb);
    }

    /// The derivative at the state registers' values into `k[out]`.
    fn deriv(&mut self, t: f64, out: usize) {
        let code = self.code;
        self.eval(&code.deriv, 0, t);
        for (s, &reg) in code.deriv.roots.iter().enumerate() {
            self.k[out][s] = self.regs[reg as usize];
        }
    }

    /// One RK4 step of every lane, written as `EventStepper`'s so the lanes
    /// round alike.
    fn rk4(&mut self, t: f64, h: f64) {
        let (n, nb) = (self.y.len(), self.nb);
        self.regs[..n].copy_from_slice(&self.y);
        self.deriv(t, 0);
        self.isa
            .stage(&mut self.regs, nb, &self.y, 0.5 * h, &self.k[0]);
        self.deriv(t + 0.5 * h, 1);
        self.isa
            .stage(&mut self.regs, nb, &self.y, 0.5 * h, &self.k[1]);
        self.deriv(t + 0.5 * h, 2);
        self.isa.stage(&mut self.regs, nb, &self.y, h, &self.k[2]);
        self.deriv(t + h, 3);
        self.isa.combine(&mut self.y, nb, h / 6.0, &self.k);
    }

    /// One step of every lane from `t`; lanes past a switch are redone by
    /// their own stepper with the switch located.
    fn step(&mut self, t: f64, h: f64) {
        let (n, nb) = (self.y.len(), self.nb);
        self.start.copy_from_slice(&self.y);
        self.rk4(t, h);
        self.regs[..n].copy_from_slice(&self.y);
        let code = self.code;
        self.eval(&code.events, 1, t + h);
        self.hit = [[false; W]; BLOCKS];
        for (tr, &g) in self.prog.transitions.iter().zip(&code.events.roots) {
            let (g, mode) = (
                &self.regs[g as usize],
                &self.regs[code.modes[tr.var as usize] as usize],
            );
            let from = f64::from(tr.from);
            for b in 0..nb {
                let (gb, mb, hb) = (&g[b], &mode[b], &mut self.hit[b]);
                for l in 0..W {
                    hb[l] |= tr.violated(gb[l]) & (mb[l] == from);
                }
            }
        }
        if !self.hit[..nb].iter().flatten().any(|&h| h) {
            return;
        }
        let mut lane_y = std::mem::take(&mut self.lane_y);
        for l in 0..self.steppers.len() {
            if !self.hit[l / W][l % W] || self.steppers[l].chattered {
                continue;
            }
            let (b, j) = (l / W, l % W);
            for (s, v) in lane_y.iter_mut().enumerate() {
                *v = self.start[s][b][j];
            }
            let st = &mut self.steppers[l];
            st.step(t, h, &mut lane_y);
            for (s, v) in lane_y.iter().enumerate() {
                self.y[s][b][j] = *v;
            }
            for (m, &v) in st.modes.iter().enumerate() {
                self.regs[self.code.modes[m] as usize][b][j] = f64::from(v);
            }
        }
        self.lane_y = lane_y;
    }

    /// Runs every lane over `grid`, calling `observe(lane, sample)` at every
    /// sample until the lane's observer breaks.
    pub fn run(
        &mut self,
        grid: &SampleGrid,
        observe: &mut dyn FnMut(usize, &Sample<'_>) -> ControlFlow<()>,
    ) {
        let lanes = self.steppers.len();
        let code = self.code;
        let mut live = vec![true; lanes];
        let mut outs = vec![0.0; self.prog.outputs.len()];
        let mut full = vec![0.0; self.prog.full_state.len()];
        walk_grid(
            grid,
            self,
            |me, t, h| me.step(t, h),
            |me, k, t| {
                let n = me.y.len();
                me.regs[..n].copy_from_slice(&me.y);
                me.eval(&code.report, 2, t);
                let (outputs, state) = code.report.roots.split_at(outs.len());
                for l in 0..lanes {
                    if !live[l] {
                        continue;
                    }
                    let (b, j) = (l / W, l % W);
                    let chattered = me.steppers[l].chattered;
                    for (o, &reg) in outs.iter_mut().zip(outputs) {
                        *o = if chattered {
                            f64::NAN
                        } else {
                            me.regs[reg as usize][b][j]
                        };
                    }
                    for (o, &reg) in full.iter_mut().zip(state) {
                        *o = me.regs[reg as usize][b][j];
                    }
                    let s = Sample {
                        index: k,
                        t,
                        state: &full,
                        outputs: &outs,
                    };
                    if observe(l, &s).is_break() {
                        live[l] = false;
                    }
                }
                if live.contains(&true) {
                    ControlFlow::Continue(())
                } else {
                    ControlFlow::Break(())
                }
            },
        );
    }
}
