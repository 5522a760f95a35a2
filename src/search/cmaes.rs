//! CMA-ES, the covariance matrix adaptation evolution strategy (Hansen and
//! Ostermeier, "Completely derandomized self-adaptation in evolution
//! strategies", 2001; the parameter settings of Hansen, "The CMA Evolution
//! Strategy: A Tutorial", 2016), with restarts of growing population (Auger
//! and Hansen, "A restart CMA evolution strategy with increasing population
//! size", 2005) as an option.
//!
//! Where the GA samples the box blindly, CMA-ES learns the shape of the cost's
//! valley — the correlated pairs a rig's parameters form (a load cell's
//! stiffness and damping trading off against each other) — and samples along
//! it.
//!
//! **Coordinates.** The strategy moves in each gene's scale space (its value,
//! or its logarithm for a log gene) divided by the gene's range, so that every
//! coordinate runs over `[0, 1]` and one step size `σ` means the same share of
//! every range.
//!
//! **Bounds.** A sample outside the box is reflected into it (as a mirror at
//! each face, repeated), so no candidate is ever scored outside the bounds.
//! The strategy learns from the point it scored: its step from the mean is
//! clipped in the strategy's own metric to `√n + 2n/(n + 2)`, the rule for
//! injected solutions (Hansen, "Injecting external solutions into CMA-ES",
//! 2011), so that a reflected point cannot drag the covariance along the face.
//!
//! **Batches.** The population `λ` is the campaign's `population`, so a batch
//! fills the evaluator as the GA's generation does; the recombination weights
//! and learning rates follow from `λ` and the number of genes by the
//! tutorial's defaults.
//!
//! **Reproducible.** Every draw comes from the executor's RNG in a fixed order
//! (per candidate, per coordinate: Box–Muller pairs); the eigendecomposition is
//! recomputed from the stored covariance, so a resumed search continues to the
//! same bits.

use nalgebra::{DMatrix, DVector, SymmetricEigen};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};

use super::SearchError;
use super::checkpoint::Fingerprint;
use super::genes::{GeneSpec, clamp_into};
use super::methods::Method;
use super::report::{TerminationReason, ranking};
use super::settings::{SearchSettings, SettingsError};
use super::solver::Solver;

/// The campaign's `"search": {"cmaes": {…}}` object.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CmaesSettings {
    /// First step size, as a share of every gene's range in scale space
    /// (default 0.3).
    #[serde(default = "default_sigma0")]
    pub sigma0: f64,
    /// Restarts with a larger population once a run converges (IPOP; default
    /// 0: a converged run ends the search).
    #[serde(default)]
    pub restarts: usize,
    /// Factor by which each restart multiplies the population (default 2).
    #[serde(default = "default_increase")]
    pub population_increase: f64,
    /// A run ends once its step, times each coordinate's spread, is below
    /// this share of the range (default 1e-11).
    #[serde(default = "default_tol_x")]
    pub tol_x: f64,
    /// A run ends once its recent best costs and its batch's costs span less
    /// than this share of the best cost (default 1e-10).
    #[serde(default = "default_tol_fun")]
    pub tol_fun: f64,
}

fn default_sigma0() -> f64 {
    0.3
}
fn default_increase() -> f64 {
    2.0
}
fn default_tol_x() -> f64 {
    1e-11
}
fn default_tol_fun() -> f64 {
    1e-10
}

impl Default for CmaesSettings {
    fn default() -> Self {
        Self {
            sigma0: default_sigma0(),
            restarts: 0,
            population_increase: default_increase(),
            tol_x: default_tol_x(),
            tol_fun: default_tol_fun(),
        }
    }
}

impl CmaesSettings {
    /// Whether every setting is its default (the campaign then need not
    /// write the object).
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }

    /// Checks each setting's range.
    pub fn validate(&self) -> Result<(), SettingsError> {
        let err = |field, expected: &str, found: f64| {
            Err(SettingsError {
                field,
                expected: expected.into(),
                found: found.to_string(),
            })
        };
        if !(self.sigma0 > 0.0 && self.sigma0 <= 1.0) {
            return err(
                "cmaes.sigma0",
                "a share of the range in (0, 1]",
                self.sigma0,
            );
        }
        if !(self.population_increase >= 1.0 && self.population_increase <= 10.0) {
            let found = self.population_increase;
            return err("cmaes.population_increase", "a factor in [1, 10]", found);
        }
        if self.restarts > 20 {
            let found = self.restarts as f64;
            return err("cmaes.restarts", "at most 20", found);
        }
        if !(self.tol_x > 0.0 && self.tol_x.is_finite()) {
            return err("cmaes.tol_x", "a value > 0", self.tol_x);
        }
        if !(self.tol_fun >= 0.0 && self.tol_fun.is_finite()) {
            return err("cmaes.tol_fun", "a value ≥ 0", self.tol_fun);
        }
        Ok(())
    }
}

