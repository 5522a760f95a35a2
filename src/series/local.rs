//! Running a series' tests in this process: several side by side, sharing
//! one device — the CPU lanes' threads, or one GPU context — so that a
//! series of short records keeps the device busy while each job's serial
//! stretches (its polish, its outputs, its report) run.
//!
//! Each test is the job `rigfit run --backend <b>` runs on its campaign file,
//! to the same bits: the evaluators give the same bits for a batch whatever
//! shares the device with them. A test already done (its status says so,
//! for the same campaign, and its `result.json` is there) is skipped; one
//! interrupted resumes from its checkpoint.

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

use super::SeriesError;
use super::manifest::{Manifest, TestEntry, TestState, TestStatus, file_sha256};
use crate::campaign::Campaign;
use crate::eval::{Backend, CpuEvaluator, EvalError, Evaluator, PrecisionChoice};
use crate::gpu::GpuContext;
use crate::job::{self, FolderMode, JobError, JobOptions, OutputFolder};
use crate::search::SearchError;

/// How to run a series' tests here.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// Tests run side by side (at least 1).
    pub jobs: usize,
    /// The evaluator every test runs on: `auto` is decided once, on the
    /// first test, by [`crate::job::backend`]'s measurement.
    pub backend: Backend,
    /// The precision asked for.
    pub precision: PrecisionChoice,
    /// The GPU adapter's selector (`--adapter`, or the one the scheduler
    /// gave the task), and how it was chosen (for the status files).
    pub adapter: Option<(String, String)>,
    /// CPU threads (0: all cores), shared by the tests side by side.
    pub threads: usize,
    /// Raised by Ctrl-C, SIGTERM or Slurm's SIGUSR1: every test stops at
    /// its next check and keeps its checkpoint.
    pub interrupt: Arc<AtomicBool>,
    /// The Slurm task running them, if one does (`--task`).
    pub task: Option<usize>,
    /// A test whose candidate takes more RK4 steps than this fails
    /// (`--max-steps`, [`crate::campaign::DEFAULT_MAX_STEPS`]).
    pub max_steps: f64,
}

/// What running one test gave.
#[derive(Debug, Clone)]
pub struct TestRun {
    /// Index of the test in the manifest.
    pub index: usize,
    /// Its status, as written.
    pub status: TestStatus,
    /// Whether it was done before and skipped.
    pub skipped: bool,
}

/// The device the tests share.
enum Device {
    Cpu(Arc<rayon::ThreadPool>),
    Gpu(Box<GpuContext>),
}

/// Runs the tests `which` (indices into `manifest.tests`) of the series in
/// `root`, `opts.jobs` side by side; `progress` hears a line as each test
/// starts and ends. Every test ends with a status file; a test's failure is
/// its status, not an error here. Errors: the device cannot be opened.
pub fn run_tests(
    root: &Path,
    manifest: &Manifest,
    which: &[usize],
    opts: &RunOptions,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<Vec<TestRun>, SeriesError> {
    let mut runs: Vec<Option<TestRun>> = vec![None; which.len()];
    // Those done before are skipped without opening a device.
    let mut todo = Vec::new();
    for (k, &i) in which.iter().enumerate() {
        let test = &manifest.tests[i];
        match done_before(root, test) {
            Some(status) => {
                progress(&format!("{}: done before, skipped", test.id));
                runs[k] = Some(TestRun {
                    index: i,
                    status,
                    skipped: true,
                });
            }
            None => todo.push(k),
        }
    }
    if todo.is_empty() {
        return Ok(runs.into_iter().flatten().collect());
    }
    let backend = decide_backend(root, manifest, which, opts, progress)?;
    let device = match backend {
        Backend::Gpu => {
            let selector = opts.adapter.as_ref().map(|a| a.0.as_str());
            let ctx = GpuContext::select(selector)
                .map_err(|e| SeriesError::Task(format!("opening the GPU: {e}")))?;
            Device::Gpu(Box::new(ctx))
        }
        _ => {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(opts.threads)
                .build()
                .map_err(|e| {
                    SeriesError::Task(format!("starting {} CPU threads: {e}", opts.threads))
                })?;
            Device::Cpu(Arc::new(pool))
        }
    };
    let next = AtomicUsize::new(0);
    let finished = AtomicUsize::new(0);
    let total = todo.len();
    let results: std::sync::Mutex<Vec<(usize, TestRun)>> = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..opts.jobs.clamp(1, total) {
            scope.spawn(|| {
                loop {
                    let n = next.fetch_add(1, Ordering::SeqCst);
                    let Some(&k) = todo.get(n) else { break };
                    let i = which[k];
                    let test = &manifest.tests[i];
                    if opts.interrupt.load(Ordering::SeqCst) {
                        break;
                    }
                    progress(&format!("{}: started", test.id));
                    let status = run_one(root, test, &device, backend, opts);
                    let _ = status.write(root);
                    let m = finished.fetch_add(1, Ordering::SeqCst) + 1;
                    progress(&format!(
                        "[{m}/{total}] {}: {}",
                        test.id,
                        outcome_line(&status)
                    ));
                    results.lock().expect("no panics hold it").push((
                        k,
                        TestRun {
                            index: i,
                            status,
                            skipped: false,
                        },
                    ));
                }
            });
        }
    });
    for (k, run) in results.into_inner().expect("no panics hold it") {
        runs[k] = Some(run);
    }
    Ok(runs.into_iter().flatten().collect())
}

