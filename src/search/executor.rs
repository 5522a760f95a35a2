//! The driver: runs any [`Solver`] against a [`BatchCost`] (ask a batch, score
//! it, tell the costs), then the Levenberg–Marquardt [`Polish`] on the same
//! cost; calls one set of observers for both, writes checkpoints and decides
//! when to stop and why.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use super::SearchError;
use super::checkpoint::{Checkpoint, Fingerprint};
use super::cost::BatchCost;
use super::genes::{GeneSpec, genome_values};
use super::islands::Migration;
use super::observers::{Observer, ObserverMode};
use super::polish::{
    Polish, PolishIteration, PolishOutcome, PolishStop, ResidualCost, distinct_starts,
};
use super::report::{
    GenerationReport, SearchOutcome, TerminationReason, diversity, elite_spread, is_diverged,
    median, ranking, sanitize_cost,
};
use super::settings::SearchSettings;
use super::solver::Solver;
use super::state::SearchState;
use crate::eval::EvalError;

/// Share of diverged candidates in a generation above which the outcome warns.
pub const DIVERGED_WARN_SHARE: f64 = 0.25;

/// Runs a search: evaluation, bookkeeping, observers, checkpoints, stopping.
///
/// Stops on the limits in the search's settings (`generations`,
/// `target_fitness`, `stall_generations`, `max_evaluations`, `max_time_s`),
/// when the method has nothing more to do ([`Solver::terminate`]) or when the
/// interrupt flag is raised; the flag and the limits are checked after every
/// generation, so an interrupt takes
/// effect once the running evaluation returns. A cost whose evaluator watches
/// the same flag ([`crate::eval::Evaluator::set_cancel`]) returns early with
/// [`EvalError::Cancelled`]; the generation in flight is then dropped and the
/// checkpoint holds the last finished one.
///
/// Checkpoints are written by the executor itself rather than by an observer:
/// they need the full state (RNG and the method's state included), taken at the
/// one point of the loop where a resumed search continues exactly as an
/// uninterrupted one would.
///
/// Every method runs through this one executor: a new method is a new
/// [`Solver`], nothing here changes.
///
/// ```
/// use std::sync::{Arc, atomic::AtomicBool};
/// use rigfit::base::Scale;
/// use rigfit::search::*;
///
/// # let dir = tempfile::tempdir().unwrap();
/// let checkpoint = dir.path().join("checkpoint.json");
/// let settings: SearchSettings =
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
    solver: Box<dyn Solver>,
    /// The solver's genes, held apart so that a batch the solver lends out
    /// can be mapped to values while it is lent.
    genes: Vec<GeneSpec>,
    cost: C,
    observers: Vec<(Box<dyn Observer>, ObserverMode)>,
    interrupt: Option<Arc<AtomicBool>>,
    fingerprint: Fingerprint,
    checkpoint_path: Option<PathBuf>,
    resume: Option<(PathBuf, Checkpoint)>,
    polish: Option<PolishStage<C>>,
    migration: Option<Box<dyn Migration>>,
}

/// The polish to run after the search: set by [`Executor::then_polish`], which
/// is only available when the cost also gives residuals, so the executor keeps
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
    /// After the search, polishes from its `starts` best distinct candidates
    /// ([`distinct_starts`]) on the same cost, under the same interrupt flag
    /// and observers ([`Observer::polished`]); the outcome carries it in
    /// [`SearchOutcome::polish`]. An interrupted search is not polished; an
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

/// One scored batch, before the bookkeeping.
struct Scored {
    /// The batch's best candidate (scale space) and its cost.
    best: (Vec<f64>, f64),
    /// Candidates scored.
    evaluated: usize,
    /// Candidates whose cost was diverged (or not finite).
    diverged: usize,
    /// Blown-up runs as the cost function counted them.
    diverged_runs: usize,
}

impl<C: BatchCost> Executor<C> {
    /// A search by `solver` scored by `cost`, under the limits of the settings
    /// the solver was built from ([`Solver::settings`]).
    pub fn new(solver: impl Solver + 'static, cost: C) -> Self {
        Self::boxed(Box::new(solver), cost)
    }

