//! `rigfit simulate`: one experiment of a campaign integrated with fixed
//! values, written as a CSV of the rig's outputs and states, or as a
//! synthetic measurement with noise.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::Args;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::campaign_file::load;
use super::exit::BadInput;
use super::options::RunLengthArgs;
use super::output::{Output, write_file};
use rigfit::base::noise::gaussian;
use rigfit::campaign::Campaign;
use rigfit::eval::{Problem, simulate_history};

/// `rigfit simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// Campaign JSON file.
    pub campaign: PathBuf,
    /// Parameter file (e.g. a result.json) whose "params" replace the campaign's values.
    #[arg(long)]
    pub params: Option<PathBuf>,
    /// CSV file to write.
    #[arg(long)]
    pub out: PathBuf,
    /// Replace the --out file when it exists (never the campaign's own input files).
    #[arg(long)]
    pub overwrite: bool,
    /// Experiment to simulate, by name (default: the first).
    #[arg(long)]
    pub experiment: Option<String>,
    /// Write a synthetic measurement with Gaussian noise of this standard deviation
    /// (in the unit of the rig's output 0, the measured one: N for the tensile rig).
    #[arg(long)]
    pub noise: Option<f64>,
    /// Seed of the noise.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Samples to simulate at the experiment's sample interval (default: the
    /// experiment's run length).
    #[arg(long)]
    pub samples: Option<usize>,
    #[command(flatten)]
    pub run_length: RunLengthArgs,
}

/// Simulates one experiment with the campaign's values and writes a CSV.
pub fn simulate(args: &SimulateArgs, out: &Output) -> Result<()> {
    let c = load(&args.campaign, args.params.as_deref())?;
    c.check_run_length(args.run_length.max_steps)?;
    check_out_file(&args.out, &c, args.params.as_deref(), args.overwrite)?;
    let e = match &args.experiment {
        None => 0,
        Some(name) => c.experiment_index(name).map_err(|names| {
            BadInput(format!(
                "--experiment `{name}`: the campaign has experiments {names}"
            ))
        })?,
    };
    if let Some(sigma) = args.noise {
        if !(sigma >= 0.0 && sigma.is_finite()) {
            return Err(BadInput(format!(
                "--noise {sigma}: expected a standard deviation ≥ 0 (N)"
            ))
            .into());
        }
    }
    let mut problem: Problem = c.problem.clone();
    let exp = &mut problem.experiments[e];
    if let Some(n) = args.samples {
        if n < 2 {
            return Err(BadInput(format!("--samples {n}: expected at least 2")).into());
        }
        exp.force.resize(n, 0.0);
        exp.window = 0..n;
    }
    let (params, offset) = (c.base[e].clone(), c.base_offsets[e]);
    let h = simulate_history(&problem, e, &params, offset);
    let exp = &problem.experiments[e];
    let mut s = String::new();
    match args.noise {
        Some(sigma) => {
            let mut rng = ChaCha8Rng::seed_from_u64(args.seed);
            let _ = writeln!(
                s,
                "# SYNTHETIC measurement: made by `rigfit simulate` from campaign {} (experiment {}),\n\
                 # rig {}, Gaussian noise sigma = {sigma} {} on output {}, seed {}. Not a measured record.",
                c.name,
                exp.name,
                c.model.id(),
                c.model.output_names()[0].1,
                c.model.output_names()[0].0,
                args.seed
            );
            s += "t_s,force_N\n";
            for (k, f) in h.outputs[0].iter().enumerate() {
                let t = exp.t_first + k as f64 * exp.dt;
                let _ = writeln!(s, "{t:.9e},{:.6e}", f + sigma * gaussian(&mut rng));
            }
        }
        None => {
            s += "t_s";
            for (name, unit) in c.model.output_names() {
                let _ = write!(s, ",{name}_{unit}");
            }
            for name in c.model.state_names() {
                let _ = write!(s, ",{name}");
            }
            s.push('\n');
            for k in 0..h.t.len() {
                let _ = write!(s, "{:.9e}", h.t[k]);
                for o in h.outputs.iter().chain(&h.states) {
                    let _ = write!(s, ",{:.9e}", o[k]);
                }
                s.push('\n');
            }
        }
    }
    write_file(&args.out, s.as_bytes())?;
    // Output 0 is the measured one, in the rig's own name and unit.
    let (name, unit) = c.model.output_names()[0];
    let peak = h.outputs[0].iter().fold(0.0_f64, |m, f| m.max(f.abs()));
    out.json(&serde_json::json!({
        "out": args.out, "experiment": exp.name, "samples": h.t.len(),
        "peak": {"output": name, "unit": unit, "abs_max": peak},
    }))?;
    out.say(|| {
        format!(
            "simulated {} ({} samples, {}): largest |{name}| {peak:.4e} {unit} → {}",
            exp.name,
            h.t.len(),
            rigfit::base::text::steps_per_sample(problem.substeps),
            args.out.display()
        )
    });
    Ok(())
}

/// Refuses an `--out` file that is one of the job's inputs, or that exists
/// without `--overwrite`.
fn check_out_file(
    out: &Path,
    c: &Campaign,
    params: Option<&Path>,
    overwrite: bool,
) -> Result<(), BadInput> {
    let Ok(meta) = std::fs::metadata(out) else {
        return Ok(());
    };
    let target = out.canonicalize().ok();
    let input = c
        .inputs
        .iter()
        .map(PathBuf::as_path)
        .chain(params)
        .find(|p| p.canonicalize().ok() == target);
    if let Some(input) = input {
        return Err(BadInput(format!(
            "--out `{}` is the input file `{}`; rigfit never writes over its inputs",
            out.display(),
            input.display()
        )));
    }
    if !meta.is_file() {
        return Err(BadInput(format!(
            "--out `{}`: expected a file name, found an existing folder or device",
            out.display()
        )));
    }
    if !overwrite {
        return Err(BadInput(format!(
            "--out `{}` exists; pass --overwrite to replace it",
            out.display()
        )));
    }
    Ok(())
}
