//! `rigfit sweep`: a calibrated rig run over a grid of design changes (or
//! points drawn from distributions), every run reduced to named metrics,
//! written as one CSV row per design point; with the calibration's
//! uncertainty, a median and a 95 % band per metric; Sobol indices and an SVG
//! picture on request.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;

use super::exit::BadInput;
use super::options::{memory_limit, memory_size};
use super::output::{Output, check_out_files, write_file};
use super::run::PrecisionArg;
use rigfit::design::figures::picture;
use rigfit::design::sensitivity::sobol_table;
use rigfit::design::{Engine, GpuRuns, RunOptions, Sweep, run_sweep};
use rigfit::eval::PrecisionChoice;

/// Where a sweep's runs are simulated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SweepBackend {
    /// The f64 CPU lanes on every core (the reference; rows equal `rigfit simulate`'s).
    Cpu,
    /// The GPU's history kernel (no adapter is an error); agrees with the CPU within the precision's tolerance.
    Gpu,
}

/// `rigfit sweep`.
#[derive(Debug, Args)]
pub struct SweepArgs {
    /// Sweep file (JSON): the campaign, optional parameter file, the design
    /// variables with their grids or distributions, and the metrics.
    pub sweep: PathBuf,
    /// CSV file to write: one row per design point.
    #[arg(long)]
    pub out: PathBuf,
    /// Also write the Sobol indices of every metric (CSV; the sweep file's
    /// "sampling" must ask for "indices").
    #[arg(long)]
    pub indices: Option<PathBuf>,
    /// Also draw one metric as an SVG picture: a line (with its band) over
    /// the first variable for each combination of the others, a heat map
    /// for two grid variables, or the Sobol indices of drawn points.
    #[arg(long)]
    pub picture: Option<PathBuf>,
    /// The metric --picture draws (default: the first).
    #[arg(long, requires = "picture")]
    pub metric: Option<String>,
    /// Replace the output files when they exist (never one of the inputs).
    #[arg(long)]
    pub overwrite: bool,
    /// Where the runs are simulated.
    #[arg(long, value_enum, default_value = "cpu")]
    pub backend: SweepBackend,
    /// GPU precision (auto: f64 where the adapter has it, else f32).
    #[arg(long, value_enum)]
    pub precision: Option<PrecisionArg>,
    /// GPU adapter to use (a name's part or an index, as `rigfit devices`
    /// lists them).
    #[arg(long)]
    pub adapter: Option<String>,
    /// Threads to run on (default: every core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Refuse a sweep whose histories held at once exceed this (bytes, or
    /// with K, M, G, T in powers of 1024: 512M, 2G); default: the memory
    /// available now (MemAvailable in /proc/meminfo).
    #[arg(long, value_parser = memory_size)]
    pub max_memory: Option<f64>,
}

