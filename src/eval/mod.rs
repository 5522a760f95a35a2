//! Scoring candidates: one [`Evaluator`] interface, a CPU and a GPU implementation.
//!
//! An evaluator receives full model parameter vectors (one per candidate and
//! experiment, already mapped from the search's genomes) and returns, per
//! candidate and experiment, the fitness `1 − R²` of the model's output 0 against
//! the measured history over the experiment's fit window. What `auto`'s
//! backend trial asks of an evaluator beyond that (making it ready, timing
//! part of a pass, its kernel variants) is [`Timed`].

mod cpu;
mod fitness;
mod problem;
mod remembered;
mod residuals;
mod timed;

use std::ops::Range;

pub use cpu::{CpuEvaluator, all_cores};
pub use fitness::{
    FitnessAccumulator, score_many, score_one, simulate_histories, simulate_history,
    simulate_scored,
};
pub use problem::{ExperimentData, Problem};
pub use remembered::Remembered;
pub use residuals::{scored_residuals, window_residuals};
pub use timed::Timed;

/// Floating-point precision of an evaluator's arithmetic.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Precision {
    /// IEEE single precision.
    F32,
    /// IEEE double precision.
    F64,
}

/// Which evaluator a job uses (campaign `"solver": {"backend": …}` or `--backend`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Backend {
    /// The faster path on this machine, by measurement
    /// ([`crate::job::backend`]); the CPU where no adapter is found (said
    /// once).
    #[default]
    Auto,
    /// The GPU; no adapter is an error.
    Gpu,
    /// The f64 CPU reference.
    Cpu,
}

/// Which precision the GPU path uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PrecisionChoice {
    /// f64 where the adapter has `SHADER_F64`, otherwise f32.
    #[default]
    Auto,
    /// Single precision.
    F32,
    /// Double precision (error where the adapter lacks `SHADER_F64`).
    F64,
}

/// What ran the evaluation, for logs and result files.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EvaluatorInfo {
    /// `"cpu"` or `"gpu"`.
    pub backend: String,
    /// Device or thread description.
    pub device: String,
    /// Arithmetic precision.
    pub precision: Precision,
}

/// The candidates of one evaluation, per experiment.
#[derive(Debug, Clone, Default)]
pub struct Batch {
    /// Number of candidates.
    pub candidates: usize,
    /// For each experiment, `candidates × P` model parameters, candidate-major
    /// (P = the model's parameter count).
    pub params: Vec<Vec<f64>>,
    /// For each experiment, the clock offset of each candidate (s):
    /// `t_model = t_record + offset`.
    pub offsets: Vec<Vec<f64>>,
}

impl Batch {
    /// Checks that every index in `which` names a candidate of the batch.
    pub fn check_indices(&self, which: &[usize]) -> Result<(), EvalError> {
        match which.iter().find(|&&i| i >= self.candidates) {
            Some(&bad) => Err(EvalError::Shape {
                expected: format!("candidate indices < {}", self.candidates),
                found: bad.to_string(),
            }),
            None => Ok(()),
        }
    }

    /// Parameters of candidate `i` in experiment `e`.
    pub fn params_of(&self, e: usize, i: usize) -> &[f64] {
        let p = self.params[e].len() / self.candidates.max(1);
        &self.params[e][i * p..(i + 1) * p]
    }
}

/// Fitness of a batch.
#[derive(Debug, Clone, PartialEq)]
pub struct Scores {
    /// Number of experiments.
    pub experiments: usize,
    /// `1 − R²` for candidate `i`, experiment `e` at `i * experiments + e`;
    /// [`DIVERGED`] for a run that blew up.
    pub values: Vec<f64>,
    /// Number of (candidate, experiment) runs that blew up.
    pub diverged: usize,
}

impl Scores {
    /// Fitness of candidate `i` in experiment `e`.
    pub fn get(&self, i: usize, e: usize) -> f64 {
        self.values[i * self.experiments + e]
    }
}

/// Fitness given to a run that produced NaN/Inf or grew without bound. Finite so
/// that sorting and statistics stay well defined; far above any real `1 − R²`.
pub const DIVERGED: f64 = 1.0e30;

/// Simulated outputs and states of one run at the measurement samples.
#[derive(Debug, Clone, PartialEq)]
pub struct History {
    /// Model time of each sample (s).
    pub t: Vec<f64>,
    /// Outputs per sample, `[output][sample]` (see the model's `output_names`).
    pub outputs: Vec<Vec<f64>>,
    /// States per sample, `[state][sample]`.
    pub states: Vec<Vec<f64>>,
}

