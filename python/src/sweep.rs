//! `rigfit.sweep`: the job `rigfit sweep` runs (the calibrated rig over a
//! design's points, every run reduced to the sweep file's metrics, Sobol
//! indices where the design asks for them), on a thread of its own while the
//! caller's thread, the GIL released in between, passes progress to Python
//! and watches for Ctrl-C.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::{Duration, Instant};

use numpy::IntoPyArray;
use numpy::ndarray::Array2;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{self, Kind};
use rigfit::design::sensitivity::{IndexTable, sobol_table};
use rigfit::design::{DesignError, Engine, GpuRuns, Points, RunOptions, Sweep, Table, run_sweep};
use rigfit::eval::PrecisionChoice;

/// How often the caller's thread looks for Ctrl-C while the sweep runs.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// A sweep's refusal in the package's exceptions: a refused record is a
/// `DataError`, a GPU that failed a `DeviceError`, the rest (the sweep file,
/// the campaign, a design point, the memory) a `CampaignError`, each with the
/// library's message (the file and the JSON path).
fn design_error(e: &DesignError) -> PyErr {
    match e {
        DesignError::Campaign(c) => errors::campaign(c),
        DesignError::Device(_) => errors::raise(Kind::Device, errors::chain(e)),
        _ => errors::raise(Kind::Campaign, errors::chain(e)),
    }
}

/// What the sweep's thread tells the caller's.
enum Message {
    /// Design points done of the total.
    Progress(usize, usize),
    /// The table, its indices (or why they failed), the wall time.
    Done(Box<Result<Finished, DesignError>>),
    /// The sweep's thread panicked.
    Panicked(String),
}

struct Finished {
    table: Table,
    indices: Option<Result<IndexTable, String>>,
    wall_s: f64,
}

/// Unwinds the sweep's thread out of `run_sweep` when the caller has gone
/// (Ctrl-C, or its progress callback raised): `run_sweep` has no cancel of
/// its own, so the sweep stops at its next chunk's progress. Unwound with
/// `resume_unwind`, so no panic message is printed.
struct Cancelled;

/// Runs the sweep read from `path` (or, with `text`, the sweep given as JSON
/// text, its paths relative to `path`'s folder). Returns a dict: `header`
/// (the table's columns), `cells` (rows × columns, NaN where a metric is not
/// defined), `indices` (`None`, or `{"variables", "metrics": [(name, rows or
/// why)]}` with rows `[first, first_lo, first_hi, total, total_lo,
/// total_hi]` per variable), `wall_s`, `runs_per_s`, `runs`, `device`,
/// `substeps` and the campaign's `warnings`. `progress(done, total)` is
/// called on the caller's thread as chunks finish.
#[pyfunction]
#[expect(
    clippy::too_many_arguments,
    reason = "the keyword arguments of rigfit.sweep"
)]
#[pyo3(signature = (path, text = None, *, threads = 0, backend = "cpu", precision = None,
    adapter = None, progress = None))]
pub fn sweep<'py>(
    py: Python<'py>,
    path: PathBuf,
    text: Option<String>,
    threads: usize,
    backend: &str,
    precision: Option<&str>,
    adapter: Option<String>,
    progress: Option<PyObject>,
) -> PyResult<Bound<'py, PyDict>> {
    errors::guard(|| {
        let gpu = match backend {
            "cpu" => {
                if precision.is_some() || adapter.is_some() {
                    return Err(errors::raise(
                        Kind::Campaign,
                        "precision= and adapter= choose the GPU's; pass backend=\"gpu\" with them",
                    ));
                }
                false
            }
            "gpu" => true,
            other => {
                return Err(errors::raise(
                    Kind::Campaign,
                    format!("backend={other:?}: expected \"cpu\" or \"gpu\""),
                ));
            }
        };
        let precision = match precision {
            None | Some("auto") => PrecisionChoice::Auto,
            Some("f32") => PrecisionChoice::F32,
            Some("f64") => PrecisionChoice::F64,
            Some(other) => {
                return Err(errors::raise(
                    Kind::Campaign,
                    format!("precision={other:?}: expected \"auto\", \"f32\" or \"f64\""),
                ));
            }
        };
        let sweep = py
            .allow_threads(|| match &text {
                None => Sweep::load(&path),
                Some(t) => Sweep::from_text(t, &path),
            })
            .map_err(|e| design_error(&e))?;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| {
                errors::raise(
                    Kind::Campaign,
                    format!("threads={threads}: the system refused to start them: {e}"),
                )
            })?;
        let gpu = if gpu {
            let opened = py.allow_threads(|| GpuRuns::open(adapter.as_deref(), precision));
            let g = opened.map_err(|e| {
                let by = adapter
                    .as_ref()
                    .map_or("backend=\"gpu\"".to_string(), |a| format!("adapter={a:?}"));
                errors::raise(Kind::Device, format!("{by}: {}", errors::chain(&e)))
            })?;
            Some(g)
        } else {
            None
        };
        let device = match &gpu {
            None => format!("{} CPU threads", pool.current_num_threads()),
            Some(g) => {
                let p = g.precision().map_err(|e| {
                    errors::raise(Kind::Device, format!("precision: {}", errors::chain(&e)))
                })?;
                format!("{} ({p:?})", g.describe())
            }
        };
        let runs_per_point = sweep.runs_per_point();
        let warnings = sweep.campaign.warnings.clone();
        let finished = run_on_thread(py, sweep, pool, gpu, progress)?;
        let Finished {
            table,
            indices,
            wall_s,
        } = finished;
        let header = table.header();
        let mut cells = Array2::<f64>::from_elem((table.rows.len(), header.len()), f64::NAN);
        for (i, r) in table.rows.iter().enumerate() {
            for (j, c) in table.cells(r).into_iter().enumerate() {
                if let Some(v) = c {
                    cells[[i, j]] = v;
                }
            }
        }
        let mut substeps: Vec<usize> = table.rows.iter().map(|r| r.substeps).collect();
        substeps.sort_unstable();
        substeps.dedup();
        let runs = table.rows.len() * runs_per_point;
        let d = PyDict::new(py);
        d.set_item("header", header)?;
        d.set_item("cells", cells.into_pyarray(py))?;
        d.set_item("wall_s", wall_s)?;
        d.set_item("runs", runs)?;
        d.set_item("runs_per_s", runs as f64 / wall_s.max(1e-9))?;
        d.set_item("device", device)?;
        d.set_item("substeps", substeps)?;
        d.set_item("warnings", warnings)?;
        match indices {
            None => d.set_item("indices", py.None())?,
            Some(Err(why)) => {
                return Err(errors::raise(Kind::Error, format!("Sobol indices: {why}")));
            }
            Some(Ok(ix)) => {
                let ixd = PyDict::new(py);
                ixd.set_item("variables", ix.variables.clone())?;
                let metrics: Vec<(String, PyObject)> = ix
                    .metrics
                    .iter()
                    .map(|(name, r)| {
                        let v: PyObject = match r {
                            Ok(rows) => rows
                                .iter()
                                .map(|x| {
                                    vec![
                                        x.first,
                                        x.first_95[0],
                                        x.first_95[1],
                                        x.total,
                                        x.total_95[0],
                                        x.total_95[1],
                                    ]
                                })
                                .collect::<Vec<_>>()
                                .into_pyobject(py)?
                                .into_any()
                                .unbind(),
                            Err(why) => why.into_pyobject(py)?.into_any().unbind(),
                        };
                        Ok((name.clone(), v))
                    })
                    .collect::<PyResult<_>>()?;
                ixd.set_item("metrics", metrics)?;
                d.set_item("indices", ixd)?;
            }
        }
        Ok(d)
    })
}

