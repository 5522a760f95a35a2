//! Choosing and opening an evaluator as `rigfit run` does: `backend`,
//! `precision` and `adapter` as the CLI takes them, refusals before any work.

use pyo3::prelude::*;

use crate::errors::{self, Kind};
use rigfit::campaign::Campaign;
use rigfit::eval::{Backend, CpuEvaluator, Evaluator, PrecisionChoice};
use rigfit::job::backend::{self, BackendTrial};

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
/// f32 lanes missing), which the Python layer turns into warnings, and for a
/// job with `auto`, what the race between the paths measured.
pub struct Opened {
    pub evaluator: Box<dyn Evaluator>,
    pub notes: Vec<String>,
    pub trial: Option<BackendTrial>,
}

/// Opens the evaluator `rigfit run` would open, refusing before any work
/// what it refuses: threads the system will not start, an adapter selector
/// that names no adapter, a rig the GPU kernels cannot hold when the GPU was
/// asked for. With `race` (a job), `auto` chooses as the CLI does: a choice
/// cached for this job on this machine, else a race of the two paths
/// (`rigfit::job::backend`); otherwise `auto` takes the GPU when there is one.
pub fn open(
    c: &Campaign,
    backend: Backend,
    precision: PrecisionChoice,
    adapter: Option<&str>,
    threads: usize,
    race: bool,
) -> PyResult<Opened> {
    let mut notes = Vec::new();
    let mut cpu = CpuEvaluator::try_new(c.problem.clone(), threads)
        .map_err(|e| errors::raise(Kind::Campaign, format!("threads={threads}: {e}")))?;
    // `auto` races the CPU against the GPU in the precision asked for.
    if backend != Backend::Gpu
        && precision == PrecisionChoice::F32
        && let Err(e) = cpu.use_f32()
        && backend == Backend::Cpu
    {
        notes.push(format!("precision f32 on the CPU: {e}; scoring in f64"));
    }
    let cpu_only = |cpu: CpuEvaluator, notes, trial| Opened {
        evaluator: Box::new(cpu),
        notes,
        trial,
    };
    if backend == Backend::Cpu {
        return Ok(cpu_only(cpu, notes, None));
    }
    if let Some((selector, selected_by)) = rigfit::gpu::requested_adapter(adapter) {
        let adapters = rigfit::gpu::list_adapters();
        if let Err(why) = rigfit::gpu::choose_adapter(&selector, &adapters) {
            return Err(errors::raise(
                Kind::Device,
                format!(
                    "{}: {why}; the adapters are: {}",
                    match adapter {
                        Some(a) => format!("adapter={a:?}"),
                        None => selected_by,
                    },
                    rigfit::gpu::adapter_list(&adapters)
                ),
            ));
        }
    }
    if backend == Backend::Gpu
        && let Err(e) = rigfit::gpu::kernel_groups(&c.problem)
    {
        return Err(errors::raise(
            Kind::Campaign,
            format!("backend=\"gpu\": {}", errors::chain(&e)),
        ));
    }
    let trial_key = (race && backend == Backend::Auto).then(|| {
        let adapters = rigfit::gpu::list_adapters()
            .iter()
            .map(|a| format!("{} ({}, {})", a.name, a.backend, a.driver))
            .collect::<Vec<_>>()
            .join(", ");
        let p = format!("{precision:?}").to_lowercase();
        backend::cache_key(c, &adapters, &p, c.search.population)
    });
    let cached = trial_key.as_deref().and_then(backend::cached);
    if let Some(t) = cached.clone().filter(|t| t.chosen == "cpu") {
        return Ok(cpu_only(cpu, notes, Some(t)));
    }
    let opened = rigfit::gpu::open_evaluator_on(c.problem.clone(), backend, precision, adapter)
        .map_err(|e| {
            errors::raise(
                Kind::Device,
                format!("opening the GPU evaluator: {}", errors::chain(&e)),
            )
        })?;
    let fell_back = opened.note.is_some();
    notes.extend(opened.note);
    let (evaluator, trial) = match (&trial_key, fell_back, cached) {
        (Some(_), false, Some(t)) => (opened.evaluator, Some(t)),
        (Some(key), false, None) => {
            let (chosen, t) =
                backend::race(c, c.search.population, opened.evaluator, Box::new(cpu))
                    .map_err(|e| errors::raise(Kind::Device, errors::chain(&e)))?;
            if let Err(e) = backend::remember(key, &t) {
                notes.push(format!(
                    "the backend choice could not be cached ({e}); the next run measures again"
                ));
            }
            (chosen, Some(t))
        }
        _ => (opened.evaluator, None),
    };
    Ok(Opened {
        evaluator,
        notes,
        trial,
    })
}
