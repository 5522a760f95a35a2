//! Whether the record is predictable at the fitted values: the check that
//! the covariance's intervals mean anything.
//!
//! The intervals linearise the response about the optimum. A chaotic
//! response (a forced double-well oscillator, a stick-slip joint on the edge
//! of sticking) is linear only over a vanishing neighbourhood: a change of
//! 1e-8 in a parameter grows until it changes the output by as much as the
//! output itself, the finite-difference Jacobian is huge and the intervals
//! come out zero-wide, all of them excluding the truth. The check moves every
//! gene by a tiny fraction `ε` of its scale-space range and by `10 ε`, along
//! two directions, and simulates the record with the f64 reference: where
//! the response is linear the second change is ten times the first; where
//! it is not, from some time on, the part of the second change that is not
//! ten times the first (`d₁₀ − 10 d₁`) stays above half of `10 d₁` and above
//! a tenth of the record's noise. Five runs per experiment, taken only after
//! a polish.

use serde::Serialize;

use crate::base::text::{echo_bare, number};
use crate::campaign::Campaign;
use crate::eval::simulate_scored;
use crate::search::GeneSpec;

/// The change of each gene, as a fraction of its scale-space range (the
/// other run takes ten times this).
pub const PERTURBATION: f64 = 1e-8;

/// Share of the linear prediction `10 d₁` (block RMS) above which the
/// rest of `d₁₀` is not linear.
pub const NONLINEAR_SHARE: f64 = 0.5;

/// The part of `d₁₀` that is not linear must also exceed this fraction of
/// the record's noise (block RMS): rounding and a lone event that moves
/// across a sample instant stay far below it.
pub const NOISE_SHARE: f64 = 0.1;

/// Consecutive blocks that must all be nonlinear: the sensitivity of a chaotic response lasts, a lone event
/// that moves across a sample instant does not.
const PERSIST: usize = 3;

/// A change below this fraction of the largest output is rounding: its
/// nonlinear share is not reported.
const ROUNDING: f64 = 1e-12;

/// Blocks a fit window is cut into (each at least [`MIN_BLOCK`] samples).
const BLOCKS: usize = 256;
const MIN_BLOCK: usize = 8;

/// One experiment's check, in `result.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExperimentSensitivity {
    /// Experiment (or channel) name.
    pub name: String,
    /// Record time (s) from which a change of the parameters by
    /// [`PERTURBATION`] of their ranges no longer changes the output in
    /// proportion; `null` where the response stays linear over the window.
    pub sensitive_from_s: Option<f64>,
    /// A fit window that keeps the record predictable, `[start, end]` in
    /// record seconds (where sensitive).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub suggested_window_s: Option<[f64; 2]>,
    /// Largest `RMS(d₁₀ − 10 d₁) / RMS(10 d₁)` over the window's blocks (about
    /// 0 for a linear response; 1 or more where it is not).
    pub largest_nonlinear_share: f64,
}

/// The check over every experiment.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sensitivity {
    /// Whether any experiment's response is sensitive to tiny changes.
    pub sensitive: bool,
    /// [`PERTURBATION`].
    pub perturbation: f64,
    /// Per experiment.
    pub experiments: Vec<ExperimentSensitivity>,
}

impl Sensitivity {
    /// The earliest time (record s) from which a response is sensitive, as
    /// messages print it (two significant digits, rounded down).
    pub fn earliest(&self) -> Option<String> {
        let t = self
            .experiments
            .iter()
            .filter_map(|e| e.sensitive_from_s)
            .fold(f64::INFINITY, f64::min);
        t.is_finite().then(|| number(round_down(t)))
    }

    /// The verdict's flag.
    pub fn flag(&self) -> Option<String> {
        Some(format!(
            "response sensitive to tiny changes from t ≈ {} s (intervals not meaningful)",
            self.earliest()?
        ))
    }

    /// The note of every parameter where the response is sensitive.
    pub fn note(&self) -> Option<String> {
        Some(format!(
            "the response is sensitive to tiny changes from t ≈ {} s: the interval is not meaningful",
            self.earliest()?
        ))
    }

