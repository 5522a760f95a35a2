//! The CPU ensemble of a compiled rig: up to [`LANES`] runs of one experiment
//! (one sample grid) advanced together. The tape's operations are translated
//! once into a register program ([`crate::compile::exec::lane_code`]); every instruction is
//! applied to all runs in blocks of [`W`] lanes (structure of arrays), so the
//! compiler turns each into a few vector instructions, and `exp`/`expm1` are
//! [`crate::compile::math`]'s branch-free forms, which vectorise too.
//!
//! Between steps every lane's state sits in the state registers, where the
//! event and report lists read it; RK4 reads each slope where the derivative
//! left it and sums them as they come, so a step copies the state once (its
//! start, kept for a lane that must redo it). A run reports every output and
//! the full state, or output 0 alone ([`Report`]), with the list that
//! computes just that.
//!
//! Plain steps, event checks and reports run over the lanes. A lane whose step
//! ends past a switch is handed to its own [`EventStepper`], which redoes that
//! step from its start with the switch located: the lanes evaluate the same
//! operations in the same order as the scalar reference, so every lane's history
//! is bit-identical to [`EventStepper`]'s (`tests/rig_cpu_ensemble.rs`).
//!
//! The interpreter's loops are in `interp.rs`, built for each vector
//! instruction set in `isa.rs`; this file holds the lane layout and the
//! runner.

use std::ops::ControlFlow;

use crate::base::{MeasuredSample, PiecewiseLinear, Report, Sample, lane_bits};
use crate::base::{SampleGrid, walk_grid};
use crate::compile::exec::events::{EventStepper, Fired};
use crate::compile::exec::interp::{Span, mark};
use crate::compile::exec::lane_code::{LaneCode, List};
use crate::compile::exec::native_calls::{Arith, Native, NativeList, REDO_FIRED, RedoLanes};
use crate::compile::exec::sampling::SampleClock;
use crate::compile::exec::tape::{Tape, table_value};
use crate::compile::program::{Direction, Program};

pub use crate::compile::exec::isa::Isa;

/// Lanes in one vector block.
pub const W: usize = 8;
/// Blocks in a register.
pub(crate) const BLOCKS: usize = 8;
/// Runs advanced together, at most.
pub const LANES: usize = W * BLOCKS;
// Lane sets are bits of a `u64`.
const _: () = assert!(LANES <= 64);

type Blk = [f64; W];
/// One value of every lane, aligned to a cache line so no vector load or
/// store straddles two.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(64))]
pub(crate) struct Reg(pub(crate) [Blk; BLOCKS]);

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
    pub(crate) const fn splat(v: f64) -> Self {
        Self([[v; W]; BLOCKS])
    }

    /// Lane `l`'s value: from the row's f32 lanes packed at its start where
    /// `packed` ([`LaneRunner::with_native`]'s f32 code), else its f64 lane.
    #[inline(always)]
    fn lane(&self, l: usize, packed: bool) -> f64 {
        if packed {
            f64::from(bytemuck::cast_slice::<Blk, f32>(&self.0)[l])
        } else {
            self[l / W][l % W]
        }
    }

    /// Sets lane `l` to `v`, rounded to f32 where the row is `packed`.
    #[inline(always)]
    fn set_lane(&mut self, l: usize, v: f64, packed: bool) {
        if packed {
            bytemuck::cast_slice_mut::<Blk, f32>(&mut self.0)[l] = v as f32;
        } else {
            self[l / W][l % W] = v;
        }
    }

    /// The row's lanes as f32, packed at its start.
    fn pack(&mut self) {
        let lanes: Vec<f32> = self.0.iter().flatten().map(|&x| x as f32).collect();
        let packed: &mut [f32] = bytemuck::cast_slice_mut(&mut self.0[..]);
        packed[..lanes.len()].copy_from_slice(&lanes);
    }

    /// The row with its lanes as f64 (`packed`: from its packed f32 lanes).
    fn unpacked(&self, packed: bool) -> Self {
        let mut r = *self;
        if packed {
            for l in 0..LANES {
                r[l / W][l % W] = self.lane(l, true);
            }
        }
        r
    }

    /// Whether lanes `0..lanes` hold the same bits.
    fn agrees(&self, lanes: usize) -> bool {
        let v0 = self[0][0].to_bits();
        (0..lanes).all(|l| self[l / W][l % W].to_bits() == v0)
    }
}

