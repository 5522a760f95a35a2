//! The local polish: Levenberg–Marquardt on the residuals, from the best few
//! distinct candidates of the GA, in the genes' own scales and bounds.
//!
//! The GA finds the right basin but crawls near the optimum: on a smooth,
//! correlated valley its best cost can stay well above the noise floor after
//! hundreds of generations. A Gauss–Newton step uses the valley's shape and gets
//! to the floor in a few iterations.
//!
//! Every iteration is one batch through a [`ResidualCost`]: for each start still
//! moving, its trial point and a central-difference stencil around it,
//! `starts × (2n + 1)` candidates, so a GPU evaluator scores them together.
//! A trial that lowers the cost is accepted and its Jacobian is already at hand;
//! one that does not raises the damping and is thrown away. Everything is a
//! pure function of the starts and the costs, so the polish is as reproducible
//! as the evaluator.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use super::SearchError;
use super::genes::{GeneSpec, clamp_into, genome_values};
use super::report::SearchOutcome;
use super::settings::PolishSettings;
use super::uncertainty::{ResidualBlock, Uncertainty};

/// Residual vectors of whole batches of genomes.
pub trait ResidualCost {
    /// For each genome (values in each gene's own unit, inside its bounds), its
    /// residuals, all of the same length, whose sum of squares is the cost the
    /// search minimises; `None` for a candidate that blew up.
    fn residuals(&mut self, genomes: &[Vec<f64>]) -> Result<Vec<Option<Vec<f64>>>, SearchError>;

    /// Lengths of the consecutive blocks of a residual vector that carry noise
    /// of their own size (a campaign: one block per experiment), so that the
    /// covariance gives each block its own variance. Empty (the default): one
    /// block.
    fn blocks(&self) -> Vec<usize> {
        Vec::new()
    }
}

impl<C: ResidualCost + ?Sized> ResidualCost for &mut C {
    fn residuals(&mut self, genomes: &[Vec<f64>]) -> Result<Vec<Option<Vec<f64>>>, SearchError> {
        (**self).residuals(genomes)
    }

    fn blocks(&self) -> Vec<usize> {
        (**self).blocks()
    }
}

/// A per-genome residual closure as a [`ResidualCost`] (tests, analytic problems).
#[derive(Debug, Clone)]
pub struct FnResiduals<F>(pub F);

impl<F: FnMut(&[f64]) -> Option<Vec<f64>>> ResidualCost for FnResiduals<F> {
    fn residuals(&mut self, genomes: &[Vec<f64>]) -> Result<Vec<Option<Vec<f64>>>, SearchError> {
        Ok(genomes.iter().map(|g| (self.0)(g)).collect())
    }
}

/// Why the polish stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PolishStop {
    /// Every start converged, or could no longer catch up with the best one.
    Converged,
    /// `max_iterations` iterations were run.
    MaxIterations,
    /// The interrupt flag was raised.
    Interrupted,
    /// Every start blew up; nothing to polish.
    NoStart,
}

impl PolishStop {
    /// Whether the polish stopped short of convergence: its result may not
    /// be the optimum the intervals assume.
    pub fn short(self) -> bool {
        self != Self::Converged
    }
}

impl std::fmt::Display for PolishStop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Converged => "converged",
            Self::MaxIterations => "stopped at its iteration limit",
            Self::Interrupted => "interrupted",
            Self::NoStart => "every start blew up",
        })
    }
}

/// One start's cost before and after.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StartReport {
    /// Cost at the GA candidate.
    pub initial: f64,
    /// Cost where the polish left it.
    pub polished: f64,
    /// Where the polish left it (values); empty for a start that blew up.
    /// Not in `result.json`: the checks of the starts' agreement read it.
    #[serde(skip)]
    pub genome: Vec<f64>,
}