/// Errors raised while evaluating.
#[derive(Debug, thiserror::Error)]
pub enum EvalError {
    /// The batch does not fit the problem.
    #[error("batch shape mismatch: expected {expected}, found {found}")]
    Shape {
        /// What was expected.
        expected: String,
        /// What was found.
        found: String,
    },
    /// The GPU device failed.
    #[error("GPU device error: {0}")]
    Device(String),
    /// The evaluator cannot handle this problem.
    #[error("unsupported: {0}")]
    Unsupported(String),
    /// The flag given to [`Evaluator::set_cancel`] was raised while the batch
    /// was being evaluated; its results are incomplete and were dropped.
    #[error("evaluation cancelled by an interrupt")]
    Cancelled,
}

/// Scores whole populations of candidates against a [`Problem`].
pub trait Evaluator: Send {
    /// What runs the evaluation.
    fn info(&self) -> EvaluatorInfo;

    /// The problem being scored.
    fn problem(&self) -> &Problem;

    /// `1 − R²` per candidate and experiment.
    fn fitness(&mut self, batch: &Batch) -> Result<Scores, EvalError>;

    /// Full histories of the chosen candidates in every experiment,
    /// `[candidate][experiment]`, over samples `0..window.end`: checks that
    /// the batch fits the problem and that every index names a candidate, then
    /// asks [`Evaluator::checked_histories`].
    fn histories(
        &mut self,
        batch: &Batch,
        which: &[usize],
    ) -> Result<Vec<Vec<History>>, EvalError> {
        self.problem().check_batch(batch)?;
        batch.check_indices(which)?;
        self.checked_histories(batch, which)
    }

    /// [`Evaluator::histories`] of a batch and indices already checked.
    fn checked_histories(
        &mut self,
        batch: &Batch,
        which: &[usize],
    ) -> Result<Vec<Vec<History>>, EvalError>;

    /// The scored output ([`ExperimentData::output`]) of the chosen
    /// candidates in every experiment, `[candidate][experiment][sample]`,
    /// over samples `0..window.end`: all the polish's residuals need of
    /// [`Evaluator::histories`], with the same bits. Checks the batch and the
    /// indices, then asks [`Evaluator::checked_scored_outputs`].
    fn scored_outputs(
        &mut self,
        batch: &Batch,
        which: &[usize],
    ) -> Result<Vec<Vec<Vec<f64>>>, EvalError> {
        self.problem().check_batch(batch)?;
        batch.check_indices(which)?;
        self.checked_scored_outputs(batch, which)
    }

    /// [`Evaluator::scored_outputs`] of a batch and indices already checked:
    /// taken from the full histories unless the evaluator can record the
    /// scored output alone (the GPU's history kernel can).
    fn checked_scored_outputs(
        &mut self,
        batch: &Batch,
        which: &[usize],
    ) -> Result<Vec<Vec<Vec<f64>>>, EvalError> {
        let scored: Vec<usize> = self
            .problem()
            .experiments
            .iter()
            .map(|x| x.output)
            .collect();
        let histories = self.checked_histories(batch, which)?;
        Ok(histories
            .into_iter()
            .map(|per_exp| {
                per_exp
                    .into_iter()
                    .zip(&scored)
                    .map(|(mut h, &o)| h.outputs.get_mut(o).map(std::mem::take).unwrap_or_default())
                    .collect()
            })
            .collect())
    }

    /// A flag that, once raised (Ctrl-C, SIGTERM), makes a [`Evaluator::fitness`]
    /// in flight stop as soon as it can and return [`EvalError::Cancelled`].
    /// An evaluator that cannot stop early ignores it.
    fn set_cancel(&mut self, _flag: std::sync::Arc<std::sync::atomic::AtomicBool>) {}
}

/// The GPU evaluators' kernel variants: `"specialised"` (the values every
/// run of a batch shares baked into the kernel as constants) and
/// `"generic"` (every value read from the run's buffer).
pub const KERNEL_VARIANTS: &[&str] = &["specialised", "generic"];

/// Samples an experiment's run must reach: `0..window.end`.
pub fn run_length(window: &Range<usize>) -> usize {
    window.end
}
