//! `rigfit simulate`: one experiment of a campaign integrated with fixed
//! values, written as a CSV of the rig's outputs and states, or as a
//! synthetic record with noise that the campaign can read back as it stands.
//! Without a record (`--dt` with `--samples` or `--duration`) the run is
//! sampled from t = 0 on a grid of the user's own.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::Args;

use super::exit::BadInput;
use super::options::{RunLengthArgs, memory_size};
use super::output::{Output, check_out_files, write_file};
use rigfit::base::data::Column;
use rigfit::base::text::number;
use rigfit::campaign::raw::{RawCampaign, RawDrive};
use rigfit::campaign::{Campaign, SimulationGrid};
use rigfit::design::prediction::prediction_bands;
use rigfit::design::uncertainty::Posterior;
use rigfit::eval::{Problem, simulate_history};

mod grid;
mod record;
mod report;
mod step;

use grid::{check_memory, check_steps, grid};
use record::{Channel, history_csv, record_layout, write_record};
use step::{step_json, step_line, substeps};

/// `rigfit simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// Campaign JSON file.
    pub campaign: PathBuf,
    /// Parameter file whose values replace the campaign's: a result.json
    /// ({"params": {...}}) or a flat object of values by name ({"k": 4e4}).
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
    /// Write a synthetic record with Gaussian noise of this standard deviation,
    /// in the unit of the rig's measured output (output 0: N for a force, m for
    /// a displacement, m/s² for an acceleration); for an experiment with
    /// several channels, one per channel, comma-separated, in channel order.
    #[arg(long, allow_negative_numbers = true, value_delimiter = ',')]
    pub noise: Option<Vec<f64>>,
    /// Seed of the noise.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Samples to simulate: at --dt from t = 0 without reading the record, or
    /// without --dt at the record's own interval from its first sample
    /// (default: the record's samples up to the end of its fit window).
    #[arg(long)]
    pub samples: Option<usize>,
    /// Length of the simulation (s), from t = 0 at --dt; the record is not read.
    #[arg(long, allow_negative_numbers = true)]
    pub duration: Option<f64>,
    /// Sample interval (s) of a simulation without a record (with --samples or
    /// --duration).
    #[arg(long, allow_negative_numbers = true)]
    pub dt: Option<f64>,
    /// Without a record (--dt), the CSV file a drive column is read from: the
    /// column, time column and scales the campaign names for its data file.
    #[arg(long)]
    pub drive: Option<PathBuf>,
    /// Refuse a simulation whose estimated memory exceeds this (bytes, or with
    /// K, M, G, T in powers of 1024: 512M, 2G); default: the memory available
    /// now (MemAvailable in /proc/meminfo).
    #[arg(long, value_parser = memory_size)]
    pub max_memory: Option<f64>,
    /// RK4 steps per sample interval (at least the stability rule's count).
    /// Default: what a fit of the record written takes on this grid, and with
    /// --noise a finer step whose integration error is at most 0.2 % of the
    /// noise and a tenth of σ/√N, and at least twice a fit's steps.
    #[arg(long)]
    pub substeps: Option<usize>,
    #[command(flatten)]
    pub run_length: RunLengthArgs,
    /// Also write a report page (one self-contained HTML file) of the model
    /// against the record: the fit and residual over time, the residual's
    /// spectrum. Needs a record (not --dt) and no --noise. An existing file
    /// is replaced only if it is a report rigfit wrote.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Prediction bands: run the experiment again at N draws of the fitted
    /// parameters from the covariance in --params (a result.json), and add
    /// each output's median and central 95 % band over them as columns
    /// <output>_<unit>.median, .lo and .hi.
    #[arg(long, value_name = "N", requires = "params", conflicts_with = "noise")]
    pub bands: Option<usize>,
    /// Seed of the --bands draws.
    #[arg(long, default_value_t = 1, requires = "bands")]
    pub bands_seed: u64,
}

