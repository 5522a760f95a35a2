//! The driver: runs a [`GeneticAlgorithm`] against a [`BatchCost`], then the
//! Levenberg–Marquardt [`Polish`] on the same cost; calls one set of observers
//! for both, writes checkpoints and decides when to stop and why.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::SearchError;
use super::checkpoint::{Checkpoint, Fingerprint};
use super::cost::BatchCost;
use super::ga::GeneticAlgorithm;
use super::genes::genome_values;
use super::observers::{Observer, ObserverMode};
use super::polish::{
    Polish, PolishIteration, PolishOutcome, PolishStop, ResidualCost, distinct_starts,
};
use super::report::{
    GenerationReport, SearchOutcome, TerminationReason, diversity, elite_spread, is_diverged,
    median, ranking, sanitize_cost,
};
use super::state::SearchState;
use crate::eval::EvalError;

/// Share of diverged candidates in a generation above which the outcome warns.
pub const DIVERGED_WARN_SHARE: f64 = 0.25;

/// Runs a search: evaluation, bookkeeping, observers, checkpoints, stopping.
///
/// Stops on the limits in the GA's settings (`generations`, `target_fitness`,
/// `stall_generations`, `max_time_s`) or when the interrupt flag is raised; the
/// flag and the limits are checked after every generation, so an interrupt takes
/// effect once the running evaluation returns. A cost whose evaluator watches
/// the same flag ([`crate::eval::Evaluator::set_cancel`]) returns early with
/// [`EvalError::Cancelled`]; the generation in flight is then dropped and the
/// checkpoint holds the last finished one.
///
/// Checkpoints are written by the executor itself rather than by an observer:
/// they need the full state (RNG included), taken at the one point of the loop
/// where a resumed search continues exactly as an uninterrupted one would.
///
/// ```
/// use std::sync::{Arc, atomic::AtomicBool};
/// use rigfit::base::Scale;
/// use rigfit::search::*;
///
/// # let dir = tempfile::tempdir().unwrap();
/// let checkpoint = dir.path().join("checkpoint.json");
/// let settings: GaSettings =
///     serde_json::from_str(r#"{"population": 16, "generations": 20}"#).unwrap();
/// let genes = vec![GeneSpec::new("k", 1e-3, 1e3, Scale::Log)];
/// let build = || {
///     let ga = GeneticAlgorithm::new(settings.clone(), genes.clone()).unwrap();
///     Executor::new(ga, FnCost(|g: &[f64]| g[0].ln().powi(2)))
///         .fingerprint(Fingerprint::new().with("rig", "demo"))
///         .checkpoint_to(&checkpoint)
///         .interrupt(Arc::new(AtomicBool::new(false)))
///         .observe(ProgressObserver::new(20, true), ObserverMode::Always)
/// };
/// let first = build().run().unwrap();
/// // Resuming a finished search just reports it again.
/// let again = build().resume_from(&checkpoint).unwrap().run().unwrap();
/// assert_eq!(first.best_cost.to_bits(), again.best_cost.to_bits());
/// ```
pub struct Executor<C: BatchCost> {
    ga: GeneticAlgorithm,
    cost: C,
    observers: Vec<(Box<dyn Observer>, ObserverMode)>,
    interrupt: Option<Arc<AtomicBool>>,
    fingerprint: Fingerprint,
    checkpoint_path: Option<PathBuf>,
    resume: Option<(PathBuf, Checkpoint)>,
    polish: Option<PolishStage<C>>,
}

/// The polish to run after the GA: set by [`Executor::then_polish`], which is
/// only available when the cost also gives residuals, so the executor keeps
/// the call as a function pointer made where that bound holds.
struct PolishStage<C> {
    polish: Polish,
    starts: usize,
    run: PolishRun<C>,
}

type PolishRun<C> = fn(
    &Polish,
    &mut C,
    &[Vec<f64>],
    &mut dyn FnMut(&PolishIteration) -> Result<(), SearchError>,
) -> Result<PolishOutcome, SearchError>;

impl<C: BatchCost + ResidualCost> Executor<C> {
    /// After the GA, polishes from its `starts` best distinct candidates
    /// ([`distinct_starts`]) on the same cost, under the same interrupt flag
    /// and observers ([`Observer::polished`]); the outcome carries it in
    /// [`SearchOutcome::polish`]. An interrupted GA is not polished; an
    /// interrupted polish makes the outcome's termination
    /// [`TerminationReason::Interrupted`].
    pub fn then_polish(mut self, polish: Polish, starts: usize) -> Self {
        self.polish = Some(PolishStage {
            polish,
            starts,
            run: |p, cost, starts, observe| p.run_observed(cost, starts, observe),
        });
        self
    }
}

