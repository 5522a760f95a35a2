//! Profile likelihoods: for each fitted parameter, a grid of held values
//! across its interval and beyond, each re-optimised over the others.
//!
//! A covariance interval assumes the cost is quadratic about the optimum
//! and misses curved valleys; the profile is the honest test of
//! identifiability. Every grid point of every parameter is one
//! Levenberg–Marquardt run of the [`Polish`] holding that parameter fixed
//! (no stencil for it, so it never moves), and all of them advance together:
//! one batch through the [`ResidualCost`] per iteration, so the profiles cost
//! a few polishes, not one per point.
//!
//! - The grid (in the gene's scale) reaches `span` covariance half-widths
//!   (`1.96 σ`), or the elite's spread where wider, on each side of the
//!   optimum, cut at the bounds, `points / 2` values a side plus the optimum;
//!   each run starts from the optimum with the gene set (a warm start).
//! - The profile's `χ²(θ) = Σ_e SSR_e(θ) / s_e²`, with each block's residual
//!   variance at the optimum as the covariance takes it
//!   ([`Uncertainty::block_variances`]). The 95 % interval is where
//!   `Δχ² ≤ q = 1.96²`, the square of the covariance interval's quantile, so
//!   that on a model linear in its parameters the two agree exactly.
//! - A side the first grid does not close, short of its bound, gets a
//!   second round of `points / 2` values out to the bound, each started
//!   from the first round's outermost point on that side.
//!
//! Levenberg–Marquardt is deterministic: the profiles are a pure function
//! of the fitted point and the costs, as reproducible as the evaluator. A
//! checkpoint ([`Profiles::checkpoint_to`]) holds every run's point,
//! damping and state after each iteration; a resumed run re-linearises the
//! stored points in one batch and ends with the same bits.

mod curve;
mod settings;
mod state;

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use serde::Serialize;

pub use curve::{DISAGREE_FACTOR, LOWER_COST_TOL, ParameterProfile, ProfileFlag};
pub use settings::ProfileSettings;
pub(crate) use settings::deserialize_profiles;

use super::genes::GeneSpec;
use super::polish::{Linear, Polish, ResidualCost, Run};
use super::settings::PolishSettings;
use super::uncertainty::{Uncertainty, Z95};
use super::{PolishStop, SearchError};
use curve::{Reading, Sample, crossing, deltas};
use state::{Saved, SavedPoint, SavedRun, digest};

/// One iteration of the profiles, as an observer sees it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ProfileIteration {
    /// Iterations so far, both rounds.
    pub iteration: usize,
    /// 1: the first grid; 2: the sides it left open, out to the bounds.
    pub round: u8,
    /// Grid points still moving.
    pub moving: usize,
    /// Grid points in all.
    pub points: usize,
    /// Candidates scored so far.
    pub evaluations: u64,
    /// Wall time since the profiles began (s).
    pub elapsed_s: f64,
}

impl std::fmt::Display for ProfileIteration {
    /// The progress line: `profiles, iteration 3 (round 1): 40 of 91 points
    /// moving, 4 200 evaluations, 1.2 s`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "profiles, iteration {} (round {}): {} of {} points moving, {} evaluations, {:.1} s",
            self.iteration, self.round, self.moving, self.points, self.evaluations, self.elapsed_s
        )
    }
}

/// What the profiles return: `result.json`'s `profiles`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProfileOutcome {
    /// The settings they ran with.
    pub settings: ProfileSettings,
    /// Candidates scored (a resumed run counts its re-linearisation).
    pub evaluations: u64,
    /// Wall time (s), across resumes.
    pub wall_time_s: f64,
    /// Iterations (batches after each round's first).
    pub iterations: usize,
    /// Why they stopped: every point converged, the iteration limit, or an
    /// interrupt (the checkpoint is kept; the parameters are then partial).
    pub stop: PolishStop,
    /// Per free parameter, in genome order.
    pub parameters: Vec<ParameterProfile>,
}

impl ProfileOutcome {
    /// The warnings of every flagged parameter.
    pub fn warnings(&self) -> Vec<String> {
        self.parameters
            .iter()
            .filter_map(ParameterProfile::warning)
            .collect()
    }

