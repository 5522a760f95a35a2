//! Validation records ([`Campaign::validation`]): simulated at the fitted
//! values, never fitted, scored as the fit's records are, each written as
//! `validation_<stem>.csv` with the fit CSVs' columns, and compared with the
//! estimation records ([`ValidationSummary`], `result.json`'s `validation`).
//!
//! The runs are the f64 CPU reference ([`crate::eval::simulate_history`]),
//! whatever evaluator the fit ran on: the job's evaluator is built for the
//! fitted records only, and the reference is the one path `rigfit validate`
//! can run again after the fact to the same bits.

use serde::Serialize;

use super::rows::{ExperimentRows, ResidualFloor, experiment_csv, r_squared};
use crate::campaign::{Campaign, file_stem};

/// A validation record's cost over its noise floor may be this many times
/// the worst estimation record's before it is flagged. At the noise floor
/// both are about 1; twice the floor means the misfit the fit did not see
/// has a mean square at least as large as the record's noise itself, more
/// than a noise estimate's error (a few to a few tens of per cent) explains.
pub const VALIDATION_FACTOR: f64 = 2.0;

/// The prefix of every validation warning in `result.json`'s `warnings`
/// (so that `rigfit validate` replaces them).
pub const WARNING_PREFIX: &str = "validation record ";

/// The prefix of every validation flag in the verdict.
pub const FLAG_PREFIX: &str = "validation ";

/// One validation record, simulated at the fitted values.
#[derive(Debug, Clone, Serialize)]
pub struct ValidationFit {
    /// Record name (`<experiment>.<output>` for a channel).
    pub name: String,
    /// R² of the measured output over the record's fit window.
    pub r2: f64,
    /// `1 − R²`.
    pub one_minus_r2: f64,
    /// Root mean square of the residual (model − measurement) over the fit
    /// window, in the measured output's unit; `None` for a run that blew up.
    pub residual_rms: Option<f64>,
    /// The measured output's unit.
    pub unit: String,
    /// The record's noise (standard deviation) estimated from the record.
    pub noise_estimate: Option<f64>,
    /// `(residual_rms / noise_estimate)²` (about 1 at the noise floor).
    pub cost_over_noise_floor: Option<f64>,
    /// The CSV with the measurement, every model output and the residual.
    pub csv: String,
    /// The CSV's rows in full precision; not in `result.json`.
    #[serde(skip)]
    pub rows: ExperimentRows,
}

/// `result.json`'s `validation`.
#[derive(Debug, Clone, Serialize)]
pub struct ValidationSummary {
    /// Per validation record.
    pub experiments: Vec<ValidationFit>,
    /// The worst (largest) cost over the noise floor among the estimation
    /// records: what each validation record is compared with; `None` where
    /// no estimation record's noise could be estimated.
    pub estimation_cost_over_noise_floor: Option<f64>,
    /// [`VALIDATION_FACTOR`]: the ratio of the two above which a validation
    /// record is flagged.
    pub factor: f64,
}

impl ValidationFit {
    /// The record in one line, as the printed summaries show it.
    pub fn line(&self) -> String {
        let mut t = format!(
            "validation {}: R² = {:.6} (1 − R² = {:.3e}",
            self.name, self.r2, self.one_minus_r2
        );
        if let Some(r) = self.residual_rms {
            t.push_str(&format!("; residual RMS {r:.4e} {}", self.unit));
        }
        match (self.noise_estimate, self.cost_over_noise_floor) {
            (Some(n), Some(k)) => t.push_str(&format!(
                ", record noise ≈ {n:.3e} {}: {k:.2}× the floor",
                self.unit
            )),
            _ => t.push_str("; noise floor unknown"),
        }
        t.push_str(") — not fitted");
        t
    }
}

/// The CSV file of validation record `name`.
pub fn validation_csv_name(name: &str) -> String {
    format!("validation_{}.csv", file_stem(name))
}

/// Every validation record of `v` simulated at `genome` (its genes' fitted
/// values, [`Campaign::validation_genome`]), with its CSV text; `None` once
/// `stop` is raised.
pub fn simulate(
    v: &Campaign,
    genome: &[f64],
    stop: &std::sync::atomic::AtomicBool,
) -> Option<Vec<(ValidationFit, String)>> {
    let full = v.full_params(genome);
    let outputs = v.model.output_names();
    let mut out = Vec::new();
    for (e, exp) in v.problem.experiments.iter().enumerate() {
        if stop.load(std::sync::atomic::Ordering::SeqCst) {
            return None;
        }
        let (params, offset) = &full[e];
        let hist = crate::eval::simulate_history(&v.problem, e, params, *offset);
        let rows = ExperimentRows::of(exp, &hist, *offset);
        let text = experiment_csv(exp, &rows, outputs, stop)?;
        let floor = ResidualFloor::of(exp, &hist);
        let r2 = r_squared(exp, &hist);
        let fit = ValidationFit {
            name: exp.name.clone(),
            r2,
            one_minus_r2: 1.0 - r2,
            residual_rms: floor.rms,
            unit: outputs
                .get(exp.output)
                .map_or(String::new(), |o| o.1.clone()),
            noise_estimate: floor.noise_estimate,
            cost_over_noise_floor: floor.cost_over_noise_floor,
            csv: validation_csv_name(&exp.name),
            rows,
        };
        out.push((fit, text));
    }
    Some(out)
}

