//! `rigfit.fit`: the job `rigfit run` runs (GA, polish, intervals, every
//! output file), on a thread of its own while the caller's thread, the GIL
//! released in between, passes progress to Python and watches for Ctrl-C.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError, Sender};
use std::time::Duration;

use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::campaign::PyCampaign;
use crate::errors::{self, Kind};
use rigfit::eval::{Backend, EvalError};
use rigfit::job::{self, FolderMode, JobError, JobOptions, OutputFolder};
use rigfit::search::{GenerationReport, Observer, PolishIteration, SearchError};

/// How often the caller's thread looks for Ctrl-C while the job runs.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// What the job's thread tells the caller's.
enum Progress {
    Generation(GenerationReport),
    Polish(PolishIteration),
}

/// Forwards every generation and polish iteration to the caller's thread.
struct Forward(Sender<Progress>);

impl Observer for Forward {
    fn observe(&mut self, report: &GenerationReport) -> Result<(), SearchError> {
        let _ = self.0.send(Progress::Generation(report.clone()));
        Ok(())
    }

    fn polished(&mut self, iteration: &PolishIteration) -> Result<(), SearchError> {
        let _ = self.0.send(Progress::Polish(*iteration));
        Ok(())
    }
}

fn progress_dict<'py>(
    py: Python<'py>,
    p: &Progress,
    generations: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    match p {
        Progress::Generation(r) => {
            d.set_item("stage", "ga")?;
            d.set_item("generation", r.generation)?;
            d.set_item("generations", generations)?;
            d.set_item("best_cost", r.best_cost)?;
            d.set_item("median_cost", r.median_cost)?;
            d.set_item("best_genome", r.best_genome.clone())?;
            d.set_item("diversity", r.diversity)?;
            d.set_item("evaluations", r.evaluations)?;
            d.set_item("evals_per_s", r.evals_per_s)?;
            d.set_item("diverged", r.diverged)?;
            d.set_item("elapsed_s", r.elapsed_s)?;
        }
        Progress::Polish(i) => {
            d.set_item("stage", "polish")?;
            d.set_item("iteration", i.iteration)?;
            d.set_item("best_cost", i.best_cost)?;
            d.set_item("moving", i.moving)?;
            d.set_item("evaluations", i.evaluations)?;
            d.set_item("elapsed_s", i.elapsed_s)?;
        }
    }
    Ok(d)
}

fn search_error(e: &JobError) -> PyErr {
    match e {
        JobError::Search(SearchError::Eval(ev)) => errors::eval(ev),
        JobError::Eval(ev) => errors::eval(ev),
        JobError::OutputInUse { .. }
        | JobError::NoCheckpoint { .. }
        | JobError::OutputPath { .. }
        | JobError::ForeignFile { .. }
        | JobError::OutputLocked { .. } => errors::raise(Kind::Campaign, errors::chain(e)),
        _ => errors::raise(Kind::Error, errors::chain(e)),
    }
}

/// Runs a calibration job into `out`. Returns `{"interrupted": bool,
/// "checkpoint": bool, "notes": [...]}`; a Ctrl-C stops it within the
/// generation in flight and is reported here, not raised, so the Python layer
/// can say where the checkpoint is.
#[pyfunction]
#[pyo3(signature = (campaign, out, *, resume = false, overwrite = false, backend = None,
    precision = None, adapter = None, threads = 0, population = None, generations = None,
    seed = None, target_fitness = None, method = None, max_memory = None, progress = None))]