    /// [`Self::new`] for a solver chosen at run time
    /// ([`super::Method::solver`]).
    pub fn boxed(solver: Box<dyn Solver>, cost: C) -> Self {
        Self {
            genes: solver.genes().to_vec(),
            solver,
            cost,
            observers: Vec::new(),
            interrupt: None,
            fingerprint: Fingerprint::new(),
            checkpoint_path: None,
            resume: None,
            polish: None,
            migration: None,
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

    /// Calls `migration` after every generation whose search goes on, before
    /// the next checkpoint (an island's exchange, [`super::islands`]); a
    /// candidate it brings in that beats the best becomes the best.
    pub fn migrate(mut self, migration: impl Migration + 'static) -> Self {
        self.migration = Some(Box::new(migration));
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
    /// seed, the method and its settings ([`Solver::fingerprint`]). Stopping
    /// limits are left out so a resumed search may run longer.
    pub fn full_fingerprint(&self) -> Fingerprint {
        let s = self.settings();
        let mut fp = self.fingerprint.clone();
        fp.insert_json("search.genes", &self.genes);
        fp.insert("search.population".into(), s.population.to_string());
        fp.insert("search.seed".into(), s.seed.to_string());
        fp.insert("search.method".into(), self.solver.method().to_string());
        self.solver.fingerprint(&mut fp);
        fp
    }

    /// Runs the search to its end.
    pub fn run(mut self) -> Result<SearchOutcome, SearchError> {
        let fingerprint = self.full_fingerprint();
        let started = Instant::now();
        let (mut state, base_elapsed) = match self.resume.take() {
            Some((path, mut cp)) => {
                cp.verify(&fingerprint, &path)?;
                self.restore(&mut cp.state, &path)?;
                for (obs, _) in &mut self.observers {
                    obs.resumed(&cp.state.history)?;
                }
                let base = cp.state.elapsed_s;
                (cp.state, base)
            }
            None => {
                let mut state = SearchState::start(self.settings().seed);
                // An interrupt inside the first batch has nothing to keep:
                // it ends the search with the evaluator's error.
                let scored = self.score(&mut state)?;
                let elapsed = started.elapsed().as_secs_f64();
                self.record(&mut state, scored, started, elapsed)?;
                self.run_migration(&mut state, elapsed)?;
                (state, 0.0)
            }
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
            let every = self.settings().checkpoint_every;
            if every > 0 && (state.generation + 1) % every == 0 {
                self.save(&fingerprint, &state)?;
            }
            let gen_start = Instant::now();
            let rng_before = state.rng.clone();
            let scored = match self.score(&mut state) {
                Err(SearchError::Eval(EvalError::Cancelled)) if self.interrupted() => {
                    // The batch in flight is dropped: the RNG goes back to
                    // where it was, the method asks the same batch again, and
                    // the loop's head checkpoints the last finished
                    // generation, so a resume repeats this one exactly.
                    state.rng = rng_before;
                    continue;
                }
                other => other?,
            };
            state.generation += 1;
            let elapsed = base_elapsed + started.elapsed().as_secs_f64();
            self.record(&mut state, scored, gen_start, elapsed)?;
            self.run_migration(&mut state, elapsed)?;
        }
    }

    /// Polishes `outcome` (a search run elsewhere: the best of several
    /// islands) with the configured polish, under this executor's interrupt
    /// flag and observers, which are then told the outcome; what
    /// [`Self::run`] does after its own search.
    pub fn polish_outcome(mut self, outcome: SearchOutcome) -> Result<SearchOutcome, SearchError> {
        let mut outcome = outcome;
        self.run_polish(&mut outcome)?;
        for (obs, _) in &mut self.observers {
            obs.finish(&outcome)?;
        }
        Ok(outcome)
    }

    /// The migration after a generation, if the search goes on: taken in
    /// before the next checkpoint, so that a resumed search never repeats it.
    fn run_migration(&mut self, state: &mut SearchState, elapsed: f64) -> Result<(), SearchError> {
        if self.migration.is_none() || self.stop_reason(state, elapsed).is_some() {
            return Ok(());
        }
        if let Some(m) = self.migration.as_mut() {
            m.migrate(state.generation, self.solver.as_mut())?;
        }
        let (population, costs) = self.solver.population();
        if let Some(&best) = ranking(costs).first()
            && costs[best] < state.best_cost
        {
            state.best_cost = costs[best];
            state.best_genome = population[best].clone();
        }
        Ok(())
    }

    /// Asks the method for a batch, scores it and tells the method its costs
    /// (sanitized: finite).
    fn score(&mut self, state: &mut SearchState) -> Result<Scored, SearchError> {
        let batch = self.solver.ask(&mut state.rng);
        let values: Vec<Vec<f64>> = batch
            .iter()
            .map(|g| genome_values(&self.genes, g))
            .collect();
        let scored = self.cost.cost(&values)?;
        if scored.costs.len() != values.len() {
            return Err(SearchError::CostLength {
                expected: values.len(),
                found: scored.costs.len(),
            });
        }
        let diverged = scored.costs.iter().filter(|&&c| is_diverged(c)).count();
        let costs: Vec<f64> = scored.costs.into_iter().map(sanitize_cost).collect();
        let best = ranking(&costs)[0];
        let best = (batch[best].clone(), costs[best]);
        self.solver.tell(&mut state.rng, &costs);
        Ok(Scored {
            best,
            evaluated: values.len(),
            diverged,
            diverged_runs: scored.diverged,
        })
    }

    /// Runs the configured polish from the search's outcome, if any and if the
    /// search was not interrupted.
    fn run_polish(&mut self, outcome: &mut SearchOutcome) -> Result<(), SearchError> {
        let Some(stage) = self.polish.take() else {
            return Ok(());
        };
        if outcome.termination == TerminationReason::Interrupted {
            return Ok(());
        }
        let starts = distinct_starts(&self.genes, outcome, stage.starts);
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

    /// The settings the solver was built from: the limits, seed and cadence.
    fn settings(&self) -> &SearchSettings {
        self.solver.settings()
    }

    /// Moves a checkpoint's method state into the solver; a state that does
    /// not fit (a hand-edited checkpoint the fingerprint cannot catch) is
    /// refused.
    fn restore(&mut self, state: &mut SearchState, path: &Path) -> Result<(), SearchError> {
        let bad = |reason: String| SearchError::CheckpointFormat {
            path: path.into(),
            reason,
        };
        if state.best_genome.len() != self.genes.len() {
            return Err(bad(format!(
                "its best genome holds {} genes, the search {}",
                state.best_genome.len(),
                self.genes.len()
            )));
        }
        self.solver
            .restore(std::mem::take(&mut state.solver))
            .map_err(bad)
    }

    /// Takes a scored batch into the state and tells the observers.
    fn record(
        &mut self,
        state: &mut SearchState,
        scored: Scored,
        gen_start: Instant,
        elapsed: f64,
    ) -> Result<(), SearchError> {
        let (best_genome, best_cost) = scored.best;
        let improved = best_cost < state.best_cost;
        if improved {
            state.best_cost = best_cost;
            state.best_genome = best_genome;
            state.stall = 0;
        } else {
            state.stall += 1;
        }
        if scored.diverged as f64 > DIVERGED_WARN_SHARE * scored.evaluated as f64 {
            state.divergence_alerts.push(state.generation);
        }
        state.evaluations += scored.evaluated as u64;
        state.elapsed_s = elapsed;
        let secs = gen_start.elapsed().as_secs_f64();
        let (population, costs) = self.solver.population();
        let report = GenerationReport {
            generation: state.generation,
            best_cost: state.best_cost,
            median_cost: median(costs),
            best_genome: genome_values(&self.genes, &state.best_genome),
            improved,
            diversity: diversity(population, self.solver.bounds()),
            evaluations: state.evaluations,
            evaluated: scored.evaluated,
            evals_per_s: if secs > 0.0 {
                scored.evaluated as f64 / secs
            } else {
                0.0
            },
            diverged: scored.diverged,
            diverged_runs: scored.diverged_runs,
            elapsed_s: elapsed,
        };
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
        let s = self.settings();
        if s.target_fitness.is_some_and(|t| state.best_cost <= t) {
            Some(TerminationReason::TargetReached)
        } else if state.generation + 1 >= s.generations {
            Some(TerminationReason::MaxGenerations)
        } else if s.stall_generations.is_some_and(|n| state.stall >= n) {
            Some(TerminationReason::Stalled)
        } else if s.max_time_s.is_some_and(|t| elapsed >= t) {
            Some(TerminationReason::Timeout)
        } else if s.max_evaluations.is_some_and(|n| state.evaluations >= n) {
            Some(TerminationReason::MaxEvaluations)
        } else if let Some(reason) = self.solver.terminate() {
            Some(reason)
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

    /// Writes a checkpoint if one is configured, with the method's state as it
    /// stands.
    fn save(&self, fingerprint: &Fingerprint, state: &SearchState) -> Result<(), SearchError> {
        match &self.checkpoint_path {
            Some(path) => Checkpoint::save_parts(fingerprint, state, self.solver.state(), path),
            None => Ok(()),
        }
    }

    fn outcome(&self, state: SearchState, termination: TerminationReason) -> SearchOutcome {
        let genes = &self.genes;
        let (population, costs) = self.solver.population();
        let order = ranking(costs);
        let sorted: Vec<Vec<f64>> = order.iter().map(|&i| population[i].clone()).collect();
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
            costs: order.iter().map(|&i| costs[i]).collect(),
            elite_spread: elite_spread(&sorted, genes),
            generations: state.generation + 1,
            evaluations: state.evaluations,
            wall_time_s: state.elapsed_s,
            termination,
            history: state.history,
            warnings,
            method: self.solver.method(),
            method_summary: self.solver.summary(),
            polish: None,
        }
    }
}
