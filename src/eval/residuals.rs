//! Residual vectors for least-squares work (the local polish and the
//! parameter uncertainty), computed on the host from evaluator histories.
//!
//! Any [`super::Evaluator`] returns histories, so residuals need nothing new
//! from the kernels: the same batch gives the same histories, hence the same
//! residual bits, on every evaluator that is deterministic today.

use super::{ExperimentData, History};

/// `model − measured` of output 0 at each sample of the experiment's fit
/// window, or `None` when the run blew up: a NaN output or one beyond
/// [`ExperimentData::blowup_limit`] anywhere before the window's end (the guard
/// of [`super::FitnessAccumulator`]), or a history too short to cover the window.
///
/// The sum of squares divided by [`ExperimentData::ss_tot`] is the run's
/// `1 − R²`.
pub fn window_residuals(exp: &ExperimentData, history: &History) -> Option<Vec<f64>> {
    let out = history.outputs.first()?;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::{score_one, simulate_history};
    use crate::fixtures::reference_problem;
    use crate::model::tensile::REFERENCE;

    #[test]
    fn sum_of_squares_over_ss_tot_is_the_fitness() {
        let mut problem = reference_problem();
        problem.experiments[0].window = 200..1500;
        let mut p = REFERENCE;
        p[crate::model::tensile::ix::K1] *= 1.1;
        let h = simulate_history(&problem, 0, &p, 0.0);
        let exp = &problem.experiments[0];
        let r = window_residuals(exp, &h).unwrap();
        assert_eq!(r.len(), 1300);
        let ssr: f64 = r.iter().map(|x| x * x).sum();
        let (fit, diverged) = score_one(&problem, 0, &p, 0.0);
        assert!(!diverged);
        assert!(
            (ssr / exp.ss_tot() / fit - 1.0).abs() < 1e-12,
            "{ssr} vs {fit}"
        );
    }

    #[test]
    fn a_blown_up_or_short_run_has_no_residuals() {
        let problem = reference_problem();
        let exp = &problem.experiments[0];
        let mut h = simulate_history(&problem, 0, &REFERENCE, 0.0);
        h.outputs[0][10] = f64::NAN;
        assert!(window_residuals(exp, &h).is_none());
        h.outputs[0].truncate(5);
        assert!(window_residuals(exp, &h).is_none());
    }
}
