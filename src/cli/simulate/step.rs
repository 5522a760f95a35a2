//! The RK4 step a simulation takes ([`substeps`]), and the step in words
//! for the console and the record's comments, and for `--json`.

use anyhow::Result;

use super::SimulateArgs;
use crate::cli::exit::BadInput;
use rigfit::base::text::steps_per_sample;
use rigfit::campaign::{Campaign, MAX_AUTO_SUBSTEPS, STABILITY_LIMIT, SimulationStep};

/// RK4 steps per sample interval for the simulation: `--substeps` (held to
/// the stability rule's count), else the campaign's step rule as a fit of the
/// record written would apply it on this grid, finer still for a synthetic
/// record (see [`Campaign::simulation_step`]).
pub(super) fn substeps(
    args: &SimulateArgs,
    c: &Campaign,
    channels: &[usize],
) -> Result<SimulationStep> {
    let sigmas: Vec<(usize, f64)> = channels
        .iter()
        .enumerate()
        .map(|(j, &i)| (i, args.noise.as_ref().map_or(0.0, |s| s[j])))
        .collect();
    if let Some(n) = args.substeps {
        let stable = channels
            .iter()
            .map(|&i| c.stable_substeps(i))
            .max()
            .unwrap_or(1);
        if n == 0 {
            return Err(BadInput(
                "--substeps 0: expected a count ≥ 1 of RK4 steps per sample".into(),
            )
            .into());
        }
        if n < stable {
            return Err(BadInput(format!(
                "--substeps {n}: expected at least {stable} RK4 steps per sample, the count the \
                 stability rule (h·ω ≤ {STABILITY_LIMIT} over the free parameters' ranges) \
                 takes on this grid; a coarser step can diverge"
            ))
            .into());
        }
        if n > MAX_AUTO_SUBSTEPS {
            return Err(BadInput(format!(
                "--substeps {n}: expected at most {MAX_AUTO_SUBSTEPS} RK4 steps per sample"
            ))
            .into());
        }
    }
    Ok(c.simulation_step(&sigmas, args.substeps, args.run_length.max_steps))
}

/// The step in words, for the console and the record's comment lines:
/// `4 RK4 steps per sample (stability alone needs 1, a fit takes 2);
/// integration error ≈ 1.2e-10 m on x, 0.06 % of σ (aimed ≤ 0.20 %)`.
pub(super) fn step_line(step: &SimulationStep, measured: &[(String, String)]) -> String {
    let how = match step.chosen_by {
        "requested" => "as --substeps asks",
        "synthetic" => "a synthetic record: at least twice a fit's, finer where the noise asks",
        _ => "a fit's step rule",
    };
    let errors: Vec<String> = step
        .channels
        .iter()
        .zip(measured)
        .map(
            |(ch, (name, unit))| match (ch.estimate, ch.fraction_of_noise) {
                (Some(e), Some(f)) => format!(
                    "{e:.2e} {unit} on {name}, {:.3} % of σ{}",
                    100.0 * f,
                    ch.allowed_fraction
                        .map(|a| format!(" (aimed ≤ {:.3} %)", 100.0 * a))
                        .unwrap_or_default()
                ),
                (Some(e), None) => format!("{e:.2e} {unit} on {name}"),
                (None, _) => format!("not estimated on {name}"),
            },
        )
        .collect();
    format!(
        "{} ({how}; stability alone needs {}, a fit of this record takes {}); RK4 integration \
         error by step doubling ≈ {}",
        steps_per_sample(step.substeps),
        step.stable,
        step.fit,
        errors.join(", ")
    )
}

/// The step for `--json`.
pub(super) fn step_json(step: &SimulationStep, measured: &[(String, String)]) -> serde_json::Value {
    let channels: Vec<serde_json::Value> = step
        .channels
        .iter()
        .zip(measured)
        .map(|(ch, (name, unit))| {
            serde_json::json!({
                "output": name, "unit": unit, "sigma": ch.sigma,
                "integration_error": ch.estimate, "observed_order": ch.observed_order,
                "fraction_of_noise": ch.fraction_of_noise,
                "allowed_fraction": ch.allowed_fraction,
            })
        })
        .collect();
    serde_json::json!({
        "substeps": step.substeps, "chosen_by": step.chosen_by, "stable": step.stable,
        "fit": step.fit, "channels": channels, "warning": step.warning,
    })
}
