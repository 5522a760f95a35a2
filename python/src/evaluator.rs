//! Choosing and opening an evaluator as `rigfit run` does: `backend`,
//! `precision` and `adapter` as the CLI takes them, refusals before any work.

use pyo3::prelude::*;

use crate::errors::{self, Kind};
use rigfit::campaign::Campaign;
use rigfit::eval::{Backend, Evaluator, PrecisionChoice};
use rigfit::job::backend::{self, AutoPick, BackendTrial, OpenError};

/// `"auto"`, `"gpu"`, `"cpu"`; `None`: the campaign's `solver.backend`.
pub fn backend(c: &Campaign, name: Option<&str>) -> PyResult<Backend> {
    Ok(match name {
        None => c.solver.backend,
        Some("auto") => Backend::Auto,
        Some("gpu") => Backend::Gpu,
        Some("cpu") => Backend::Cpu,
        Some(other) => {
            return Err(errors::raise(
                Kind::Campaign,
                format!("backend={other:?}: expected \"auto\", \"gpu\" or \"cpu\""),
            ));
        }
    })
}

/// `"auto"`, `"f32"`, `"f64"`; `None`: the campaign's `solver.precision`.
pub fn precision(c: &Campaign, name: Option<&str>) -> PyResult<PrecisionChoice> {
    Ok(match name {
        None => c.solver.precision,
        Some("auto") => PrecisionChoice::Auto,
        Some("f32") => PrecisionChoice::F32,
        Some("f64") => PrecisionChoice::F64,
        Some(other) => {
            return Err(errors::raise(
                Kind::Campaign,
                format!("precision={other:?}: expected \"auto\", \"f32\" or \"f64\""),
            ));
        }
    })
}

/// An opened evaluator, the notes the CLI prints (a fallback to the CPU,
/// f32 lanes missing, a choice not cached), which the Python layer turns
/// into warnings, and for a job with `auto`, what was measured.
pub struct Opened {
    pub evaluator: Box<dyn Evaluator>,
    pub notes: Vec<String>,
    pub trial: Option<BackendTrial>,
}

/// Opens the evaluator `rigfit run` would open
/// ([`backend::open_job_evaluator`], the CLI's own flow), refusing before any
/// work what it refuses, in the package's exceptions. With `race` (a job),
/// `auto` chooses as the CLI does; otherwise it takes the GPU when there is
/// one.
pub fn open(
    c: &Campaign,
    backend: Backend,
    precision: PrecisionChoice,
    adapter: Option<&str>,
    threads: usize,
    race: bool,
) -> PyResult<Opened> {
    let pick = if race {
        AutoPick::Measure
    } else {
        AutoPick::Gpu
    };
    let opened = backend::open_job_evaluator(c, backend, precision, adapter, threads, pick)
        .map_err(|e| match e {
            OpenError::Threads { threads, source } => {
                errors::raise(Kind::Campaign, format!("threads={threads}: {source}"))
            }
            OpenError::Adapter {
                selected_by,
                why,
                adapters,
            } => {
                let by = adapter.map_or(selected_by, |a| format!("adapter={a:?}"));
                errors::raise(
                    Kind::Device,
                    format!("{by}: {why}; the adapters are: {adapters}"),
                )
            }
            OpenError::KernelLimits(e) => errors::raise(
                Kind::Campaign,
                format!("backend=\"gpu\": {}", errors::chain(&e)),
            ),
            e @ (OpenError::Gpu(_) | OpenError::Trial(_)) => {
                errors::raise(Kind::Device, errors::chain(&e))
            }
        })?;
    Ok(Opened {
        evaluator: opened.evaluator,
        notes: opened.notes.iter().map(ToString::to_string).collect(),
        trial: opened.trial,
    })
}

/// The evaluator of a function of the ensemble (the objective, the
/// residuals): the backend and precision by name, opened without the job's
/// race (`auto` takes the GPU when there is one), the GIL released.
pub fn open_named(
    py: Python<'_>,
    c: &Campaign,
    backend_name: Option<&str>,
    precision_name: Option<&str>,
    adapter: Option<&str>,
    threads: usize,
) -> PyResult<Opened> {
    let b = backend(c, backend_name)?;
    let pr = precision(c, precision_name)?;
    py.allow_threads(|| open(c, b, pr, adapter, threads, false))
}