    /// The verdict's short flags.
    pub fn flags(&self) -> Vec<String> {
        self.parameters
            .iter()
            .filter_map(ParameterProfile::short_flag)
            .collect()
    }
}

/// The profile likelihoods of every gene at a fitted point; see the module
/// docs.
///
/// ```
/// use rigfit::base::Scale;
/// use rigfit::search::{FnResiduals, GeneSpec, Polish, PolishSettings, ProfileSettings, Profiles};
/// // y = a + b·t with a little fixed noise: a linear model, whose profile
/// // intervals are its covariance intervals.
/// let t: Vec<f64> = (0..50).map(|k| k as f64 * 0.1).collect();
/// let y: Vec<f64> = t.iter().enumerate().map(|(k, &t)| 1.0 + 2.0 * t + 0.1 * ((k * 37 % 11) as f64 / 5.0 - 1.0)).collect();
/// let residuals = |g: &[f64]| Some(t.iter().zip(&y).map(|(&t, y)| g[0] + g[1] * t - y).collect::<Vec<f64>>());
/// let genes = vec![GeneSpec::new("a", -10.0, 10.0, Scale::Linear), GeneSpec::new("b", -10.0, 10.0, Scale::Linear)];
/// let fit = Polish::new(PolishSettings::default(), genes.clone()).run(FnResiduals(residuals), &[vec![0.0, 0.0]]).unwrap();
/// let u = fit.uncertainty.unwrap();
/// let out = Profiles::new(ProfileSettings::default(), genes).run(FnResiduals(residuals), &fit.best_genome, &u).unwrap();
/// for (p, g) in out.parameters.iter().zip(&u.genes) {
///     let [lo, hi] = p.interval.unwrap();
///     let [a, b] = g.interval_95.unwrap();
///     assert!((lo.unwrap() - a).abs() < 1e-3 * (b - a) && (hi.unwrap() - b).abs() < 1e-3 * (b - a));
///     assert!(p.flag.is_none());
/// }
/// ```
#[derive(Debug, Clone)]
pub struct Profiles {
    settings: ProfileSettings,
    polish: Polish,
    units: Vec<String>,
    elite_widths: Vec<Option<f64>>,
    checkpoint: Option<PathBuf>,
    resume: bool,
}

/// A grid point in memory.
struct Point {
    gene: usize,
    at: f64,
    round: u8,
    run: Option<Run>,
}

impl Profiles {
    /// Profiles of `genes` with `settings`, central differences of step
    /// `cbrt(ε_f64)` of each gene's scale-space range (as the polish's).
    pub fn new(settings: ProfileSettings, genes: Vec<GeneSpec>) -> Self {
        let polish = PolishSettings {
            enabled: true,
            starts: 1,
            max_iterations: settings.max_iterations,
        };
        Self {
            settings,
            polish: Polish::new(polish, genes),
            units: Vec::new(),
            elite_widths: Vec::new(),
            checkpoint: None,
            resume: false,
        }
    }

    /// Profiles with the genes and finite-difference step of `polish` (not
    /// its interrupt flag: see [`Self::interrupt`]).
    pub fn from_polish(settings: ProfileSettings, polish: &Polish) -> Self {
        Self::new(settings, polish.genes().to_vec()).relative_step(polish.step())
    }

    /// The finite-difference step ([`Polish::relative_step`]): the job's
    /// polish's.
    pub fn relative_step(mut self, step: f64) -> Self {
        self.polish = self.polish.relative_step(step);
        self
    }

    /// Stops between two iterations when `flag` is raised (the checkpoint
    /// is written first).
    pub fn interrupt(mut self, flag: Arc<AtomicBool>) -> Self {
        self.polish = self.polish.interrupt(flag);
        self
    }

    /// Each gene's unit, for the outcome.
    pub fn units(mut self, units: Vec<String>) -> Self {
        self.units = units;
        self
    }