/// Largest population a restart grows to: a bound on the batch, not a
/// setting a campaign reaches in practice.
const MAX_POPULATION: usize = 1 << 22;

/// A condition number of the covariance beyond which a run ends.
const MAX_CONDITION: f64 = 1e14;

/// One run of the strategy (a restart begins a new one), in the normalised
/// coordinates.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct Run {
    /// Population λ.
    lambda: usize,
    /// Mean.
    mean: Vec<f64>,
    /// Step size σ.
    sigma: f64,
    /// Covariance C, row by row.
    cov: Vec<f64>,
    /// Evolution path of σ.
    p_sigma: Vec<f64>,
    /// Evolution path of C.
    p_c: Vec<f64>,
    /// Generations of this run.
    generation: usize,
    /// Best cost of each recent generation (the last `tol_fun_window`).
    recent_best: Vec<f64>,
}

/// The strategy's state between two batches.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct State {
    run: Run,
    /// Restarts made so far.
    restarts: usize,
    /// Why each ended run ended, in order.
    stops: Vec<String>,
    /// Whether the last run ended with no restart left.
    finished: bool,
    /// The last batch (scale space) and its costs.
    population: Vec<Vec<f64>>,
    costs: Vec<f64>,
}

/// The batch in hand: the normalised points asked for, the same points in
/// scale space, and the covariance's axes they were drawn along (which the
/// update reuses: the covariance does not change between ask and tell).
#[derive(Debug, Clone, Default)]
struct Asked {
    unit: Vec<Vec<f64>>,
    scaled: Vec<Vec<f64>>,
    axes: Option<(DMatrix<f64>, DVector<f64>)>,
}

/// CMA-ES over a fixed set of genes.
#[derive(Debug, Clone)]
pub struct Cmaes {
    settings: SearchSettings,
    genes: Vec<GeneSpec>,
    bounds: Vec<(f64, f64)>,
    state: State,
    asked: Asked,
}

impl Cmaes {
    /// Checks the settings and genes; the first run starts at the genes'
    /// starting guesses (the middle of the range in scale space where a gene
    /// has none) with step `sigma0`.
    pub fn new(settings: &SearchSettings, genes: Vec<GeneSpec>) -> Result<Self, SearchError> {
        let invalid = |field, reason: String| SearchError::InvalidSettings { field, reason };
        if genes.is_empty() {
            return Err(invalid("genes", "no free parameters to search".into()));
        }
        for g in &genes {
            g.validate()?;
        }
        if settings.population < 4 {
            let found = settings.population;
            return Err(invalid(
                "population",
                format!("need at least 4, found {found}"),
            ));
        }
        if settings.generations < 1 {
            return Err(invalid("generations", "need at least 1".into()));
        }
        settings.cmaes.validate().map_err(|e| {
            invalid(
                e.field,
                format!("expected {}, found {}", e.expected, e.found),
            )
        })?;
        let bounds: Vec<(f64, f64)> = genes.iter().map(GeneSpec::scaled_bounds).collect();
        let start: Vec<f64> = genes
            .iter()
            .zip(&bounds)
            .map(|(g, &(lo, hi))| match g.init {
                Some(v) if hi > lo => clamp_into((g.to_scaled(v) - lo) / (hi - lo), 0.0, 1.0),
                _ => 0.5,
            })
            .collect();
        let run = Run::new(settings.population, start, settings.cmaes.sigma0);
        Ok(Self {
            settings: settings.clone(),
            genes,
            bounds,
            state: State {
                run,
                restarts: 0,
                stops: Vec::new(),
                finished: false,
                population: Vec::new(),
                costs: Vec::new(),
            },
            asked: Asked::default(),
        })
    }

