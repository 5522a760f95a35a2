//! `rigfit sweep`: a calibrated rig run over a grid of design changes, every
//! run reduced to named metrics, written as one CSV row per design point.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;

use super::exit::BadInput;
use super::options::{memory_limit, memory_size};
use super::output::{Output, check_out_files, write_file};
use rigfit::design::{RunOptions, Sweep, run_sweep};

/// `rigfit sweep`.
#[derive(Debug, Args)]
pub struct SweepArgs {
    /// Sweep file (JSON): the campaign, optional parameter file, the design
    /// variables with their grids, and the metrics.
    pub sweep: PathBuf,
    /// CSV file to write: one row per design point.
    #[arg(long)]
    pub out: PathBuf,
    /// Replace the --out file when it exists (never one of the inputs).
    #[arg(long)]
    pub overwrite: bool,
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
    // Every refusal of the library's is the input's fault (exit code 2).
    let bad = |e: rigfit::design::DesignError| BadInput(e.to_string());
    let sweep = Sweep::load(&args.sweep).map_err(bad)?;
    for w in &sweep.campaign.warnings {
        eprintln!("rigfit: warning: {w}");
    }
    let inputs: Vec<&Path> = sweep.inputs.iter().map(PathBuf::as_path).collect();
    check_out_files(&[("--out", &args.out)], &inputs, args.overwrite)?;
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = args.threads {
        builder = builder.num_threads(n);
    }
    let pool = builder.build().context("starting the sweep's threads")?;
    let options = RunOptions {
        max_memory: memory_limit(args.max_memory).map(|(m, from)| (m, from.to_string())),
        ..RunOptions::default()
    };
    let start = Instant::now();
    let quiet = out.quiet;
    let progress = move |done: usize, total: usize| {
        let s = start.elapsed().as_secs_f64();
        if !quiet && done < total && s > 2.0 {
            eprintln!(
                "rigfit: sweep: {done} of {total} design points ({:.0} per second)",
                done as f64 / s
            );
        }
    };
    let table = pool
        .install(|| run_sweep(&sweep, &options, &progress))
        .map_err(bad)?;
    let wall = start.elapsed().as_secs_f64();
    write_file(&args.out, table.csv().as_bytes())?;
    let points = table.rows.len();
    let rate = points as f64 / wall.max(1e-9);
    out.json(&serde_json::json!({
        "out": args.out, "points": points, "variables": table.variables,
        "metrics": table.metrics, "wall_s": wall, "runs_per_s": rate,
        "threads": pool.current_num_threads(),
        "experiment": sweep.campaign.problem.experiments[sweep.experiment].name,
    }))?;
    out.say(|| {
        format!(
            "swept {points} design points of {} ({} × {} metrics) in {wall:.2} s, {rate:.0} runs/s \
             on {} threads → {}",
            sweep.campaign.problem.experiments[sweep.experiment].name,
            table.variables.join(" × "),
            table.metrics.len(),
            pool.current_num_threads(),
            args.out.display()
        )
    });
    Ok(())
}