    /// Each gene's elite spread (values, smallest and largest; `None`
    /// unknown): a grid reaches at least as far on each side as the
    /// spread is wide.
    pub fn elite_ranges(mut self, ranges: &[Option<[f64; 2]>]) -> Self {
        let genes = self.polish.genes();
        self.elite_widths = ranges
            .iter()
            .zip(genes)
            .map(|(r, g)| r.map(|[a, b]| (g.to_scaled(b) - g.to_scaled(a)).abs()))
            .collect();
        self
    }

    /// Writes the checkpoint to `path` after every iteration; with `resume`,
    /// continues from it where it exists.
    pub fn checkpoint_to(mut self, path: impl Into<PathBuf>, resume: bool) -> Self {
        self.checkpoint = Some(path.into());
        self.resume = resume;
        self
    }

    /// The profiles at `best` (values), whose uncertainty the polish gave.
    pub fn run(
        &self,
        cost: impl ResidualCost,
        best: &[f64],
        uncertainty: &Uncertainty,
    ) -> Result<ProfileOutcome, SearchError> {
        self.run_observed(cost, best, uncertainty, &mut |_| Ok(()))
    }

    /// [`Self::run`], telling `observe` after every iteration.
    pub fn run_observed(
        &self,
        mut cost: impl ResidualCost,
        best: &[f64],
        uncertainty: &Uncertainty,
        observe: &mut dyn FnMut(&ProfileIteration) -> Result<(), SearchError>,
    ) -> Result<ProfileOutcome, SearchError> {
        let started = Instant::now();
        let genes = self.polish.genes();
        let x_best = self.polish.to_scaled(best);
        let fingerprint = self.fingerprint(&x_best, uncertainty);
        let resumed = match &self.checkpoint {
            Some(path) if self.resume && path.exists() => Some(Saved::load(path, &fingerprint)?),
            _ => None,
        };
        let mut saved = Saved::stamp(fingerprint);
        let mut points;
        let before;
        let chi2_opt;
        match resumed {
            Some(s) => {
                before = f64::from_bits(s.wall_time_s);
                chi2_opt = f64::from_bits(s.chi2_opt);
                points = self.restore(&mut cost, &s.points, &mut saved.evaluations)?;
                saved.evaluations += s.evaluations;
                saved.round = s.round;
                saved.round_iterations = s.round_iterations;
                saved.iterations = s.iterations;
            }
            None => {
                before = 0.0;
                let lin = self.polish.linearise(
                    &mut cost,
                    std::slice::from_ref(&x_best),
                    &[],
                    &mut saved.evaluations,
                )?;
                let Some(lin) = lin.into_iter().next().flatten() else {
                    return Err(SearchError::Cost(
                        "the fitted point blew up: nothing to profile".into(),
                    ));
                };
                chi2_opt = chi2(&lin, uncertainty);
                let grid = self.first_grid(&x_best, uncertainty);
                points = self.start(&mut cost, grid, 1, &mut saved.evaluations)?;
            }
        }
        saved.chi2_opt = chi2_opt.to_bits();
        let q = Z95 * Z95;
        let mut stop = PolishStop::Converged;
        loop {
            while saved.round_iterations < self.settings.max_iterations {
                if self.polish.interrupted() {
                    stop = PolishStop::Interrupted;
                    break;
                }
                let moving = self.iterate(&mut cost, &mut points, &mut saved.evaluations)?;
                if moving == 0 {
                    break;
                }
                saved.iterations += 1;
                saved.round_iterations += 1;
                let elapsed_s = before + started.elapsed().as_secs_f64();
                self.save(&mut saved, &points, elapsed_s)?;
                observe(&ProfileIteration {
                    iteration: saved.iterations,
                    round: saved.round,
                    moving: points.iter().flatten_run().filter(|r| !r.done).count(),
                    points: points.len(),
                    evaluations: saved.evaluations,
                    elapsed_s,
                })?;
            }
            if stop == PolishStop::Interrupted {
                self.save(
                    &mut saved,
                    &points,
                    before + started.elapsed().as_secs_f64(),
                )?;
                break;
            }
            if saved.round == 1 {
                let more = self.extensions(&points, &x_best, chi2_opt, uncertainty, q);
                if !more.is_empty() {
                    points.extend(self.start(&mut cost, more, 2, &mut saved.evaluations)?);
                    saved.round = 2;
                    saved.round_iterations = 0;
                    self.save(
                        &mut saved,
                        &points,
                        before + started.elapsed().as_secs_f64(),
                    )?;
                    continue;
                }
            }
            break;
        }
        if stop != PolishStop::Interrupted && points.iter().flatten_run().any(|r| !r.done) {
            stop = PolishStop::MaxIterations;
        }
        let parameters = (0..genes.len())
            .map(|j| {
                let u = uncertainty.genes.get(j);
                Reading {
                    gene: &genes[j],
                    unit: self.units.get(j).cloned().unwrap_or_default(),
                    centre_at: x_best[j],
                    value: best[j],
                    chi2_opt,
                    q,
                    std_error_scaled: u.and_then(|u| u.std_error_scaled),
                    covariance_interval: u.and_then(|u| u.interval_95),
                }
                .read(samples(&points, j, uncertainty))
            })
            .collect();
        Ok(ProfileOutcome {
            settings: self.settings,
            evaluations: saved.evaluations,
            wall_time_s: before + started.elapsed().as_secs_f64(),
            iterations: saved.iterations,
            stop,
            parameters,
        })
    }

