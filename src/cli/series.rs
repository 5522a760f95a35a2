//! `rigfit series`: a lab's test series, run here, planned for Slurm, run
//! task by task, or summarised.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{Context as _, Result};
use clap::Args;

use super::exit::{BadInput, EXIT_FAILED, EXIT_INTERRUPTED};
use super::options::RunLengthArgs;
use super::output::Output;
use rigfit::eval::{Backend, PrecisionChoice};
use rigfit::series::local::{RunOptions, TestRun, run_tests};
use rigfit::series::{Manifest, SeriesFile, TestState};

/// `rigfit series`.
#[derive(Debug, Args)]
pub struct SeriesArgs {
    /// The series file (JSON: a campaign and a table of tests, or a list of
    /// campaigns), or the folder a series was prepared in.
    pub series: PathBuf,
    /// The series' folder (default: the series file's "output").
    #[arg(long, conflicts_with = "slurm")]
    pub out: Option<PathBuf>,
    /// Prepare the series in DIR and write a Slurm plan there (an array of
    /// tasks and a summary job after it); nothing is submitted.
    #[arg(long, value_name = "DIR")]
    pub slurm: Option<PathBuf>,
    /// Run task N of a prepared series (what a Slurm array task runs).
    #[arg(long, value_name = "N", conflicts_with_all = ["slurm", "summary"])]
    pub task: Option<usize>,
    /// Write the summary (summary.csv, summary.html) of a prepared series
    /// from its tests' results, and print it.
    #[arg(long, conflicts_with = "slurm")]
    pub summary: bool,
    /// Tests run side by side on this machine's device.
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u16).range(1..=256))]
    pub jobs: u16,
    /// Evaluator backend of every test: auto (measured once, on the first
    /// test), cpu or gpu.
    #[arg(long, value_parser = backend, default_value = "auto")]
    pub backend: Backend,
    /// Precision: auto, f32 or f64.
    #[arg(long, value_parser = precision, default_value = "auto")]
    pub precision: PrecisionChoice,
    /// GPU adapter: its index, PCI bus id or a piece of its name (default:
    /// the GPU the scheduler gave the task, else RIGFIT_ADAPTER, else the
    /// first high-performance adapter).
    #[arg(long)]
    pub adapter: Option<String>,
    /// CPU threads shared by the tests (0: all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    #[command(flatten)]
    pub run_length: RunLengthArgs,
    /// With --slurm: one GPU per task (--gres=gpu:1); each task takes the GPU
    /// Slurm gave it, matched by PCI bus id.
    #[arg(long, requires = "slurm")]
    pub gpus: bool,
    /// With --slurm: at most K tasks at once (%K).
    #[arg(long, value_name = "K", requires = "slurm")]
    pub throttle: Option<usize>,
    /// With --slurm: pack short tests into one task up to this many
    /// estimated minutes (0: one test a task).
    #[arg(long, value_name = "M", default_value_t = 0.0, requires = "slurm")]
    pub pack_minutes: f64,
    /// With --slurm: each task's time limit, as sbatch --time takes it.
    #[arg(long, value_name = "T", default_value = "2:00:00", requires = "slurm")]
    pub time: String,
    /// With --slurm: the partition (default: the cluster's).
    #[arg(long, requires = "slurm")]
    pub partition: Option<String>,
    /// With --slurm: the cluster's MaxArraySize (scontrol show config);
    /// larger series are split into several arrays.
    #[arg(long, value_name = "N", default_value_t = rigfit::series::slurm::DEFAULT_MAX_ARRAY_SIZE, requires = "slurm")]
    pub max_array_size: usize,
    /// With --slurm: CPUs per task (default: --threads where given, else 1
    /// for GPU tasks and 2 for CPU tasks); a task uses that many threads.
    #[arg(long, value_name = "N", requires = "slurm")]
    pub cpus_per_task: Option<usize>,
}

fn backend(s: &str) -> Result<Backend, String> {
    match s {
        "auto" => Ok(Backend::Auto),
        "cpu" => Ok(Backend::Cpu),
        "gpu" => Ok(Backend::Gpu),
        _ => Err(format!(
            "expected auto, cpu or gpu, found {}",
            rigfit::base::text::echo(s)
        )),
    }
}