/// Simulates one experiment with the campaign's values and writes a CSV.
pub fn simulate(args: &SimulateArgs, out: &Output) -> Result<()> {
    let grid = grid(args)?;
    if let Some(n) = grid.samples() {
        // Before the campaign allocates a single sample of the grid.
        check_steps(args, n as f64, 1)?;
        check_memory(args, n, 2)?;
    }
    let c = load(args, &grid)?;
    let raw: RawCampaign = serde_json::from_str(&c.raw_json)?;
    let e = match &args.experiment {
        None => 0,
        // An experiment with channels by its own name: its first channel.
        Some(name) => match raw.experiments.iter().position(|x| &x.name == name) {
            Some(owner) => c.owners.iter().position(|&o| o == owner).unwrap_or(0),
            None => c.experiment_index(name).map_err(|names| {
                BadInput(format!(
                    "--experiment `{name}`: the campaign has experiments {names}"
                ))
            })?,
        },
    };
    let owner = c.owners[e];
    // The channels the record holds: every one of the experiment's.
    let channels: Vec<usize> = (0..c.owners.len())
        .filter(|&i| c.owners[i] == owner)
        .collect();
    let outputs = c.model.output_names();
    let measured: Vec<(String, String)> = channels
        .iter()
        .map(|&i| outputs[c.problem.experiments[i].output].clone())
        .collect();
    let (out_name, unit) = measured[0].clone();
    let listed = || {
        measured
            .iter()
            .map(|(n, u)| format!("'{n}' ({u})"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    if let Some(sigmas) = &args.noise {
        if sigmas.len() != channels.len() {
            return Err(BadInput(format!(
                "--noise {}: expected {} standard deviation(s), one per measured channel: {}",
                sigmas
                    .iter()
                    .map(|s| number(*s))
                    .collect::<Vec<_>>()
                    .join(","),
                channels.len(),
                listed()
            ))
            .into());
        }
        if let Some(sigma) = sigmas.iter().find(|s| !(**s >= 0.0 && s.is_finite())) {
            return Err(BadInput(format!(
                "--noise {sigma}: expected a standard deviation ≥ 0 in the unit of the \
                 measured output {}",
                listed()
            ))
            .into());
        }
    }
    if let Some(page) = &args.report
        && (args.noise.is_some() || !grid.reads_records())
    {
        return Err(BadInput(format!(
            "--report `{}`: expected a simulation against the record (without --noise and \
             --dt): a report sets the model against what was measured",
            page.display()
        ))
        .into());
    }
    let x = &raw.experiments[owner];
    let drive_column = match &x.drive {
        RawDrive::Force(t) => t.column.clone(),
        RawDrive::Velocity => None,
    };
    if let (Some(file), None) = (&args.drive, &drive_column) {
        return Err(BadInput(format!(
            "--drive `{}`: experiment '{}' reads no drive column (its drive is {}); \
             leave --drive out",
            file.display(),
            c.problem.experiments[e].name,
            match &x.drive {
                RawDrive::Velocity => "the rig's own \"velocity\" drive laws",
                RawDrive::Force(_) => "an inline table",
            }
        ))
        .into());
    }
    let step = substeps(args, &c, &channels)?;
    let substeps = step.substeps;
    let n = c.problem.experiments[e].window.end;
    let mut c = c;
    c.problem.substeps = substeps;
    c.check_run_length(args.run_length.max_steps)?;
    if let Some(w) = &step.warning {
        eprintln!("rigfit: warning: {w}");
    }
    let drives = usize::from(drive_column.is_some());
    check_memory(
        args,
        n,
        1 + c.model.output_names().len() + c.model.state_names().len() + drives,
    )?;
    check_out_file(
        &args.out,
        &c,
        args.params.as_deref(),
        args.drive.as_deref(),
        args.overwrite,
    )?;

    let bands = match args.bands {
        None => None,
        Some(n) => {
            let file = args.params.as_deref().expect("clap requires --params");
            if !(2..=rigfit::design::file::MAX_DRAWS).contains(&n) {
                return Err(BadInput(format!(
                    "--bands {n}: expected from 2 to {} draws",
                    rigfit::design::file::MAX_DRAWS
                ))
                .into());
            }
            let posterior = Posterior::from_result(file)
                .map_err(|why| BadInput(format!("--bands: `{}`: {why}", file.display())))?;
            check_memory(
                args,
                n.saturating_mul(c.problem.experiments[e].window.end),
                1 + c.model.output_names().len() + c.model.state_names().len(),
            )?;
            Some(prediction_bands(
                &c,
                e,
                &posterior,
                n,
                args.bands_seed,
                rigfit::design::file::BAND_LEVEL,
                file,
            )?)
        }
    };
    let mut problem: Problem = c.problem.clone();
    problem.substeps = substeps;
    let (params, offset) = (c.base[e].clone(), c.base_offsets[e]);
    let h = simulate_history(&problem, e, &params, offset);
    let exp = &problem.experiments[e];
    let drive = drive_column.as_ref().map(|col| {
        let table = exp
            .drive
            .force_table()
            .expect("a drive column is a force table");
        let values: Vec<f64> = (0..h.t.len())
            .map(|k| table.at(exp.t_first + k as f64 * exp.dt) / x.data.force_scale)
            .collect();
        (col, values)
    });
    let text = match &args.noise {
        Some(sigmas) => {
            let columns: Vec<(Column, String)> = match &x.channels {
                Some(chs) => chs
                    .iter()
                    .zip(&measured)
                    .map(|(ch, (n, u))| (ch.column.clone(), format!("{n}_{u}")))
                    .collect(),
                None => vec![(
                    x.data.force_column.clone().unwrap_or(Column::Index(1)),
                    format!("{out_name}_{unit}"),
                )],
            };
            let scales: Vec<f64> = match &x.channels {
                Some(chs) => chs.iter().map(|ch| ch.scale).collect(),
                None => vec![x.data.force_scale],
            };
            let layout = record_layout(&x.data, &columns, drive.as_ref().map(|d| d.0))?;
            let noise = measured
                .iter()
                .zip(sigmas)
                .map(|((n, u), s)| format!("sigma = {} {u} on output {n}", number(*s)))
                .collect::<Vec<_>>()
                .join(", ");
            let mut s = String::new();
            let _ = writeln!(
                s,
                "# SYNTHETIC measurement: made by `rigfit simulate` from campaign {} (experiment {}),\n\
                 # rig {}, Gaussian noise {noise}, seed {}. Not a measured record.",
                c.name,
                x.name,
                c.model.id(),
                args.seed
            );
            let _ = writeln!(s, "# {}", step_line(&step, &measured));
            let channels: Vec<Channel> = channels
                .iter()
                .zip(sigmas)
                .zip(&scales)
                .map(|((&i, &sigma), &scale)| Channel {
                    output: c.problem.experiments[i].output,
                    sigma,
                    scale,
                })
                .collect();
            write_record(
                &mut s,
                &layout,
                &h,
                exp,
                &x.data,
                &channels,
                args.seed,
                drive.as_ref(),
            );
            s
        }
        None => history_csv(&c, &h, drive.as_ref(), bands.as_deref()),
    };
    write_file(&args.out, text.as_bytes())?;
    if let Some(page) = &args.report {
        report::write_page(page, &c, e, &h)?;
    }
    let o = exp.output;
    let peak = h.outputs[o].iter().fold(0.0_f64, |m, f| m.max(f.abs()));
    let noise_json = args.noise.as_ref().map(|sigmas| {
        let one = |s: f64, u: &str| serde_json::json!({"sigma": s, "unit": u, "seed": args.seed});
        match sigmas.as_slice() {
            [s] => one(*s, &unit),
            many => serde_json::Value::Array(
                many.iter()
                    .zip(&measured)
                    .map(|(s, (n, u))| {
                        let mut v = one(*s, u);
                        v["output"] = serde_json::json!(n);
                        v
                    })
                    .collect(),
            ),
        }
    });
    out.json(&serde_json::json!({
        "out": args.out, "experiment": exp.name, "samples": h.t.len(),
        "dt": exp.dt, "substeps": substeps, "record_read": grid.reads_records(),
        "step": step_json(&step, &measured),
        "noise": noise_json,
        "drive_column": drive.as_ref().map(|d| column_label(d.0)),
        "peak": {"output": out_name, "unit": unit, "abs_max": peak},
        "bands": args.bands.map(|n| serde_json::json!({"draws": n, "seed": args.bands_seed, "level": rigfit::design::file::BAND_LEVEL})),
    }))?;
    out.say(|| {
        let noise = args
            .noise
            .as_ref()
            .map(|sigmas| {
                let each: Vec<String> = sigmas
                    .iter()
                    .zip(&measured)
                    .map(|(s, (n, u))| format!("{} {u} on {n}", number(*s)))
                    .collect();
                format!(", noise σ = {}", each.join(", "))
            })
            .unwrap_or_default();
        format!(
            "simulated {} ({} samples at dt = {:e} s{noise}): largest |{out_name}| {peak:.4e} {unit} → {}\n  {}",
            x.name,
            h.t.len(),
            exp.dt,
            args.out.display(),
            step_line(&step, &measured)
        )
    });
    Ok(())
}

/// The campaign read for `grid`, a parameter file's values applied, its
/// warnings printed.
fn load(args: &SimulateArgs, grid: &SimulationGrid) -> Result<Campaign> {
    let mut c = Campaign::load_for_simulation(&args.campaign, grid)?;
    if let Some(p) = &args.params {
        c.apply_param_file(p)?;
    }
    for w in &c.warnings {
        eprintln!("rigfit: warning: {w}");
    }
    Ok(c)
}

/// A column as JSON names it: its header name or its 0-based position.
fn column_label(c: &Column) -> serde_json::Value {
    match c {
        Column::Name(n) => n.clone().into(),
        Column::Index(i) => (*i).into(),
    }
}

/// Refuses an `--out` file that is one of the job's inputs (the campaign's
/// files, `--params`, `--drive`), or exists without `--overwrite`, or cannot be
/// a file: the check every command that writes a file makes.
fn check_out_file(
    out: &Path,
    c: &Campaign,
    params: Option<&Path>,
    drive: Option<&Path>,
    overwrite: bool,
) -> Result<(), BadInput> {
    let inputs: Vec<&Path> = c
        .inputs
        .iter()
        .map(PathBuf::as_path)
        .chain(params)
        .chain(drive)
        .collect();
    check_out_files(&[("--out", out)], &inputs, overwrite)
}