impl<C: BatchCost> Executor<C> {
    /// A search of `ga` scored by `cost`.
    pub fn new(ga: GeneticAlgorithm, cost: C) -> Self {
        Self {
            ga,
            cost,
            observers: Vec::new(),
            interrupt: None,
            fingerprint: Fingerprint::new(),
            checkpoint_path: None,
            resume: None,
            polish: None,
        }
    }

    /// Adds an observer called per `mode`.
    pub fn observe(mut self, observer: impl Observer + 'static, mode: ObserverMode) -> Self {
        self.observers.push((Box::new(observer), mode));
        self
    }

    /// A flag that stops the search (with a checkpoint, if configured) when set.
    pub fn interrupt(mut self, flag: Arc<AtomicBool>) -> Self {
        self.interrupt = Some(flag);
        self
    }

    /// What a checkpoint must match to be resumed (the caller's items; the
    /// search's own items are added by [`Self::full_fingerprint`]).
    pub fn fingerprint(mut self, fingerprint: Fingerprint) -> Self {
        self.fingerprint = fingerprint;
        self
    }

    /// Writes checkpoints to `path`: every `checkpoint_every` generations (if
    /// non-zero) and whenever the search stops.
    pub fn checkpoint_to(mut self, path: impl Into<PathBuf>) -> Self {
        self.checkpoint_path = Some(path.into());
        self
    }

    /// Continues from the checkpoint at `path` instead of starting afresh. The
    /// fingerprint is compared when [`Self::run`] starts.
    pub fn resume_from(mut self, path: impl AsRef<Path>) -> Result<Self, SearchError> {
        let path = path.as_ref();
        self.resume = Some((path.into(), Checkpoint::load(path)?));
        Ok(self)
    }

    /// The caller's fingerprint plus the search's items: genes, population,
    /// seed, operators. Stopping limits are left out so a resumed search may
    /// run longer.
    pub fn full_fingerprint(&self) -> Fingerprint {
        let s = self.ga.settings();
        let mut fp = self.fingerprint.clone();
        fp.insert("search.genes".into(), json(&self.ga.genes()));
        fp.insert("search.population".into(), s.population.to_string());
        fp.insert("search.seed".into(), s.seed.to_string());
        fp.insert("search.tournament".into(), s.tournament.to_string());
        fp.insert("search.crossover".into(), json(&s.crossover));
        fp.insert("search.mutation".into(), json(&s.mutation));
        fp.insert("search.elitism".into(), s.elitism.to_string());
        fp.insert("search.init".into(), json(&s.init));
        fp
    }

    /// Runs the search to its end.
    pub fn run(mut self) -> Result<SearchOutcome, SearchError> {
        let fingerprint = self.full_fingerprint();
        let started = Instant::now();
        let (mut state, base_elapsed) = match self.resume.take() {
            Some((path, cp)) => {
                cp.verify(&fingerprint, &path)?;
                self.check_shape(&cp.state, &path)?;
                for (obs, _) in &mut self.observers {
                    obs.resumed(&cp.state.history)?;
                }
                let base = cp.state.elapsed_s;
                (cp.state, base)
            }
            None => (self.first_generation(started)?, 0.0),
        };
        loop {
            let elapsed = base_elapsed + started.elapsed().as_secs_f64();
            if let Some(reason) = self.stop_reason(&state, elapsed) {
                state.elapsed_s = elapsed;
                self.save(&fingerprint, &state)?;
                let mut outcome = self.outcome(state, reason);
                self.run_polish(&mut outcome)?;
                for (obs, _) in &mut self.observers {
                    obs.finish(&outcome)?;
                }
                return Ok(outcome);
            }
            let every = self.ga.settings().checkpoint_every;
            if every > 0 && (state.generation + 1) % every == 0 {
                self.save(&fingerprint, &state)?;
            }
            let gen_start = Instant::now();
            let rng_before = state.rng.clone();
            let off = self
                .ga
                .next_generation(&mut state.rng, &state.population, &state.costs);
            let (child_costs, diverged_runs) = match self.evaluate(&off.children) {
                Err(SearchError::Eval(EvalError::Cancelled)) if self.interrupted() => {
                    // The generation in flight is dropped: the state goes back to
                    // the last finished one, which the loop's head checkpoints, so
                    // a resume repeats this generation exactly.
                    state.rng = rng_before;
                    continue;
                }
                other => other?,
            };
            let mut population: Vec<Vec<f64>> = off
                .elites
                .iter()
                .map(|&i| state.population[i].clone())
                .collect();
            let mut costs: Vec<f64> = off.elites.iter().map(|&i| state.costs[i]).collect();
            let evaluated = off.children.len();
            let first_child = costs.len();
            population.extend(off.children);
            costs.extend(child_costs);
            state.generation += 1;
            let elapsed = base_elapsed + started.elapsed().as_secs_f64();
            let generation = Generation {
                population,
                costs,
                first_child,
                evaluated,
                diverged_runs,
            };
            self.record(&mut state, generation, gen_start, elapsed)?;
        }
    }