#[expect(
    clippy::too_many_arguments,
    reason = "the keyword arguments of rigfit.fit"
)]
pub fn run_job<'py>(
    py: Python<'py>,
    campaign: &PyCampaign,
    out: PathBuf,
    resume: bool,
    overwrite: bool,
    backend: Option<&str>,
    precision: Option<&str>,
    adapter: Option<String>,
    threads: usize,
    population: Option<usize>,
    generations: Option<usize>,
    seed: Option<u64>,
    target_fitness: Option<f64>,
    method: Option<&str>,
    max_memory: Option<crate::memory::MaxMemory>,
    progress: Option<PyObject>,
) -> PyResult<Bound<'py, PyDict>> {
    errors::guard(|| {
        let mut c = (*campaign.inner).clone();
        c.require_search().map_err(|e| errors::campaign(&e))?;
        if let Some(n) = population {
            c.search.population = n;
        }
        if let Some(n) = generations {
            c.search.generations = n;
        }
        if let Some(s) = seed {
            c.search.seed = s;
        }
        if let Some(t) = target_fitness {
            c.search.target_fitness = Some(t);
        }
        if let Some(m) = method {
            c.search.method = m
                .parse()
                .map_err(|e: String| errors::raise(Kind::Campaign, e))?;
        }
        c.search.validate().map_err(|e| {
            errors::raise(Kind::Campaign, format!("{}: search.{e}", c.path.display()))
        })?;
        c.require_genes().map_err(|e| errors::campaign(&e))?;
        c.check_run_length(rigfit::campaign::DEFAULT_MAX_STEPS)
            .map_err(|e| errors::campaign(&e))?;
        let backend_choice = crate::evaluator::backend(&c, backend)?;
        let precision_choice = crate::evaluator::precision(&c, precision)?;
        crate::memory::check(
            &c,
            max_memory.as_ref(),
            population,
            backend_choice,
            precision_choice,
        )?;
        let opened = py.allow_threads(|| {
            crate::evaluator::open(
                &c,
                backend_choice,
                precision_choice,
                adapter.as_deref(),
                threads,
                true,
            )
        })?;
        let mut evaluator = opened.evaluator;
        let trial = opened.trial;
        let mode = match (resume, overwrite) {
            (true, _) => FolderMode::Resume,
            (false, true) => FolderMode::Overwrite,
            (false, false) => FolderMode::New,
        };
        let folder = OutputFolder::open(&out, &job::output_files(&c), &c.inputs, mode)
            .map_err(|e| search_error(&e))?;
        let interrupt = Arc::new(AtomicBool::new(false));
        evaluator.set_cancel(interrupt.clone());
        let opts = JobOptions {
            out: out.clone(),
            resume,
            quiet: true,
            interrupt: interrupt.clone(),
            require_gpu: backend_choice == Backend::Gpu || rigfit::gpu::gpu_required(),
            threads,
        };
        let total = c.search.generations;
        let (tx, rx) = mpsc::channel();
        let mut pending: Option<PyErr> = None;
        let (c, opts, progress, pending_ref, interrupt_ref) =
            (&c, &opts, &progress, &mut pending, &interrupt);
        let outcome = py.allow_threads(move || {
            std::thread::scope(|s| {
                let worker = s.spawn(|| {
                    let observers: Vec<Box<dyn Observer>> = vec![Box::new(Forward(tx))];
                    job::run_observed(c, evaluator, opts, trial, observers)
                });
                loop {
                    let message = match rx.recv_timeout(SIGNAL_POLL) {
                        Ok(m) => Some(m),
                        Err(RecvTimeoutError::Timeout) => None,
                        Err(RecvTimeoutError::Disconnected) => break,
                    };
                    Python::with_gil(|py| {
                        let mut result = py.check_signals();
                        if let (Ok(()), Some(m), Some(cb)) = (&result, &message, progress) {
                            result = progress_dict(py, m, total)
                                .and_then(|d| cb.call1(py, (d,)).map(drop));
                        }
                        if let Err(e) = result {
                            interrupt_ref.store(true, Ordering::SeqCst);
                            pending_ref.get_or_insert(e);
                        }
                    });
                }
                worker.join()
            })
        });
        drop(folder);
        let outcome = outcome.map_err(|p| {
            errors::raise(
                Kind::Error,
                format!(
                    "internal error (a bug in rigfit, please report it): {}",
                    errors::panic_text(&*p)
                ),
            )
        })?;
        // A KeyboardInterrupt from Python raised the interrupt flag: the
        // outcome says whether it stopped the search; any other error of the
        // progress callback is the caller's to see.
        if let Some(e) = pending
            && !e.is_instance_of::<PyKeyboardInterrupt>(py)
        {
            return Err(e);
        }
        let d = PyDict::new(py);
        d.set_item("notes", opened.notes)?;
        match outcome {
            // Stopped before the first generation was complete (no
            // checkpoint), within the polish (the search's last checkpoint
            // stands) or while the outputs were written (kept as well).
            Err(
                JobError::Search(SearchError::Eval(EvalError::Cancelled))
                | JobError::OutputsInterrupted { .. },
            ) => {
                d.set_item("interrupted", true)?;
                d.set_item("checkpoint", out.join(job::CHECKPOINT_FILE).exists())?;
            }
            // Any other error the interrupt caused (a profile or a
            // validation run cancelled part way): interrupted as well.
            Err(e) if interrupt.load(Ordering::SeqCst) && cancelled(&e) => {
                d.set_item("interrupted", true)?;
                d.set_item("checkpoint", out.join(job::CHECKPOINT_FILE).exists())?;
            }
            Err(e) => return Err(search_error(&e)),
            Ok(summary) => {
                // A Ctrl-C that lands once the search has ended (in the
                // polish's last step, while the files are written) stops
                // nothing: the job is complete and its result returned.
                let stopped = summary.stop_reason
                    == rigfit::search::TerminationReason::Interrupted.to_string();
                d.set_item("interrupted", stopped)?;
                d.set_item("checkpoint", out.join(job::CHECKPOINT_FILE).exists())?;
                d.set_item("arrays", crate::fitted::arrays(py, c, &summary)?)?;
                d.set_item("stop_reason", summary.stop_reason)?;
            }
        }
        Ok(d)
    })
}

/// Whether `e` comes, through any chain of causes, from an evaluation
/// cancelled by the interrupt flag.
fn cancelled(e: &JobError) -> bool {
    let mut next: Option<&(dyn std::error::Error + 'static)> = Some(e);
    while let Some(err) = next {
        // SearchError::Eval's source is its EvalError: the walk reaches it.
        if matches!(err.downcast_ref::<EvalError>(), Some(EvalError::Cancelled)) {
            return true;
        }
        next = err.source();
    }
    false
}