    /// The population of the last restart `settings` allow: the largest
    /// batch the strategy asks for.
    pub fn largest_population(settings: &SearchSettings) -> usize {
        let c = &settings.cmaes;
        let mut lambda = settings.population.max(4);
        for _ in 0..c.restarts {
            lambda = grown(lambda, c.population_increase);
        }
        lambda
    }

    fn dim(&self) -> usize {
        self.genes.len()
    }

    /// A normalised point in scale space.
    fn to_scaled(&self, unit: &[f64]) -> Vec<f64> {
        unit.iter()
            .zip(&self.bounds)
            .map(|(&u, &(lo, hi))| clamp_into(lo + u * (hi - lo), lo, hi))
            .collect()
    }

    /// Ends the run that just stopped for `why`: a restart with a larger
    /// population from a uniform point, or the end of the search.
    fn end_run(&mut self, rng: &mut ChaCha8Rng, why: &str) {
        self.state.stops.push(why.to_string());
        if self.state.restarts >= self.settings.cmaes.restarts {
            self.state.finished = true;
            return;
        }
        self.state.restarts += 1;
        let lambda = grown(
            self.state.run.lambda,
            self.settings.cmaes.population_increase,
        );
        let start: Vec<f64> = (0..self.dim()).map(|_| rng.random::<f64>()).collect();
        self.state.run = Run::new(lambda, start, self.settings.cmaes.sigma0);
    }
}

/// The population after a restart from one of `lambda`.
fn grown(lambda: usize, increase: f64) -> usize {
    ((lambda as f64 * increase).round() as usize).clamp(4, MAX_POPULATION)
}

/// The learning rates and weights of a run of `lambda` in `n` dimensions
/// (the tutorial's defaults).
struct Rates {
    weights: Vec<f64>,
    mu_eff: f64,
    c_sigma: f64,
    d_sigma: f64,
    c_c: f64,
    c_1: f64,
    c_mu: f64,
    chi_n: f64,
}

impl Rates {
    fn new(n: usize, lambda: usize) -> Self {
        let nf = n as f64;
        let mu = (lambda / 2).max(1);
        let raw: Vec<f64> = (0..mu)
            .map(|i| ((lambda as f64 + 1.0) / 2.0).ln() - ((i + 1) as f64).ln())
            .collect();
        let sum: f64 = raw.iter().sum();
        let weights: Vec<f64> = raw.iter().map(|w| w / sum).collect();
        let mu_eff = 1.0 / weights.iter().map(|w| w * w).sum::<f64>();
        let c_sigma = (mu_eff + 2.0) / (nf + mu_eff + 5.0);
        let d_sigma = 1.0 + 2.0 * (((mu_eff - 1.0) / (nf + 1.0)).sqrt() - 1.0).max(0.0) + c_sigma;
        let c_c = (4.0 + mu_eff / nf) / (nf + 4.0 + 2.0 * mu_eff / nf);
        let c_1 = 2.0 / ((nf + 1.3).powi(2) + mu_eff);
        let c_mu =
            (1.0 - c_1).min(2.0 * (mu_eff - 2.0 + 1.0 / mu_eff) / ((nf + 2.0).powi(2) + mu_eff));
        let chi_n = nf.sqrt() * (1.0 - 1.0 / (4.0 * nf) + 1.0 / (21.0 * nf * nf));
        Self {
            weights,
            mu_eff,
            c_sigma,
            d_sigma,
            c_c,
            c_1,
            c_mu,
            chi_n,
        }
    }
}

impl Run {
    fn new(lambda: usize, mean: Vec<f64>, sigma: f64) -> Self {
        let n = mean.len();
        let cov = DMatrix::<f64>::identity(n, n).as_slice().to_vec();
        Self {
            lambda,
            mean,
            sigma,
            cov,
            p_sigma: vec![0.0; n],
            p_c: vec![0.0; n],
            generation: 0,
            recent_best: Vec::new(),
        }
    }

    fn cov(&self) -> DMatrix<f64> {
        let n = self.mean.len();
        DMatrix::from_column_slice(n, n, &self.cov)
    }

    /// `C = B diag(d²) Bᵀ`: the eigenvectors and the axes' lengths `d`.
    fn axes(&self) -> (DMatrix<f64>, DVector<f64>) {
        let eig = SymmetricEigen::new(self.cov());
        let d = eig.eigenvalues.map(|l| l.max(1e-300).sqrt());
        (eig.eigenvectors, d)
    }

