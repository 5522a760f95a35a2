//! The integration error a fit carries, estimated again at the fitted
//! parameters; the step chosen for a tolerance given after loading (a
//! library call); and the step a simulation takes (`rigfit simulate`: at
//! least a fit's, finer for a synthetic record, [`SimulationStep`]).

use std::path::Path;

use serde::Serialize;

use super::stability::{MAX_AUTO_SUBSTEPS, NOISE_FRACTION, choose};
use super::{Campaign, CampaignError};
use crate::base::text::{echo_bare, steps_per_sample};
use crate::campaign::raw::RawSubsteps;
use crate::model::step_error::StepDoubling;

/// One experiment's integration error at the job's step, in `result.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IntegrationError {
    /// RK4 steps per sample the estimate is for (the job's).
    pub substeps: usize,
    /// RMS over the fit window of output 0's integration error (output 0's
    /// unit), estimated by step doubling with the f64 reference (runs at 1,
    /// 2 and 4 times the job's steps) at the fitted parameters; `None` where a
    /// run is not finite.
    pub estimate: Option<f64>,
    /// The order of convergence the runs show (4 for smooth runs; less where
    /// output 0 jumps at an event), which the estimate assumes.
    pub observed_order: Option<f64>,
    /// `estimate` over the residual's RMS.
    pub fraction_of_residual_rms: Option<f64>,
    /// The fraction of the residual's RMS above which the job warns.
    pub allowed_fraction: f64,
    /// The campaign's `solver.tolerance` (output 0's unit): an error within
    /// it is not warned of.
    pub tolerance: Option<f64>,
}

/// Most times the job's steps the integration-error warning advises; a
/// count beyond it is no advice (a run of the record would cost as much
/// times more, and a response that needs it is not predictable).
pub const MAX_ADVISED_FACTOR: usize = 64;

/// Observed order of convergence below which the runs at 1, 2 and 4 times
/// the steps do not converge like RK4 (even an output that jumps at events
/// shows about 1): the step-doubling estimate gives no step to advise.
pub const MIN_ADVISED_ORDER: f64 = 0.5;

impl IntegrationError {
    /// Whether the error is more than [`Self::allowed_fraction`] of the
    /// residual's RMS and above the tolerance, where one is given: what
    /// [`Self::warning`] warns of.
    pub fn above_allowed(&self) -> bool {
        match (self.estimate, self.fraction_of_residual_rms) {
            (Some(est), Some(frac)) => {
                frac > self.allowed_fraction && self.tolerance.is_none_or(|t| est > t)
            }
            _ => false,
        }
    }

    /// The warning when the error is more than [`Self::allowed_fraction`] of
    /// the residual's RMS (and above the tolerance, where one is given), with
    /// the substeps that would bring it there.
    pub fn warning(&self, experiment: &str, unit: &str) -> Option<String> {
        if !self.above_allowed() {
            return None;
        }
        let (est, frac) = (self.estimate?, self.fraction_of_residual_rms?);
        let order = self.observed_order.unwrap_or(4.0);
        let need = (self.substeps as f64 * (frac / self.allowed_fraction).powf(1.0 / order)).ceil();
        // Beyond this the step is not what is wrong: a response that parts
        // from itself at every step (chaotic) or runs that do not converge
        // at RK4's order. No count is advised.
        if !(need <= (MAX_ADVISED_FACTOR * self.substeps) as f64
            && need <= MAX_AUTO_SUBSTEPS as f64)
            || order < MIN_ADVISED_ORDER
        {
            return Some(format!(
                "{}: the estimated RK4 integration error ({est:.3e} {unit} at {}, observed order \
                 {order:.2}) is {:.2} % of the residual's RMS, and no step brings it to {:.0} % \
                 within {MAX_ADVISED_FACTOR} times the steps: the record is not predictable at any \
                 practical step (a response sensitive to tiny changes, see the sensitivity check \
                 in result.json); fit a shorter window rather than a finer step",
                echo_bare(experiment),
                steps_per_sample(self.substeps),
                100.0 * frac,
                100.0 * self.allowed_fraction,
            ));
        }
        Some(format!(
            "{}: the estimated RK4 integration error ({est:.3e} {unit} at {}) is {:.2} % of the \
             residual's RMS, more than {:.0} %: the step, not only the rig and the noise, shapes \
             the fit; about {need} steps per sample (\"solver\": {{\"substeps\": {need}}}) would \
             bring it to {:.0} %",
            echo_bare(experiment),
            steps_per_sample(self.substeps),
            100.0 * frac,
            100.0 * self.allowed_fraction,
            100.0 * self.allowed_fraction,
        ))
    }
}

