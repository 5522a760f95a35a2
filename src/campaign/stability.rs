//! Choosing (or refusing) the number of RK4 steps per sample interval.
//!
//! Classic RK4 is stable for real eigenvalues while `h·|λ| < 2.785` and for
//! imaginary ones while `h·|λ| < 2.828` (issue 6). The model bounds `|λ|` over the
//! free parameters' ranges with [`crate::model::CompiledRig::omega_bound`]; we require
//! `h·ω_bound ≤` [`STABILITY_LIMIT`] = 2.0, a margin of about 30 % for the
//! looseness of nonlinear springs beyond their linearisation.

use super::raw::RawSubsteps;
use crate::eval::{Backend, ExperimentData, PrecisionChoice};
use crate::model::CompiledRig;

/// Largest `h·ω_bound` accepted (RK4's own limit is about 2.8).
pub const STABILITY_LIMIT: f64 = 2.0;

/// Most substeps `"auto"` will choose (or a campaign may ask for) before the
/// campaign is refused.
pub const MAX_AUTO_SUBSTEPS: usize = 10_000;

/// The campaign's `"solver"` object after validation.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SolverSettings {
    /// RK4 steps per sample interval.
    pub substeps: usize,
    /// Evaluator choice.
    pub backend: Backend,
    /// GPU precision choice.
    pub precision: PrecisionChoice,
    /// Whether `substeps` was chosen automatically.
    pub auto: bool,
    /// How the step was chosen or checked: worst `h·ω`, experiment and limiting
    /// parameter, for the log.
    pub note: String,
}

/// The tightest experiment: its index, ω bound (rad/s) and limiting parameter.
struct Worst {
    exp: usize,
    omega: f64,
    name: &'static str,
    need: usize,
}

/// Substeps for `requested`, or the one-line reason it cannot work.
/// `bounds(e)` gives experiment `e`'s lower and upper parameter vectors,
/// `offset(e)` its latest clock offset (s).
pub(crate) fn choose(
    model: &CompiledRig,
    exps: &[ExperimentData],
    bounds: impl Fn(usize) -> (Vec<f64>, Vec<f64>),
    offset: impl Fn(usize) -> f64,
    requested: RawSubsteps,
) -> Result<(usize, bool, String), String> {
    let mut worst: Option<Worst> = None;
    for (e, x) in exps.iter().enumerate() {
        let (lo, hi) = bounds(e);
        // The run's last model time: what the drive can reach bounds what the
        // model must stay stable for.
        let t_end = x.t_first + x.window.end.saturating_sub(1) as f64 * x.dt + offset(e);
        let (omega, name) = model.omega_bound_in_run(&lo, &hi, &x.drive, t_end);
        if !omega.is_finite() {
            return Err(format!(
                "experiment '{}': the frequency bound is not finite (limited by '{name}'); \
                 expected finite masses, stiffnesses and dampings",
                x.name
            ));
        }
        let need = ((omega * x.dt / STABILITY_LIMIT).ceil() as usize).max(1);
        if worst.as_ref().is_none_or(|w| need > w.need) {
            worst = Some(Worst {
                exp: e,
                omega,
                name,
                need,
            });
        }
    }
    let w = worst.expect("at least one experiment");
    let x = &exps[w.exp];
    match requested {
        RawSubsteps::Auto => {
            if w.need > MAX_AUTO_SUBSTEPS {
                return Err(format!(
                    "\"auto\" would need {} substeps (more than {MAX_AUTO_SUBSTEPS}) for \
                     experiment '{}': ω ≤ {:.3e} rad/s limited by '{}' at dt = {:e} s; \
                     narrow the range of '{}'",
                    w.need, x.name, w.omega, w.name, x.dt, w.name
                ));
            }
            let hw = w.omega * x.dt / w.need as f64;
            let note = format!(
                "substeps = {} chosen automatically: h·ω ≤ {hw:.2} (limit {STABILITY_LIMIT}, \
                 RK4 diverges near 2.8), tightest in experiment '{}' where ω ≤ {:.3e} rad/s \
                 is limited by '{}' at dt = {:e} s",
                w.need, x.name, w.omega, w.name, x.dt
            );
            Ok((w.need, true, note))
        }
        RawSubsteps::Count(n) if n > MAX_AUTO_SUBSTEPS as u64 => Err(format!(
            "expected at most {MAX_AUTO_SUBSTEPS} substeps, found {n}"
        )),
        RawSubsteps::Count(n) => {
            let n = n as usize;
            let hw = w.omega * x.dt / n as f64;
            if hw > STABILITY_LIMIT {
                let dt_ok = STABILITY_LIMIT * n as f64 / w.omega;
                return Err(format!(
                    "expected a stable RK4 step (h·ω ≤ {STABILITY_LIMIT}), found substeps = {n} \
                     giving h·ω = {hw:.2} in experiment '{}': ω ≤ {:.3e} rad/s is limited by \
                     '{}'; use substeps ≥ {} (or \"auto\"), a sample interval ≤ {dt_ok:.3e} s, \
                     or narrow the range of '{}'",
                    x.name, w.omega, w.name, w.need, w.name
                ));
            }
            let note = format!(
                "substeps = {n} as requested: h·ω ≤ {hw:.2} (limit {STABILITY_LIMIT}), \
                 tightest in experiment '{}' limited by '{}'",
                x.name, w.name
            );
            Ok((n, false, note))
        }
    }
}