    /// What a checkpoint must agree with: the genes, the fitted point, the
    /// noise, the settings and the step.
    fn fingerprint(&self, x_best: &[f64], u: &Uncertainty) -> String {
        let bits = |v: &[f64]| {
            v.iter()
                .map(|x| format!("{:x}", x.to_bits()))
                .collect::<Vec<_>>()
        };
        digest(&format!(
            "{:?}|{:?}|{:?}|{:?}|{:?}",
            self.polish.genes(),
            bits(x_best),
            bits(&u.block_variances),
            self.settings,
            self.elite_widths,
        ))
    }

    /// The first round's grid: `(gene, held value, start)` in scale space.
    fn first_grid(&self, x_best: &[f64], u: &Uncertainty) -> Vec<(usize, f64, Vec<f64>)> {
        let left = self.settings.points / 2;
        let right = self.settings.points - left;
        let mut grid = Vec::new();
        for (j, g) in self.polish.genes().iter().enumerate() {
            let (lo, hi) = g.scaled_bounds();
            let c = x_best[j];
            let half = u
                .genes
                .get(j)
                .and_then(|u| u.std_error_scaled)
                .map(|s| self.settings.span * Z95 * s)
                .filter(|w| w.is_finite() && *w > 0.0);
            let elite = self.elite_widths.get(j).copied().flatten();
            // Out to `span` half-widths, and on to the elite's spread where
            // that is wider (half the points beyond the half-widths, so the
            // interval keeps its resolution).
            let (near, far) = match (half, elite) {
                (Some(h), Some(e)) if e > h => (h, e),
                (Some(h), _) => (h, h),
                (None, Some(e)) if e > 0.0 => (e, e),
                _ => (hi - lo, hi - lo),
            };
            let set = |at: f64| {
                let mut x = x_best.to_vec();
                x[j] = at;
                (j, at, x)
            };
            grid.extend(reach(c, -near, -far, lo, left).into_iter().rev().map(set));
            grid.push(set(c));
            grid.extend(reach(c, near, far, hi, right).into_iter().map(set));
        }
        grid
    }

    /// The second round: each side the first did not close, short of its
    /// bound, out to the bound, started from its outermost point's end.
    fn extensions(
        &self,
        points: &[Point],
        x_best: &[f64],
        chi2_opt: f64,
        u: &Uncertainty,
        q: f64,
    ) -> Vec<(usize, f64, Vec<f64>)> {
        let left = self.settings.points / 2;
        let right = self.settings.points - left;
        let mut more = Vec::new();
        for (j, g) in self.polish.genes().iter().enumerate() {
            let (lo, hi) = g.scaled_bounds();
            let mut s = samples(points, j, u);
            let (centre, delta) = deltas(&mut s, x_best[j], chi2_opt);
            let at: Vec<f64> = s.iter().map(|s| s.at).collect();
            for (right_side, bound, count) in [(false, lo, left), (true, hi, right)] {
                let outer = if right_side { at[at.len() - 1] } else { at[0] };
                if outer == bound || crossing(&at, &delta, centre, q, right_side).is_some() {
                    continue;
                }
                let from = points
                    .iter()
                    .filter(|p| p.gene == j && p.at == outer)
                    .find_map(|p| p.run.as_ref())
                    .map_or_else(|| x_best.to_vec(), |r| r.x.clone());
                for at in side(outer, bound, bound, count) {
                    let mut x = from.clone();
                    x[j] = at;
                    more.push((j, at, x));
                }
            }
        }
        more
    }

