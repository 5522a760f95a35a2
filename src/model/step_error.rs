//! The RK4 step chosen for accuracy: the integration error of the measured
//! output estimated by step doubling with the f64 reference.
//!
//! Classic RK4 is fourth order: runs at `n`, `2n` and `4n` steps per sample
//! differ by `d₁ = RMS(y_n − y_2n)` and `d₂ = RMS(y_2n − y_4n)`, and with the
//! observed ratio `r = d₁/d₂` (16 for fourth order) the error of the coarsest
//! is `err(n) ≈ d₁·r/(r − 1)`: `d₁·16/15` on a smooth run. Every switch is a
//! located event, yet an output that jumps at one (an acceleration at a
//! contact or a slip) converges more slowly, and a fixed `16/15` would then
//! miss the error by half or more; the observed ratio, held to
//! [`MIN_RATIO`]`..=16`, keeps the estimate near the error either way.

use std::ops::{ControlFlow, Range};

use super::CompiledRig;
use crate::base::{Drive, SampleGrid};

/// The smallest convergence ratio `d₁/d₂` the estimate believes (an order of
/// ½): below it the runs are not yet converging, and the estimate is
/// `d₁·√2/(√2 − 1)`, about `3.4·d₁`.
pub const MIN_RATIO: f64 = std::f64::consts::SQRT_2;

/// The largest (fourth order's 16): a larger observed ratio is rounding or
/// luck, and the estimate is `d₁·16/15`.
pub const MAX_RATIO: f64 = 16.0;

/// Reference runs a choice may take: two per substep count tried, and the
/// counts tried step up at least as fast as a fourth-order error predicts.
pub const MAX_TRIES: usize = 6;

/// One reference run's output 0 over `window` with `substeps` per sample;
/// `None` when the run is not finite there (it diverged or chattered).
pub fn output_0(
    model: &CompiledRig,
    params: &[f64],
    drive: &Drive,
    grid: &SampleGrid,
    window: &Range<usize>,
) -> Option<Vec<f64>> {
    let mut out = Vec::with_capacity(window.len());
    let mut finite = true;
    model.simulate(params, drive, grid, &mut |s| {
        if window.contains(&s.index) {
            let y = s.outputs.first().copied().unwrap_or(f64::NAN);
            if !y.is_finite() {
                finite = false;
                return ControlFlow::Break(());
            }
            out.push(y);
        }
        ControlFlow::Continue(())
    });
    (finite && out.len() == window.len()).then_some(out)
}

/// Root mean square of `a − b`.
pub fn rms_difference(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len()).max(1) as f64;
    let ss: f64 = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum();
    (ss / n).sqrt()
}

/// One run (its parameters, drive and samples) whose step is being judged.
#[derive(Debug, Clone)]
pub struct StepDoubling<'a> {
    model: &'a CompiledRig,
    params: &'a [f64],
    drive: &'a Drive,
    grid: SampleGrid,
    window: Range<usize>,
    runs: Vec<(usize, Option<Vec<f64>>)>,
    steps: f64,
}

impl<'a> StepDoubling<'a> {
    /// The run of `model` with `params` and `drive` on `grid` (its `substeps`
    /// ignored), its output 0 judged over the samples in `window`.
    pub fn new(
        model: &'a CompiledRig,
        params: &'a [f64],
        drive: &'a Drive,
        grid: SampleGrid,
        window: Range<usize>,
    ) -> Self {
        Self {
            model,
            params,
            drive,
            grid,
            window,
            runs: Vec::new(),
            steps: 0.0,
        }
    }

    /// RK4 steps of one run at `substeps` per sample, prologue included.
    pub fn steps_of(&self, substeps: usize) -> f64 {
        SampleGrid {
            substeps,
            ..self.grid
        }
        .total_steps() as f64
    }

    /// RK4 steps the reference runs have taken so far.
    pub fn steps_taken(&self) -> f64 {
        self.steps
    }