impl Campaign {
    /// The integration error of experiment `e` with `params` and clock
    /// `offset` at the campaign's substeps, against the residual's RMS
    /// (`residual_rms`, output 0's unit) where there is one. A run longer than
    /// a candidate's (the campaign's run length was checked before the job)
    /// is never taken: the three runs take 7 candidate-runs of steps.
    pub fn integration_error(
        &self,
        e: usize,
        params: &[f64],
        offset: f64,
        residual_rms: Option<f64>,
    ) -> IntegrationError {
        let x = &self.problem.experiments[e];
        let n = self.problem.substeps;
        let model = self.problem.scoring_model(e);
        let mut run = StepDoubling::new(
            &model,
            params,
            &x.drive,
            x.grid(offset, n),
            x.window.clone(),
        );
        let found = run.error_and_order(n);
        let estimate = found.map(|f| f.0);
        IntegrationError {
            substeps: n,
            estimate,
            observed_order: found.map(|f| f.1),
            fraction_of_residual_rms: estimate
                .zip(residual_rms)
                .filter(|(_, r)| *r > 0.0)
                .map(|(est, r)| est / r),
            allowed_fraction: NOISE_FRACTION,
            tolerance: self.solver.tolerance,
        }
    }

    /// Chooses `"auto"` substeps again so that the integration error of
    /// output 0 estimated at the campaign's current values (its initial
    /// values, or those a parameter file set) is at most `tolerance` (output
    /// 0's unit, > 0) in every experiment; an explicit count is kept and only
    /// checked. For a simulation, whose record may be a placeholder without
    /// noise. A reference run longer than [`super::ESTIMATE_MAX_RUN_STEPS`] is not
    /// taken: the stable step is kept and the note says so.
    pub fn choose_step_for_tolerance(&mut self, tolerance: f64) -> Result<(), CampaignError> {
        if !(tolerance > 0.0 && tolerance.is_finite()) {
            return Err(super::error::invalid(
                &self.path,
                "solver.tolerance",
                "a tolerance > 0 in the unit of the rig's output 0",
                tolerance.to_string(),
            ));
        }
        let path = self.path.clone();
        self.choose_step_again(Some(tolerance), &path, "solver.tolerance")
    }

    /// Chooses the substeps again at the campaign's current values (an
    /// explicit count is kept and only checked) for `tolerance`, or the noise
    /// rule without one; a refusal names `file` and `at`. After a parameter
    /// file or a tolerance given after loading.
    pub(super) fn choose_step_again(
        &mut self,
        tolerance: Option<f64>,
        file: &Path,
        at: &str,
    ) -> Result<(), CampaignError> {
        let requested = if self.solver.auto {
            RawSubsteps::Auto
        } else {
            RawSubsteps::Count(self.solver.substeps as u64)
        };
        let c = &*self;
        let step = choose(
            &c.model,
            &c.problem.experiments,
            &c.genes,
            |e| c.bounds(e),
            |e| super::build::latest_offset(c.base_offsets[e], &c.genes, e),
            |e| (c.base[e].clone(), c.base_offsets[e]),
            requested,
            tolerance,
        )
        .map_err(|message| CampaignError::Unstable {
            file: file.to_path_buf(),
            path: at.into(),
            message,
        })?;
        if let Some(w) = &step.warning
            && !self.warnings.contains(w)
        {
            self.warnings.push(w.clone());
        }
        self.solver = step.settings(self.solver.backend, self.solver.precision);
        self.problem.substeps = step.substeps;
        Ok(())
    }
}