fn precision(s: &str) -> Result<PrecisionChoice, String> {
    match s {
        "auto" => Ok(PrecisionChoice::Auto),
        "f32" => Ok(PrecisionChoice::F32),
        "f64" => Ok(PrecisionChoice::F64),
        _ => Err(format!(
            "expected auto, f32 or f64, found {}",
            rigfit::base::text::echo(s)
        )),
    }
}

/// Runs `rigfit series`.
pub fn series(a: &SeriesArgs, out: &Output) -> Result<ExitCode> {
    // First: a SIGUSR1 that comes while the series is read must not end the
    // process (its default action) but stop it with what it has.
    let interrupt = Arc::new(AtomicBool::new(false));
    // Ctrl-C, SIGTERM and SIGUSR1 (Slurm's warning before a task's time
    // limit) stop every test at its next check with its checkpoint kept.
    #[cfg(unix)]
    super::interrupt::install_usr1(&interrupt).context("installing the SIGUSR1 handler")?;
    super::interrupt::install(
        &interrupt,
        "every test stops at its next check and keeps its checkpoint",
    );
    let given_folder = a.series.is_dir();
    if given_folder && a.slurm.is_some() {
        return Err(BadInput(format!(
            "--slurm: `{}` is a series' folder; give the series file to plan it",
            a.series.display()
        ))
        .into());
    }
    let series = if given_folder {
        None
    } else {
        Some(SeriesFile::load(&a.series)?)
    };
    let root = match (&a.slurm, &a.out, &series) {
        (Some(dir), _, _) | (None, Some(dir), _) => dir.clone(),
        (None, None, Some(s)) => s.output.clone(),
        (None, None, None) => a.series.clone(),
    };
    if a.summary {
        return summary(&root, out);
    }
    let manifest = match (&series, a.task) {
        // A task never prepares: the other tasks read the same folder.
        (Some(_), Some(_)) | (None, _) => Manifest::read(&root)?,
        (Some(s), None) => {
            let m = rigfit::series::prepare(s, &root)?;
            let failed: Vec<&str> = m
                .tests
                .iter()
                .filter(|t| t.error.is_some())
                .map(|t| t.id.as_str())
                .collect();
            out.note(&format!(
                "series \"{}\" prepared in {}: {} tests{}",
                m.name,
                root.display(),
                m.tests.len(),
                if failed.is_empty() {
                    String::new()
                } else {
                    format!(" ({} cannot run: {})", failed.len(), failed.join(", "))
                }
            ));
            m
        }
    };
    if a.slurm.is_some() {
        return plan(a, &root, manifest, out);
    }
    let which: Vec<usize> = match a.task {
        Some(n) => manifest.task(n)?.to_vec(),
        None => (0..manifest.tests.len()).collect(),
    };
    let adapter = match &a.adapter {
        Some(s) => Some((s.clone(), format!("--adapter {s}"))),
        None => rigfit::series::scheduler_gpu::scheduler_gpu()
            .map_err(BadInput)?
            .map(|g| (g.selector, g.how)),
    };
    let opts = RunOptions {
        jobs: usize::from(a.jobs),
        backend: a.backend,
        precision: a.precision,
        adapter,
        threads: task_threads(a),
        interrupt: interrupt.clone(),
        task: a.task,
        max_steps: a.run_length.max_steps,
    };
    let progress = |line: &str| out.note(line);
    let started = std::time::Instant::now();
    let runs = run_tests(&root, &manifest, &which, &opts, &progress)?;
    let wall = started.elapsed().as_secs_f64();
    let count = |s: TestState| runs.iter().filter(|r| r.status.state == s).count();
    let (done, failed, stopped) = (
        count(TestState::Done),
        count(TestState::Failed),
        count(TestState::Interrupted),
    );
    let not_started = which.len() - runs.len();
    out.note(&format!(
        "{} of {} tests done ({} before), {failed} failed, {} interrupted or not started, in {wall:.1} s",
        done,
        which.len(),
        runs.iter().filter(|r| r.skipped).count(),
        stopped + not_started
    ));
    out.json(&runs_json(&runs, &manifest))?;
    if a.task.is_none() && !interrupt.load(Ordering::SeqCst) {
        summary(&root, out)?;
    }
    if interrupt.load(Ordering::SeqCst) || stopped + not_started > 0 {
        out.note(&format!(
            "interrupted; the same command goes on from where each test stopped ({})",
            root.display()
        ));
        return Ok(ExitCode::from(EXIT_INTERRUPTED));
    }
    Ok(if failed > 0 {
        ExitCode::from(EXIT_FAILED)
    } else {
        ExitCode::SUCCESS
    })
}