const ZERO: Reg = Reg::splat(0.0);

/// Up to [`LANES`] runs of one program on one grid.
#[derive(Debug)]
pub struct LaneRunner<'p> {
    prog: &'p Program,
    code: &'p LaneCode,
    force: Option<&'p PiecewiseLinear>,
    /// Active blocks.
    nb: usize,
    isa: Isa,
    /// Per list (derivative, events, report, measured output, update):
    /// each instruction's span (every lane, or one value all share).
    spans: [Vec<Span>; 5],
    /// The register file; between steps its state registers hold every
    /// lane's state, which the event and report lists read where it is.
    regs: Vec<Reg>,
    steppers: Vec<EventStepper<'p>>,
    /// The state at the start of the step being taken.
    y: Vec<Reg>,
    /// RK4's running sum of slopes, `k₀ + 2k₁ + 2k₂`.
    acc: Vec<Reg>,
    /// Per block, a bit per lane whose step ended past an armed switch.
    hit: [u8; BLOCKS],
    /// One lane's state, for a step its stepper redoes, and where the lanes'
    /// plain step ended.
    lane_y: Vec<f64>,
    lane_end: Vec<f64>,
    /// The lane code built to native code, which then runs the steps and
    /// lists instead of the interpreter.
    native: Option<&'p Native>,
    /// Table values for `native`'s calls.
    tab: Vec<f64>,
    /// Whether every active lane shares `native`'s `hoist_reads`.
    hoist: bool,
    /// Buffers for `native`'s redone steps ([`Native::redo`]), and each
    /// lane's per-run constants for them (in `code.constants`' order): set
    /// by [`Self::with_native`] where it redoes steps.
    redo: RedoLanes,
    redo_constants: Vec<f64>,
    /// Per register, whether its row holds its lanes as f32 packed at its
    /// start (the states and per-run constants of f32 native code).
    packed: Vec<bool>,
    /// A bit per lane whose stepper found its run chattering (its outputs
    /// NaN from then on).
    chattered: u64,
    /// The number the observer is given for lane 0.
    first: usize,
    /// The next sample instant (every lane shares the schedule).
    clock: SampleClock,
    /// The update list's roots, gathered before any held register changes.
    updated: Vec<Reg>,
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
        // Each run's constants, and the initial state and regimes its stepper
        // found; idle lanes repeat lane 0, so they compute something finite.
        for l in 0..nb * W {
            let s = steppers.get(l).unwrap_or(&steppers[0]);
            let (b, j) = (l / W, l % W);
            for &(id, reg) in &code.constants {
                regs[reg as usize][b][j] = s.frame.get(id);
            }
            for (i, &v) in s.y0.iter().enumerate() {
                regs[i][b][j] = v;
            }
            for (m, &v) in s.regimes.iter().enumerate() {
                regs[code.regimes[m] as usize][b][j] = f64::from(v);
            }
            for (k, &v) in s.held.iter().enumerate() {
                regs[code.held[k] as usize][b][j] = v;
            }
        }
        // Registers every active lane shares: time, tables and the per-run
        // constants whose values agree (fixed parameters, literals).
        let lists = code.lists();
        let mut shared = vec![false; code.registers];
        shared[code.time as usize] = true;
        for l in lists {
            for &(_, reg) in &l.tables {
                shared[reg as usize] = true;
            }
        }
        for &(_, reg) in &code.constants {
            shared[reg as usize] = regs[reg as usize].agrees(nb * W);
        }
        let spans = lists.map(|l| Span::of(l, &l.uniform(&mut shared.clone())));
        Self {
            prog,
            code,
            force,
            nb,
            isa: Isa::detect(),
            spans,
            regs,
            steppers,
            y: vec![ZERO; n],
            acc: vec![ZERO; n],
            hit: [0; BLOCKS],
            lane_y: vec![0.0; n],
            lane_end: vec![0.0; n],
            native: None,
            tab: vec![],
            hoist: false,
            redo: RedoLanes::default(),
            redo_constants: vec![],
            packed: vec![false; code.registers],
            chattered: 0,
            first: 0,
            clock: SampleClock::default(),
            updated: vec![ZERO; code.held.len()],
        }
    }

    /// The same runs through `native`, the build of this runner's lane code
    /// ([`Native::build`]), instead of the interpreter.
    pub fn with_native(mut self, native: &'p Native) -> Self {
        self.tab = vec![0.0; 4 * native.table_stride];
        let lanes = self.nb * W;
        self.hoist = native
            .hoist_reads
            .iter()
            .all(|&reg| self.regs[reg as usize].agrees(lanes));
        if native.arith == Arith::F32 {
            // The f32 code reads and writes each state and per-run constant
            // as f32, its lanes packed at the start of its row, instead of
            // rounding it from f64 and back at every step.
            let constants = self.code.constants.iter().map(|&(_, r)| usize::from(r));
            for reg in (0..self.y.len()).chain(constants) {
                self.regs[reg].pack();
                self.packed[reg] = true;
            }
        }
        if native.redoes() {
            // Each lane's per-run constants in f64 for the redone steps, from
            // its stepper's frame (an f32 runner's rows hold them rounded).
            self.redo = native.redo_buffers();
            self.redo_constants = self
                .steppers
                .iter()
                .flat_map(|st| self.code.constants.iter().map(|&(id, _)| st.frame.get(id)))
                .collect();
        } else {
            // A build that redoes steps itself has no one-run derivative.
            for st in &mut self.steppers {
                st.with_native_deriv(self.code, native);
            }
        }
        self.native = Some(native);
        self
    }

    /// Lane `l` is run `first + l` to the observer (a group of a larger
    /// batch).
    pub fn numbered_from(mut self, first: usize) -> Self {
        self.first = first;
        self
    }

    /// `native`'s table values at each time of `tt`.
    fn fill_tables(&mut self, tt: &[f64]) {
        let stride = self.tab.len() / 4;
        for (s, &t) in tt.iter().enumerate() {
            for k in 0..stride {
                self.tab[s * stride + k] = table_value(self.prog, self.force, k as u32, t);
            }
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

    /// Fills the time and table registers for `list` (whose spans are
    /// `self.spans[which]`) at `t`, then runs it.
    fn eval(&mut self, list: &List, which: usize, t: f64) {
        let nb = self.nb;
        if let Some(native) = self.native {
            let which = match which {
                2 => NativeList::Report,
                3 => NativeList::Measured,
                4 => NativeList::Update,
                _ => unreachable!("native code runs the derivative and the events in rig_rk4"),
            };
            self.fill_tables(&[t]);
            native.list(which, &mut self.regs, nb, t, &self.tab);
            return;
        }
        if list.uses_time {
            self.regs[self.code.time as usize].0[..nb].fill([t; W]);
        }
        for &(table, reg) in &list.tables {
            let v = table_value(self.prog, self.force, table, t);
            self.regs[reg as usize].0[..nb].fill([v; W]);
        }
        self.isa
            .exec(&list.code, &self.spans[which], &mut self.regs, nb);
    }

    /// The derivative at the state registers' values, its slopes left in the
    /// registers `code.slopes`.
    fn deriv(&mut self, t: f64) {
        let code = self.code;
        self.eval(&code.deriv, 0, t);
        for &(state, copy) in &code.slope_copies {
            self.regs[copy as usize] = self.regs[state as usize];
        }
    }

    /// One RK4 step of every lane from the state registers' values, its
    /// start kept in `y`; written as `EventStepper`'s so the lanes round
    /// alike.
    fn rk4(&mut self, t: f64, h: f64) {
        if let Some(native) = self.native {
            let tt = [t, t + 0.5 * h, t + 0.5 * h, t + h];
            self.fill_tables(&tt);
            let (ch, h6) = (0.5 * h, h / 6.0);
            native.rk4(
                &mut self.regs,
                &mut self.y,
                self.nb,
                &tt,
                &self.tab,
                ch,
                h,
                h6,
                self.hoist,
                &mut self.hit,
            );
            return;
        }
        let (n, nb, isa, slopes) = (self.y.len(), self.nb, self.isa, &self.code.slopes);
        self.y.copy_from_slice(&self.regs[..n]);
        for (s, c) in [0.5 * h, 0.5 * h, h].into_iter().enumerate() {
            self.deriv(if s == 0 { t } else { t + 0.5 * h });
            isa.stage(
                &mut self.regs,
                nb,
                &self.y,
                &mut self.acc,
                slopes,
                c,
                s == 0,
            );
        }
        self.deriv(t + h);
        isa.finish(&mut self.regs, nb, &self.y, &self.acc, slopes, h / 6.0);
    }

    /// Sets the bit in `hit` of each lane whose event function (in its
    /// register) is past an armed switch.
    fn mark_hits(&mut self) {
        let (code, nb) = (self.code, self.nb);
        for ((&(mode, from, dir), &g), guard) in
            code.armed.iter().zip(&code.events.roots).zip(&code.guards)
        {
            let (g, mode) = (&self.regs[g as usize], &self.regs[mode as usize]);
            let guard = (&guard[..], &self.regs[..]);
            // `Transition::violated`, its direction fixed outside the loop.
            match dir {
                Direction::Up => mark(&mut self.hit, nb, g, mode, from, guard, |g| {
                    Direction::Up.past(g)
                }),
                Direction::Down => {
                    mark(&mut self.hit, nb, g, mode, from, guard, |g| {
                        Direction::Down.past(g)
                    });
                }
            }
        }
    }

    /// One step of every lane from `t`, split at the controllers' sample
    /// instants inside it as [`EventStepper::step`] splits it.
    fn step(&mut self, t: f64, h: f64) {
        let mut clock = self.clock;
        clock.step(
            self.prog.sampling.as_ref(),
            self,
            t,
            h,
            &mut |me, ta, len| me.piece(ta, len),
            &mut |me, tn| me.sample(tn),
        );
        self.clock = clock;
    }

    /// Every lane's held states set from their updates at `t` (a sample
    /// instant), all from the values before.
    fn sample(&mut self, t: f64) {
        let code = self.code;
        self.eval(&code.update, 4, t);
        for (u, &root) in self.updated.iter_mut().zip(&code.update.roots) {
            *u = self.regs[root as usize].unpacked(self.packed[root as usize]);
        }
        for (u, &reg) in self.updated.iter().zip(&code.held) {
            self.regs[reg as usize] = *u;
        }
    }

    /// Takes the sample instants not yet taken at or before `t`.
    fn catch_up(&mut self, t: f64) {
        let mut clock = self.clock;
        clock.catch_up(self.prog.sampling.as_ref(), self, t, &mut |me, t| {
            me.sample(t)
        });
        self.clock = clock;
    }

    /// One piece of a step (between sample instants) for every lane; lanes
    /// past a switch are redone by their own stepper with the switch located.
    fn piece(&mut self, t: f64, h: f64) {
        let nb = self.nb;
        self.rk4(t, h);
        let code = self.code;
        // Native code ran the event list at the step's end and set the hit
        // bits within its step.
        if self.native.is_none() {
            self.hit = [0; BLOCKS];
            self.eval(&code.events, 1, t + h);
            self.mark_hits();
        }
        if self.hit[..nb].iter().all(|&h| h == 0) {
            return;
        }
        if let Some(native) = self.native.filter(|n| n.redoes()) {
            self.redo(native, t, h);
            return;
        }
        let mut lane_y = std::mem::take(&mut self.lane_y);
        let mut lane_end = std::mem::take(&mut self.lane_end);
        // The states' rows (and the step's start, kept alike) are packed or
        // not together.
        let packed = self.packed[0];
        for l in 0..self.steppers.len() {
            let (b, j) = (l / W, l % W);
            if self.hit[b] >> j & 1 == 0 || self.chattered >> l & 1 == 1 {
                continue;
            }
            for (s, v) in lane_y.iter_mut().enumerate() {
                *v = self.y[s].lane(l, packed);
            }
            for (s, v) in lane_end.iter_mut().enumerate() {
                *v = self.regs[s].lane(l, packed);
            }
            let st = &mut self.steppers[l];
            for (k, v) in st.held.iter_mut().enumerate() {
                *v = self.regs[self.code.held[k] as usize][b][j];
            }
            st.step_ending_at(t, h, &mut lane_y, &lane_end);
            for (s, &v) in lane_y.iter().enumerate() {
                self.regs[s].set_lane(l, v, packed);
            }
            for (m, &v) in st.regimes.iter().enumerate() {
                self.regs[self.code.regimes[m] as usize][b][j] = f64::from(v);
            }
            self.chattered |= u64::from(st.chattered) << l;
        }
        self.lane_y = lane_y;
        self.lane_end = lane_end;
    }

    /// The lanes past a switch at the piece's end redone by `native`, an
    /// f64 vector of them at a time ([`Native::redo`]), as their steppers
    /// would redo them one by one. They are gathered into as few vectors as
    /// hold them (the lanes a rig's switch takes in one step are seldom
    /// neighbours); a vector's slots past its last lane keep what they held
    /// (masked off, never read).
    fn redo(&mut self, native: &Native, t: f64, h: f64) {
        let (code, dw, n) = (self.code, native.redo_lanes, self.y.len());
        let packed = self.packed[0];
        let lanes = self.steppers.len();
        let mut b = std::mem::take(&mut self.redo);
        let nc = code.constants.len();
        let mut todo = [0_usize; LANES];
        let mut count = 0;
        for l in 0..lanes {
            if self.hit[l / W] >> (l % W) & 1 == 1 && self.chattered >> l & 1 == 0 {
                todo[count] = l;
                count += 1;
            }
        }
        for group in todo[..count].chunks(dw) {
            for (k, &l) in group.iter().enumerate() {
                let (bl, j) = (l / W, l % W);
                for (&(_, reg), &v) in code.constants.iter().zip(&self.redo_constants[l * nc..]) {
                    b.r[usize::from(reg) * dw + k] = v;
                }
                for &reg in code.regimes.iter().chain(&code.held) {
                    b.r[usize::from(reg) * dw + k] = self.regs[usize::from(reg)][bl][j];
                }
                for s in 0..n {
                    b.y[s * dw + k] = self.y[s].lane(l, packed);
                    b.y_end[s * dw + k] = self.regs[s].lane(l, packed);
                }
            }
            native.redo(&mut b, t, h, (1 << group.len()) - 1);
            for (k, &l) in group.iter().enumerate() {
                let (bl, j) = (l / W, l % W);
                for s in 0..n {
                    self.regs[s].set_lane(l, b.y[s * dw + k], packed);
                }
                let st = &mut self.steppers[l];
                for (m, &reg) in code.regimes.iter().enumerate() {
                    let v = b.r[usize::from(reg) * dw + k];
                    st.regimes[m] = v as u32;
                    self.regs[usize::from(reg)][bl][j] = v;
                }
                let fired = usize::try_from(b.fired[k]).expect("a count");
                st.fired
                    .extend((k * REDO_FIRED..).take(fired).map(|i| Fired {
                        t: b.times[i],
                        transition: usize::try_from(b.transitions[i]).expect("a transition"),
                    }));
                st.chattered |= b.chattered[k] != 0;
                self.chattered |= u64::from(st.chattered) << l;
            }
        }
        self.redo = b;
    }

    /// Runs every lane over `grid`, handing output 0 of every lane to
    /// `observe` at each sample (as [`crate::model::CompiledRig::simulate_measured`]
    /// does: lanes numbered from [`Self::numbered_from`], `live` a bit per
    /// lane still observed), until no lane is left.
    pub fn run_measured(
        &mut self,
        grid: &SampleGrid,
        observe: &mut dyn FnMut(&MeasuredSample<'_>, &mut u64),
    ) {
        let lanes = self.steppers.len();
        let code = self.code;
        let out = code.measured.roots[0] as usize;
        let mut live = lane_bits(lanes);
        let mut values = vec![0.0; lanes];
        walk_grid(
            grid,
            self,
            |me, t, h| me.step(t, h),
            |me, k, t| {
                me.catch_up(t);
                me.eval(&code.measured, 3, t);
                // The lanes in order are the register's row as it lies; a
                // copy only where a chattering lane must read NaN,
                // or of an output packed as f32 (a state's own row).
                let row = &me.regs[out];
                let values: &[f64] = if me.chattered == 0 && !me.packed[out] {
                    &row.0.as_flattened()[..lanes]
                } else {
                    for (l, v) in values.iter_mut().enumerate() {
                        *v = if me.chattered >> l & 1 == 1 {
                            f64::NAN
                        } else {
                            row.lane(l, me.packed[out])
                        };
                    }
                    &values
                };
                let s = MeasuredSample {
                    first: me.first,
                    index: k,
                    t,
                    values,
                };
                observe(&s, &mut live);
                if live != 0 {
                    ControlFlow::Continue(())
                } else {
                    ControlFlow::Break(())
                }
            },
        );
    }

    /// Runs every lane over `grid`, calling `observe(lane, sample)` at every
    /// sample until the lane's observer breaks, with what `report` asks for
    /// in each sample (only the list that computes it runs).
    pub fn run(
        &mut self,
        grid: &SampleGrid,
        report: Report,
        observe: &mut dyn FnMut(usize, &Sample<'_>) -> ControlFlow<()>,
    ) {
        let lanes = self.steppers.len();
        let code = self.code;
        let (list, which) = match report {
            Report::Full => (&code.report, 2),
            Report::Measured => (&code.measured, 3),
        };
        // A bit per lane whose observer has not broken.
        let mut live = lane_bits(lanes);
        let n_out = match report {
            Report::Full => self.prog.outputs.len(),
            Report::Measured => list.roots.len(),
        };
        let mut outs = vec![0.0; n_out];
        let mut full = vec![0.0; list.roots.len() - n_out];
        let (outputs, state) = list.roots.split_at(n_out);
        walk_grid(
            grid,
            self,
            |me, t, h| me.step(t, h),
            |me, k, t| {
                me.catch_up(t);
                me.eval(list, which, t);
                let mut left = live;
                while left != 0 {
                    let l = left.trailing_zeros() as usize;
                    left &= left - 1;
                    let chattered = me.chattered >> l & 1 == 1;
                    let lane = |reg: u16| me.regs[reg as usize].lane(l, me.packed[reg as usize]);
                    for (o, &reg) in outs.iter_mut().zip(outputs) {
                        *o = if chattered { f64::NAN } else { lane(reg) };
                    }
                    for (o, &reg) in full.iter_mut().zip(state) {
                        *o = lane(reg);
                    }
                    let s = Sample {
                        index: k,
                        t,
                        state: &full,
                        outputs: &outs,
                    };
                    if observe(me.first + l, &s).is_break() {
                        live &= !(1 << l);
                    }
                }
                if live != 0 {
                    ControlFlow::Continue(())
                } else {
                    ControlFlow::Break(())
                }
            },
        );
    }
}
