//! An experiment's rows as its CSV holds them ([`ExperimentRows`]), the CSV
//! text, and the R² of its fit.

use std::fmt::Write as _;

use crate::eval::History;

/// R² of the measured output against the measurement over the fit window.
pub fn r_squared(exp: &crate::eval::ExperimentData, hist: &History) -> f64 {
    let w = exp.window.clone();
    let n = w.len() as f64;
    let mean = exp.measured[w.clone()].iter().sum::<f64>() / n;
    let mut ss_res = 0.0;
    let mut ss_tot = 0.0;
    for k in w {
        let m = hist.outputs[exp.output].get(k).copied().unwrap_or(f64::NAN);
        ss_res += (m - exp.measured[k]).powi(2);
        ss_tot += (exp.measured[k] - mean).powi(2);
    }
    1.0 - ss_res / ss_tot
}

/// A record's residual over its fit window set against its noise: what a
/// fitted record and a validation record both report.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ResidualFloor {
    /// The residuals over the fit window (`None` for fewer than two).
    pub residuals: Option<Vec<f64>>,
    /// Their RMS, in the measured output's unit.
    pub rms: Option<f64>,
    /// The record's noise estimated from the record itself.
    pub noise_estimate: Option<f64>,
    /// The mean square residual as a multiple of the floor that noise
    /// implies, `(rms / noise)²`.
    pub cost_over_noise_floor: Option<f64>,
}

impl ResidualFloor {
    /// `exp`'s residual in `hist` against `exp`'s noise.
    pub fn of(exp: &crate::eval::ExperimentData, hist: &History) -> Self {
        let residuals = crate::eval::window_residuals(exp, hist).filter(|r| r.len() > 1);
        let rms = residuals
            .as_ref()
            .map(|r| (r.iter().map(|x| x * x).sum::<f64>() / r.len() as f64).sqrt());
        let noise_estimate = exp.noise_estimate();
        let cost_over_noise_floor = match (rms, noise_estimate) {
            (Some(r), Some(n)) if n > 0.0 => Some((r / n).powi(2)),
            _ => None,
        };
        Self {
            residuals,
            rms,
            noise_estimate,
            cost_over_noise_floor,
        }
    }
}

/// An experiment's rows as its CSV holds them, in full precision: record
/// and model time, the measurement, every model output, the residual of the
/// measured output and whether the sample is in the fit window.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ExperimentRows {
    /// Record time of each sample (s).
    pub t_record: Vec<f64>,
    /// Model time of each sample (s): record time + the clock offset.
    pub t_model: Vec<f64>,
    /// The measurement, in the measured output's unit.
    pub measured: Vec<f64>,
    /// Every model output at each sample, `[sample][output]` (NaN past a
    /// run that stopped short).
    pub model: Vec<Vec<f64>>,
    /// Measured output − measurement.
    pub residual: Vec<f64>,
    /// Whether each sample is scored.
    pub in_fit_window: Vec<bool>,
}

impl ExperimentRows {
    /// The rows of `exp` against the run `hist` at clock offset `offset`.
    pub fn of(exp: &crate::eval::ExperimentData, hist: &History, offset: f64) -> Self {
        let n = hist.t.len().min(exp.measured.len());
        let value = |o: usize, k: usize| {
            hist.outputs
                .get(o)
                .and_then(|h| h.get(k))
                .copied()
                .unwrap_or(f64::NAN)
        };
        let t_record: Vec<f64> = (0..n).map(|k| exp.t_first + k as f64 * exp.dt).collect();
        Self {
            t_model: t_record.iter().map(|t| t + offset).collect(),
            t_record,
            measured: exp.measured[..n].to_vec(),
            model: (0..n)
                .map(|k| (0..hist.outputs.len()).map(|o| value(o, k)).collect())
                .collect(),
            residual: (0..n)
                .map(|k| value(exp.output, k) - exp.measured[k])
                .collect(),
            in_fit_window: (0..n).map(|k| exp.window.contains(&k)).collect(),
        }
    }
}

/// The experiment's CSV ([`ExperimentRows`]), the model outputs named
/// `model_<name>_<unit>` from the rig.
pub(super) fn experiment_csv(
    exp: &crate::eval::ExperimentData,
    rows: &ExperimentRows,
    outputs: &[(String, String)],
    stop: &std::sync::atomic::AtomicBool,
) -> Option<String> {
    let (name0, unit0) = &outputs[exp.output];
    let mut s = format!("t_record_s,t_model_s,measured_{name0}_{unit0}");
    for (name, unit) in outputs {
        let _ = write!(s, ",model_{name}_{unit}");
    }
    let _ = writeln!(s, ",residual_{unit0},in_fit_window");
    for k in 0..rows.t_record.len() {
        // A record of millions of rows takes seconds: an interrupt is
        // honoured every 65 536 of them.
        if k % 65_536 == 0 && stop.load(std::sync::atomic::Ordering::SeqCst) {
            return None;
        }
        let _ = write!(
            s,
            "{:.9e},{:.9e},{:.6e}",
            rows.t_record[k], rows.t_model[k], rows.measured[k]
        );
        for o in 0..outputs.len() {
            let v = rows.model[k].get(o).copied().unwrap_or(f64::NAN);
            let _ = write!(s, ",{v:.6e}");
        }
        let _ = writeln!(
            s,
            ",{:.6e},{}",
            rows.residual[k],
            u8::from(rows.in_fit_window[k]),
        );
    }
    Some(s)
}