/// The tests' ends, for `--json`.
fn runs_json(runs: &[TestRun], manifest: &Manifest) -> serde_json::Value {
    serde_json::json!({
        "series": manifest.name,
        "tests": runs.iter().map(|r| serde_json::json!({
            "test": manifest.tests[r.index].id,
            "skipped": r.skipped,
            "status": r.status,
        })).collect::<Vec<_>>(),
    })
}

/// `--summary`, and the end of a local run.
fn summary(root: &Path, out: &Output) -> Result<ExitCode> {
    let summary = rigfit::series::summary::write_summary(root)?;
    out.say(|| {
        format!(
            "{summary}\nsummary: {} and {}",
            root.join(rigfit::series::SUMMARY_CSV).display(),
            root.join(rigfit::series::SUMMARY_HTML).display()
        )
    });
    Ok(ExitCode::SUCCESS)
}

/// `--slurm DIR`.
fn plan(a: &SeriesArgs, root: &Path, mut manifest: Manifest, out: &Output) -> Result<ExitCode> {
    let rigfit = std::env::current_exe().context("finding the rigfit binary the tasks run")?;
    let mut task_args = vec![
        "--backend".to_string(),
        word(a.backend),
        "--precision".into(),
        format!("{:?}", a.precision).to_lowercase(),
        "--jobs".into(),
        a.jobs.to_string(),
        "--threads".into(),
        a.threads.to_string(),
        "--max-steps".into(),
        a.run_length.max_steps.to_string(),
    ];
    if let Some(adapter) = &a.adapter {
        task_args.extend(["--adapter".to_string(), adapter.clone()]);
    }
    let opts = rigfit::series::slurm::PlanOptions {
        gpus: a.gpus,
        throttle: a.throttle,
        pack_seconds: a.pack_minutes * 60.0,
        time_limit: a.time.clone(),
        partition: a.partition.clone(),
        max_array_size: a.max_array_size,
        rigfit,
        cpus_per_task: a.cpus_per_task.unwrap_or(match (a.threads, a.gpus) {
            (0, true) => 1,
            (0, false) => 2,
            (n, _) => n,
        }),
        task_args,
        ..Default::default()
    };
    let plan = rigfit::series::slurm::write_plan(root, &mut manifest, &opts)?;
    out.json(&serde_json::json!({
        "series": manifest.name,
        "tests": manifest.tests.len(),
        "tasks": manifest.tasks.len(),
        "arrays": plan.arrays.iter().map(|p| p.script.display().to_string()).collect::<Vec<_>>(),
        "summary": plan.summary.display().to_string(),
        "submit": plan.submit.display().to_string(),
    }))?;
    out.say(|| {
        format!(
            "Slurm plan for \"{}\": {} tests in {} tasks, {} array{} and a summary job after them.\n\
             Submit it with:\n  bash {}",
            manifest.name,
            manifest.tests.len(),
            manifest.tasks.len(),
            plan.arrays.len(),
            if plan.arrays.len() == 1 { "" } else { "s" },
            plan.submit.display()
        )
    });
    Ok(ExitCode::SUCCESS)
}

/// The CPU threads: `--threads`, or in a Slurm task without it the CPUs
/// Slurm gave the task (`SLURM_CPUS_PER_TASK`), never every core of a node
/// it shares.
fn task_threads(a: &SeriesArgs) -> usize {
    let slurm = std::env::var("SLURM_CPUS_PER_TASK")
        .ok()
        .and_then(|v| v.trim().parse::<usize>().ok());
    match (a.threads, slurm) {
        (0, Some(n)) if n > 0 => n,
        (n, _) => n,
    }
}

/// A backend as the command line writes it.
fn word(b: Backend) -> String {
    match b {
        Backend::Auto => "auto",
        Backend::Cpu => "cpu",
        Backend::Gpu => "gpu",
    }
    .into()
}
