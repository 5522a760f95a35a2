//! Where the integrator stops to report: uniform measurement samples.

use std::ops::ControlFlow;

/// Uniform sample times `t_k = t0 + k·dt`, `k = 0..samples`, each split into
/// `substeps` RK4 steps of `h = dt / substeps`. Times are computed from the step
/// index (never accumulated), so long runs do not drift.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleGrid {
    /// Model time of the first sample (s). The system is at rest for `t ≤ 0`; when
    /// `t0 > 0` the integrator first runs a prologue from `t = 0` to `t0`.
    pub t0: f64,
    /// Sample interval (s).
    pub dt: f64,
    /// Number of samples reported.
    pub samples: usize,
    /// RK4 steps per sample interval (≥ 1).
    pub substeps: usize,
}

impl SampleGrid {
    /// RK4 step length (s).
    pub fn step(&self) -> f64 {
        self.dt / self.substeps as f64
    }

    /// Model time of sample `k` (s).
    pub fn time(&self, k: usize) -> f64 {
        self.t0 + k as f64 * self.dt
    }

    /// Number of prologue steps from `t = 0` up to `t0` (0 when `t0 ≤ 0`). Their
    /// common length is `t0 / prologue_steps()`, never longer than [`Self::step`].
    pub fn prologue_steps(&self) -> usize {
        if self.t0 <= 0.0 {
            0
        } else {
            (self.t0 / self.step()).ceil() as usize
        }
    }

    /// Total RK4 steps for the whole run, prologue included (saturating: a
    /// clock offset of 1e300 s is a count to refuse, not an overflow).
    pub fn total_steps(&self) -> usize {
        self.prologue_steps()
            .saturating_add(self.samples.saturating_sub(1).saturating_mul(self.substeps))
    }
}

/// Walks `grid` as every integrator of rigfit does: the prologue from `t = 0`
/// to `t0` when `t0 > 0`, then `substeps` steps per sample, every step's time
/// computed from its index, calling `step(ctx, t, h)` for each step and
/// `observe(ctx, k, t_k)` at every sample (which may stop the walk).
pub fn walk_grid<C>(
    grid: &SampleGrid,
    ctx: &mut C,
    mut step: impl FnMut(&mut C, f64, f64),
    mut observe: impl FnMut(&mut C, usize, f64) -> ControlFlow<()>,
) {
    let pro = grid.prologue_steps();
    if pro > 0 {
        let hp = grid.t0 / pro as f64;
        for i in 0..pro {
            step(ctx, i as f64 * hp, hp);
        }
    }
    let h = grid.step();
    for k in 0..grid.samples {
        if k > 0 {
            for j in 0..grid.substeps {
                let i = (k - 1) * grid.substeps + j;
                step(ctx, grid.t0 + i as f64 * h, h);
            }
        }
        if observe(ctx, k, grid.time(k)).is_break() {
            return;
        }
    }
}