/// A synthetic record's integration error is held to at most this fraction
/// of the noise it carries (`rigfit simulate --noise`), five times tighter
/// than a fit's own rule ([`NOISE_FRACTION`] aimed at half of it), so that
/// the record is made at a finer step than the fit uses.
pub const SYNTHETIC_NOISE_FRACTION: f64 = 0.002;

/// ... and to at most this share of `σ/√N` (`N` the samples scored): a
/// systematic error `ε` over `N` samples can shift a fitted parameter by up
/// to about `ε·√N/σ` of its standard error, so this keeps that shift within a
/// tenth of one however long the record is.
pub const SYNTHETIC_BIAS_SHARE: f64 = 0.1;

/// A synthetic record takes at most this many times the substeps stability
/// needs (and at most [`super::stability::MAX_AUTO_SUBSTEPS`], and never more
/// than the run length allows): one run, so a finer cap than a search's.
pub const SYNTHETIC_CAP_FACTOR: usize = 64;

/// One measured channel of a simulation and its integration error at the
/// chosen step.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChannelStep {
    /// The channel's experiment (an index into the problem's experiments).
    pub experiment: usize,
    /// The noise added to it (its output's unit); 0 without noise.
    pub sigma: f64,
    /// RMS over the samples of the integration error of the channel's output
    /// at the chosen step, by step doubling as a fit estimates it; `None`
    /// where a reference run is not finite or would be too long.
    pub estimate: Option<f64>,
    /// The order of convergence the estimate assumed.
    pub observed_order: Option<f64>,
    /// `estimate / sigma`.
    pub fraction_of_noise: Option<f64>,
    /// The fraction of `sigma` the default step aims at: the smaller of
    /// [`SYNTHETIC_NOISE_FRACTION`] and [`SYNTHETIC_BIAS_SHARE`]`/√N`.
    pub allowed_fraction: Option<f64>,
}

/// The RK4 step of a simulation (`rigfit simulate`) and how it was chosen.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SimulationStep {
    /// RK4 steps per sample interval the simulation takes.
    pub substeps: usize,
    /// Steps per sample stability alone needs over the free parameters'
    /// ranges on this grid.
    pub stable: usize,
    /// Steps per sample a fit of the record written takes on this grid: the
    /// campaign's count, or `"auto"`'s rule (stability, then the integration
    /// error held to [`NOISE_FRACTION`] of the record's noise or to the
    /// campaign's tolerance) at the simulated values.
    pub fit: usize,
    /// `requested` (`--substeps`), `synthetic` (with noise: at least twice
    /// a fit's steps, finer where the noise asks), or `fit_rule` (no noise:
    /// the fit's own rule).
    pub chosen_by: &'static str,
    /// Each measured channel's integration error at `substeps`.
    pub channels: Vec<ChannelStep>,
    /// Said to the user: the cap or the run length held the error above its
    /// aim.
    pub warning: Option<String>,
}

