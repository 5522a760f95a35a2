//! The one interface every search method implements: ask for a batch of
//! candidates, tell their costs (argmin's `Solver`, in the ask/tell form of
//! pycma and evosax).
//!
//! A method is pure state transitions: no clock, no files, no evaluation, all
//! randomness from the RNG the caller passes. What every method shares — the
//! limits, the observers, Ctrl-C, checkpoints and resume, the polish after —
//! lives once in the [`super::Executor`]. Because asking and telling are two
//! calls, a caller can ask several searches for their batches, score all of
//! them in one dispatch, and tell each its share of the costs.

use rand_chacha::ChaCha8Rng;
use serde_json::Value;

use super::checkpoint::Fingerprint;
use super::genes::GeneSpec;
use super::methods::Method;
use super::report::TerminationReason;
use super::settings::SearchSettings;

/// A search method driven by the [`super::Executor`].
///
/// Candidates are in scale space (see [`super::genes`]) and always inside the
/// genes' scale-space bounds: a method never asks for a point outside them.
pub trait Solver {
    /// Which method this is.
    fn method(&self) -> Method;

    /// The settings the method was built from: the executor reads the
    /// limits, the seed and the checkpoints' cadence there.
    fn settings(&self) -> &SearchSettings;

    /// The genes searched, in genome order.
    fn genes(&self) -> &[GeneSpec];

    /// Scale-space bounds per gene.
    fn bounds(&self) -> &[(f64, f64)];

    /// Adds the method's own items to what a checkpoint must match (its
    /// operators or step sizes; not the genes, batch size or seed, which
    /// the executor adds).
    fn fingerprint(&self, fingerprint: &mut Fingerprint);

    /// The next batch to score. The first call gives the first batch.
    ///
    /// Only the batch in hand may change: a batch whose scoring is
    /// interrupted is dropped, the RNG put back, and the next `ask` must give
    /// the same batch again.
    fn ask(&mut self, rng: &mut ChaCha8Rng) -> &[Vec<f64>];

    /// The costs of the batch last asked, in its order (sanitized: finite,
    /// lower is better). May draw from `rng` (a restart's new start).
    fn tell(&mut self, rng: &mut ChaCha8Rng, costs: &[f64]);

    /// The candidates the method holds now, with their costs (the GA's
    /// population; CMA-ES's last batch): what a generation's report, the
    /// final elite's spread and the polish's starts are taken from.
    fn population(&self) -> (&[Vec<f64>], &[f64]);

    /// Why the method has nothing more to do, if so (the executor's limits
    /// are checked apart).
    fn terminate(&self) -> Option<TerminationReason> {
        None
    }

    /// The method's state between two batches, for a checkpoint. Floats are
    /// kept to the bit by the checkpoint's writer.
    fn state(&self) -> Value;

    /// Continues from a state [`Self::state`] gave; the error says what does
    /// not fit (a hand-edited or foreign checkpoint).
    fn restore(&mut self, state: Value) -> Result<(), String>;

    /// Takes in candidates from another search (an island's neighbour,
    /// [`super::islands`]), scale space and inside the bounds, with their
    /// costs, best first: they replace as many of the worst the method
    /// holds. Called between a `tell` and the next `ask`. `false` when the
    /// method cannot take them (the default).
    fn immigrate(&mut self, _genomes: &[Vec<f64>], _costs: &[f64]) -> bool {
        false
    }

    /// What the method learned that a user should see beside the polish's
    /// results (CMA-ES's covariance), for `result.json`.
    fn summary(&self) -> Option<Value> {
        None
    }
}
