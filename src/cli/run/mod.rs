//! `rigfit run`: the calibration job. The checks that refuse a job before
//! any work are in `limits`, the summary printed at its end in `summary`.

mod limits;
mod summary;

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::Result;
use clap::{Args, ValueEnum};

use super::exit::{BadInput, EXIT_INTERRUPTED};
use super::options::{RunLengthArgs, memory_size};
use super::output::Output;
use rigfit::campaign::Campaign;
use rigfit::eval::{Backend, EvalError, PrecisionChoice};
use rigfit::job::backend::{OpenError, OpenNote};
use rigfit::job::memory::human_bytes;
use rigfit::job::{self, FolderMode, JobError, JobOptions, OutputFolder};
use rigfit::search::SearchError;

/// Evaluator backend on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum BackendArg {
    /// The faster of the two on this machine: measured by a short trial of each (cached per machine and job); a job estimated under 4 s runs on the CPU unmeasured; the CPU where no GPU adapter is found.
    Auto,
    /// GPU only (no adapter is an error).
    Gpu,
    /// The CPU lanes (f64 reference arithmetic).
    Cpu,
}

/// Arithmetic precision on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum PrecisionArg {
    /// GPU: f64 when the adapter supports it, else f32. CPU: f64.
    Auto,
    /// Single precision (on the CPU: a compiled rig's native f32 lanes).
    F32,
    /// Double precision.
    F64,
}

/// `rigfit run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Campaign JSON file.
    pub campaign: PathBuf,
    /// Output folder (default: the campaign's "output").
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Evaluator backend (default: the campaign's solver.backend).
    #[arg(long, value_enum)]
    pub backend: Option<BackendArg>,
    /// Precision (default: the campaign's solver.precision); on the CPU only
    /// f32 differs from the f64 reference.
    #[arg(long, value_enum)]
    pub precision: Option<PrecisionArg>,
    /// Continue from the checkpoint in the output folder.
    #[arg(long)]
    pub resume: bool,
    /// Replace an output folder that holds an earlier job's files.
    #[arg(long)]
    pub overwrite: bool,
    /// Override the campaign's search.population.
    #[arg(long)]
    pub population: Option<usize>,
    /// Override the campaign's search.generations.
    #[arg(long)]
    pub generations: Option<usize>,
    /// Override the campaign's search.seed.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Override the campaign's search.target_fitness (stop once 1 − R² ≤ this).
    #[arg(long)]
    pub target_fitness: Option<f64>,
    /// CPU threads for the CPU evaluator (0: all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    #[command(flatten)]
    pub run_length: RunLengthArgs,
    /// Refuse a job whose estimated memory exceeds this (bytes, or with K, M,
    /// G, T in powers of 1024: 512M, 2G); default: the memory available now
    /// (MemAvailable in /proc/meminfo).
    #[arg(long, value_parser = memory_size)]
    pub max_memory: Option<f64>,
    /// GPU adapter: its index, PCI bus id or a piece of its name, as `rigfit
    /// devices` lists them (default: RIGFIT_ADAPTER, else the first
    /// high-performance adapter). Recorded in result.json.
    #[arg(long)]
    pub adapter: Option<String>,
}

/// How to get the GPU path when `auto` fell back to the CPU.
const GPU_HINT: &str = "for the GPU path install a Vulkan driver (Debian: \
    `apt-get install mesa-vulkan-drivers` for the software adapter lavapipe, or your GPU vendor's driver)";