    /// Generations of recent best costs the flat-cost test looks back over.
    fn window(&self) -> usize {
        let n = self.mean.len() as f64;
        10 + (30.0 * n / self.lambda as f64).ceil() as usize
    }
}

/// `t` reflected into `[0, 1]` by mirrors at 0 and 1.
fn reflect(t: f64) -> f64 {
    if !t.is_finite() {
        return 0.5;
    }
    let r = t.rem_euclid(2.0);
    if r > 1.0 { 2.0 - r } else { r }
}

/// A standard normal deviate pair by Box–Muller, two uniforms per pair.
fn normal_pair(rng: &mut ChaCha8Rng) -> (f64, f64) {
    let u1 = 1.0 - rng.random::<f64>();
    let u2: f64 = rng.random();
    let r = (-2.0 * u1.ln()).sqrt();
    let a = std::f64::consts::TAU * u2;
    (r * a.cos(), r * a.sin())
}

impl Solver for Cmaes {
    fn method(&self) -> Method {
        Method::Cmaes
    }

    fn settings(&self) -> &SearchSettings {
        &self.settings
    }

    fn genes(&self) -> &[GeneSpec] {
        &self.genes
    }

    fn bounds(&self) -> &[(f64, f64)] {
        &self.bounds
    }

    fn fingerprint(&self, fp: &mut Fingerprint) {
        fp.insert_json("search.cmaes", &self.settings.cmaes);
    }

    fn ask(&mut self, rng: &mut ChaCha8Rng) -> &[Vec<f64>] {
        let run = &self.state.run;
        let n = self.dim();
        let (b, d) = run.axes();
        let mut unit = Vec::with_capacity(run.lambda);
        let mut z = vec![0.0; n];
        for _ in 0..run.lambda {
            for pair in z.chunks_mut(2) {
                let (a, c) = normal_pair(rng);
                pair[0] = a;
                if pair.len() > 1 {
                    pair[1] = c;
                }
            }
            let scaled_z = DVector::from_iterator(n, (0..n).map(|i| d[i] * z[i]));
            let y = &b * scaled_z;
            let point: Vec<f64> = (0..n)
                .map(|i| reflect(run.mean[i] + run.sigma * y[i]))
                .collect();
            unit.push(point);
        }
        let scaled = unit.iter().map(|u| self.to_scaled(u)).collect();
        self.asked = Asked {
            unit,
            scaled,
            axes: Some((b, d)),
        };
        &self.asked.scaled
    }

    fn tell(&mut self, rng: &mut ChaCha8Rng, costs: &[f64]) {
        let asked = std::mem::take(&mut self.asked);
        let n = self.dim();
        let nf = n as f64;
        let run = &mut self.state.run;
        let rates = Rates::new(n, run.lambda);
        let (b, d) = asked.axes.unwrap_or_else(|| run.axes());
        let inv_sqrt = &b * DMatrix::from_diagonal(&d.map(|x| 1.0 / x)) * b.transpose();
        let mean = DVector::from_column_slice(&run.mean);
        let clip = nf.sqrt() + 2.0 * nf / (nf + 2.0);
        // Steps from the mean to each scored point, clipped in the
        // strategy's metric (a reflected point counts as an injected one).
        let steps: Vec<DVector<f64>> = asked
            .unit
            .iter()
            .map(|u| {
                let y = (DVector::from_column_slice(u) - &mean) / run.sigma;
                let norm = (&inv_sqrt * &y).norm();
                if norm > clip { y * (clip / norm) } else { y }
            })
            .collect();
        let order = ranking(costs);
        let mut y_w = DVector::<f64>::zeros(n);
        for (w, &i) in rates.weights.iter().zip(&order) {
            y_w += &steps[i] * *w;
        }
        let new_mean = &mean + &y_w * run.sigma;
        let cs = rates.c_sigma;
        let p_sigma = DVector::from_column_slice(&run.p_sigma) * (1.0 - cs)
            + (&inv_sqrt * &y_w) * (cs * (2.0 - cs) * rates.mu_eff).sqrt();
        let generations = (run.generation + 1) as f64;
        let norm_ps = p_sigma.norm();
        let h_sigma = norm_ps / (1.0 - (1.0 - cs).powf(2.0 * generations)).sqrt()
            < (1.4 + 2.0 / (nf + 1.0)) * rates.chi_n;
        let h = if h_sigma { 1.0 } else { 0.0 };
        let cc = rates.c_c;
        let p_c = DVector::from_column_slice(&run.p_c) * (1.0 - cc)
            + &y_w * (h * (cc * (2.0 - cc) * rates.mu_eff).sqrt());
        let mut rank_mu = DMatrix::<f64>::zeros(n, n);
        for (w, &i) in rates.weights.iter().zip(&order) {
            rank_mu += (&steps[i] * steps[i].transpose()) * *w;
        }
        let keep = 1.0 - rates.c_1 - rates.c_mu + (1.0 - h) * rates.c_1 * cc * (2.0 - cc);
        let cov = run.cov() * keep + (&p_c * p_c.transpose()) * rates.c_1 + rank_mu * rates.c_mu;
        let cov = (&cov + cov.transpose()) * 0.5;
        let sigma = run.sigma * ((cs / rates.d_sigma) * (norm_ps / rates.chi_n - 1.0)).exp();
        run.mean = new_mean.iter().map(|&m| m.clamp(0.0, 1.0)).collect();
        run.sigma = sigma;
        run.cov = cov.as_slice().to_vec();
        run.p_sigma = p_sigma.as_slice().to_vec();
        run.p_c = p_c.as_slice().to_vec();
        run.generation += 1;
        let best = costs[order[0]];
        run.recent_best.push(best);
        let window = run.window();
        if run.recent_best.len() > window {
            run.recent_best.remove(0);
        }
        let stop = run_stop(run, costs, &self.settings.cmaes);
        self.state.population = asked.scaled;
        self.state.costs = costs.to_vec();
        if let Some(why) = stop {
            self.end_run(rng, why);
        }
    }

