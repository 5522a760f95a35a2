//! Residual vectors for least-squares work (the local polish and the
//! parameter uncertainty), computed on the host from evaluator histories.
//!
//! Any [`super::Evaluator`] returns histories, so residuals need nothing new
//! from the kernels: the same batch gives the same histories, hence the same
//! residual bits, on every evaluator that is deterministic today.

use super::{ExperimentData, History};

/// `model − measured` of the measured output ([`ExperimentData::output`]) at each sample of the experiment's fit
/// window, or `None` when the run blew up: a NaN output or one beyond
/// [`ExperimentData::blowup_limit`] anywhere before the window's end (the guard
/// of [`super::FitnessAccumulator`]), or a history too short to cover the window.
///
/// The sum of squares divided by [`ExperimentData::ss_tot`] is the run's
/// `1 − R²`.
pub fn window_residuals(exp: &ExperimentData, history: &History) -> Option<Vec<f64>> {
    let out = history.outputs.get(exp.output)?;
    if out.len() < exp.window.end {
        return None;
    }
    let limit = exp.blowup_limit();
    if out[..exp.window.end]
        .iter()
        .any(|m| m.is_nan() || m.abs() > limit)
    {
        return None;
    }
    Some(exp.window.clone().map(|k| out[k] - exp.force[k]).collect())
}