impl Campaign {
    /// The RK4 steps per sample for simulating the channels `channels`
    /// (experiment index and the noise σ added to it, in its output's unit)
    /// with the campaign's current values: `requested` where given (the
    /// caller has held it to [`Campaign::stable_substeps`] and
    /// [`super::stability::MAX_AUTO_SUBSTEPS`]), else at least what a fit of
    /// the record written takes on this grid, and with noise at least twice
    /// that and finer still until every channel's integration error is at most
    /// [`SYNTHETIC_NOISE_FRACTION`] of its σ and [`SYNTHETIC_BIAS_SHARE`]
    /// of `σ/√N`, up to [`SYNTHETIC_CAP_FACTOR`] times the stable count and
    /// within `max_steps` RK4 steps per run of the campaign.
    pub fn simulation_step(
        &self,
        channels: &[(usize, f64)],
        requested: Option<usize>,
        max_steps: f64,
    ) -> SimulationStep {
        let stable = channels
            .iter()
            .map(|&(e, _)| self.stable_substeps(e))
            .max()
            .unwrap_or(1);
        let loaded = self.problem.substeps.max(stable);
        // Per campaign run and substep, to keep a default within max_steps.
        let per = self.run_length().steps_per_candidate / self.problem.substeps as f64;
        let slack = self.problem.experiments.len() as f64;
        let by_length = ((max_steps - slack) / per).floor().max(1.0) as usize;
        let cap = stable
            .saturating_mul(SYNTHETIC_CAP_FACTOR)
            .min(super::stability::MAX_AUTO_SUBSTEPS)
            .min(by_length)
            .max(loaded);
        let models: Vec<_> = channels
            .iter()
            .map(|&(e, _)| self.problem.scoring_model(e))
            .collect();
        let estimate_steps = super::stability::estimate_max_steps(self.model.state_names().len());
        let mut runs: Vec<StepDoubling<'_>> = channels
            .iter()
            .zip(&models)
            .map(|(&(e, _), m)| {
                let x = &self.problem.experiments[e];
                StepDoubling::new(
                    m,
                    &self.base[e],
                    &x.drive,
                    x.grid(self.base_offsets[e], loaded),
                    x.window.clone(),
                )
            })
            .collect();
        let fit = if self.solver.auto {
            let fit_cap = stable
                .saturating_mul(super::stability::ACCURACY_CAP_FACTOR)
                .min(super::stability::MAX_AUTO_SUBSTEPS)
                .max(loaded);
            let mut n = loaded;
            for (&(e, sigma), run) in channels.iter().zip(&mut runs) {
                if let Some(t) = self.fit_target(e, sigma, loaded) {
                    let c = run.choose(
                        loaded,
                        fit_cap,
                        super::stability::ACCURACY_MARGIN * t,
                        estimate_steps,
                    );
                    n = n.max(c.substeps);
                }
            }
            n
        } else {
            loaded
        };
        let aim = |e: usize, sigma: f64| {
            (sigma > 0.0).then(|| {
                let samples = self.problem.experiments[e].window.len().max(1) as f64;
                SYNTHETIC_NOISE_FRACTION.min(SYNTHETIC_BIAS_SHARE / samples.sqrt())
            })
        };
        let noisy = channels.iter().any(|&(_, s)| s > 0.0);
        let (substeps, chosen_by) = match requested {
            Some(n) => (n, "requested"),
            None if noisy => {
                // Twice a fit's steps at least: a fit whose model shares the
                // record's discretisation would see no integration error at
                // the truth, however large it is.
                let mut n = fit.saturating_mul(2).min(cap).max(loaded);
                for (&(e, sigma), run) in channels.iter().zip(&mut runs) {
                    if let Some(f) = aim(e, sigma) {
                        let c = run.choose(n, cap, f * sigma, estimate_steps);
                        n = n.max(c.substeps);
                    }
                }
                (n.max(fit), "synthetic")
            }
            None => (fit, "fit_rule"),
        };
        let channels: Vec<ChannelStep> = channels
            .iter()
            .zip(&mut runs)
            .map(|(&(e, sigma), run)| {
                let found = (run.steps_of(4 * substeps) <= estimate_steps)
                    .then(|| run.error_and_order(substeps))
                    .flatten();
                let estimate = found.map(|f| f.0);
                ChannelStep {
                    experiment: e,
                    sigma,
                    estimate,
                    observed_order: found.map(|f| f.1),
                    fraction_of_noise: estimate.filter(|_| sigma > 0.0).map(|x| x / sigma),
                    allowed_fraction: aim(e, sigma),
                }
            })
            .collect();
        let warning = channels.iter().find_map(|ch| {
            let (frac, allowed) = (ch.fraction_of_noise?, ch.allowed_fraction?);
            (frac > allowed).then(|| {
                format!(
                    "experiment '{}': at {} the synthetic record's integration error is still \
                     ≈ {:.2} % of its noise, above the {:.2} % aimed at ({}); a fit of it may \
                     feel the step: give --substeps a larger count or shorten the record",
                    echo_bare(&self.problem.experiments[ch.experiment].name),
                    steps_per_sample(substeps),
                    100.0 * frac,
                    100.0 * allowed,
                    if requested.is_some() {
                        "--substeps as given".to_string()
                    } else if substeps >= by_length {
                        format!("the run length limit {max_steps:e} RK4 steps holds the step")
                    } else {
                        format!("at most {SYNTHETIC_CAP_FACTOR}× the {stable} stability needs")
                    }
                )
            })
        });
        SimulationStep {
            substeps,
            stable,
            fit,
            chosen_by,
            channels,
            warning,
        }
    }

