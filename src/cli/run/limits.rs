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
    let estimate = MemoryEstimate::of_job(c, backend, precision);
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
    Err(BadInput(estimate.refusal(
        &whom,
        limit,
        source,
        "--max-memory",
        max_memory.is_some(),
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