/// Runs the sweep and writes its table.
pub fn sweep(args: &SweepArgs, out: &Output) -> Result<()> {
    if args.threads == Some(0) {
        return Err(BadInput("--threads 0: expected at least 1 thread".into()).into());
    }
    if args.backend == SweepBackend::Cpu && (args.precision.is_some() || args.adapter.is_some()) {
        return Err(BadInput(
            "--precision and --adapter choose the GPU's; pass --backend gpu with them".into(),
        )
        .into());
    }
    // Every refusal of the library's is the input's fault (exit code 2).
    let bad = |e: rigfit::design::DesignError| BadInput(e.to_string());
    let sweep = Sweep::load(&args.sweep).map_err(bad)?;
    for w in &sweep.campaign.warnings {
        eprintln!("rigfit: warning: {w}");
    }
    let inputs: Vec<&Path> = sweep.inputs.iter().map(PathBuf::as_path).collect();
    let mut outs: Vec<(&str, &Path)> = vec![("--out", &args.out)];
    if let Some(p) = &args.indices {
        outs.push(("--indices", p));
    }
    if let Some(p) = &args.picture {
        outs.push(("--picture", p));
    }
    check_out_files(&outs, &inputs, args.overwrite)?;
    // What the pictures and indices need is refused before any run.
    let indexed = matches!(&sweep.points, rigfit::design::Points::Drawn(d) if d.indices);
    if args.indices.is_some() && !indexed {
        return Err(BadInput(format!(
            "--indices: {}: the design has no Sobol indices; draw its points with \
             \"sampling\": {{…, \"indices\": true}}",
            args.sweep.display()
        ))
        .into());
    }
    let metric = match &args.metric {
        None => 0,
        Some(m) => sweep
            .metrics
            .iter()
            .position(|x| &x.name == m)
            .ok_or_else(|| {
                let names: Vec<&str> = sweep.metrics.iter().map(|x| x.name.as_str()).collect();
                BadInput(format!(
                    "--metric '{m}': expected a metric of the sweep file ({})",
                    names.join(", ")
                ))
            })?,
    };
    if args.picture.is_some() {
        rigfit::design::figures::check(&sweep)
            .map_err(|why| BadInput(format!("--picture: {}: {why}", args.sweep.display())))?;
    }
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = args.threads {
        builder = builder.num_threads(n);
    }
    let pool = builder.build().context("starting the sweep's threads")?;
    let options = RunOptions {
        max_memory: memory_limit(args.max_memory).map(|(m, from)| (m, from.to_string())),
        ..RunOptions::default()
    };
    let mut gpu = match args.backend {
        SweepBackend::Cpu => None,
        SweepBackend::Gpu => {
            let precision = args
                .precision
                .map_or(PrecisionChoice::Auto, PrecisionChoice::from);
            Some(GpuRuns::open(args.adapter.as_deref(), precision).context("--backend gpu")?)
        }
    };
    let device = match &gpu {
        None => format!("{} CPU threads", pool.current_num_threads()),
        Some(g) => format!(
            "{} ({:?})",
            g.describe(),
            g.precision().context("--precision")?
        ),
    };
    let start = Instant::now();
    let quiet = out.quiet;
    let total_runs = sweep.points() * sweep.runs_per_point();
    if !quiet {
        eprintln!(
            "rigfit: sweep: {} design points × {} run(s) each = {total_runs} runs on {device}",
            sweep.points(),
            sweep.runs_per_point()
        );
    }
    let progress = move |done: usize, total: usize| {
        let s = start.elapsed().as_secs_f64();
        if !quiet && done > 0 && done < total && s > 2.0 {
            eprintln!(
                "rigfit: sweep: {done} of {total} design points ({:.0} per second)",
                done as f64 / s
            );
        }
    };
    let engine = match gpu.as_mut() {
        None => Engine::Cpu,
        Some(g) => Engine::Gpu(g),
    };
    let table = pool
        .install(|| run_sweep(&sweep, &options, engine, &progress))
        .map_err(bad)?;
    let wall = start.elapsed().as_secs_f64();
    let indices = if indexed {
        Some(sobol_table(&sweep, &table).map_err(|why| anyhow::anyhow!("Sobol indices: {why}"))?)
    } else {
        None
    };
    let svg = match &args.picture {
        Some(_) => {
            Some(picture(&sweep, &table, metric, indices.as_ref()).context("drawing --picture")?)
        }
        None => None,
    };
    write_file(&args.out, table.csv().as_bytes())?;
    if let (Some(p), Some(ix)) = (&args.indices, &indices) {
        write_file(p, ix.csv().as_bytes())?;
    }
    if let (Some(p), Some(svg)) = (&args.picture, &svg) {
        write_file(p, svg.as_bytes())?;
    }
    let points = table.rows.len();
    let rate = (points * sweep.runs_per_point()) as f64 / wall.max(1e-9);
    let steps: Vec<usize> = {
        let mut s: Vec<usize> = table.rows.iter().map(|r| r.substeps).collect();
        s.sort_unstable();
        s.dedup();
        s
    };
    out.json(&serde_json::json!({
        "out": args.out, "points": points, "runs": points * sweep.runs_per_point(),
        "variables": table.variables, "metrics": table.metrics, "wall_s": wall,
        "runs_per_s": rate, "device": device, "substeps": steps,
        "indices": indices.as_ref().map(|i| i.json()),
        "experiment": sweep.campaign.problem.experiments[sweep.experiment].name,
    }))?;
    out.say(|| {
        let mut s = format!(
            "swept {points} design points of {} ({} × {} metrics{}) in {wall:.2} s, {rate:.0} \
             runs/s on {device} → {}",
            sweep.campaign.problem.experiments[sweep.experiment].name,
            table.variables.join(" × "),
            table.metrics.len(),
            if table.banded {
                format!(", {} draws each", sweep.runs_per_point() - 1)
            } else {
                String::new()
            },
            args.out.display()
        );
        if let Some(ix) = &indices {
            s.push_str(&format!("\n{}", ix.text()));
        }
        s
    });
    Ok(())
}