/// One polish iteration, as the executor's observers see it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PolishIteration {
    /// Iterations so far (1 after the first batch of trial steps).
    pub iteration: usize,
    /// Lowest cost over the starts so far.
    pub best_cost: f64,
    /// Starts still moving.
    pub moving: usize,
    /// Candidates scored so far.
    pub evaluations: u64,
    /// Wall time since the polish began (s).
    pub elapsed_s: f64,
}

/// What the polish returns.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PolishOutcome {
    /// Best genome (values).
    pub best_genome: Vec<f64>,
    /// Its cost (sum of squared residuals).
    pub best_cost: f64,
    /// Which start it came from (0: the GA's best).
    pub best_start: usize,
    /// Per start, in the order started (best GA candidate first).
    pub starts: Vec<StartReport>,
    /// Iterations (batches after the first).
    pub iterations: usize,
    /// Candidates scored.
    pub evaluations: u64,
    /// Wall time (s).
    pub wall_time_s: f64,
    /// Why it stopped.
    pub stop: PolishStop,
    /// Starts that had not converged when it stopped (0 when
    /// [`PolishStop::Converged`]).
    pub unconverged_starts: usize,
    /// Whether the start that gave the result had converged.
    pub best_converged: bool,
    /// One entry per iteration.
    pub history: Vec<PolishIteration>,
    /// Standard errors at the best genome; `None` if every start blew up.
    pub uncertainty: Option<Uncertainty>,
}

/// Levenberg–Marquardt from several starts at once; see the module docs.
///
/// ```
/// use rigfit::base::Scale;
/// use rigfit::search::{FnResiduals, GeneSpec, Polish, PolishSettings};
/// // y = a·exp(−t/τ) sampled without noise: the polish recovers a and τ.
/// let t: Vec<f64> = (0..40).map(|k| k as f64 * 0.1).collect();
/// let model = |g: &[f64], t: f64| g[0] * (-t / g[1]).exp();
/// let y: Vec<f64> = t.iter().map(|&t| model(&[2.0, 0.7], t)).collect();
/// let cost = FnResiduals(|g: &[f64]| Some(t.iter().zip(&y).map(|(&t, y)| model(g, t) - y).collect()));
/// let genes = vec![
///     GeneSpec::new("a", 0.0, 10.0, Scale::Linear),
///     GeneSpec::new("tau", 1e-2, 1e2, Scale::Log),
/// ];
/// let polish = Polish::new(PolishSettings::default(), genes);
/// let out = polish.run(cost, &[vec![1.0, 3.0]]).unwrap();
/// assert!((out.best_genome[0] - 2.0).abs() < 1e-6 && (out.best_genome[1] - 0.7).abs() < 1e-6);
/// ```
#[derive(Debug, Clone)]
pub struct Polish {
    settings: PolishSettings,
    genes: Vec<GeneSpec>,
    step: f64,
    interrupt: Option<Arc<AtomicBool>>,
}

/// Cost decrease, as a fraction of the residual variance `s²`, below which an
/// accepted step ends a start: near the optimum a move of `k` standard errors
/// changes the cost by `k² s²`, so the start is within ~3 % of a standard
/// error of where it would end.
const FTOL: f64 = 1e-3;
/// Accepted steps over which a start's pace (its largest cost decrease) is taken.
const PACE_WINDOW: usize = 3;
/// How much faster than its recent pace a start may still get (a
/// Levenberg–Marquardt start often speeds up once it is in the valley).
const PACE_MARGIN: f64 = 10.0;
/// Cosine between the residuals and every Jacobian column below which a start
/// is at a stationary point.
const GTOL: f64 = 1e-10;
/// Step, as a fraction of each gene's scale-space range, below which a start
/// has stopped moving.
const XTOL: f64 = 1e-12;
/// Damping beyond which a start gives up (no step lowers its cost).
const MAX_DAMPING: f64 = 1e16;