    fn run(&mut self, substeps: usize) -> Option<&[f64]> {
        if let Some(i) = self.runs.iter().position(|(n, _)| *n == substeps) {
            return self.runs[i].1.as_deref();
        }
        let grid = SampleGrid {
            substeps,
            ..self.grid
        };
        self.steps += grid.total_steps() as f64;
        let y = output_0(self.model, self.params, self.drive, &grid, &self.window);
        self.runs.push((substeps, y));
        self.runs.last().and_then(|(_, y)| y.as_deref())
    }

    /// Estimated RMS integration error of output 0 at `substeps` per sample
    /// (output 0's unit), from runs at `substeps`, twice and four times as
    /// many (see the module's notes). `None` when a run is not finite.
    pub fn error(&mut self, substeps: usize) -> Option<f64> {
        self.error_and_order(substeps).map(|(e, _)| e)
    }

    /// [`Self::error`] and the observed order of convergence it assumed
    /// (`log₂` of the ratio, ½ to 4).
    pub fn error_and_order(&mut self, substeps: usize) -> Option<(f64, f64)> {
        let finest = self.run(4 * substeps)?.to_vec();
        let fine = self.run(2 * substeps)?.to_vec();
        let coarse = self.run(substeps)?;
        let d1 = rms_difference(coarse, &fine);
        let d2 = rms_difference(&fine, &finest);
        let r = if d2 > 0.0 { d1 / d2 } else { MAX_RATIO };
        let r = r.clamp(MIN_RATIO, MAX_RATIO);
        Some((d1 * r / (r - 1.0), r.log2()))
    }

    /// The smallest substeps from `from` up to `cap` whose estimated error is
    /// at most `target` (output 0's unit), stepping up by the prediction
    /// `n·(err/target)^(1/p)` of the observed order `p`, and never taking a run
    /// of more than `max_run_steps` RK4 steps.
    pub fn choose(
        &mut self,
        from: usize,
        cap: usize,
        target: f64,
        max_run_steps: f64,
    ) -> StepChoice {
        let from = from.max(1);
        let cap = cap.max(from);
        let mut n = from;
        let mut last = None;
        for _ in 0..MAX_TRIES {
            if self.steps_of(4 * n) > max_run_steps {
                return StepChoice {
                    substeps: n,
                    error: last.filter(|(m, _)| *m == n).map(|(_, e)| e),
                    stop: StepStop::TooLong,
                };
            }
            let Some((err, order)) = self.error_and_order(n) else {
                return StepChoice {
                    substeps: n,
                    error: None,
                    stop: StepStop::NotFinite,
                };
            };
            last = Some((n, err));
            if err <= target {
                return StepChoice {
                    substeps: n,
                    error: Some(err),
                    stop: StepStop::Met,
                };
            }
            if n >= cap {
                return StepChoice {
                    substeps: n,
                    error: Some(err),
                    stop: StepStop::Cap,
                };
            }
            let predicted = (n as f64 * (err / target).powf(1.0 / order)).ceil();
            n = if predicted.is_finite() {
                (predicted as usize).clamp(n + 1, cap)
            } else {
                cap
            };
        }
        let (n, err) = last.expect("at least one try");
        StepChoice {
            substeps: n,
            error: Some(err),
            stop: StepStop::Tries,
        }
    }
}

/// How [`StepDoubling::choose`] ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StepStop {
    /// The estimated error is at most the target.
    Met,
    /// The cap was reached with the error still above the target.
    Cap,
    /// [`MAX_TRIES`] counts were tried with the error still above the target.
    Tries,
    /// A reference run would have been longer than allowed.
    TooLong,
    /// A reference run was not finite (it diverged or chattered).
    NotFinite,
}

/// The substeps [`StepDoubling::choose`] settled on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepChoice {
    /// RK4 steps per sample.
    pub substeps: usize,
    /// The estimated RMS error of output 0 at `substeps` (output 0's unit),
    /// where it was estimated.
    pub error: Option<f64>,
    /// Why the choice stopped there.
    pub stop: StepStop,
}