    fn population(&self) -> (&[Vec<f64>], &[f64]) {
        (&self.state.population, &self.state.costs)
    }

    fn terminate(&self) -> Option<TerminationReason> {
        self.state.finished.then_some(TerminationReason::Converged)
    }

    fn state(&self) -> Value {
        serde_json::to_value(&self.state).unwrap_or(Value::Null)
    }

    fn restore(&mut self, state: Value) -> Result<(), String> {
        let state: State = serde_json::from_value(state).map_err(|e| e.to_string())?;
        let n = self.dim();
        let run = &state.run;
        let fits = run.mean.len() == n
            && run.cov.len() == n * n
            && run.p_sigma.len() == n
            && run.p_c.len() == n
            && run.lambda >= 4
            && state.population.len() == state.costs.len()
            && state.population.iter().all(|x| x.len() == n);
        if !fits {
            return Err(format!("state does not hold a CMA-ES run over {n} genes"));
        }
        self.state = state;
        self.asked = Asked::default();
        Ok(())
    }

    fn summary(&self) -> Option<Value> {
        let run = &self.state.run;
        let cov = run.cov();
        let n = self.dim();
        let spread: Vec<f64> = (0..n).map(|i| cov[(i, i)].max(0.0).sqrt()).collect();
        let std: Vec<f64> = (0..n)
            .map(|i| {
                let (lo, hi) = self.bounds[i];
                run.sigma * spread[i] * (hi - lo)
            })
            .collect();
        let correlation: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| {
                        let s = spread[i] * spread[j];
                        match (i == j, s > 0.0) {
                            (true, _) => 1.0,
                            (false, true) => cov[(i, j)] / s,
                            (false, false) => 0.0,
                        }
                    })
                    .collect()
            })
            .collect();
        let mean: Vec<f64> = self
            .to_scaled(&run.mean)
            .iter()
            .zip(&self.genes)
            .map(|(&x, g)| g.to_value(x))
            .collect();
        let names: Vec<&str> = self.genes.iter().map(|g| g.name.as_str()).collect();
        Some(json!({
            "genes": names,
            "mean": mean,
            "sigma": run.sigma,
            "std_scaled": std,
            "correlation": correlation,
            "population": run.lambda,
            "generations_of_run": run.generation,
            "restarts": self.state.restarts,
            "run_stops": self.state.stops,
            "coordinates": "each gene's scale space: ln(value) for a log gene, the value for a linear one",
        }))
    }
}

