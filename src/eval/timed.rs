//! What `auto`'s backend trial asks of an evaluator beyond scoring.
//!
//! A search only scores ([`Evaluator`]); the trial
//! ([`crate::job::backend::race`]) also makes each path ready before it
//! times it, times a long record's pass over its first steps, tries each
//! GPU kernel variant, and starts the CPU lanes' native builds early. Those
//! hooks live here, apart from [`Evaluator`], so that an evaluator a search
//! runs on need not know about the trial. Every hook has a default that
//! does the plain thing, so an evaluator with nothing to make ready
//! implements [`Timed`] with an empty `impl`.

use super::{Batch, EvalError, Evaluator};

/// An [`Evaluator`] that `auto`'s trial can make ready and time: the CPU
/// and GPU evaluators, and [`super::Remembered`] around either.
pub trait Timed: Evaluator {
    /// Makes ready what scoring `batch` needs, so that a batch timed after
    /// it measures the scoring alone: the GPU builds the kernel that scores
    /// it and runs its first chunk. By default it scores the batch once.
    fn warm_up(&mut self, batch: &Batch) -> Result<(), EvalError> {
        self.fitness(batch).map(|_| ())
    }

    /// Runs the fitness pass of `batch` for its first `steps` steps or so
    /// (whole chunks), its scores never read, and returns the most steps a
    /// run advanced: what `auto`'s trial times a long record's path on
    /// before it knows whether it keeps it. `None` (by default) where the
    /// evaluator cannot stop a pass partway: the trial then times a whole
    /// pass.
    fn fitness_part(&mut self, _batch: &Batch, _steps: usize) -> Result<Option<usize>, EvalError> {
        Ok(None)
    }

    /// Makes ready now what the evaluator would make ready once it pays (the
    /// CPU lanes' native build), so that a timed trial measures the path
    /// the job runs. Nothing by default.
    fn prepare(&mut self) {}

    /// Starts making ready, in the background, what [`Timed::prepare`]
    /// makes ready now (and what the polish's histories run), for a job
    /// long enough to want it: scoring goes on meanwhile as it would
    /// without. Nothing by default.
    fn prepare_soon(&mut self) {}

    /// The kernel variants it can score with, the one it starts with first
    /// (the GPU's [`super::KERNEL_VARIANTS`]); none by default. Which is
    /// fastest depends on the adapter and its driver, so `auto` times each.
    fn kernel_variants(&self) -> &'static [&'static str] {
        &[]
    }

    /// Scores with `variant`, one of [`Timed::kernel_variants`], from now
    /// on (the same values to rounding); any other name changes nothing.
    fn use_kernel_variant(&mut self, _variant: &str) {}
}
