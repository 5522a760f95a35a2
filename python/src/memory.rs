//! The memory check `rigfit run` makes before any work
//! (`src/cli/run/limits.rs`), for `rigfit.fit`: the job's estimate
//! (`rigfit::job::memory`) against `max_memory=` or the memory available
//! now, refused with the CLI's message, its flags in the package's spelling.

use pyo3::prelude::*;

use crate::errors::{self, Kind};
use rigfit::campaign::Campaign;
use rigfit::eval::{Backend, PrecisionChoice};
use rigfit::job::memory::{self, MemoryEstimate};

/// `max_memory=`: bytes, or a size with K, M, G or T as `--max-memory`
/// takes it (`"512M"`, `"2G"`).
#[derive(FromPyObject)]
pub enum MaxMemory {
    Bytes(f64),
    Text(String),
}

impl MaxMemory {
    fn bytes(&self) -> PyResult<f64> {
        let parsed = match self {
            Self::Bytes(b) => (b.is_finite() && *b > 0.0).then_some(*b),
            Self::Text(s) => memory::parse_bytes(s),
        };
        parsed.ok_or_else(|| {
            let found = match self {
                Self::Bytes(b) => b.to_string(),
                Self::Text(s) => rigfit::base::text::echo(s),
            };
            errors::raise(
                Kind::Campaign,
                format!(
                    "max_memory: expected a size > 0 in bytes or with K, M, G or T (512M, 2G), \
                     found {found}"
                ),
            )
        })
    }
}

/// Refuses, as a `CampaignError`, a job whose estimated memory exceeds
/// `max_memory` or the memory available now; the refusal blames
/// `population=` when `population` was given, else the campaign's file.
pub fn check(
    c: &Campaign,
    max_memory: Option<&MaxMemory>,
    population: Option<usize>,
    backend: Backend,
    precision: PrecisionChoice,
) -> PyResult<()> {
    let estimate = MemoryEstimate::of_job(c, backend, precision);
    let (limit, source) = match max_memory {
        Some(m) => (m.bytes()?, "max_memory"),
        None => match memory::available_memory() {
            Some(m) => (m, "the memory available now, MemAvailable in /proc/meminfo"),
            None => return Ok(()),
        },
    };
    if estimate.total <= limit {
        return Ok(());
    }
    let whom = match population {
        Some(n) => format!("population={n}"),
        None => format!("{}: search.population", c.path.display()),
    };
    Err(errors::raise(
        Kind::Campaign,
        estimate.refusal(&whom, limit, source, "max_memory", max_memory.is_some()),
    ))
}