/// Why the run should end now, if it should: its steps are below `tol_x`, its
/// costs flat within `tol_fun`, its covariance degenerate, or its steps no
/// longer move the mean.
fn run_stop(run: &Run, costs: &[f64], s: &CmaesSettings) -> Option<&'static str> {
    let n = run.mean.len();
    let cov = run.cov();
    let diag_max = (0..n).map(|i| cov[(i, i)]).fold(0.0, f64::max).sqrt();
    let pc_max = run.p_c.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    if run.sigma * diag_max < s.tol_x && run.sigma * pc_max < s.tol_x {
        return Some("tol_x: the step fell below the tolerance");
    }
    if run.recent_best.len() >= run.window() {
        let all = run.recent_best.iter().chain(costs);
        let lo = all.clone().fold(f64::INFINITY, |a, &b| a.min(b));
        let hi = all.fold(f64::NEG_INFINITY, |a, &b| a.max(b));
        if hi - lo <= s.tol_fun * lo.abs() {
            return Some("tol_fun: the costs stopped changing");
        }
    }
    let eig = SymmetricEigen::new(cov.clone());
    let (min, max) = eig
        .eigenvalues
        .iter()
        .fold((f64::INFINITY, 0.0_f64), |(a, b), &l| (a.min(l), b.max(l)));
    if min.is_nan() || min <= 0.0 || max / min > MAX_CONDITION {
        return Some("condition: the covariance became degenerate");
    }
    // σ growing while C shrinks as fast: the strategy creeps, it no longer
    // learns (pycma's `tolupsigma`).
    if run.sigma / s.sigma0 > 1e20 * max.sqrt() {
        return Some("creeping: the step grew while the covariance shrank");
    }
    let unmoved = (0..n).all(|i| run.mean[i] == run.mean[i] + 0.2 * run.sigma * cov[(i, i)].sqrt());
    if unmoved {
        return Some("no effect: steps no longer move the mean");
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::base::Scale;
    use rand::SeedableRng;

    fn settings(population: usize) -> SearchSettings {
        serde_json::from_value(json!({
            "method": "cmaes", "population": population, "generations": 200, "seed": 1
        }))
        .unwrap()
    }

    #[test]
    fn reflection_keeps_points_in_the_box() {
        for t in [-3.7, -1.0, -0.2, 0.0, 0.4, 1.0, 1.3, 2.0, 5.25, f64::NAN] {
            let r = reflect(t);
            assert!((0.0..=1.0).contains(&r), "{t} → {r}");
        }
        assert!((reflect(1.3) - 0.7).abs() < 1e-12);
        assert!((reflect(-0.2) - 0.2).abs() < 1e-12);
    }

    #[test]
    fn weights_and_rates_follow_the_tutorial() {
        let r = Rates::new(5, 10);
        assert_eq!(r.weights.len(), 5);
        assert!((r.weights.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        assert!(r.weights.windows(2).all(|w| w[0] > w[1]));
        // The tutorial's μ_eff for λ = 10: about 3.17.
        assert!((r.mu_eff - 3.1672).abs() < 1e-3, "{}", r.mu_eff);
        assert!(r.c_1 + r.c_mu <= 1.0);
    }

    #[test]
    fn asked_points_stay_inside_bounds() {
        let genes = vec![
            GeneSpec::new("a", 0.0, 1.0, Scale::Linear),
            GeneSpec::new("k", 1e-3, 1e3, Scale::Log),
        ];
        let mut s = settings(40);
        s.cmaes.sigma0 = 1.0;
        let mut es = Cmaes::new(&s, genes).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        for _ in 0..5 {
            let batch = es.ask(&mut rng).to_vec();
            for x in &batch {
                for (v, &(lo, hi)) in x.iter().zip(&es.bounds) {
                    assert!((lo..=hi).contains(v));
                }
            }
            let costs: Vec<f64> = batch.iter().map(|x| x[0]).collect();
            es.tell(&mut rng, &costs);
        }
    }

    #[test]
    fn a_converged_run_restarts_with_twice_the_population() {
        let genes = vec![GeneSpec::new("a", -1.0, 1.0, Scale::Linear)];
        let mut s = settings(8);
        s.cmaes.restarts = 1;
        let mut es = Cmaes::new(&s, genes).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        // A flat cost: the run ends on tol_fun after its window.
        for _ in 0..100 {
            let n = es.ask(&mut rng).len();
            es.tell(&mut rng, &vec![1.0; n]);
            if es.state.restarts == 1 {
                break;
            }
        }
        assert_eq!(es.state.restarts, 1);
        assert_eq!(es.state.run.lambda, 16);
        assert!(es.state.stops[0].starts_with("tol_fun"));
        assert!(es.terminate().is_none());
    }
}
