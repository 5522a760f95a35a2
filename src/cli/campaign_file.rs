//! Loading a campaign for the commands that read one without searching
//! (`simulate`, `modes`, `check`).

use std::path::Path;

use anyhow::Result;

use rigfit::campaign::Campaign;
use rigfit::eval::Backend;
use rigfit::gpu::GpuError;

use super::exit::BadInput;

/// Loads and validates a campaign, applies a parameter file's values (e.g. a
/// result.json's "params") when given, and prints the campaign's warnings.
pub fn load(path: &Path, params: Option<&Path>) -> Result<Campaign> {
    let mut c = Campaign::load(path)?;
    if let Some(p) = params {
        c.apply_param_file(p)?;
    }
    for w in &c.warnings {
        eprintln!("rigfit: warning: {w}");
    }
    Ok(c)
}

/// [`load`] for `check`: a rig with more located switches than the GPU
/// kernels hold is refused, as `run` refuses it, where the campaign asks for
/// the GPU (`solver.backend "gpu"`), and otherwise said in a warning (`run`
/// scores it on the CPU).
pub fn load_for_check(path: &Path) -> Result<Campaign> {
    let mut c = Campaign::load(path)?;
    if let Err(e @ GpuError::TooManySwitches { .. }) = rigfit::gpu::kernel_groups(&c.problem) {
        if c.solver.backend == Backend::Gpu {
            return Err(
                BadInput(format!("{}: solver.backend \"gpu\": {e}", path.display())).into(),
            );
        }
        c.warnings.push(format!(
            "{e}; `run` scores it on the CPU and refuses --backend gpu"
        ));
    }
    for w in &c.warnings {
        eprintln!("rigfit: warning: {w}");
    }
    Ok(c)
}