/// The status of a test done before with the same campaign, its result
/// still there and no checkpoint left.
fn done_before(root: &Path, test: &TestEntry) -> Option<TestStatus> {
    let status = TestStatus::read(root, &test.id)?;
    let out = root.join(&test.out);
    let same = file_sha256(&root.join(&test.campaign)).ok()? == status.campaign_sha256;
    (status.state == TestState::Done
        && same
        && out.join(job::RESULT_FILE).is_file()
        && !out.join(job::CHECKPOINT_FILE).exists())
    .then_some(status)
}

/// The backend every test runs on: `auto` measured once, on the first test
/// that can be read, as `rigfit run` would measure it.
fn decide_backend(
    root: &Path,
    manifest: &Manifest,
    which: &[usize],
    opts: &RunOptions,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<Backend, SeriesError> {
    if opts.backend != Backend::Auto {
        return Ok(opts.backend);
    }
    let first = which.iter().find_map(|&i| {
        let t = &manifest.tests[i];
        t.error
            .is_none()
            .then(|| Campaign::load(&root.join(&t.campaign)).ok())
            .flatten()
    });
    let Some(c) = first else {
        return Ok(Backend::Cpu);
    };
    let selector = opts.adapter.as_ref().map(|a| a.0.as_str());
    let opened = job::backend::open_job_evaluator(
        &c,
        Backend::Auto,
        opts.precision,
        selector,
        opts.threads,
        job::backend::AutoPick::Measure,
    )
    .map_err(|e| SeriesError::Task(format!("choosing the backend on test `{}`: {e}", c.name)))?;
    let chosen = opened.evaluator.info().backend;
    progress(&format!(
        "backend auto: every test on the {chosen}, as measured on the first ({})",
        opened
            .trial
            .as_ref()
            .map_or_else(|| "no trial: short or no GPU".to_string(), |t| t.line())
    ));
    Ok(if chosen == "gpu" {
        Backend::Gpu
    } else {
        Backend::Cpu
    })
}

/// Runs one test to its status.
fn run_one(
    root: &Path,
    test: &TestEntry,
    device: &Device,
    backend: Backend,
    opts: &RunOptions,
) -> TestStatus {
    let started = Instant::now();
    let campaign_file = root.join(&test.campaign);
    let mut status = TestStatus {
        id: test.id.clone(),
        state: TestState::Failed,
        error: None,
        campaign_sha256: file_sha256(&campaign_file).unwrap_or_default(),
        wall_time_s: 0.0,
        backend: None,
        device: None,
        adapter: opts.adapter.as_ref().map(|a| a.1.clone()),
        host: host_name(),
        task: opts.task,
        slurm_job: slurm_job(),
        restarts: std::env::var("SLURM_RESTART_COUNT")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(0),
    };
    let result = match &test.error {
        Some(e) => Err(e.clone()),
        None => run_job(
            &campaign_file,
            &root.join(&test.out),
            device,
            backend,
            opts,
            &mut status,
        ),
    };
    status.wall_time_s = started.elapsed().as_secs_f64();
    match result {
        Ok(state) => status.state = state,
        Err(e) => {
            status.state = TestState::Failed;
            status.error = Some(e);
        }
    }
    status
}

/// The job of one test, as `rigfit run` runs it; its end state, or the
/// error with its causes.
fn run_job(
    campaign_file: &Path,
    out: &Path,
    device: &Device,
    backend: Backend,
    opts: &RunOptions,
    status: &mut TestStatus,
) -> Result<TestState, String> {
    let c = Campaign::load(campaign_file).map_err(|e| chain(&e))?;
    c.require_search().map_err(|e| chain(&e))?;
    c.require_genes().map_err(|e| chain(&e))?;
    c.check_run_length(opts.max_steps).map_err(|e| chain(&e))?;
    // The memory available now leaves out what the tests beside it hold.
    let memory = crate::job::memory::MemoryEstimate::of_job(&c, backend, opts.precision);
    if let Some(available) = crate::job::memory::available_memory()
        && memory.total > available
    {
        return Err(format!(
            "the job needs about {} and {} are available now (the tests beside it included); run the series with fewer --jobs, or this test alone",
            crate::job::memory::human_bytes(memory.total),
            crate::job::memory::human_bytes(available)
        ));
    }
    let mut evaluator: Box<dyn Evaluator> = match device {
        Device::Cpu(pool) => {
            let mut cpu = CpuEvaluator::on_pool(c.problem.clone(), pool.clone());
            if opts.precision == PrecisionChoice::F32 {
                // As `rigfit run`: f32 lanes where the rig has them, else f64.
                let _ = cpu.use_f32();
            }
            if job::backend::worth_building_early(&c) {
                // As `rigfit run`: the lanes' native code built from the start.
                use crate::eval::Timed as _;
                cpu.prepare_soon();
            }
            Box::new(cpu)
        }
        Device::Gpu(ctx) => {
            crate::gpu::evaluator_on_context((**ctx).clone(), c.problem.clone(), opts.precision)
                .map_err(|e| chain(&e))?
        }
    };
    let info = evaluator.info();
    status.backend = Some(info.backend.clone());
    status.device = Some(info.device.clone());
    let checkpoint = out.join(job::CHECKPOINT_FILE);
    let resume = checkpoint.is_file();
    let mode = if resume {
        FolderMode::Resume
    } else if out.is_dir() {
        FolderMode::Overwrite
    } else {
        FolderMode::New
    };
    let _folder =
        OutputFolder::open(out, &job::output_files(&c), &c.inputs, mode).map_err(|e| chain(&e))?;
    evaluator.set_cancel(opts.interrupt.clone());
    let job_opts = JobOptions {
        out: out.to_path_buf(),
        resume,
        quiet: true,
        interrupt: opts.interrupt.clone(),
        require_gpu: backend == Backend::Gpu,
        threads: opts.threads,
    };
    match job::run_chosen(&c, evaluator, &job_opts, None) {
        Ok(_) if checkpoint.exists() => Ok(TestState::Interrupted),
        Ok(_) => Ok(TestState::Done),
        Err(JobError::Search(SearchError::Eval(EvalError::Cancelled)))
        | Err(JobError::OutputsInterrupted { .. }) => Ok(TestState::Interrupted),
        Err(e) => Err(chain(&e)),
    }
}

/// An error and its causes, on one line.
fn chain(e: &dyn std::error::Error) -> String {
    let mut s = e.to_string();
    let mut source = e.source();
    while let Some(cause) = source {
        s.push_str(": ");
        s.push_str(&cause.to_string());
        source = cause.source();
    }
    s
}

/// How a test ended, in a progress line.
fn outcome_line(s: &TestStatus) -> String {
    match s.state {
        TestState::Done => format!("done in {:.1} s", s.wall_time_s),
        TestState::Interrupted => "interrupted; its checkpoint is kept".into(),
        TestState::Failed => format!(
            "FAILED: {}",
            crate::base::text::shorten_quotes(s.error.as_deref().unwrap_or("unknown"), 300)
        ),
    }
}

/// This machine's name, for the status files.
fn host_name() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|s| s.trim().to_string())
        .or_else(|_| std::env::var("HOSTNAME"))
        .unwrap_or_default()
}

/// The Slurm job running this process, if one is.
fn slurm_job() -> Option<String> {
    let var = |k: &str| std::env::var(k).ok().filter(|v| !v.is_empty());
    match (var("SLURM_ARRAY_JOB_ID"), var("SLURM_ARRAY_TASK_ID")) {
        (Some(a), Some(t)) => Some(format!("{a}_{t}")),
        _ => var("SLURM_JOB_ID"),
    }
}