/// Runs the sweep on a thread of its own (on `pool`, or the GPU), the caller's
/// thread, the GIL released between its wakes, passing progress to
/// `progress` and looking for Ctrl-C every [`SIGNAL_POLL`]. A Ctrl-C (or an
/// exception from `progress`) is raised at once; the sweep's thread stops at
/// its next chunk and its work is dropped.
fn run_on_thread(
    py: Python<'_>,
    sweep: Sweep,
    pool: rayon::ThreadPool,
    gpu: Option<GpuRuns>,
    progress: Option<PyObject>,
) -> PyResult<Finished> {
    let cancel = Arc::new(AtomicBool::new(false));
    let (tx, rx) = mpsc::channel::<Message>();
    let worker_cancel = cancel.clone();
    // The thread is not joined: on Ctrl-C the caller returns at once and the
    // sweep's thread ends on its own at its next chunk.
    std::thread::Builder::new()
        .name("rigfit-sweep".into())
        .spawn(move || {
            let mut gpu = gpu;
            let tx_done = tx.clone();
            let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(
                || -> Result<Finished, DesignError> {
                    let start = Instant::now();
                    let tx = std::sync::Mutex::new(tx);
                    let report = |done: usize, total: usize| {
                        if worker_cancel.load(Ordering::SeqCst) {
                            std::panic::resume_unwind(Box::new(Cancelled));
                        }
                        if let Ok(tx) = tx.lock() {
                            let _ = tx.send(Message::Progress(done, total));
                        }
                    };
                    let engine = match gpu.as_mut() {
                        None => Engine::Cpu,
                        Some(g) => Engine::Gpu(g),
                    };
                    let options = RunOptions::default();
                    let table = pool.install(|| run_sweep(&sweep, &options, engine, &report))?;
                    let wall_s = start.elapsed().as_secs_f64();
                    let indexed = matches!(&sweep.points, Points::Drawn(d) if d.indices);
                    let indices = indexed.then(|| pool.install(|| sobol_table(&sweep, &table)));
                    Ok(Finished {
                        table,
                        indices,
                        wall_s,
                    })
                },
            ));
            let message = match outcome {
                Ok(r) => Message::Done(Box::new(r)),
                Err(p) if p.is::<Cancelled>() => return,
                Err(p) => Message::Panicked(errors::panic_text(&*p)),
            };
            let _ = tx_done.send(message);
        })
        .map_err(|e| errors::raise(Kind::Error, format!("starting the sweep's thread: {e}")))?;
    let stop = |e: PyErr| {
        cancel.store(true, Ordering::SeqCst);
        e
    };
    let progress = &progress;
    py.allow_threads(move || {
        loop {
            let message = match rx.recv_timeout(SIGNAL_POLL) {
                Ok(m) => Some(m),
                Err(RecvTimeoutError::Timeout) => None,
                Err(RecvTimeoutError::Disconnected) => {
                    return Err(errors::raise(
                        Kind::Error,
                        "internal error (a bug in rigfit, please report it): the sweep's thread \
                         ended without a result",
                    ));
                }
            };
            let finished = Python::with_gil(|py| -> PyResult<Option<Finished>> {
                py.check_signals().map_err(stop)?;
                match message {
                    None => Ok(None),
                    Some(Message::Progress(done, total)) => {
                        if let Some(cb) = progress {
                            cb.call1(py, (done, total)).map_err(stop)?;
                        }
                        Ok(None)
                    }
                    Some(Message::Done(r)) => (*r).map(Some).map_err(|e| design_error(&e)),
                    Some(Message::Panicked(text)) => Err(errors::raise(
                        Kind::Error,
                        format!("internal error (a bug in rigfit, please report it): {text}"),
                    )),
                }
            })?;
            if let Some(f) = finished {
                return Ok(f);
            }
        }
    })
}
