//! The integration error a fit carries, estimated again at the fitted
//! parameters, and the step chosen for a tolerance given after loading
//! (`rigfit simulate --tolerance`).

use std::path::Path;

use serde::Serialize;

use super::stability::{NOISE_FRACTION, choose};
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

impl IntegrationError {
    /// The warning when the error is more than [`Self::allowed_fraction`] of
    /// the residual's RMS (and above the tolerance, where one is given), with
    /// the substeps that would bring it there.
    pub fn warning(&self, experiment: &str, unit: &str) -> Option<String> {
        let (est, frac) = (self.estimate?, self.fraction_of_residual_rms?);
        if frac <= self.allowed_fraction || self.tolerance.is_some_and(|t| est <= t) {
            return None;
        }
        let order = self.observed_order.unwrap_or(4.0);
        let need = (self.substeps as f64 * (frac / self.allowed_fraction).powf(1.0 / order)).ceil();
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
