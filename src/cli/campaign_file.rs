//! Loading a campaign for the commands that read one without searching
//! (`simulate`, `modes`, `check`).

use std::path::Path;

use anyhow::Result;

use rigfit::campaign::Campaign;

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