/// Loads, validates, runs and reports one calibration job.
pub fn run(a: &RunArgs, out: &Output) -> Result<ExitCode> {
    let mut c = Campaign::load(&a.campaign)?;
    c.require_search()?;
    if let Some(n) = a.population {
        c.search.population = n;
    }
    if let Some(n) = a.generations {
        c.search.generations = n;
    }
    if let Some(s) = a.seed {
        c.search.seed = s;
    }
    if let Some(t) = a.target_fitness {
        c.search.target_fitness = Some(t);
    }
    c.search.validate().map_err(|e| {
        // Blame the flag that set the value, not the campaign file.
        let flag = match e.field {
            "population" => a.population.map(|n| format!("--population {n}")),
            "generations" => a.generations.map(|n| format!("--generations {n}")),
            "target_fitness" => a.target_fitness.map(|t| format!("--target-fitness {t}")),
            "tournament" | "elitism" => a.population.map(|n| {
                format!(
                    "--population {n}: the campaign's search.{} = {} needs a larger population",
                    e.field, e.found
                )
            }),
            _ => None,
        };
        match flag {
            Some(flag) => BadInput(format!(
                "{flag}: expected {}, found {}",
                e.expected, e.found
            )),
            None => BadInput(format!("{}: search.{e}", a.campaign.display())),
        }
    })?;
    c.require_genes()?;
    let length = c.check_run_length(a.run_length.max_steps)?;
    let backend = match a.backend {
        Some(BackendArg::Auto) => Backend::Auto,
        Some(BackendArg::Gpu) => Backend::Gpu,
        Some(BackendArg::Cpu) => Backend::Cpu,
        None => c.solver.backend,
    };
    let precision = match a.precision {
        Some(PrecisionArg::Auto) => PrecisionChoice::Auto,
        Some(PrecisionArg::F32) => PrecisionChoice::F32,
        Some(PrecisionArg::F64) => PrecisionChoice::F64,
        None => c.solver.precision,
    };
    let memory = limits::check_memory(
        &c,
        &a.campaign,
        a.max_memory,
        a.population,
        backend,
        precision,
    )?;
    for w in &c.warnings {
        out.note(&format!("warning: {w}"));
    }
    let cores = rigfit::eval::all_cores();
    if a.threads > 2 * cores {
        out.note(&format!(
            "warning: --threads {} is far above the {cores} cores here; threads beyond the \
             cores only slow the job down",
            a.threads
        ));
    }
    // The evaluator before the output folder, refusing before any work what
    // cannot run (threads the system will not start, an adapter selector that
    // names none, a rig the GPU kernels cannot hold when the GPU was asked
    // for); a GPU that is required and missing leaves no folder behind.
    // `auto` chooses as src/job/backend/ says: a named adapter is that GPU,
    // else the choice cached for this job on this machine, else a race.
    let opened = job::backend::open_job_evaluator(
        &c,
        backend,
        precision,
        a.adapter.as_deref(),
        a.threads,
        job::backend::AutoPick::Measure,
    )
    .map_err(|e| open_error(e, a))?;
    for note in &opened.notes {
        out.note(&match note {
            OpenNote::CpuF32 { reason } => {
                let asked = match a.precision {
                    Some(_) => "--precision f32".to_string(),
                    None => format!("{}: solver.precision \"f32\"", a.campaign.display()),
                };
                format!("warning: {asked} on the CPU: {reason}; scoring in f64")
            }
            // A driver helps only where the model has kernels to run.
            OpenNote::Fallback { note, driver_helps } if *driver_helps => {
                format!("note: {note}; {GPU_HINT}")
            }
            OpenNote::Fallback { note, .. } => format!("note: {note}"),
            OpenNote::NotCached { .. } => format!("warning: {note}"),
            OpenNote::ShortJob { .. } => format!("note: {note}"),
        });
    }
    let (mut evaluator, backend_trial) = (opened.evaluator, opened.trial);
    if let Some(t) = &backend_trial {
        out.note(&format!("note: {}", t.line()));
    }
    if a.out.is_none() {
        limits::check_output_inside(&c, &a.campaign)?;
    }
    let dir = a.out.clone().unwrap_or_else(|| c.output.clone());
    let mode = match (a.resume, a.overwrite) {
        (true, _) => FolderMode::Resume,
        (false, true) => FolderMode::Overwrite,
        (false, false) => FolderMode::New,
    };
    // Held to the end of the job: the lock keeps other jobs out of the folder.
    let _folder = OutputFolder::open(&dir, &job::output_files(&c), &c.inputs, mode).map_err(
        |e| -> anyhow::Error {
            match (&e, &a.out) {
                (JobError::OutputPath { .. }, None) => {
                    BadInput(format!("{}: output: {e}", a.campaign.display())).into()
                }
                (JobError::OutputPath { .. }, Some(_)) => BadInput(format!("--out: {e}")).into(),
                _ => e.into(),
            }
        },
    )?;

    let info = evaluator.info();
    out.note(&format!(
        "{} on {} ({}, {}), {} ({}), {:.3e} steps per candidate, \
         memory {} of {}",
        rigfit::base::text::echo_bare(&c.name),
        info.backend,
        info.device,
        format!("{:?}", info.precision).to_lowercase(),
        rigfit::base::text::steps_per_sample(c.solver.substeps),
        c.solver.note,
        length.steps_per_candidate,
        human_bytes(memory.0.total),
        memory.1
    ));

    let interrupt = Arc::new(AtomicBool::new(false));
    {
        let flag = interrupt.clone();
        // A second signal while the job is winding down ends the process.
        let _ = ctrlc::set_handler(move || {
            if flag.swap(true, Ordering::SeqCst) {
                std::process::exit(i32::from(EXIT_INTERRUPTED));
            }
            eprintln!(
                "\nrigfit: interrupted; stopping the evaluation and keeping the last checkpoint"
            );
        });
    }
    evaluator.set_cancel(interrupt.clone());
    let opts = JobOptions {
        out: dir.clone(),
        resume: a.resume,
        quiet: out.quiet || out.json,
        interrupt: interrupt.clone(),
        require_gpu: backend == Backend::Gpu || rigfit::gpu::gpu_required(),
        threads: a.threads,
    };
    let summary = match job::run_chosen(&c, evaluator, &opts, backend_trial) {
        Err(JobError::Search(SearchError::Eval(EvalError::Cancelled))) => {
            out.note(&format!(
                "interrupted before the first generation was complete: nothing to keep; \
                 start it again with: {}",
                this_command(false)
            ));
            return Ok(ExitCode::from(EXIT_INTERRUPTED));
        }
        other => other?,
    };
    out.json(&summary)?;
    out.say(|| summary::summary_text(&summary, &dir, job::steps_per_candidate(&c)));
    if interrupt.load(Ordering::SeqCst) {
        out.note(&format!(
            "checkpoint kept in {}; continue with: {}",
            dir.display(),
            this_command(true)
        ));
        return Ok(ExitCode::from(EXIT_INTERRUPTED));
    }
    Ok(ExitCode::SUCCESS)
}