    /// New grid points of `round`, their starts linearised in one batch.
    fn start(
        &self,
        cost: &mut impl ResidualCost,
        grid: Vec<(usize, f64, Vec<f64>)>,
        round: u8,
        evaluations: &mut u64,
    ) -> Result<Vec<Point>, SearchError> {
        let xs: Vec<Vec<f64>> = grid.iter().map(|(_, _, x)| x.clone()).collect();
        let fixed: Vec<Option<usize>> = grid.iter().map(|(j, _, _)| Some(*j)).collect();
        let lins = self.polish.linearise(cost, &xs, &fixed, evaluations)?;
        Ok(grid
            .into_iter()
            .zip(lins)
            .map(|((gene, at, x), lin)| Point {
                gene,
                at,
                round,
                run: lin.map(|lin| Run::new(x, lin)),
            })
            .collect())
    }

    /// The points of a checkpoint, re-linearised in one batch.
    fn restore(
        &self,
        cost: &mut impl ResidualCost,
        saved: &[SavedPoint],
        evaluations: &mut u64,
    ) -> Result<Vec<Point>, SearchError> {
        let from = |v: &[u64]| v.iter().map(|&b| f64::from_bits(b)).collect::<Vec<f64>>();
        let live: Vec<&SavedPoint> = saved.iter().filter(|p| p.run.is_some()).collect();
        let xs: Vec<Vec<f64>> = live
            .iter()
            .filter_map(|p| p.run.as_ref().map(|r| from(&r.x)))
            .collect();
        let fixed: Vec<Option<usize>> = live.iter().map(|p| Some(p.gene)).collect();
        let mut lins = self
            .polish
            .linearise(cost, &xs, &fixed, evaluations)?
            .into_iter()
            .zip(xs);
        let mut points = Vec::with_capacity(saved.len());
        for p in saved {
            let run = match &p.run {
                Some(r) => {
                    let (lin, x) = lins.next().expect("one linearisation per live point");
                    let Some(lin) = lin else {
                        return Err(SearchError::Cost(
                            "a profile point that had a cost blew up when resumed: the \
                             evaluator does not give the same results as before"
                                .into(),
                        ));
                    };
                    let (lambda, nu) = (f64::from_bits(r.lambda), f64::from_bits(r.nu));
                    Some(Run::restore(x, lin, lambda, nu, r.done))
                }
                None => None,
            };
            points.push(Point {
                gene: p.gene,
                at: f64::from_bits(p.at),
                round: p.round,
                run,
            });
        }
        Ok(points)
    }

    /// One Levenberg–Marquardt iteration of every moving point, in one
    /// batch; returns how many moved.
    fn iterate(
        &self,
        cost: &mut impl ResidualCost,
        points: &mut [Point],
        evaluations: &mut u64,
    ) -> Result<usize, SearchError> {
        let mut moving = Vec::new();
        let mut trials = Vec::new();
        let mut fixed = Vec::new();
        for (i, p) in points.iter_mut().enumerate() {
            if let Some(run) = p.run.as_mut().filter(|r| !r.done) {
                match self.polish.trial(run) {
                    Some(t) => {
                        moving.push(i);
                        trials.push(t);
                        fixed.push(Some(p.gene));
                    }
                    None => run.done = true,
                }
            }
        }
        if trials.is_empty() {
            return Ok(0);
        }
        let lins = self.polish.linearise(cost, &trials, &fixed, evaluations)?;
        let n = moving.len();
        for ((i, x), lin) in moving.into_iter().zip(trials).zip(lins) {
            if let Some(run) = points[i].run.as_mut() {
                run.update(x, lin);
            }
        }
        Ok(n)
    }