impl Polish {
    /// A polish of `genes` with `settings`; central differences of step
    /// `cbrt(ε_f64)` of each gene's scale-space range.
    pub fn new(settings: PolishSettings, genes: Vec<GeneSpec>) -> Self {
        Self {
            settings,
            genes,
            step: f64::EPSILON.cbrt(),
            interrupt: None,
        }
    }

    /// Finite-difference step as a fraction of each gene's scale-space range;
    /// `cbrt(ε)` of the evaluator's arithmetic balances truncation and rounding
    /// (≈ 6e-6 for f64, ≈ 5e-3 for f32).
    pub fn relative_step(mut self, step: f64) -> Self {
        self.step = step;
        self
    }

    /// Stops after the running iteration when `flag` is raised.
    pub fn interrupt(mut self, flag: Arc<AtomicBool>) -> Self {
        self.interrupt = Some(flag);
        self
    }

    /// Polishes from `starts` (values, best first) and estimates the
    /// uncertainty at the best point reached.
    pub fn run(
        &self,
        cost: impl ResidualCost,
        starts: &[Vec<f64>],
    ) -> Result<PolishOutcome, SearchError> {
        self.run_observed(cost, starts, &mut |_| Ok(()))
    }

    /// [`Self::run`], telling `observe` after every iteration (the executor's
    /// observers, when the polish runs under [`super::Executor::then_polish`]).
    pub fn run_observed(
        &self,
        mut cost: impl ResidualCost,
        starts: &[Vec<f64>],
        observe: &mut dyn FnMut(&PolishIteration) -> Result<(), SearchError>,
    ) -> Result<PolishOutcome, SearchError> {
        let started = Instant::now();
        let mut evaluations = 0u64;
        let x0: Vec<Vec<f64>> = starts.iter().map(|s| self.to_scaled(s)).collect();
        let mut runs: Vec<Option<Run>> = self
            .linearise(&mut cost, &x0, &[], &mut evaluations)?
            .into_iter()
            .zip(x0)
            .map(|(lin, x)| lin.map(|lin| Run::new(x, lin)))
            .collect();
        let initial: Vec<f64> = runs
            .iter()
            .map(|r| r.as_ref().map_or(f64::INFINITY, |r| r.lin.cost))
            .collect();
        let mut iterations = 0;
        let mut history = Vec::new();
        let mut stop = PolishStop::MaxIterations;
        for _ in 0..self.settings.max_iterations {
            if self
                .interrupt
                .as_ref()
                .is_some_and(|f| f.load(Ordering::SeqCst))
            {
                stop = PolishStop::Interrupted;
                break;
            }
            let mut moving = Vec::new();
            let mut trials = Vec::new();
            for (i, run) in runs.iter_mut().enumerate() {
                if let Some(run) = run.as_mut().filter(|r| !r.done) {
                    match self.trial(run) {
                        Some(t) => {
                            moving.push(i);
                            trials.push(t);
                        }
                        None => run.done = true,
                    }
                }
            }
            if trials.is_empty() {
                break;
            }
            let lins = self.linearise(&mut cost, &trials, &[], &mut evaluations)?;
            for ((i, x), lin) in moving.into_iter().zip(trials).zip(lins) {
                if let Some(run) = runs[i].as_mut() {
                    run.update(x, lin);
                }
            }
            iterations += 1;
            retire_the_hopeless(&mut runs, self.settings.max_iterations - iterations);
            let step = PolishIteration {
                iteration: iterations,
                best_cost: runs
                    .iter()
                    .flatten()
                    .map(|r| r.lin.cost)
                    .fold(f64::INFINITY, f64::min),
                moving: runs.iter().flatten().filter(|r| !r.done).count(),
                evaluations,
                elapsed_s: started.elapsed().as_secs_f64(),
            };
            observe(&step)?;
            history.push(step);
            if log::log_enabled!(log::Level::Debug) {
                let costs: Vec<String> = runs
                    .iter()
                    .map(|r| {
                        r.as_ref()
                            .map_or("-".into(), |r| format!("{:.6e}", r.lin.cost))
                    })
                    .collect();
                log::debug!("polish iteration {iterations}: {}", costs.join(" "));
            }
        }
        if stop != PolishStop::Interrupted && runs.iter().flatten().all(|r| r.done) {
            stop = PolishStop::Converged;
        }
        let best = runs
            .iter()
            .enumerate()
            .filter_map(|(i, r)| r.as_ref().map(|r| (i, r)))
            .min_by(|a, b| a.1.lin.cost.total_cmp(&b.1.lin.cost).then(a.0.cmp(&b.0)));
        let report = |i: usize| StartReport {
            initial: initial[i],
            polished: runs[i].as_ref().map_or(f64::INFINITY, |r| r.lin.cost),
            genome: runs[i]
                .as_ref()
                .map_or_else(Vec::new, |r| genome_values(&self.genes, &r.x)),
        };
        let starts_report = (0..runs.len()).map(report).collect();
        let unconverged_starts = runs.iter().flatten().filter(|r| !r.done).count();
        let wall_time_s = started.elapsed().as_secs_f64();
        Ok(match best {
            Some((i, run)) => PolishOutcome {
                best_genome: genome_values(&self.genes, &run.x),
                best_cost: run.lin.cost,
                best_start: i,
                starts: starts_report,
                iterations,
                evaluations,
                wall_time_s,
                stop,
                unconverged_starts,
                best_converged: run.done,
                history,
                uncertainty: Some(Uncertainty::at_blocks(&self.genes, &run.x, &run.lin.blocks)),
            },
            None => PolishOutcome {
                best_genome: starts.first().cloned().unwrap_or_default(),
                best_cost: f64::INFINITY,
                best_start: 0,
                starts: starts_report,
                iterations,
                evaluations,
                wall_time_s,
                stop: PolishStop::NoStart,
                unconverged_starts,
                best_converged: false,
                history,
                uncertainty: None,
            },
        })
    }