    /// Steps per sample stability needs in experiment `e` over the free
    /// parameters' ranges (the first half of the step rule).
    pub fn stable_substeps(&self, e: usize) -> usize {
        let (lo, hi) = self.bounds(e);
        let offset = super::build::latest_offset(self.base_offsets[e], &self.genes, e);
        let (_, _, need) = super::stability::stability_need(
            &self.model,
            &self.problem.experiments[e],
            &lo,
            &hi,
            offset,
        );
        if need.is_finite() {
            need.clamp(1.0, usize::MAX as f64) as usize
        } else {
            usize::MAX
        }
    }

    /// The integration error a fit of experiment `e`'s record allows (its
    /// output's unit): the campaign's tolerance, else the noise rule on the
    /// record simulate writes, with noise `sigma` or, without noise, the
    /// simulated output itself at `substeps` as the record.
    fn fit_target(&self, e: usize, sigma: f64, substeps: usize) -> Option<f64> {
        if let Some(t) = self.solver.tolerance {
            return Some(t);
        }
        if sigma > 0.0 {
            return Some(NOISE_FRACTION * sigma);
        }
        let x = &self.problem.experiments[e];
        let model = self.problem.scoring_model(e);
        let y = crate::model::step_error::output_0(
            &model,
            &self.base[e],
            &x.drive,
            &x.grid(self.base_offsets[e], substeps),
            &x.window,
        )?;
        let mut record = x.clone();
        record.measured[x.window.clone()].copy_from_slice(&y);
        super::stability::target(&record, None, "").map(|t| t.0)
    }
}

#[cfg(test)]
mod advice {
    use super::*;

    fn error(substeps: usize, frac: f64, order: f64) -> IntegrationError {
        IntegrationError {
            substeps,
            estimate: Some(frac),
            observed_order: Some(order),
            fraction_of_residual_rms: Some(frac),
            allowed_fraction: NOISE_FRACTION,
            tolerance: None,
        }
    }

    #[test]
    fn a_step_within_reach_is_advised_and_an_absurd_one_is_not() {
        // 16 × the allowed fraction at order 4: twice the steps.
        let w = error(3, 16.0 * NOISE_FRACTION, 4.0)
            .warning("x", "N")
            .unwrap();
        assert!(w.contains("\"substeps\": 6"), "{w}");
        // A response whose error does not fall with the step (a chaotic
        // record: order 0.1, 20× the residual) gets no count.
        for e in [error(3, 20.0, 0.1), error(3, 1e12 * NOISE_FRACTION, 4.0)] {
            let w = e.warning("x", "N").unwrap();
            assert!(!w.contains("\"substeps\""), "{w}");
            assert!(w.contains("not predictable at any practical step"), "{w}");
        }
    }
}
