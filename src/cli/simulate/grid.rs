//! The grid a simulation samples ([`grid`]: the record's, or `--dt` with
//! `--samples` or `--duration`), and the limits it is held to before any
//! work: `--max-steps` and the memory available.

use super::SimulateArgs;
use crate::cli::exit::BadInput;
use crate::cli::options::memory_limit;
use rigfit::campaign::SimulationGrid;
use rigfit::job::memory::human_bytes;

/// The grid the options ask for; the record is read unless `--dt` is given.
pub(super) fn grid(args: &SimulateArgs) -> Result<SimulationGrid, BadInput> {
    let positive = |flag: &str, v: f64, what: &str| {
        if v > 0.0 && v.is_finite() {
            Ok(v)
        } else {
            Err(BadInput(format!("{flag} {v}: expected {what}")))
        }
    };
    if let Some(n) = args.samples
        && n < 2
    {
        return Err(BadInput(format!("--samples {n}: expected at least 2")));
    }
    let Some(dt) = args.dt else {
        if let Some(d) = args.duration {
            return Err(BadInput(format!(
                "--duration {d}: expected --dt with it (the sample interval in s of a \
                 simulation without a record)"
            )));
        }
        if let Some(f) = &args.drive {
            return Err(BadInput(format!(
                "--drive `{}`: expected --dt and --samples or --duration with it; with the \
                 record the drive column is read from the record",
                f.display()
            )));
        }
        return Ok(match args.samples {
            Some(samples) => SimulationGrid::RecordInterval { samples },
            None => SimulationGrid::Record,
        });
    };
    let dt = positive("--dt", dt, "a sample interval > 0 (s)")?;
    let samples = match (args.samples, args.duration) {
        (Some(n), None) => n,
        (None, Some(d)) => {
            let d = positive("--duration", d, "a length > 0 (s)")?;
            let intervals = (d / dt * (1.0 + 1e-12)).floor();
            check_steps(args, intervals + 1.0, 1)?;
            if intervals < 1.0 {
                return Err(BadInput(format!(
                    "--duration {d}: expected at least one sample interval (--dt {dt:e} s)"
                )));
            }
            intervals as usize + 1
        }
        (Some(n), Some(d)) => {
            return Err(BadInput(format!(
                "--samples {n} and --duration {d}: expected one of them, not both"
            )));
        }
        (None, None) => {
            return Err(BadInput(format!(
                "--dt {dt:e}: expected --samples N or --duration S with it"
            )));
        }
    };
    Ok(SimulationGrid::Uniform {
        dt,
        samples,
        drive_file: args.drive.clone(),
        experiment: args.experiment.clone(),
    })
}

/// The option that set the simulation's length, for messages.
fn length_of(args: &SimulateArgs) -> String {
    match (args.samples, args.duration, args.dt) {
        (_, Some(d), Some(dt)) => format!("--duration {d} at --dt {dt:e}"),
        (Some(n), _, _) => format!("--samples {n}"),
        _ => "the record".into(),
    }
}

/// Refuses `samples` samples that take more RK4 steps than `--max-steps` at
/// `substeps` steps per sample interval (1: the fewest any step rule takes).
pub(super) fn check_steps(
    args: &SimulateArgs,
    samples: f64,
    substeps: usize,
) -> Result<(), BadInput> {
    let max = args.run_length.max_steps;
    let steps = (samples - 1.0) * substeps as f64;
    if steps <= max {
        return Ok(());
    }
    Err(BadInput(format!(
        "{}: expected at most {max:e} RK4 steps per run (raise with --max-steps), found \
         {samples:e} samples taking at least {steps:e} steps, one per sample interval",
        length_of(args)
    )))
}

/// Bytes each value of a simulated sample holds at the peak: the history's
/// f64 and its text in the CSV (about 17 characters, and room for the text to
/// grow into).
const BYTES_PER_VALUE: f64 = 8.0 + 2.0 * 17.0;

/// Refuses a simulation of `samples` samples of `values` values each (time,
/// outputs, states, drives) that does not fit in `--max-memory` or the memory
/// available now; the record's own copy and the grid's placeholder count too.
pub(super) fn check_memory(
    args: &SimulateArgs,
    samples: usize,
    values: usize,
) -> Result<(), BadInput> {
    let need = samples as f64 * (values as f64 * BYTES_PER_VALUE + 16.0);
    let Some((limit, source)) = memory_limit(args.max_memory) else {
        return Ok(());
    };
    if need <= limit {
        return Ok(());
    }
    Err(BadInput(format!(
        "{}: expected a simulation that fits in {} ({source}), found about {} ({samples} \
         samples of {values} values); shorten it{}",
        length_of(args),
        human_bytes(limit),
        human_bytes(need),
        if args.max_memory.is_some() {
            " or raise --max-memory"
        } else {
            ", free memory, or set --max-memory"
        }
    )))
}