    /// Runs the configured polish from the GA's outcome, if any and if the GA
    /// was not interrupted.
    fn run_polish(&mut self, outcome: &mut SearchOutcome) -> Result<(), SearchError> {
        let Some(stage) = self.polish.take() else {
            return Ok(());
        };
        if outcome.termination == TerminationReason::Interrupted {
            return Ok(());
        }
        let starts = distinct_starts(self.ga.genes(), outcome, stage.starts);
        let polish = match &self.interrupt {
            Some(flag) => stage.polish.interrupt(flag.clone()),
            None => stage.polish,
        };
        let observers = &mut self.observers;
        let mut observe = |step: &PolishIteration| -> Result<(), SearchError> {
            for (obs, mode) in observers.iter_mut() {
                if *mode != ObserverMode::Never {
                    obs.polished(step)?;
                }
            }
            Ok(())
        };
        let p = (stage.run)(&polish, &mut self.cost, &starts, &mut observe)?;
        if p.stop == PolishStop::Interrupted {
            outcome.termination = TerminationReason::Interrupted;
        }
        outcome.polish = Some(p);
        Ok(())
    }

    /// Guards against hand-edited checkpoints that the fingerprint cannot catch.
    fn check_shape(&self, state: &SearchState, path: &Path) -> Result<(), SearchError> {
        let (n, g) = (self.ga.settings().population, self.ga.genes().len());
        let ok = state.population.len() == n
            && state.costs.len() == n
            && state.best_genome.len() == g
            && state.population.iter().all(|x| x.len() == g);
        if ok {
            Ok(())
        } else {
            Err(SearchError::CheckpointFormat {
                path: path.into(),
                reason: format!("state does not hold {n} genomes of {g} genes with costs"),
            })
        }
    }

    fn first_generation(&mut self, started: Instant) -> Result<SearchState, SearchError> {
        let mut rng = ChaCha8Rng::seed_from_u64(self.ga.settings().seed);
        let population = self.ga.init(&mut rng);
        let (costs, diverged_runs) = self.evaluate(&population)?;
        let mut state = SearchState {
            best_genome: population[0].clone(),
            best_cost: f64::INFINITY,
            population: Vec::new(),
            costs: Vec::new(),
            rng,
            generation: 0,
            stall: 0,
            evaluations: 0,
            elapsed_s: 0.0,
            history: Vec::new(),
            divergence_alerts: Vec::new(),
        };
        let evaluated = population.len();
        let generation = Generation {
            population,
            costs,
            first_child: 0,
            evaluated,
            diverged_runs,
        };
        self.record(
            &mut state,
            generation,
            started,
            started.elapsed().as_secs_f64(),
        )?;
        Ok(state)
    }

    /// Scores scale-space genomes; returns the raw costs and the cost
    /// function's diverged-run count.
    fn evaluate(&mut self, scaled: &[Vec<f64>]) -> Result<(Vec<f64>, usize), SearchError> {
        let genes = self.ga.genes();
        let values: Vec<Vec<f64>> = scaled.iter().map(|g| genome_values(genes, g)).collect();
        let batch = self.cost.cost(&values)?;
        if batch.costs.len() != values.len() {
            return Err(SearchError::CostLength {
                expected: values.len(),
                found: batch.costs.len(),
            });
        }
        Ok((batch.costs, batch.diverged))
    }

