//! One parameter's profile read: where it crosses the likelihood-ratio
//! threshold on each side, its interval and its flag.

use serde::Serialize;

use crate::search::genes::GeneSpec;

/// A profile interval whose width (in the gene's scale) differs from the
/// covariance interval's by more than this factor, either way, is flagged
/// [`ProfileFlag::Disagrees`]: the cost is far from quadratic over the
/// interval, and the profile is the one to trust.
pub const DISAGREE_FACTOR: f64 = 2.0;

/// A grid point whose `χ²` lies this far below the optimum's (in `χ²` units,
/// a tenth of a one-standard-error change) means the polish did not reach
/// the optimum: [`ProfileFlag::LowerCost`].
pub const LOWER_COST_TOL: f64 = 0.1;

/// What a parameter's profile says beyond its interval.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum ProfileFlag {
    /// `Δχ²` stays below the threshold on both sides out to both bounds.
    #[serde(rename = "not identifiable")]
    NotIdentifiable,
    /// The profile crosses the threshold on one side only; it reaches the
    /// bound on the other.
    #[serde(rename = "one-sided")]
    OneSided,
    /// The profile interval's width differs from the covariance interval's
    /// by more than [`DISAGREE_FACTOR`].
    #[serde(rename = "disagrees")]
    Disagrees,
    /// A grid point found a lower cost than the optimum (by more than
    /// [`LOWER_COST_TOL`] in `χ²`).
    #[serde(rename = "lower cost found")]
    LowerCost,
}

impl ProfileFlag {
    /// The flag as `result.json` writes it.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::NotIdentifiable => "not identifiable",
            Self::OneSided => "one-sided",
            Self::Disagrees => "disagrees",
            Self::LowerCost => "lower cost found",
        }
    }
}

/// One parameter's profile in `result.json` (`profiles.parameters[i]`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ParameterProfile {
    /// The parameter (gene) name.
    pub name: String,
    /// Its SI unit (empty where the caller gave none).
    pub unit: String,
    /// The fitted value (unit above).
    pub value: f64,
    /// The values it was held at, ascending (unit above); the fitted value
    /// is one of them.
    pub grid: Vec<f64>,
    /// The cost (sum of squared weighted residuals, the joint `1 − R²`)
    /// re-optimised over the other parameters at each grid value; `null`
    /// where the run blew up.
    pub cost: Vec<Option<f64>>,
    /// `χ² − χ²_min` at each grid value, `χ² = Σ_e SSR_e / s_e²` with each
    /// experiment's residual variance `s_e²` at the optimum.
    pub delta_chi2: Vec<Option<f64>>,
    /// The threshold `q` on `Δχ²`: the square of the covariance interval's
    /// quantile (`1.96² = 3.84`).
    pub threshold: f64,
    /// The 95 % profile interval `[lo, hi]` (unit above), each end located
    /// by interpolating the signed root `±√Δχ²` linearly between grid
    /// values; an end is `null` where the profile stays below the threshold
    /// out to the bound, the whole interval `null` where it does on both.
    pub interval: Option<[Option<f64>; 2]>,
    /// The covariance 95 % interval the polish reported, for comparison.
    pub covariance_interval: Option<[f64; 2]>,
    /// What the profile says beyond its interval; `null` when nothing.
    pub flag: Option<ProfileFlag>,
    /// Whether each grid value's re-optimisation converged.
    pub converged: Vec<bool>,
}

impl ParameterProfile {
    /// The warning a person reads in `result.json`'s `warnings`.
    pub fn warning(&self) -> Option<String> {
        let name = &self.name;
        let show = |v: Option<f64>| v.map_or("open".to_string(), |v| format!("{v:.4e}"));
        Some(match self.flag? {
            ProfileFlag::NotIdentifiable => format!(
                "{name}: profile is flat to both bounds: not identifiable from these records"
            ),
            ProfileFlag::OneSided => {
                let [lo, hi] = self.interval.unwrap_or([None, None]);
                let (limit, bound) = if lo.is_some() {
                    ("a lower", "upper")
                } else {
                    ("an upper", "lower")
                };
                format!(
                    "{name}: profile stays below the 95 % threshold out to its {bound} bound: \
                     the records give {limit} limit ({}), not a value",
                    show(lo.or(hi))
                )
            }
            ProfileFlag::Disagrees => {
                let [lo, hi] = self.interval.unwrap_or([None, None]);
                let cov = self
                    .covariance_interval
                    .map_or("none".into(), |[a, b]| format!("[{a:.4e}, {b:.4e}]"));
                format!(
                    "{name}: profile interval [{}, {}] and covariance interval {cov} differ in \
                     width by more than {DISAGREE_FACTOR}×: the cost is not quadratic there; \
                     trust the profile",
                    show(lo),
                    show(hi)
                )
            }
            ProfileFlag::LowerCost => {
                let (k, c) = self
                    .cost
                    .iter()
                    .enumerate()
                    .filter_map(|(k, c)| c.map(|c| (k, c)))
                    .min_by(|a, b| a.1.total_cmp(&b.1))?;
                format!(
                    "{name}: profile found a lower cost ({c:.6e}) at {name} = {:.6e} than \
                     the fit's optimum: the polish stopped short of the optimum; run the job \
                     again with more polish iterations or starts",
                    self.grid[k]
                )
            }
        })
    }

