//! What `auto`'s trial measured and chose ([`BackendTrial`], with the line a
//! job starts with), why it failed ([`TrialError`]), and what watches it as
//! it runs ([`TrialWatch`]: a line per stage, an interrupt flag).

use std::collections::BTreeMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use serde::{Deserialize, Serialize};

use crate::eval::{EvalError, Evaluator};

/// What `auto` measured and chose.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BackendTrial {
    /// `"gpu"` or `"cpu"`: the path chosen.
    pub chosen: String,
    /// The GPU path's rate (candidate-steps per second), with its fastest
    /// kernel variant.
    pub gpu_rate: f64,
    /// The GPU kernel variant chosen ([`crate::eval::KERNEL_VARIANTS`]), the
    /// fastest on this adapter; `None` where the GPU has no variants.
    #[serde(default)]
    pub gpu_kernel: Option<String>,
    /// Each GPU kernel variant's rate (candidate-steps per second).
    #[serde(default)]
    pub gpu_kernel_rates: BTreeMap<String, f64>,
    /// The CPU path's rate (candidate-steps per second).
    pub cpu_rate: f64,
    /// Candidates in the timed batch.
    pub candidates: usize,
    /// The campaign measured: its name and file, as `rigfit devices` lists
    /// the choices kept on this machine; `None` in a cache written before
    /// it was kept.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub campaign: Option<String>,
    /// Steps of each run the GPU was timed over, where a long record was
    /// timed over its first part ([`trial_part`](super::trial_part)); `None` for whole passes.
    #[serde(default)]
    pub gpu_steps_timed: Option<usize>,
    /// Steps of each run both paths were timed over where the trial was
    /// shortened ([`TrialPlan`](super::TrialPlan): a very long record, or whole runs that
    /// would have cost more than [`TRIAL_SHARE`](super::TRIAL_SHARE) of the job); `None` where
    /// the CPU was timed over whole runs.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steps_timed: Option<usize>,
    /// Why the trial was shortened or skipped, where it was.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shortened: Option<String>,
    /// Whether the trial was skipped (`shortened` says why): the CPU was
    /// taken unmeasured and the rates are 0. Never cached.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub skipped: bool,
    /// Wall time the trial took (s), warm-up batches included; 0 when the
    /// choice came from the cache.
    pub trial_s: f64,
    /// Whether the choice came from the cache ([`cache_file`](super::cache_file)).
    pub cached: bool,
    /// Wall time from asking for the GPU to its first kernel variant built
    /// and warmed up (s): what a job on the GPU spends before its first
    /// generation beyond the CPU's start-up (`check` estimates from it);
    /// `None` in a cache written before it was measured.
    #[serde(default)]
    pub gpu_startup_s: Option<f64>,
}

impl BackendTrial {
    /// One line for the job's start: the choice and the rates behind it.
    pub fn line(&self) -> String {
        if self.skipped {
            return format!(
                "backend auto chose the CPU without a trial: {}",
                self.shortened.as_deref().unwrap_or("no trial")
            );
        }
        let how = if self.cached {
            "as measured before on this machine".to_string()
        } else {
            format!("measured in {:.2} s", self.trial_s)
        };
        let kernels = match &self.gpu_kernel {
            Some(k) if self.gpu_kernel_rates.len() > 1 => {
                let others: Vec<String> = self
                    .gpu_kernel_rates
                    .iter()
                    .filter(|(v, _)| *v != k)
                    .map(|(v, r)| format!("{v} {r:.2e}"))
                    .collect();
                format!(" with {k} kernels ({})", others.join(", "))
            }
            _ => String::new(),
        };
        let part = match (self.steps_timed, self.gpu_steps_timed) {
            (Some(_), _) => String::new(),
            (None, Some(steps)) => format!(" over each run's first {steps} steps"),
            (None, None) => String::new(),
        };
        let both = match (self.steps_timed, &self.shortened) {
            (Some(steps), Some(why)) => {
                format!(", both over each run's first {steps} steps ({why})")
            }
            (Some(steps), None) => format!(", both over each run's first {steps} steps"),
            (None, _) => String::new(),
        };
        format!(
            "backend auto chose the {}: GPU {:.2e}{kernels}{part}, CPU {:.2e} candidate-steps/s{both} ({how})",
            self.chosen.to_uppercase(),
            self.gpu_rate,
            self.cpu_rate
        )
    }
}

/// Errors of a trial.
#[derive(Debug, thiserror::Error)]
pub enum TrialError {
    /// A path failed to score the trial batch.
    #[error("the {path} trial batch failed: {source}")]
    Eval {
        /// `"gpu"` or `"cpu"`.
        path: &'static str,
        /// What failed.
        source: EvalError,
    },
    /// The interrupt flag ([`TrialWatch::cancel`]) was raised during the
    /// trial: nothing was chosen, cached or written.
    #[error("interrupted during auto's backend trial")]
    Cancelled,
}

impl TrialError {
    /// Whether the trial stopped because it was interrupted.
    pub fn is_cancelled(&self) -> bool {
        matches!(
            self,
            Self::Cancelled
                | Self::Eval {
                    source: EvalError::Cancelled,
                    ..
                }
        )
    }
}

/// What watches `auto`'s trial: a line for each of its stages (what it
/// builds or times, and how far it is), and a flag that, once raised
/// (Ctrl-C), stops it between two stages or, where the evaluator can stop
/// a batch partway, within one ([`Evaluator::set_cancel`]).
#[derive(Clone, Copy)]
pub struct TrialWatch<'a> {
    /// Called with one line per stage.
    pub progress: &'a dyn Fn(&str),
    /// Raised to stop the trial.
    pub cancel: Option<&'a Arc<AtomicBool>>,
}

impl TrialWatch<'_> {
    /// Nothing said, never cancelled.
    pub const SILENT: TrialWatch<'static> = TrialWatch {
        progress: &|_| {},
        cancel: None,
    };

    pub(super) fn say(&self, line: &str) {
        (self.progress)(line);
    }

    pub(super) fn check(&self) -> Result<(), TrialError> {
        match self.cancel {
            Some(flag) if flag.load(Ordering::SeqCst) => Err(TrialError::Cancelled),
            _ => Ok(()),
        }
    }

    pub(super) fn arm(&self, evaluator: &mut dyn Evaluator) {
        if let Some(flag) = self.cancel {
            evaluator.set_cancel(flag.clone());
        }
    }
}