    /// Takes an evaluated generation into the state and tells the observers.
    fn record(
        &mut self,
        state: &mut SearchState,
        g: Generation,
        gen_start: Instant,
        elapsed: f64,
    ) -> Result<(), SearchError> {
        let diverged = g.costs[g.first_child..]
            .iter()
            .filter(|&&c| is_diverged(c))
            .count();
        let costs: Vec<f64> = g.costs.into_iter().map(sanitize_cost).collect();
        let best = ranking(&costs)[0];
        let improved = costs[best] < state.best_cost;
        if improved {
            state.best_cost = costs[best];
            state.best_genome = g.population[best].clone();
            state.stall = 0;
        } else {
            state.stall += 1;
        }
        if diverged as f64 > DIVERGED_WARN_SHARE * g.evaluated as f64 {
            state.divergence_alerts.push(state.generation);
        }
        state.evaluations += g.evaluated as u64;
        state.elapsed_s = elapsed;
        let secs = gen_start.elapsed().as_secs_f64();
        let report = GenerationReport {
            generation: state.generation,
            best_cost: state.best_cost,
            median_cost: median(&costs),
            best_genome: genome_values(self.ga.genes(), &state.best_genome),
            improved,
            diversity: diversity(&g.population, self.ga.bounds()),
            evaluations: state.evaluations,
            evaluated: g.evaluated,
            evals_per_s: if secs > 0.0 {
                g.evaluated as f64 / secs
            } else {
                0.0
            },
            diverged,
            diverged_runs: g.diverged_runs,
            elapsed_s: elapsed,
        };
        state.population = g.population;
        state.costs = costs;
        let last = self.stop_reason(state, elapsed).is_some();
        for (obs, mode) in &mut self.observers {
            if mode.selects(&report, last) {
                obs.observe(&report)?;
            }
        }
        state.history.push(report);
        Ok(())
    }

    fn stop_reason(&self, state: &SearchState, elapsed: f64) -> Option<TerminationReason> {
        let s = self.ga.settings();
        if s.target_fitness.is_some_and(|t| state.best_cost <= t) {
            Some(TerminationReason::TargetReached)
        } else if state.generation + 1 >= s.generations {
            Some(TerminationReason::MaxGenerations)
        } else if s.stall_generations.is_some_and(|n| state.stall >= n) {
            Some(TerminationReason::Stalled)
        } else if s.max_time_s.is_some_and(|t| elapsed >= t) {
            Some(TerminationReason::Timeout)
        } else if self.interrupted() {
            Some(TerminationReason::Interrupted)
        } else {
            None
        }
    }

    fn interrupted(&self) -> bool {
        self.interrupt
            .as_ref()
            .is_some_and(|f| f.load(Ordering::SeqCst))
    }

    fn save(&self, fingerprint: &Fingerprint, state: &SearchState) -> Result<(), SearchError> {
        match &self.checkpoint_path {
            Some(path) => Checkpoint::save_parts(fingerprint, state, path),
            None => Ok(()),
        }
    }

    fn outcome(&self, state: SearchState, termination: TerminationReason) -> SearchOutcome {
        let genes = self.ga.genes();
        let order = ranking(&state.costs);
        let sorted: Vec<Vec<f64>> = order.iter().map(|&i| state.population[i].clone()).collect();
        let mut warnings = Vec::new();
        if let Some(&first) = state.divergence_alerts.first() {
            warnings.push(format!(
                "{} generation(s) had more than {:.0}% diverged candidates (first: generation {first}); \
                 check the bounds and the integration time step",
                state.divergence_alerts.len(),
                DIVERGED_WARN_SHARE * 100.0
            ));
        }
        if is_diverged(state.best_cost) {
            warnings.push("every candidate diverged; the best cost is meaningless".into());
        }
        SearchOutcome {
            best_genome: genome_values(genes, &state.best_genome),
            best_cost: state.best_cost,
            population: sorted.iter().map(|g| genome_values(genes, g)).collect(),
            costs: order.iter().map(|&i| state.costs[i]).collect(),
            elite_spread: elite_spread(&sorted, genes),
            generations: state.generation + 1,
            evaluations: state.evaluations,
            wall_time_s: state.elapsed_s,
            termination,
            history: state.history,
            warnings,
            polish: None,
        }
    }
}

/// An evaluated generation before bookkeeping.
struct Generation {
    population: Vec<Vec<f64>>,
    costs: Vec<f64>,
    /// Index of the first newly evaluated candidate (after the elites).
    first_child: usize,
    evaluated: usize,
    diverged_runs: usize,
}

fn json<T: serde::Serialize + ?Sized>(v: &T) -> String {
    serde_json::to_string(v).unwrap_or_default()
}
