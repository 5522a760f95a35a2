//! Options that several commands share, and the parsers of their values.

use clap::Args;

/// `--max-steps`, for every command that integrates a campaign.
#[derive(Debug, Args)]
pub struct RunLengthArgs {
    /// Refuse a job whose candidate takes more RK4 steps than this (all
    /// experiments together).
    #[arg(long, default_value_t = rigfit::campaign::DEFAULT_MAX_STEPS, value_parser = positive)]
    pub max_steps: f64,
}

/// A finite number > 0.
fn positive(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v > 0.0 && v.is_finite() => Ok(v),
        _ => Err(format!(
            "expected a number > 0, found {}",
            rigfit::base::text::echo(s)
        )),
    }
}

/// `--max-memory`'s parser, for every command that takes it: a memory size,
/// `2G`, `512M`, `1048576`.
pub fn memory_size(s: &str) -> Result<f64, String> {
    rigfit::job::memory::parse_bytes(s).ok_or_else(|| {
        format!(
            "expected a size > 0 in bytes or with K, M, G or T (512M, 2G), found {}",
            rigfit::base::text::echo(s)
        )
    })
}

/// The memory a command may use (bytes) and where that limit comes from:
/// `--max-memory` (`max_memory`) where given, else the memory available now;
/// `None` when neither is known.
pub fn memory_limit(max_memory: Option<f64>) -> Option<(f64, &'static str)> {
    match (max_memory, rigfit::job::memory::available_memory()) {
        (Some(m), _) => Some((m, "--max-memory")),
        (None, Some(m)) => Some((m, "the memory available now, MemAvailable in /proc/meminfo")),
        (None, None) => None,
    }
}
