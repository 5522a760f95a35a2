//! How long one candidate's runs are, estimated before any work: a clock offset
//! of 10⁶ s or a record whose time column holds epoch seconds would otherwise
//! start a job that integrates for ever.

use serde::Serialize;

use super::{Campaign, CampaignError};

/// Default limit on the RK4 steps one candidate takes over all experiments.
/// The shipped example takes 2 500; a record of 10⁶ samples at 20 steps per
/// sample takes 2·10⁷.
pub const DEFAULT_MAX_STEPS: f64 = 1e8;

/// Candidate-steps per second of one CPU core on the CPU path (the native
/// f64 lanes, the GA's own work included), for the time estimate before any
/// run of the job is measured: the shipped campaigns' searches ran 1.4e7 to
/// 6.3e7 per core on a 2-core Xeon with AVX-512 (2026-11-26; slowest the
/// inertial rig, fastest the bearing and the tensile example), so an
/// estimate from it is within about 2× either way.
pub const CPU_STEPS_PER_S_PER_CORE: f64 = 3e7;

/// One experiment's run at its latest clock offset.
#[derive(Debug, Clone, Serialize)]
pub struct ExperimentRun {
    /// Experiment name.
    pub name: String,
    /// Model time (s) of the first scored sample; the run starts at rest at
    /// t = 0 and integrates up to it first.
    pub t_first_s: f64,
    /// Model time (s) where the run ends.
    pub t_end_s: f64,
    /// RK4 step length (s).
    pub step_s: f64,
    /// RK4 steps of the run.
    pub steps: f64,
}

/// The length of one candidate's runs.
#[derive(Debug, Clone, Serialize)]
pub struct RunLength {
    /// Per experiment.
    pub experiments: Vec<ExperimentRun>,
    /// RK4 steps over all experiments.
    pub steps_per_candidate: f64,
    /// Seconds one candidate takes on one CPU core (estimate).
    pub cpu_core_seconds_per_candidate: f64,
}

impl Campaign {
    /// RK4 steps of one candidate, each experiment at the latest clock offset
    /// its bounds allow.
    pub fn run_length(&self) -> RunLength {
        let p = &self.problem;
        let experiments: Vec<ExperimentRun> = p
            .experiments
            .iter()
            .enumerate()
            .map(|(e, x)| {
                let offset = super::build::latest_offset(self.base_offsets[e], &self.genes, e);
                let t_first = x.t_first + offset;
                let step = x.dt / p.substeps as f64;
                let prologue = if t_first > 0.0 {
                    (t_first / step).ceil()
                } else {
                    0.0
                };
                let samples = x.window.end.saturating_sub(1) as f64;
                ExperimentRun {
                    name: x.name.clone(),
                    t_first_s: t_first,
                    t_end_s: t_first + samples * x.dt,
                    step_s: step,
                    steps: prologue + samples * p.substeps as f64,
                }
            })
            .collect();
        let steps: f64 = experiments.iter().map(|x| x.steps).sum();
        RunLength {
            experiments,
            steps_per_candidate: steps,
            cpu_core_seconds_per_candidate: steps / CPU_STEPS_PER_S_PER_CORE,
        }
    }

    /// [`Campaign::run_length`], refused when one candidate would take more
    /// than `max_steps` RK4 steps; the message gives the estimate and names the
    /// experiment that takes longest.
    pub fn check_run_length(&self, max_steps: f64) -> Result<RunLength, CampaignError> {
        let r = self.run_length();
        if r.steps_per_candidate <= max_steps {
            return Ok(r);
        }
        let (e, x) = r
            .experiments
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.steps.total_cmp(&b.1.steps))
            .expect("a campaign has experiments");
        let record = &self.problem.experiments[e];
        let span = x.t_end_s - x.t_first_s;
        let hint = if record.t_first > 1e3 * span {
            format!(
                "; the record starts at t = {:e} s and the model at rest at t = 0, so a record \
                 whose t = 0 is not the actuator's start needs experiments[{e}].offset \
                 (about {:e} s here)",
                record.t_first, -record.t_first
            )
        } else if x.t_first_s - record.t_first > 1e3 * span {
            format!(
                "; its clock offset reaches {:e} s",
                x.t_first_s - record.t_first
            )
        } else {
            String::new()
        };
        Err(CampaignError::TooLong {
            file: self.path.clone(),
            path: format!("experiments[{e}]"),
            message: format!(
                "expected at most {max_steps:e} RK4 steps per candidate (raise with --max-steps), \
                 found {:.3e}: experiment '{}' runs from t = 0 to {:e} s in steps of {:e} s, \
                 about {} per candidate on one CPU core{hint}",
                r.steps_per_candidate,
                crate::base::text::echo_bare(&x.name),
                x.t_end_s,
                x.step_s,
                human_duration(r.cpu_core_seconds_per_candidate)
            ),
        })
    }
}

/// `12 s`, `3.4 h`, `2.1e3 years`.
pub fn human_duration(s: f64) -> String {
    match s {
        s if s < 0.01 => format!("{:.1} ms", s * 1e3),
        s if s < 120.0 => format!("{s:.2} s"),
        s if s < 7200.0 => format!("{:.1} min", s / 60.0),
        s if s < 3.0 * 86400.0 => format!("{:.1} h", s / 3600.0),
        s if s < 3.0e7 => format!("{:.1} days", s / 86400.0),
        s => format!("{:.2e} years", s / 3.156e7),
    }
}