    /// The warning a sensitive response gets, naming the earliest time and
    /// the window to fit instead.
    pub fn warning(&self) -> Option<String> {
        let first = self
            .experiments
            .iter()
            .filter_map(|e| Some((e, e.sensitive_from_s?)))
            .min_by(|a, b| a.1.total_cmp(&b.1))?;
        let (e, t) = first;
        let window = e.suggested_window_s.map_or_else(String::new, |[a, b]| {
            format!(
                "; fit a window that ends before it, e.g. \"fit_window\": {{\"start\": {}, \"end\": \
                 {}}} in experiment '{}'",
                number(a),
                number(b),
                echo_bare(&e.name)
            )
        });
        Some(format!(
            "the response is sensitive to tiny changes from t ≈ {} s in '{}': a change of the \
             parameters by {:.0e} of their ranges grows out of proportion there (chaotic or on \
             the edge of a regime), so the record beyond it does not determine them and the 95 % \
             intervals are not meaningful; no parameter is marked determined{window}",
            number(round_down(t)),
            echo_bare(&e.name),
            self.perturbation
        ))
    }
}

/// `x` to two significant digits, towards zero (a window's end is better
/// early than late).
fn round_down(x: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let p = 10f64.powf(x.abs().log10().floor() - 1.0);
    let r = (x / p).trunc() * p;
    // Printed without the binary representation's tail.
    format!("{r:.12e}").parse().unwrap_or(r)
}

/// Runs the check at `best` (gene values).
pub fn check(campaign: &Campaign, genes: &[GeneSpec], best: &[f64]) -> Sensitivity {
    let x: Vec<f64> = genes
        .iter()
        .zip(best)
        .map(|(g, &v)| g.to_scaled(v))
        .collect();
    // Two directions: every gene up, and alternate signs (a chaotic
    // response does not care; a direction the record does not see is rare
    // in both at once).
    let directions: [Vec<f64>; 2] = [
        vec![1.0; genes.len()],
        (0..genes.len())
            .map(|j| if j % 2 == 0 { 1.0 } else { -1.0 })
            .collect(),
    ];
    let moved = |dir: &[f64], times: f64| -> Vec<f64> {
        genes
            .iter()
            .zip(&x)
            .zip(dir)
            .map(|((g, &xj), &s)| {
                let (lo, hi) = g.scaled_bounds();
                let h = PERTURBATION * (hi - lo);
                // Inwards from a bound.
                let s = if xj + 10.0 * h * s > hi || xj + 10.0 * h * s < lo {
                    -s
                } else {
                    s
                };
                g.to_value(xj + times * h * s)
            })
            .collect()
    };
    let mut genomes = vec![best.to_vec()];
    for d in &directions {
        genomes.push(moved(d, 1.0));
        genomes.push(moved(d, 10.0));
    }
    let full: Vec<Vec<(Vec<f64>, f64)>> = genomes.iter().map(|g| campaign.full_params(g)).collect();
    let problem = &campaign.problem;
    let experiments: Vec<ExperimentSensitivity> = problem
        .experiments
        .iter()
        .enumerate()
        .map(|(e, exp)| {
            // One lane ensemble where the clock offset is not moved (the
            // same bits as one by one).
            let offset = full[0][e].1;
            let runs: Vec<Vec<f64>> = if full.iter().all(|f| f[e].1 == offset) {
                let params: Vec<&[f64]> = full.iter().map(|f| f[e].0.as_slice()).collect();
                simulate_scored(problem, e, &params, offset)
            } else {
                full.iter()
                    .map(|f| {
                        let (p, offset) = &f[e];
                        simulate_scored(problem, e, &[p.as_slice()], *offset)
                            .pop()
                            .unwrap_or_default()
                    })
                    .collect()
            };
            let sigma = exp.noise_estimate().unwrap_or_else(|| {
                let w = &exp.measured[exp.window.clone()];
                1e-6 * (w.iter().map(|v| v * v).sum::<f64>() / w.len().max(1) as f64).sqrt()
            });
            let mut first: Option<usize> = None;
            let mut largest = 0.0_f64;
            for pair in runs[1..].chunks(2) {
                let (k, share) =
                    first_nonlinear(&runs[0], &pair[0], &pair[1], exp.window.clone(), sigma);
                largest = largest.max(share);
                if let Some(k) = k {
                    first = Some(first.map_or(k, |f| f.min(k)));
                }
            }
            let time = |k: usize| exp.t_first + k as f64 * exp.dt;
            let sensitive_from_s = first.map(time);
            let start = time(exp.window.start);
            let suggested_window_s = sensitive_from_s
                .filter(|&t| t > start)
                .map(|t| [start, round_down(start + 0.5 * (t - start))]);
            ExperimentSensitivity {
                name: exp.name.clone(),
                sensitive_from_s,
                suggested_window_s,
                largest_nonlinear_share: largest,
            }
        })
        .collect();
    Sensitivity {
        sensitive: experiments.iter().any(|e| e.sensitive_from_s.is_some()),
        perturbation: PERTURBATION,
        experiments,
    }
}