    /// The genes polished.
    pub(super) fn genes(&self) -> &[GeneSpec] {
        &self.genes
    }

    /// The finite-difference step ([`Self::relative_step`]).
    pub(super) fn step(&self) -> f64 {
        self.step
    }

    /// Whether the interrupt flag is raised.
    pub(super) fn interrupted(&self) -> bool {
        self.interrupt
            .as_ref()
            .is_some_and(|f| f.load(Ordering::SeqCst))
    }

    pub(super) fn to_scaled(&self, values: &[f64]) -> Vec<f64> {
        self.genes
            .iter()
            .zip(values)
            .map(|(g, &v)| {
                let (lo, hi) = g.scaled_bounds();
                clamp_into(g.to_scaled(v), lo, hi)
            })
            .collect()
    }

    /// The secant interval `[a, b] ∋ x` of gene `j`: `x ± h`, cut at the bounds.
    fn stencil(&self, j: usize, x: f64) -> (f64, f64) {
        let (lo, hi) = self.genes[j].scaled_bounds();
        let h = self.step * (hi - lo);
        ((x - h).max(lo), (x + h).min(hi))
    }

    /// The genes whose stencil a point with gene `fixed` held scores.
    fn stenciled(&self, fixed: Option<usize>) -> impl Iterator<Item = usize> {
        (0..self.genes.len()).filter(move |&j| Some(j) != fixed)
    }