/// A refusal of the job's evaluator as the CLI words it: the flag (or the
/// campaign's setting) to blame first.
fn open_error(e: OpenError, a: &RunArgs) -> anyhow::Error {
    match e {
        OpenError::Threads { threads, source } => {
            BadInput(format!("--threads {threads}: {source}")).into()
        }
        e @ OpenError::Adapter { .. } => BadInput(e.to_string()).into(),
        OpenError::KernelLimits(e) => {
            let asked = match a.backend {
                Some(_) => "--backend gpu".to_string(),
                None => format!("{}: solver.backend \"gpu\"", a.campaign.display()),
            };
            let cpu = match e {
                rigfit::gpu::GpuError::TooManySwitches { .. } => {
                    "; run it on the CPU (--backend cpu)"
                }
                _ => "",
            };
            BadInput(format!("{asked}: {e}{cpu}")).into()
        }
        OpenError::Gpu(e) => anyhow::Error::new(e).context("opening the GPU evaluator"),
        OpenError::Trial(e) => e.into(),
    }
}

/// The command line this job was started with, quoted for a POSIX shell, so
/// that typed literally (in the same folder) it runs the same job: with
/// `--resume` added (and `--overwrite`, which would discard the checkpoint,
/// left out) when `resume`, as it was otherwise. The output folder, the
/// overrides and the options are kept: a checkpoint resumes only under the
/// settings it was written with.
fn this_command(resume: bool) -> String {
    let mut args: Vec<String> = std::env::args_os()
        .map(|a| a.to_string_lossy().into_owned())
        .collect();
    if resume {
        args.retain(|a| a != "--overwrite");
        if !args.iter().any(|a| a == "--resume") {
            args.push("--resume".into());
        }
    }
    args.iter()
        .map(|a| shell_quoted(a))
        .collect::<Vec<_>>()
        .join(" ")
}

/// `s` as one word of a POSIX shell command: as it is when it holds only
/// characters no shell treats specially, otherwise in single quotes.
fn shell_quoted(s: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "_-./=:,+@%".contains(c);
    if !s.is_empty() && s.chars().all(plain) {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', "'\\''"))
    }
}
