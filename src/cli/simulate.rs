//! `rigfit simulate`: one experiment of a campaign integrated with fixed
//! values, written as a CSV of the rig's outputs and states, or as a
//! synthetic record with noise that the campaign can read back as it stands.
//! Without a record (`--dt` with `--samples` or `--duration`) the run is
//! sampled from t = 0 on a grid of the user's own.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::Args;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::exit::BadInput;
use super::options::{RunLengthArgs, memory_limit, memory_size};
use super::output::{Output, check_out_files, write_file};
use rigfit::base::data::Column;
use rigfit::base::noise::gaussian;
use rigfit::base::text::steps_per_sample;
use rigfit::base::text::{echo, number};
use rigfit::campaign::raw::{RawCampaign, RawData, RawDrive};
use rigfit::campaign::{
    Campaign, MAX_AUTO_SUBSTEPS, STABILITY_LIMIT, SimulationGrid, SimulationStep,
};
use rigfit::eval::{History, Problem, simulate_history};
use rigfit::job::memory::human_bytes;

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
        None => history_csv(&c, &h, drive.as_ref()),
    };
    write_file(&args.out, text.as_bytes())?;
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

/// RK4 steps per sample interval for the simulation: `--substeps` (held to
/// the stability rule's count), else the campaign's step rule as a fit of the
/// record written would apply it on this grid, finer still for a synthetic
/// record (see [`Campaign::simulation_step`]).
fn substeps(args: &SimulateArgs, c: &Campaign, channels: &[usize]) -> Result<SimulationStep> {
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
fn step_line(step: &SimulationStep, measured: &[(String, String)]) -> String {
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
fn step_json(step: &SimulationStep, measured: &[(String, String)]) -> serde_json::Value {
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

/// The grid the options ask for; the record is read unless `--dt` is given.
fn grid(args: &SimulateArgs) -> Result<SimulationGrid, BadInput> {
    let positive = |flag: &str, v: f64, what: &str| {
        if v > 0.0 && v.is_finite() {
            Ok(v)
        } else {
            Err(BadInput(format!("{flag} {v}: expected {what}")))
        }
    };
    if let Some(n) = args.samples {
        if n < 2 {
            return Err(BadInput(format!("--samples {n}: expected at least 2")));
        }
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
fn check_steps(args: &SimulateArgs, samples: f64, substeps: usize) -> Result<(), BadInput> {
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
fn check_memory(args: &SimulateArgs, samples: usize, values: usize) -> Result<(), BadInput> {
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

/// What one column of a synthetic record holds.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Cell {
    Time,
    /// Measured channel `j` (in the order of [`Channel`]s).
    Measured(usize),
    Drive,
    /// A column between two the campaign reads by position: zeros.
    Unused,
}

/// One measured column of a synthetic record: the output, its noise (the
/// output's unit) and the campaign's multiplier to that unit.
struct Channel {
    output: usize,
    sigma: f64,
    scale: f64,
}

/// The record's columns in order, each with its header, placed where the
/// campaign's `data` reads them: by name, or at a 0-based position.
/// `measured`: each channel's column and default header.
fn record_layout(
    data: &RawData,
    measured: &[(Column, String)],
    drive: Option<&Column>,
) -> Result<Vec<(String, Cell)>, BadInput> {
    let time = data.time_column.clone().unwrap_or(Column::Index(0));
    let mut wanted = vec![(time, "t_s".to_string(), Cell::Time)];
    for (j, (column, header)) in measured.iter().enumerate() {
        wanted.push((column.clone(), header.clone(), Cell::Measured(j)));
    }
    if let Some(d) = drive {
        wanted.push((d.clone(), "drive".into(), Cell::Drive));
    }
    let width = wanted
        .iter()
        .map(|(c, ..)| match c {
            Column::Index(i) => i + 1,
            Column::Name(_) => 0,
        })
        .max()
        .unwrap_or(0)
        .max(wanted.len());
    if width > 64 {
        return Err(BadInput(format!(
            "the campaign reads a column at position {}: expected positions below 64 for a \
             record rigfit simulate writes; name the columns instead",
            width - 1
        )));
    }
    let mut slots: Vec<Option<(String, Cell)>> = vec![None; width];
    for (c, default, cell) in &wanted {
        if let Column::Index(i) = c {
            if let Some((_, other)) = &slots[*i] {
                return Err(BadInput(format!(
                    "the campaign reads its {other:?} and {cell:?} columns both at position {i}; \
                     expected one column per position"
                )));
            }
            slots[*i] = Some((default.clone(), *cell));
        }
    }
    for (c, _, cell) in &wanted {
        if let Column::Name(name) = c {
            if name.contains([',', ';', '\t', '"', '\n', '\r']) {
                return Err(BadInput(format!(
                    "column name {}: expected a name without separators, quotes or line breaks \
                     for a record rigfit simulate writes",
                    echo(name)
                )));
            }
            let free = slots
                .iter()
                .position(Option::is_none)
                .expect("as many slots as columns");
            slots[free] = Some((name.clone(), *cell));
        }
    }
    Ok(slots
        .into_iter()
        .enumerate()
        .map(|(i, s)| s.unwrap_or_else(|| (format!("unused_{i}"), Cell::Unused)))
        .collect())
}

/// Significant digits that keep the rounding of a noisy value well below the
/// noise: at least the 7 the shipped records carry.
fn digits(peak: f64, sigma: f64) -> usize {
    if sigma > 0.0 && peak > 0.0 {
        ((peak / sigma).log10().ceil() as usize + 3).clamp(7, 17)
    } else {
        17
    }
}

/// Writes the synthetic record's header and rows: the record's time, each
/// measured channel with its noise, the drive column, each in the unit the
/// campaign reads it in.
#[expect(
    clippy::too_many_arguments,
    reason = "one row writer, every part named"
)]
fn write_record(
    s: &mut String,
    layout: &[(String, Cell)],
    h: &History,
    exp: &rigfit::eval::ExperimentData,
    data: &RawData,
    channels: &[Channel],
    seed: u64,
    drive: Option<&(&Column, Vec<f64>)>,
) {
    let names: Vec<&str> = layout.iter().map(|(n, _)| n.as_str()).collect();
    *s += &names.join(",");
    s.push('\n');
    let precision: Vec<usize> = channels
        .iter()
        .map(|ch| {
            let peak = h.outputs[ch.output]
                .iter()
                .fold(0.0_f64, |m, f| m.max(f.abs()));
            digits(peak, ch.sigma) - 1
        })
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut noisy = vec![0.0; channels.len()];
    for k in 0..h.t.len() {
        let t = exp.t_first + k as f64 * exp.dt;
        // One draw per sample and channel whatever the layout, so a seed
        // gives one noise.
        for (v, ch) in noisy.iter_mut().zip(channels) {
            *v = h.outputs[ch.output][k] + ch.sigma * gaussian(&mut rng);
        }
        for (i, (_, cell)) in layout.iter().enumerate() {
            if i > 0 {
                s.push(',');
            }
            let _ = match *cell {
                Cell::Time => write!(s, "{:.9e}", t / data.time_scale),
                Cell::Measured(j) => {
                    let p = precision[j];
                    write!(s, "{:.p$e}", noisy[j] / channels[j].scale)
                }
                Cell::Drive => write!(s, "{:e}", drive.map_or(0.0, |d| d.1[k])),
                Cell::Unused => write!(s, "0"),
            };
        }
        s.push('\n');
    }
}

/// The history without noise: `t_s`, every output and state by the rig's own
/// names, then the drive column by the campaign's name for it.
fn history_csv(c: &Campaign, h: &History, drive: Option<&(&Column, Vec<f64>)>) -> String {
    let mut s = String::from("t_s");
    let mut names = vec!["t_s".to_string()];
    for (name, unit) in c.model.output_names() {
        names.push(format!("{name}_{unit}"));
    }
    names.extend(c.model.state_names().iter().map(ToString::to_string));
    for n in &names[1..] {
        let _ = write!(s, ",{n}");
    }
    if let Some((col, _)) = drive {
        let name = match col {
            Column::Name(n) if !names.contains(n) && !n.contains([',', '"', '\n', '\r']) => {
                n.clone()
            }
            Column::Name(n) => format!("drive_{}", n.replace([',', '"', '\n', '\r'], "_")),
            Column::Index(_) => "drive".into(),
        };
        let _ = write!(s, ",{name}");
    }
    s.push('\n');
    for k in 0..h.t.len() {
        let _ = write!(s, "{:.9e}", h.t[k]);
        for o in h.outputs.iter().chain(&h.states) {
            let _ = write!(s, ",{:.9e}", o[k]);
        }
        if let Some((_, d)) = drive {
            let _ = write!(s, ",{:e}", d[k]);
        }
        s.push('\n');
    }
    s
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