    /// Scores each point and its stencil in one batch; returns each point's
    /// cost, `JᵀJ` and `Jᵀr`, or `None` where the point itself blew up.
    /// `fixed[i]` (missing: none) is a gene point `i` holds: it gets no
    /// stencil and a zero Jacobian column, so [`Self::trial`] never moves it.
    pub(super) fn linearise(
        &self,
        cost: &mut impl ResidualCost,
        points: &[Vec<f64>],
        fixed: &[Option<usize>],
        evaluations: &mut u64,
    ) -> Result<Vec<Option<Linear>>, SearchError> {
        let n = self.genes.len();
        let held = |i: usize| fixed.get(i).copied().flatten();
        let mut batch = Vec::with_capacity(points.len() * (2 * n + 1));
        for (i, x) in points.iter().enumerate() {
            batch.push(x.clone());
            for j in self.stenciled(held(i)) {
                let (a, b) = self.stencil(j, x[j]);
                for s in [a, b] {
                    let mut y = x.clone();
                    y[j] = s;
                    batch.push(y);
                }
            }
        }
        let values: Vec<Vec<f64>> = batch
            .iter()
            .map(|y| genome_values(&self.genes, y))
            .collect();
        let res = cost.residuals(&values)?;
        let blocks = cost.blocks();
        if res.len() != values.len() {
            return Err(SearchError::CostLength {
                expected: values.len(),
                found: res.len(),
            });
        }
        *evaluations += values.len() as u64;
        let mut rest = &res[..];
        let mut lins = Vec::with_capacity(points.len());
        for (i, x) in points.iter().enumerate() {
            let (r, tail) = rest.split_at(1 + 2 * self.stenciled(held(i)).count());
            rest = tail;
            lins.push(self.linear(r, x, held(i), &blocks));
        }
        Ok(lins)
    }

    fn linear(
        &self,
        r: &[Option<Vec<f64>>],
        x: &[f64],
        fixed: Option<usize>,
        blocks: &[usize],
    ) -> Option<Linear> {
        let n = self.genes.len();
        let r0 = r[0].as_ref()?;
        let m = r0.len();
        let mut jac = DMatrix::zeros(m, n);
        for (p, j) in self.stenciled(fixed).enumerate() {
            let (a, b) = self.stencil(j, x[j]);
            // A gene with an empty range, or a stencil run that blew up,
            // leaves its column at zero: the step does not move it.
            if let (Some(ra), Some(rb)) = (&r[1 + 2 * p], &r[2 + 2 * p])
                && b > a
                && ra.len() == m
                && rb.len() == m
            {
                for k in 0..m {
                    jac[(k, j)] = (rb[k] - ra[k]) / (b - a);
                }
            }
        }
        let rv = DVector::from_column_slice(r0);
        // Blocks that do not tile the residuals (a cost that does not know
        // them) count as one.
        let lengths = if blocks.iter().sum::<usize>() == m && !blocks.is_empty() {
            blocks.to_vec()
        } else {
            vec![m]
        };
        let mut start = 0;
        let blocks = lengths
            .into_iter()
            .map(|len| {
                let rows = jac.rows(start, len);
                let ssr = r0[start..start + len].iter().map(|v| v * v).sum();
                start += len;
                ResidualBlock {
                    jtj: rows.tr_mul(&rows),
                    ssr,
                    residuals: len,
                }
            })
            .collect();
        Some(Linear {
            cost: r0.iter().map(|v| v * v).sum(),
            jtj: jac.tr_mul(&jac),
            jtr: jac.tr_mul(&rv),
            residuals: m,
            blocks,
        })
    }