/// The summary of `fits` against the estimation records' costs over their
/// noise floors (`estimation`, `None` where unknown), with its warnings and
/// verdict flags.
pub fn summarise(
    fits: Vec<ValidationFit>,
    estimation: &[Option<f64>],
) -> (ValidationSummary, Vec<String>, Vec<String>) {
    let known: Vec<f64> = estimation.iter().flatten().copied().collect();
    let worst = (known.len() == estimation.len() && !known.is_empty())
        .then(|| known.iter().copied().fold(f64::NEG_INFINITY, f64::max))
        .filter(|x| x.is_finite());
    let mut warnings = Vec::new();
    let mut flags = Vec::new();
    for f in &fits {
        let name = crate::base::text::echo_bare(&f.name);
        let Some(rms) = f.residual_rms else {
            warnings.push(format!(
                "{WARNING_PREFIX}'{name}': the run at the fitted values blew up or stopped \
                 short: the fitted rig does not predict this record at all"
            ));
            flags.push(format!("{FLAG_PREFIX}{name}: run blew up"));
            continue;
        };
        match (f.cost_over_noise_floor, worst) {
            (Some(k), Some(w)) if k > VALIDATION_FACTOR * w => {
                warnings.push(format!(
                    "{WARNING_PREFIX}'{name}' is fitted {:.2}× its noise floor (residual RMS \
                     {rms:.4e} {}), over {VALIDATION_FACTOR}× the worst estimation record's \
                     {w:.2}×: the fitted values do not carry over to it (over-fitting, or a rig \
                     that does not generalise: check what differs in this record)",
                    k, f.unit
                ));
                flags.push(format!(
                    "{FLAG_PREFIX}{name}: {:.1}× the fit's misfit",
                    k / w
                ));
            }
            (Some(_), Some(_)) => {}
            (None, _) => warnings.push(format!(
                "{WARNING_PREFIX}'{name}': its noise could not be estimated (a fit window \
                 too short), so its cost over the noise floor is unknown; R² = {:.5}",
                f.r2
            )),
            (Some(_), None) => warnings.push(format!(
                "{WARNING_PREFIX}'{name}': an estimation record's noise is unknown, so its \
                 cost over the noise floor cannot be compared with the fit's"
            )),
        }
    }
    let summary = ValidationSummary {
        experiments: fits,
        estimation_cost_over_noise_floor: worst,
        factor: VALIDATION_FACTOR,
    };
    (summary, warnings, flags)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fit(name: &str, rms: Option<f64>, noise: Option<f64>) -> ValidationFit {
        ValidationFit {
            name: name.into(),
            r2: 0.99,
            one_minus_r2: 0.01,
            residual_rms: rms,
            unit: "N".into(),
            noise_estimate: noise,
            cost_over_noise_floor: rms.zip(noise).map(|(r, n)| (r / n).powi(2)),
            csv: validation_csv_name(name),
            rows: ExperimentRows::default(),
        }
    }

    #[test]
    fn a_record_worse_than_the_factor_is_flagged_and_one_within_it_is_not() {
        let fits = vec![
            fit("near", Some(1.3), Some(1.0)),
            fit("far", Some(2.0), Some(1.0)),
            fit("quiet", Some(1.0), None),
            fit("blown", None, Some(1.0)),
        ];
        let (s, warnings, flags) = summarise(fits, &[Some(1.0), Some(0.9)]);
        assert_eq!(s.estimation_cost_over_noise_floor, Some(1.0));
        assert_eq!(s.factor, VALIDATION_FACTOR);
        // 1.69 < 2 × 1.0: not flagged; 4.0 > 2: flagged.
        assert_eq!(warnings.len(), 3, "{warnings:?}");
        assert!(warnings[0].contains("'far'") && warnings[0].contains("4.00×"));
        assert!(warnings[1].contains("'quiet'") && warnings[1].contains("unknown"));
        assert!(warnings[2].contains("'blown'"));
        assert!(warnings.iter().all(|w| w.starts_with(WARNING_PREFIX)));
        assert_eq!(
            flags,
            [
                "validation far: 4.0× the fit's misfit",
                "validation blown: run blew up"
            ]
        );
        let json = serde_json::to_value(&s).unwrap();
        assert_eq!(json["experiments"][0]["csv"], "validation_near.csv");
        assert!(json["experiments"][0].get("rows").is_none());
    }

    #[test]
    fn an_unknown_estimation_floor_is_said_not_guessed() {
        let (s, warnings, flags) = summarise(vec![fit("w", Some(5.0), Some(1.0))], &[None]);
        assert_eq!(s.estimation_cost_over_noise_floor, None);
        assert!(flags.is_empty());
        assert!(warnings[0].contains("cannot be compared"), "{warnings:?}");
    }
}
