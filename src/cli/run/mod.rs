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
use rigfit::job::backend::{OpenError, OpenNote, TrialWatch};
use rigfit::job::memory::human_bytes;
use rigfit::job::{self, FolderMode, JobError, JobOptions, OutputFolder};
use rigfit::search::{IslandSettings, Method, SearchError};

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

impl From<PrecisionArg> for PrecisionChoice {
    fn from(p: PrecisionArg) -> Self {
        match p {
            PrecisionArg::Auto => Self::Auto,
            PrecisionArg::F32 => Self::F32,
            PrecisionArg::F64 => Self::F64,
        }
    }
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
    /// Override the campaign's search.method: `ga` (the genetic algorithm) or
    /// `cmaes` (CMA-ES, which learns how the parameters trade off; see
    /// docs/reference/campaign.md, "search").
    #[arg(long, value_parser = method_name)]
    pub method: Option<Method>,
    /// Override the campaign's search.max_evaluations (stop once this many
    /// candidates were scored).
    #[arg(long)]
    pub max_evaluations: Option<u64>,
    /// Run K islands: K seeded searches that trade their best candidates
    /// every few generations, then the best polished (overrides the
    /// campaign's search.islands.count; see docs/guide/command-line.md,
    /// "Islands").
    #[arg(long, value_name = "K")]
    pub islands: Option<usize>,
    /// Run island I of the islands alone (a process or array task of its
    /// own), writing only its files under <out>/islands/; `--gather` then
    /// polishes the best of them.
    #[arg(long, value_name = "I", conflicts_with = "gather")]
    pub island: Option<usize>,
    /// Gather islands run with `--island I`: polish the best of those that
    /// finished and write the job's outputs.
    #[arg(long)]
    pub gather: bool,
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
    let reading = (!out.quiet).then(|| {
        SlowNotice::after(
            std::time::Duration::from_secs(2),
            format!(
                "rigfit: reading {} and its records, choosing the step…",
                a.campaign.display()
            ),
        )
    });
    let c = Campaign::load(&a.campaign);
    drop(reading);
    let mut c = c?;
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
    if let Some(m) = a.method {
        c.search.method = m;
    }
    if let Some(n) = a.max_evaluations {
        c.search.max_evaluations = Some(n);
    }
    if let Some(k) = a.islands {
        c.search.islands = Some(match c.search.islands {
            Some(s) => IslandSettings { count: k, ..s },
            None => IslandSettings::with_count(k),
        });
    }
    if c.search.islands.is_none() && (a.island.is_some() || a.gather) {
        let flag = if a.gather { "--gather" } else { "--island" };
        return Err(BadInput(format!(
            "{flag} needs islands: pass --islands K or set search.islands in the campaign"
        ))
        .into());
    }
    c.search.validate().map_err(|e| {
        // Blame the flag that set the value, not the campaign file.
        let flag = match e.field {
            "population" => a.population.map(|n| format!("--population {n}")),
            "generations" => a.generations.map(|n| format!("--generations {n}")),
            "target_fitness" => a.target_fitness.map(|t| format!("--target-fitness {t}")),
            "max_evaluations" => a.max_evaluations.map(|n| format!("--max-evaluations {n}")),
            "islands.count" | "islands" => a.islands.map(|n| format!("--islands {n}")),
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
    let precision = a
        .precision
        .map_or(c.solver.precision, PrecisionChoice::from);
    let memory = limits::check_memory(
        &c,
        &a.campaign,
        a.max_memory,
        a.population,
        backend,
        precision,
    )?;
    // Ctrl-C (and SIGTERM) from here on: the first stops whatever runs
    // (the trial, the search, the polish, the outputs) at its next check,
    // within a second or two, and the job winds down as its hint says; a
    // third ends the process at once.
    let interrupt = Arc::new(AtomicBool::new(false));
    super::interrupt::install(
        &interrupt,
        "stopping at the next check (within a second or two)",
    );
    out.note(&first_line(&c, a));
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
    // else the choice cached for this job on this machine, else a race,
    // bounded to a share of the job and said stage by stage.
    let progress = |line: &str| out.note(line);
    let watch = TrialWatch {
        progress: &progress,
        cancel: Some(&interrupt),
    };
    let opened = job::backend::open_job_evaluator_watched(
        &c,
        backend,
        precision,
        a.adapter.as_deref(),
        a.threads,
        job::backend::AutoPick::Measure,
        watch,
    );
    let opened = match opened {
        Err(OpenError::Trial(e)) if e.is_cancelled() => {
            out.note(&format!(
                "interrupted during auto's backend trial, before any output: nothing was \
                 written; start it again with: {}",
                this_command(false)
            ));
            return Ok(ExitCode::from(EXIT_INTERRUPTED));
        }
        other => other.map_err(|e| open_error(e, a))?,
    };
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
            OpenNote::ShortJob { .. } | OpenNote::GpuUnderfilled { .. } => {
                format!("note: {note}")
            }
        });
    }
    let (mut evaluator, backend_trial) = (opened.evaluator, opened.trial);
    if let Some(t) = &backend_trial {
        out.note(&format!("note: {}", t.line()));
    }
    if interrupt.load(Ordering::SeqCst) {
        out.note(&format!(
            "interrupted before the search began: nothing was written; start it again with: {}",
            this_command(false)
        ));
        return Ok(ExitCode::from(EXIT_INTERRUPTED));
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
    // Islands keep no checkpoint in the folder itself: each island resumes
    // its own, in its folder (which it locks; `--island I` locks only that).
    let islands = c.search.islands.is_some();
    let main_mode = match mode {
        FolderMode::Resume if islands => FolderMode::Overwrite,
        m => m,
    };
    let files = match a.island {
        Some(_) => Vec::new(),
        None => job::output_files(&c),
    };
    // Held to the end of the job: the lock keeps other jobs out of the folder.
    let _folder = (a.island.is_none())
        .then(|| OutputFolder::open(&dir, &files, &c.inputs, main_mode))
        .transpose()
        .map_err(|e| -> anyhow::Error {
            match (&e, &a.out) {
                (JobError::OutputPath { .. }, None) => {
                    BadInput(format!("{}: output: {e}", a.campaign.display())).into()
                }
                (JobError::OutputPath { .. }, Some(_)) => BadInput(format!("--out: {e}")).into(),
                _ => e.into(),
            }
        })?;

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

    evaluator.set_cancel(interrupt.clone());
    let opts = JobOptions {
        out: dir.clone(),
        resume: a.resume,
        quiet: out.quiet || out.json,
        interrupt: interrupt.clone(),
        require_gpu: backend == Backend::Gpu || rigfit::gpu::gpu_required(),
        threads: a.threads,
    };
    if islands {
        return run_islands(a, &c, evaluator, &opts, backend_trial, mode, out);
    }
    let summary = match job::run_chosen(&c, evaluator, &opts, backend_trial) {
        Err(JobError::Search(SearchError::Eval(EvalError::Cancelled)))
            if dir.join(job::CHECKPOINT_FILE).exists() =>
        {
            // Stopped within the polish's residuals or the profiles: the
            // search's last checkpoint stands (and the profiles' own), and a
            // resume polishes again from it and goes on.
            if dir.join(job::PROFILE_CHECKPOINT_FILE).exists() {
                out.note("interrupted during the profiles: their checkpoint is kept");
            } else {
                out.note("interrupted during the polish: no interim result");
            }
            out.note(&interrupted_hint(&dir, "continue"));
            return Ok(ExitCode::from(EXIT_INTERRUPTED));
        }
        Err(JobError::Search(SearchError::Eval(EvalError::Cancelled))) => {
            out.note(&format!(
                "interrupted before the first generation was complete: nothing to keep; \
                 start it again with: {}",
                this_command(false)
            ));
            return Ok(ExitCode::from(EXIT_INTERRUPTED));
        }
        Err(e @ JobError::OutputsInterrupted { .. }) => {
            out.note(&format!("{e}"));
            out.note(&interrupted_hint(&dir, "continue"));
            return Ok(ExitCode::from(EXIT_INTERRUPTED));
        }
        other => other?,
    };
    out.json(&summary)?;
    out.say(|| summary::summary_text(&summary, &dir, job::steps_per_candidate(&c)));
    if interrupt.load(Ordering::SeqCst) {
        if !dir.join(job::CHECKPOINT_FILE).exists() {
            // The signal came once the job had written its last file.
            out.note(&format!(
                "interrupted as the job ended: its outputs in {} are complete",
                dir.display()
            ));
            return Ok(ExitCode::SUCCESS);
        }
        out.note(&interrupted_hint(&dir, "continue"));
        return Ok(ExitCode::from(EXIT_INTERRUPTED));
    }
    Ok(ExitCode::SUCCESS)
}

/// `rigfit run` with islands: all of them on threads then the gather, one
/// of them alone (`--island I`), or the gather alone (`--gather`).
fn run_islands(
    a: &RunArgs,
    c: &Campaign,
    evaluator: Box<dyn rigfit::eval::Evaluator>,
    opts: &JobOptions,
    backend_trial: Option<rigfit::job::backend::BackendTrial>,
    mode: FolderMode,
    out: &Output,
) -> Result<ExitCode> {
    use rigfit::job::islands;
    let dir = &opts.out;
    let interrupted = |what: &str| -> Result<ExitCode> {
        out.note(&format!(
            "interrupted {what}: the islands' checkpoints are kept in {}; continue with: {}",
            dir.join(islands::ISLANDS_DIR).display(),
            this_command(true)
        ));
        Ok(ExitCode::from(EXIT_INTERRUPTED))
    };
    let cancelled =
        |e: &JobError| matches!(e, JobError::Search(SearchError::Eval(EvalError::Cancelled)));
    let summary = if let Some(i) = a.island {
        let record = match islands::run_island(c, evaluator, opts, i, mode) {
            Err(e) if cancelled(&e) => return interrupted("in the first generation"),
            other => other?,
        };
        if record.status == islands::IslandStatus::Interrupted {
            return interrupted("during the search");
        }
        let o = &record.outcome;
        out.json(&serde_json::json!({
            "island": i,
            "seed": record.seed,
            "best_cost": o.best_cost,
            "evaluations": o.evaluations,
            "generations": o.generations,
            "exchanges": record.exchanges,
        }))?;
        out.say(|| {
            format!(
                "island {i} (seed {}): best 1 − R² {:.4e} after {} generations, {} evaluations; \
                 gather the islands with --gather once they have ended\n",
                record.seed, o.best_cost, o.generations, o.evaluations
            )
        });
        return Ok(ExitCode::SUCCESS);
    } else if a.gather {
        match islands::gather(c, evaluator, opts, backend_trial) {
            Err(e) if cancelled(&e) => return interrupted("during the polish"),
            other => other?,
        }
    } else {
        match islands::run_islands(c, evaluator, opts, backend_trial, mode) {
            Ok(Some(s)) => s,
            Ok(None) => return interrupted("during the search"),
            Err(e) if cancelled(&e) => return interrupted("during the polish"),
            Err(e) => return Err(e.into()),
        }
    };
    out.json(&summary)?;
    out.say(|| summary::summary_text(&summary, dir, job::steps_per_candidate(c)));
    if opts.interrupt.load(Ordering::SeqCst) {
        return interrupted("as the outputs were written");
    }
    Ok(ExitCode::SUCCESS)
}

/// What to type after an interrupt that kept the checkpoint: `--resume`,
/// which continues from it (a checkpoint of a finished search polishes again
/// from the search's end, then writes the outputs).
fn interrupted_hint(dir: &std::path::Path, what: &str) -> String {
    format!(
        "checkpoint kept in {}; {what} with: {}",
        dir.display(),
        this_command(true)
    )
}

/// A line printed on stderr once `after` has passed, unless dropped before:
/// what a slow step says while a user would otherwise see nothing.
struct SlowNotice {
    done: Option<std::sync::mpsc::Sender<()>>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl SlowNotice {
    fn after(after: std::time::Duration, line: String) -> Self {
        let (done, wait) = std::sync::mpsc::channel::<()>();
        let thread = std::thread::spawn(move || {
            if let Err(std::sync::mpsc::RecvTimeoutError::Timeout) = wait.recv_timeout(after) {
                use std::io::Write as _;
                let _ = writeln!(std::io::stderr(), "{line}");
            }
        });
        Self {
            done: Some(done),
            thread: Some(thread),
        }
    }
}

impl Drop for SlowNotice {
    fn drop(&mut self) {
        drop(self.done.take());
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// The job's first line, before any work: the campaign, its rig, its
/// records and the search's size.
fn first_line(c: &Campaign, a: &RunArgs) -> String {
    let experiments = &c.problem.experiments;
    let samples: usize = experiments.iter().map(|x| x.window.end).sum();
    let longest = experiments
        .iter()
        .max_by_key(|x| x.window.end)
        .map(|x| {
            format!(
                "longest {} with {} samples over {:.4} s at {:.3e} s",
                rigfit::base::text::echo_bare(&x.name),
                x.window.end,
                x.window.end.saturating_sub(1) as f64 * x.dt,
                x.dt
            )
        })
        .unwrap_or_default();
    format!(
        "{} ({}): rig {}, {} record{} of {} samples ({longest}), {} candidates × {} generations ({})",
        rigfit::base::text::echo_bare(&c.name),
        a.campaign.display(),
        c.model.id(),
        experiments.len(),
        if experiments.len() == 1 { "" } else { "s" },
        samples,
        c.search.population,
        c.search.generations,
        c.search.method
    )
}

/// `--method NAME`: one of the registered search methods.
fn method_name(s: &str) -> Result<Method, String> {
    s.parse()
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