    /// The damped Gauss–Newton step from `run`, projected into the bounds;
    /// `None` when the start has converged or cannot move.
    pub(super) fn trial(&self, run: &mut Run) -> Option<Vec<f64>> {
        let n = self.genes.len();
        let (a, g) = (run.lin.jtj.clone(), run.lin.jtr.clone());
        if run.lin.cost <= 0.0 {
            return None;
        }
        let bounds: Vec<(f64, f64)> = self.genes.iter().map(GeneSpec::scaled_bounds).collect();
        // Stationary: every column is (nearly) orthogonal to the residuals.
        let gnorm = (0..n)
            .filter(|&i| a[(i, i)] > 0.0)
            .map(|i| g[i].abs() / (a[(i, i)] * run.lin.cost).sqrt())
            .fold(0.0_f64, f64::max);
        if gnorm <= GTOL {
            return None;
        }
        // A gene at a bound that the descent direction pushes outwards stays.
        let free: Vec<usize> = (0..n)
            .filter(|&i| {
                let (lo, hi) = bounds[i];
                a[(i, i)] > 0.0
                    && !(run.x[i] <= lo && g[i] > 0.0)
                    && !(run.x[i] >= hi && g[i] < 0.0)
            })
            .collect();
        if free.is_empty() {
            return None;
        }
        while run.lambda <= MAX_DAMPING {
            let k = free.len();
            let m = DMatrix::from_fn(k, k, |p, q| {
                let v = a[(free[p], free[q])];
                if p == q { v * (1.0 + run.lambda) } else { v }
            });
            let rhs = DVector::from_fn(k, |p, _| -g[free[p]]);
            let Some(delta) = m.cholesky().map(|c| c.solve(&rhs)) else {
                run.raise_damping();
                continue;
            };
            let mut x = run.x.clone();
            for (p, &i) in free.iter().enumerate() {
                x[i] = clamp_into(run.x[i] + delta[p], bounds[i].0, bounds[i].1);
            }
            let d = DVector::from_fn(n, |i, _| x[i] - run.x[i]);
            let moved = (0..n)
                .map(|i| d[i].abs() / (bounds[i].1 - bounds[i].0).max(f64::MIN_POSITIVE))
                .fold(0.0_f64, f64::max);
            if moved <= XTOL {
                return None;
            }
            run.predicted = -(2.0 * d.dot(&g) + d.dot(&(&a * &d)));
            return Some(x);
        }
        None
    }
}

/// A point's cost and its linearisation.
#[derive(Debug, Clone)]
pub(super) struct Linear {
    pub(super) cost: f64,
    jtj: DMatrix<f64>,
    jtr: DVector<f64>,
    residuals: usize,
    /// `JᵀJ` and the residuals' sum of squares block by block (for the
    /// covariance).
    pub(super) blocks: Vec<ResidualBlock>,
}

/// One start's Levenberg–Marquardt state (Nielsen's damping update).
#[derive(Debug, Clone)]
pub(super) struct Run {
    pub(super) x: Vec<f64>,
    pub(super) lin: Linear,
    pub(super) lambda: f64,
    pub(super) nu: f64,
    predicted: f64,
    pub(super) done: bool,
    /// Cost decreases of the last [`PACE_WINDOW`] accepted steps.
    decreases: Vec<f64>,
}

/// Ends every start that could not reach the best start's cost in the
/// iterations left even at [`PACE_MARGIN`] times its recent pace: a start
/// crawling along a worse valley would otherwise take up every remaining batch.
fn retire_the_hopeless(runs: &mut [Option<Run>], left: usize) {
    let best = runs
        .iter()
        .flatten()
        .map(|r| r.lin.cost)
        .fold(f64::INFINITY, f64::min);
    for run in runs.iter_mut().flatten().filter(|r| !r.done) {
        if run.decreases.len() >= PACE_WINDOW {
            let pace = run.decreases.iter().fold(0.0_f64, |m, &d| m.max(d));
            if run.lin.cost - best > PACE_MARGIN * left as f64 * pace {
                run.done = true;
            }
        }
    }
}

impl Run {
    pub(super) fn new(x: Vec<f64>, lin: Linear) -> Self {
        Self::restore(x, lin, 1e-3, 2.0, false)
    }

    /// A run as a checkpoint left it: its point (re-linearised), damping
    /// and whether it had ended. Its pace is not kept: only the polish's
    /// retiring of hopeless starts reads it.
    pub(super) fn restore(x: Vec<f64>, lin: Linear, lambda: f64, nu: f64, done: bool) -> Self {
        Self {
            x,
            lin,
            lambda,
            nu,
            predicted: 0.0,
            done,
            decreases: Vec::new(),
        }
    }