    /// The verdict's short flag.
    pub fn short_flag(&self) -> Option<String> {
        self.flag
            .map(|f| format!("profile of {}: {}", self.name, f.as_str()))
        // Keep in step with `job::verdict::PROFILE_FLAG_PREFIX`.
    }
}

/// One grid point as the reading sees it (scale space).
#[derive(Debug, Clone, Copy)]
pub(super) struct Sample {
    pub at: f64,
    pub chi2: Option<f64>,
    pub cost: Option<f64>,
    pub converged: bool,
}

/// Where `Δχ²` first rises above `q` walking out from the optimum at index
/// `centre` (right: towards larger values), interpolating the root `√Δχ²`
/// linearly between the last point below and the first above (exact for a
/// quadratic profile); `None` when it does not within the samples.
pub(super) fn crossing(
    at: &[f64],
    delta: &[Option<f64>],
    centre: usize,
    q: f64,
    right: bool,
) -> Option<f64> {
    let order: Vec<usize> = if right {
        (centre..at.len()).collect()
    } else {
        (0..=centre).rev().collect()
    };
    let mut last: Option<(f64, f64)> = None;
    for k in order {
        let Some(d) = delta[k] else { continue };
        let root = d.max(0.0).sqrt();
        if d > q {
            return Some(match last {
                Some((a, r)) => a + (q.sqrt() - r) / (root - r) * (at[k] - a),
                None => at[k],
            });
        }
        last = Some((at[k], root));
    }
    None
}

/// The samples of one gene in ascending order, the index of the optimum
/// among them and `Δχ²` of each against the lowest `χ²` (the optimum's or
/// a lower point's).
pub(super) fn deltas(
    samples: &mut [Sample],
    centre_at: f64,
    chi2_opt: f64,
) -> (usize, Vec<Option<f64>>) {
    samples.sort_by(|a, b| a.at.total_cmp(&b.at));
    let centre = samples
        .iter()
        .position(|s| s.at == centre_at)
        .unwrap_or(samples.len() / 2);
    let min = samples
        .iter()
        .filter_map(|s| s.chi2)
        .fold(chi2_opt, f64::min);
    let delta = samples.iter().map(|s| s.chi2.map(|c| c - min)).collect();
    (centre, delta)
}

/// Reads one gene's profile: its interval and flag.
pub(super) struct Reading<'a> {
    pub gene: &'a GeneSpec,
    pub unit: String,
    pub centre_at: f64,
    /// The fitted value (unit).
    pub value: f64,
    pub chi2_opt: f64,
    pub q: f64,
    /// The covariance standard error in scale space.
    pub std_error_scaled: Option<f64>,
    pub covariance_interval: Option<[f64; 2]>,
}

impl Reading<'_> {
    pub(super) fn read(&self, mut samples: Vec<Sample>) -> ParameterProfile {
        let (centre, delta) = deltas(&mut samples, self.centre_at, self.chi2_opt);
        let at: Vec<f64> = samples.iter().map(|s| s.at).collect();
        let lo = crossing(&at, &delta, centre, self.q, false);
        let hi = crossing(&at, &delta, centre, self.q, true);
        let lower = samples
            .iter()
            .filter_map(|s| s.chi2)
            .any(|c| c < self.chi2_opt - LOWER_COST_TOL);
        let flag = if lower {
            Some(ProfileFlag::LowerCost)
        } else {
            match (lo, hi) {
                (None, None) => Some(ProfileFlag::NotIdentifiable),
                (None, Some(_)) | (Some(_), None) => Some(ProfileFlag::OneSided),
                (Some(a), Some(b)) => {
                    let cov = self.std_error_scaled.map(|s| 2.0 * super::super::Z95 * s);
                    let apart = cov.is_none_or(|c| {
                        let r = (b - a) / c;
                        !(r.is_finite() && (1.0 / DISAGREE_FACTOR..=DISAGREE_FACTOR).contains(&r))
                    });
                    apart.then_some(ProfileFlag::Disagrees)
                }
            }
        };
        let back = |y: f64| self.gene.to_value(y);
        let interval = match (lo, hi) {
            (None, None) => None,
            (a, b) => Some([a.map(back), b.map(back)]),
        };
        ParameterProfile {
            name: self.gene.name.clone(),
            unit: self.unit.clone(),
            value: self.value,
            grid: at.iter().map(|&a| back(a)).collect(),
            cost: samples.iter().map(|s| s.cost).collect(),
            delta_chi2: delta,
            threshold: self.q,
            interval,
            covariance_interval: self.covariance_interval,
            flag,
            converged: samples.iter().map(|s| s.converged).collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quadratic_profile_is_crossed_exactly() {
        // Δχ² = ((θ − 1) / 0.5)²: crosses q at 1 ± 0.5 √q.
        let q = 3.84;
        let at: Vec<f64> = (0..=12).map(|k| -0.5 + 0.25 * k as f64).collect();
        let delta: Vec<Option<f64>> = at
            .iter()
            .map(|a| Some(((a - 1.0) / 0.5f64).powi(2)))
            .collect();
        let lo = crossing(&at, &delta, 6, q, false).unwrap();
        let hi = crossing(&at, &delta, 6, q, true).unwrap();
        assert!((lo - (1.0 - 0.5 * q.sqrt())).abs() < 1e-12, "{lo}");
        assert!((hi - (1.0 + 0.5 * q.sqrt())).abs() < 1e-12, "{hi}");
        let flat = vec![Some(0.1); at.len()];
        assert_eq!(crossing(&at, &flat, 6, q, true), None);
    }
}