    fn save(&self, saved: &mut Saved, points: &[Point], elapsed_s: f64) -> Result<(), SearchError> {
        let Some(path) = &self.checkpoint else {
            return Ok(());
        };
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect();
        saved.wall_time_s = elapsed_s.to_bits();
        saved.points = points
            .iter()
            .map(|p| SavedPoint {
                gene: p.gene,
                at: p.at.to_bits(),
                round: p.round,
                run: p.run.as_ref().map(|r| SavedRun {
                    x: bits(&r.x),
                    lambda: r.lambda.to_bits(),
                    nu: r.nu.to_bits(),
                    done: r.done,
                }),
            })
            .collect();
        saved.save(path)
    }
}

/// `count` values out from `c` (outwards first): evenly to `c + near`,
/// then, where `far` reaches further, half of them evenly on to `c + far`;
/// cut at `bound` ([`side`]).
fn reach(c: f64, near: f64, far: f64, bound: f64, count: usize) -> Vec<f64> {
    if far.abs() <= near.abs() {
        return side(c, c + near, bound, count);
    }
    let outer = count / 2;
    let mut v = side(c, c + near, bound, count - outer);
    if let Some(&last) = v.last()
        && last != bound
    {
        v.extend(side(last, c + far, bound, outer));
    }
    v
}

/// `count` values from `c` towards `to`, evenly spaced, the last exactly at
/// `to`, or at `bound` where `to` lies beyond it; none where `c` is at the
/// bound.
fn side(c: f64, to: f64, bound: f64, count: usize) -> Vec<f64> {
    let end = if to < c { to.max(bound) } else { to.min(bound) };
    if end == c || count == 0 {
        return Vec::new();
    }
    (1..=count)
        .map(|k| {
            if k == count {
                end
            } else {
                c + (end - c) * k as f64 / count as f64
            }
        })
        .collect()
}

/// `χ²` of a linearised point: each block's sum of squares over its
/// variance at the optimum.
fn chi2(lin: &Linear, u: &Uncertainty) -> f64 {
    if lin.blocks.len() == u.block_variances.len() {
        lin.blocks
            .iter()
            .zip(&u.block_variances)
            .map(|(b, s2)| b.ssr / s2.max(f64::MIN_POSITIVE))
            .sum()
    } else {
        lin.cost / u.residual_variance.max(f64::MIN_POSITIVE)
    }
}

/// Gene `j`'s points as the reading takes them.
fn samples(points: &[Point], j: usize, u: &Uncertainty) -> Vec<Sample> {
    points
        .iter()
        .filter(|p| p.gene == j)
        .map(|p| Sample {
            at: p.at,
            chi2: p.run.as_ref().map(|r| chi2(&r.lin, u)),
            cost: p.run.as_ref().map(|r| r.lin.cost),
            converged: p.run.as_ref().is_some_and(|r| r.done),
        })
        .collect()
}

/// The runs of the points that have one.
trait FlattenRun<'a> {
    fn flatten_run(self) -> impl Iterator<Item = &'a Run>;
}

impl<'a, I: Iterator<Item = &'a Point>> FlattenRun<'a> for I {
    fn flatten_run(self) -> impl Iterator<Item = &'a Run> {
        self.filter_map(|p| p.run.as_ref())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_side_is_cut_at_its_bound_and_ends_on_it() {
        assert_eq!(side(0.0, 3.0, 10.0, 3), vec![1.0, 2.0, 3.0]);
        assert_eq!(side(0.0, -3.0, -1.5, 3), vec![-0.5, -1.0, -1.5]);
        assert!(side(1.0, 4.0, 1.0, 3).is_empty());
        // Half the points out to the far reach, half to the near one.
        assert_eq!(
            reach(0.0, 3.0, 9.0, 100.0, 6),
            vec![1.0, 2.0, 3.0, 5.0, 7.0, 9.0]
        );
        // The near reach already at the bound: the far one adds nothing.
        assert_eq!(reach(0.0, -3.0, -9.0, -3.0, 4), vec![-1.5, -3.0]);
    }
}