    fn remember(&mut self, decrease: f64) {
        if self.decreases.len() == PACE_WINDOW {
            self.decreases.remove(0);
        }
        self.decreases.push(decrease);
    }

    fn raise_damping(&mut self) {
        self.lambda *= self.nu;
        self.nu *= 2.0;
    }

    /// Takes the trial `x` if it lowered the cost.
    pub(super) fn update(&mut self, x: Vec<f64>, lin: Option<Linear>) {
        match lin {
            Some(lin) if lin.cost < self.lin.cost && self.predicted > 0.0 => {
                let actual = self.lin.cost - lin.cost;
                let rho = actual / self.predicted;
                self.lambda *= (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
                self.nu = 2.0;
                let s2 = lin.cost / lin.residuals.max(1) as f64;
                self.done = actual <= FTOL * s2;
                self.remember(actual);
                self.x = x;
                self.lin = lin;
            }
            _ => {
                self.raise_damping();
                self.done = self.lambda > MAX_DAMPING;
            }
        }
    }
}

/// Up to `k` starts for the polish: the GA's best, then the final population
/// in cost order, skipping any candidate within 0.1 % of a gene's
/// scale-space range of one already taken (in every gene).
pub fn distinct_starts(genes: &[GeneSpec], outcome: &SearchOutcome, k: usize) -> Vec<Vec<f64>> {
    let scaled =
        |v: &[f64]| -> Vec<f64> { genes.iter().zip(v).map(|(g, &x)| g.to_scaled(x)).collect() };
    let ranges: Vec<f64> = genes
        .iter()
        .map(|g| {
            let (lo, hi) = g.scaled_bounds();
            hi - lo
        })
        .collect();
    let mut taken: Vec<Vec<f64>> = Vec::new();
    let mut starts = Vec::new();
    for (cand, cost) in std::iter::once((&outcome.best_genome, outcome.best_cost))
        .chain(outcome.population.iter().zip(outcome.costs.iter().copied()))
    {
        if starts.len() >= k {
            break;
        }
        if super::report::is_diverged(cost) {
            continue;
        }
        let x = scaled(cand);
        let near = |y: &Vec<f64>| {
            x.iter()
                .zip(y)
                .zip(&ranges)
                .all(|((a, b), r)| (a - b).abs() <= 1e-3 * r)
        };
        if !taken.iter().any(near) {
            taken.push(x);
            starts.push(cand.clone());
        }
    }
    starts
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::base::Scale;

    fn decay(g: &[f64], t: f64) -> f64 {
        g[0] * (-t / g[1]).exp() + g[2]
    }

    fn genes() -> Vec<GeneSpec> {
        vec![
            GeneSpec::new("a", 0.0, 10.0, Scale::Linear),
            GeneSpec::new("tau", 1e-2, 1e2, Scale::Log),
            GeneSpec::new("c", -1.0, 1.0, Scale::Linear),
        ]
    }

    /// A noisy decay; the noise is a fixed deterministic sequence.
    fn data() -> (Vec<f64>, Vec<f64>) {
        let t: Vec<f64> = (0..200).map(|k| k as f64 * 0.02).collect();
        let y = t
            .iter()
            .enumerate()
            .map(|(k, &t)| {
                decay(&[2.0, 0.7, 0.1], t) + 0.01 * ((k * 7919 % 200) as f64 / 100.0 - 1.0)
            })
            .collect();
        (t, y)
    }

    fn residuals(t: &[f64], y: &[f64]) -> impl FnMut(&[f64]) -> Option<Vec<f64>> {
        let (t, y) = (t.to_vec(), y.to_vec());
        move |g| Some(t.iter().zip(&y).map(|(&t, y)| decay(g, t) - y).collect())
    }

    #[test]
    fn reaches_the_least_squares_optimum_from_far_away() {
        let (t, y) = data();
        let polish = Polish::new(PolishSettings::default(), genes());
        let out = polish
            .run(
                FnResiduals(residuals(&t, &y)),
                &[vec![9.0, 30.0, -0.8], vec![0.5, 0.05, 0.5]],
            )
            .unwrap();
        assert_eq!(out.stop, PolishStop::Converged);
        // At the optimum the gradient vanishes: no coordinate move lowers the cost.
        let mut f = residuals(&t, &y);
        let mut ssr = |g: &[f64]| f(g).unwrap().iter().map(|r| r * r).sum::<f64>();
        for j in 0..3 {
            for s in [-1e-4, 1e-4] {
                let mut g = out.best_genome.clone();
                g[j] *= 1.0 + s;
                assert!(ssr(&g) >= out.best_cost, "gene {j} {s}");
            }
        }
        let u = out.uncertainty.unwrap();
        for (g, truth) in u.genes.iter().zip([2.0, 0.7, 0.1]) {
            let [lo, hi] = g.interval_95.unwrap();
            assert!(
                lo < truth && truth < hi,
                "{}: [{lo}, {hi}] ∌ {truth}",
                g.name
            );
            assert!(g.determined);
        }
    }

    #[test]
    fn stays_inside_the_bounds() {
        let (t, y) = data();
        // The optimum's offset 0.1 lies outside [-1, 0]: the polish stops at 0.
        let mut gs = genes();
        gs[2] = GeneSpec::new("c", -1.0, 0.0, Scale::Linear);
        let out = Polish::new(PolishSettings::default(), gs)
            .run(FnResiduals(residuals(&t, &y)), &[vec![1.0, 1.0, -0.5]])
            .unwrap();
        assert_eq!(out.best_genome[2], 0.0);
        assert!(out.best_genome[0] > 0.0 && out.best_genome[1] >= 1e-2);
    }

    #[test]
    fn blown_up_starts_are_skipped_and_the_batches_have_the_stated_size() {
        let (t, y) = data();
        let mut inner = residuals(&t, &y);
        let mut sizes = Vec::new();
        struct Counting<'a, F>(F, &'a mut Vec<usize>);
        impl<F: FnMut(&[f64]) -> Option<Vec<f64>>> ResidualCost for Counting<'_, F> {
            fn residuals(
                &mut self,
                genomes: &[Vec<f64>],
            ) -> Result<Vec<Option<Vec<f64>>>, SearchError> {
                self.1.push(genomes.len());
                Ok(genomes.iter().map(|g| (self.0)(g)).collect())
            }
        }
        let cost = Counting(
            |g: &[f64]| if g[0] > 8.0 { None } else { inner(g) },
            &mut sizes,
        );
        let out = Polish::new(PolishSettings::default(), genes())
            .run(cost, &[vec![9.0, 1.0, 0.0], vec![1.0, 1.0, 0.0]])
            .unwrap();
        assert_eq!(out.best_start, 1);
        assert!(out.starts[0].initial.is_infinite());
        assert_eq!(sizes[0], 2 * 7);
        assert!(sizes[1..].iter().all(|&s| s == 7), "{sizes:?}");
    }

    #[test]
    fn zero_iterations_only_estimate_the_uncertainty() {
        let (t, y) = data();
        let settings = PolishSettings {
            max_iterations: 0,
            ..PolishSettings::default()
        };
        let start = vec![2.1, 0.69, 0.1];
        let out = Polish::new(settings, genes())
            .run(FnResiduals(residuals(&t, &y)), std::slice::from_ref(&start))
            .unwrap();
        for (a, b) in out.best_genome.iter().zip(&start) {
            assert!((a / b - 1.0).abs() < 1e-14);
        }
        assert_eq!(out.iterations, 0);
        assert!(out.uncertainty.is_some());
    }
}
