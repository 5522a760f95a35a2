//! Choosing and opening an evaluator as `rigfit run` does: `backend`,
//! `precision` and `adapter` as the CLI takes them, refusals before any work.

use pyo3::prelude::*;

use crate::errors::{self, Kind};
use rigfit::campaign::Campaign;
use rigfit::eval::{Backend, CpuEvaluator, Evaluator, PrecisionChoice};

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

/// An opened evaluator and the notes the CLI prints (a fallback to the CPU,
/// f32 lanes missing), which the Python layer turns into warnings.
pub struct Opened {
    pub evaluator: Box<dyn Evaluator>,
    pub notes: Vec<String>,
}

/// Opens the evaluator `rigfit run` would open, refusing before any work
/// what it refuses: threads the system will not start, an adapter selector
/// that names no adapter, a rig the GPU kernels cannot hold when the GPU was
/// asked for.
pub fn open(
    c: &Campaign,
    backend: Backend,
    precision: PrecisionChoice,
    adapter: Option<&str>,
    threads: usize,
) -> PyResult<Opened> {
    let mut notes = Vec::new();
    if backend == Backend::Cpu {
        let mut cpu = CpuEvaluator::try_new(c.problem.clone(), threads)
            .map_err(|e| errors::raise(Kind::Campaign, format!("threads={threads}: {e}")))?;
        if precision == PrecisionChoice::F32
            && let Err(e) = cpu.use_f32()
        {
            notes.push(format!("precision f32 on the CPU: {e}; scoring in f64"));
        }
        return Ok(Opened {
            evaluator: Box::new(cpu),
            notes,
        });
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
    let opened = rigfit::gpu::open_evaluator_on(c.problem.clone(), backend, precision, adapter)
        .map_err(|e| {
            errors::raise(
                Kind::Device,
                format!("opening the GPU evaluator: {}", errors::chain(&e)),
            )
        })?;
    notes.extend(opened.note);
    Ok(Opened {
        evaluator: opened.evaluator,
        notes,
    })
}
