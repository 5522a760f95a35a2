//! Residual vectors for least-squares work (the local polish and the
//! parameter uncertainty), computed on the host from the scored output of
//! evaluator histories ([`super::Evaluator::scored_outputs`] or a full
//! [`History`]): the same batch gives the same outputs, hence the same
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
    scored_residuals(exp, history.outputs.get(exp.output)?)
}

/// [`window_residuals`] of the scored output alone, `out` over samples
/// `0..window.end` (one experiment's [`super::Evaluator::scored_outputs`]).
pub fn scored_residuals(exp: &ExperimentData, out: &[f64]) -> Option<Vec<f64>> {
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
    Some(
        exp.window
            .clone()
            .map(|k| out[k] - exp.measured[k])
            .collect(),
    )
}