/// The first sample of the first of [`PERSIST`] consecutive blocks of
/// `window` where `d₁₀ − 10 d₁` is not small against `10 d₁` and the noise
/// `sigma`, and the largest share seen. A run that blew up or stopped short
/// counts as nonlinear from where it did.
fn first_nonlinear(
    base: &[f64],
    one: &[f64],
    ten: &[f64],
    window: std::ops::Range<usize>,
    sigma: f64,
) -> (Option<usize>, f64) {
    let len = window.len();
    let scale = base[window.start..window.end.min(base.len())]
        .iter()
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    let block = (len / BLOCKS).max(MIN_BLOCK);
    let starts: Vec<usize> = window.clone().step_by(block).collect();
    let mut flags = Vec::with_capacity(starts.len());
    let mut largest = 0.0_f64;
    for &s in &starts {
        let end = (s + block).min(window.end);
        let (mut lin, mut non) = (0.0, 0.0);
        let mut broken = false;
        for k in s..end {
            let (Some(b), Some(o), Some(t)) = (base.get(k), one.get(k), ten.get(k)) else {
                broken = true;
                break;
            };
            let d1 = 10.0 * (o - b);
            let d10 = t - b;
            if !(d1.is_finite() && d10.is_finite()) {
                broken = true;
                break;
            }
            lin += d1 * d1;
            non += (d10 - d1) * (d10 - d1);
        }
        let n = (end - s).max(1) as f64;
        let (lin, non) = ((lin / n).sqrt(), (non / n).sqrt());
        let share = if lin > 0.0 {
            non / lin
        } else if non > 0.0 {
            f64::INFINITY
        } else {
            0.0
        };
        // The share where the change is above rounding (of the record's
        // scale): elsewhere both parts are rounding, and so is their ratio.
        if share.is_finite() && lin > ROUNDING * scale {
            largest = largest.max(share);
        }
        flags.push(broken || (share > NONLINEAR_SHARE && non > NOISE_SHARE * sigma));
    }
    let first = (0..flags.len())
        .find(|&i| i + PERSIST <= flags.len() && flags[i..i + PERSIST].iter().all(|&f| f))
        .map(|i| starts[i]);
    (first, largest)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_linear_change_is_not_flagged_and_a_growing_one_is() {
        let n = 2000;
        let base: Vec<f64> = (0..n).map(|k| (k as f64 * 0.01).sin()).collect();
        let lin = |e: f64| -> Vec<f64> {
            base.iter()
                .enumerate()
                .map(|(k, b)| b + e * (k as f64 * 0.03).cos())
                .collect()
        };
        let (one, ten) = (lin(1e-8), lin(1e-7));
        assert_eq!(first_nonlinear(&base, &one, &ten, 0..n, 1e-3).0, None);
        // From sample 1200 on, both runs are off by an O(1) amount unrelated
        // to their size (the runs of a chaotic response once they part).
        let part = |v: &[f64], phase: f64| -> Vec<f64> {
            v.iter()
                .enumerate()
                .map(|(k, x)| {
                    if k >= 1200 {
                        x + (k as f64 * 0.07 + phase).sin()
                    } else {
                        *x
                    }
                })
                .collect()
        };
        let (one, ten) = (part(&one, 0.0), part(&ten, 1.0));
        let (k, share) = first_nonlinear(&base, &one, &ten, 0..n, 1e-3);
        let k = k.unwrap();
        assert!((1190..=1200).contains(&k), "{k}");
        assert!(share > 1.0);
        // A lone outlier (an event across a sample instant) is not.
        let mut ten = lin(1e-7);
        ten[500] += 1.0;
        assert_eq!(first_nonlinear(&base, &lin(1e-8), &ten, 0..n, 1e-3).0, None);
    }

    #[test]
    fn rounding_down_keeps_two_digits() {
        assert_eq!(round_down(123.456), 120.0);
        assert_eq!(round_down(0.0876), 0.087);
        assert_eq!(round_down(7.0), 7.0);
    }
}
