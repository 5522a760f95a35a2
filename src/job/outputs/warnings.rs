//! The warnings a job's summary carries: parameters not determined, genes
//! at a bound, a search stopped while still improving or polished starts
//! that disagree, and a misfit that is more than noise or has a shape.

use super::{ExperimentFit, ParamSummary};
use crate::campaign::Campaign;
use crate::search::{AtBound, PolishOutcome, SearchOutcome, TerminationReason, Uncertainty};

/// Every free parameter not determined, with the sensitivity as the reason
/// (the intervals stay, as the covariance gives them, for the record).
pub(super) fn not_determined_where_sensitive(
    parameters: &mut [ParamSummary],
    s: &crate::job::sensitivity::Sensitivity,
) {
    let Some(note) = s.note() else {
        return;
    };
    for p in parameters.iter_mut().filter(|p| p.determined.is_some()) {
        p.determined = Some(false);
        let note = note.clone();
        p.uncertainty_note = Some(match p.uncertainty_note.take() {
            Some(n) => format!("{n}; {note}"),
            None => note,
        });
    }
}

/// One warning per gene the polish left at a bound, naming the bound to widen.
pub(super) fn at_bound_warnings(
    campaign: &Campaign,
    uncertainty: Option<&Uncertainty>,
) -> Vec<String> {
    let Some(u) = uncertainty else {
        return Vec::new();
    };
    u.genes
        .iter()
        .zip(&campaign.genes)
        .filter_map(|(g, spec)| {
            let (side, bound) = match g.at_bound? {
                AtBound::Lower => ("lower", spec.lower),
                AtBound::Upper => ("upper", spec.upper),
            };
            Some(format!(
                "{} = {:.6e} sits at its {side} bound {bound:.6e}: the record may want a value \
                 beyond it, so it is not determined and its 95 % interval is open on that side; \
                 widen its range and run again",
                g.name, g.value
            ))
        })
        .collect()
}

/// Relative fall of the GA's best cost over the last generations above which
/// a search that stopped on its generation or time limit was still improving.
pub const STILL_IMPROVING: f64 = 5e-3;

/// Relative spread of the polished starts' costs above which they found
/// different minima.
pub const STARTS_DISAGREE: f64 = 1e-2;

/// Warnings on how the search ended: stopped by a limit while the search's best
/// was still falling, or polished starts that ended in different minima;
/// each with the verdict's short flag for it.
pub(super) fn search_warnings(
    outcome: &SearchOutcome,
    polish: Option<&PolishOutcome>,
) -> Vec<(&'static str, String)> {
    let mut out = Vec::new();
    let limited = matches!(
        outcome.termination,
        TerminationReason::MaxGenerations
            | TerminationReason::Timeout
            | TerminationReason::MaxEvaluations
    );
    if limited && let Some(last) = outcome.history.last() {
        let window = (outcome.history.len() / 10).max(5);
        let then = outcome.history[outcome.history.len().saturating_sub(window + 1)].best_cost;
        let fall = 1.0 - last.best_cost / then;
        if then.is_finite() && fall > STILL_IMPROVING {
            out.push((
                "search still improving when it stopped",
                format!(
                    "the search was still improving when it stopped ({}): its best 1 − R² fell \
                     {:.2} % over the last {window} generations; more generations or a larger \
                     population may fit better, and the intervals assume the optimum was reached",
                    outcome.termination,
                    100.0 * fall
                ),
            ));
        }
    }
    if let Some(p) = polish {
        let costs: Vec<f64> = p
            .starts
            .iter()
            .map(|s| s.polished)
            .filter(|c| c.is_finite())
            .collect();
        let best = costs.iter().copied().fold(f64::INFINITY, f64::min);
        let worst = costs.iter().copied().fold(0.0, f64::max);
        if costs.len() > 1 && worst > best * (1.0 + STARTS_DISAGREE) {
            out.push((
                "polish starts ended at different costs",
                format!(
                    "the polish's {} starts ended at different costs (1 − R² from {best:.4e} to \
                     {worst:.4e}): the cost has several minima near the {}'s best; the result is \
                     the lowest found, and a longer search may find a lower one",
                    costs.len(),
                    outcome.method.label()
                ),
            ));
        }
    }
    out
}

/// The fit's mean square above which, as a multiple of the noise floor the
/// record's own noise implies, the misfit is more than noise.
pub const SYSTEMATIC_MISFIT: f64 = 4.0;

/// Lag-one autocorrelation of the residual above which it is not white: the
/// misfit has a shape, whatever its size against the noise.
pub const NOT_WHITE: f64 = 0.2;

/// `Σ (r_k − r̄)(r_{k+1} − r̄) / Σ (r_k − r̄)²`; `None` for a constant residual.
pub(super) fn lag_one_autocorrelation(r: &[f64]) -> Option<f64> {
    let mean = r.iter().sum::<f64>() / r.len() as f64;
    let var: f64 = r.iter().map(|x| (x - mean) * (x - mean)).sum();
    let cov: f64 = r.windows(2).map(|w| (w[0] - mean) * (w[1] - mean)).sum();
    (var > 0.0).then(|| cov / var)
}

/// One warning per experiment whose residual is well above the record's noise
/// or is not white.
pub(super) fn misfit_warnings(experiments: &[ExperimentFit]) -> Vec<String> {
    let shaped = experiments.iter().filter_map(|e| {
        let rho = e.residual_autocorrelation.filter(|r| *r > NOT_WHITE)?;
        Some(format!(
            "{}: the residual is not white (lag-one autocorrelation {rho:.2}, about 0 for noise): \
             part of the misfit has a shape the rig does not follow, and the intervals, which \
             assume white residuals, are too narrow",
            e.name
        ))
    });
    let large = experiments
        .iter()
        .filter_map(|e| {
            let k = e.cost_over_noise_floor.filter(|k| *k > SYSTEMATIC_MISFIT)?;
            Some(format!(
                "{}: the residual's RMS ({:.3e} {unit}) is {:.1}× the record's noise ({:.3e} {unit}, \
                 estimated from the record): the misfit is more than noise (a rig that cannot \
                 follow the record, or a search that did not finish), and the intervals assume it is not",
                e.name,
                e.residual_rms.unwrap_or(f64::NAN),
                k.sqrt(),
                e.noise_estimate.unwrap_or(f64::NAN),
                unit = e.unit
            ))
        });
    large.chain(shaped).collect()
}
