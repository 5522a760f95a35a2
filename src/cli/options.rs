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
