//! The checks that refuse a calibration job before any work: its memory, and
//! where a campaign may send its output.

use std::path::{Component, Path, PathBuf};

use crate::cli::exit::BadInput;
use crate::cli::options::memory_limit;
use rigfit::campaign::Campaign;
use rigfit::eval::{Backend, PrecisionChoice};
use rigfit::job::memory::{MemoryEstimate, human_bytes};

/// Estimates the job's memory and refuses it, with the estimate and the
/// limit, when it exceeds `max_memory` (`--max-memory`) or the memory
/// available now; the refusal blames `--population` when `population` was
/// given, else the campaign `file`. Returns the estimate and the limit's
/// description.
pub(super) fn check_memory(
    c: &Campaign,
    file: &Path,
    max_memory: Option<f64>,
    population: Option<usize>,
    backend: Backend,
    precision: PrecisionChoice,
) -> Result<(MemoryEstimate, String), BadInput> {
    let gpu_real = match (backend, precision) {
        (Backend::Cpu, _) => None,
        _ if rigfit::gpu::kernel_groups(&c.problem).is_err() => None,
        (_, PrecisionChoice::F32) => Some(4),
        _ => Some(8),
    };
    let estimate = MemoryEstimate::of(c, gpu_real);
    let Some((limit, source)) = memory_limit(max_memory) else {
        return Ok((estimate, "an unknown amount available".into()));
    };
    let what = match max_memory {
        Some(_) => format!("--max-memory {}", human_bytes(limit)),
        None => format!("{} available", human_bytes(limit)),
    };
    if estimate.total <= limit {
        return Ok((estimate, what));
    }
    let whom = match population {
        Some(n) => format!("--population {n}"),
        None => format!("{}: search.population", file.display()),
    };
    let hint = if max_memory.is_some() {
        "lower the population or raise --max-memory"
    } else {
        "lower the population, free memory, or set --max-memory to the memory the job may use"
    };
    Err(BadInput(format!(
        "{whom}: expected a job that fits in {limit_text} ({source}), found {estimate}; {hint}",
        limit_text = human_bytes(limit),
    )))
}

/// A campaign's own `output` must stay inside the campaign's folder or the
/// current folder: a campaign from someone else must not send files to `/etc`.
/// `--out` is the user's own choice and goes anywhere.
pub(super) fn check_output_inside(c: &Campaign, file: &Path) -> Result<(), BadInput> {
    let Ok(cwd) = std::env::current_dir() else {
        return Ok(());
    };
    let absolute = |p: &Path| -> PathBuf {
        let mut out = PathBuf::new();
        for part in cwd.join(p).components() {
            match part {
                Component::ParentDir => {
                    out.pop();
                }
                Component::CurDir => {}
                other => out.push(other),
            }
        }
        out
    };
    let output = absolute(&c.output);
    let home = absolute(c.path.parent().unwrap_or(Path::new(".")));
    if output.starts_with(&home) || output.starts_with(absolute(Path::new("."))) {
        return Ok(());
    }
    Err(BadInput(format!(
        "{}: output: expected a folder inside the campaign's folder `{}` or the current \
         folder, found `{}`; pass --out DIR to write elsewhere",
        file.display(),
        home.display(),
        output.display()
    )))
}
