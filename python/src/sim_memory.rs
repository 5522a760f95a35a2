//! The memory `rigfit.simulate` needs, refused before any work: the
//! histories it returns, the parameter sets it copies and the batch it
//! builds, against `max_memory=` or the memory available now, as `rigfit
//! simulate --max-memory` and `rigfit.fit(max_memory=...)` refuse theirs.

use pyo3::prelude::*;

use crate::errors::{self, Kind};
use crate::memory::MaxMemory;
use rigfit::campaign::Campaign;
use rigfit::job::memory::{self, human_bytes};

/// Bytes a simulation of `sets` parameter sets over `runs` runs of `samples`
/// samples holds at its peak: the f64 histories of every output, each set's
/// genome (a vector and its header) and the batch's model parameters and
/// clock offset per run, and on the GPU path one chunk's histories of every
/// output and state beside them.
pub fn need(c: &Campaign, sets: usize, runs: usize, samples: usize) -> f64 {
    let (s, r, n) = (sets as f64, runs as f64, samples as f64);
    let outputs = c.model.output_names().len() as f64;
    let states = c.model.state_names().len() as f64;
    let params = c.model.params().len() as f64;
    let genes = c.genes.len() as f64;
    let chunk = (sets.min(crate::ensemble::CHUNK)) as f64;
    8.0 * s * r * (n * outputs + params + 1.0)
        + s * (8.0 * genes + 24.0)
        + 8.0 * chunk * r * n * (outputs + states)
}

/// Refuses, as a `CampaignError` naming `max_memory`, a simulation of `sets`
/// parameter sets over `runs` runs of `samples` samples that does not fit in
/// `max_memory` or the memory available now.
pub fn check(
    c: &Campaign,
    sets: usize,
    runs: usize,
    samples: usize,
    max_memory: Option<&MaxMemory>,
) -> PyResult<()> {
    let need = need(c, sets, runs, samples);
    let (limit, source, given) = match max_memory {
        Some(m) => {
            let (bytes, text) = match m {
                MaxMemory::Bytes(b) => ((b.is_finite() && *b > 0.0).then_some(*b), b.to_string()),
                MaxMemory::Text(s) => (memory::parse_bytes(s), s.clone()),
            };
            let Some(bytes) = bytes else {
                return Err(errors::raise(
                    Kind::Campaign,
                    format!(
                        "max_memory: expected a size > 0 in bytes or with K, M, G or T (512M, \
                         2G), found {}",
                        rigfit::base::text::echo(&text)
                    ),
                ));
            };
            (bytes, format!("max_memory={text}"), true)
        }
        None => match memory::available_memory() {
            Some(m) => (
                m,
                "the memory available now, MemAvailable in /proc/meminfo".to_string(),
                false,
            ),
            None => return Ok(()),
        },
    };
    if need <= limit {
        return Ok(());
    }
    Err(errors::raise(
        Kind::Campaign,
        format!(
            "max_memory: expected a simulation that fits in {} ({source}), found about {} \
             ({sets} parameter set(s) × {runs} run(s) × {samples} samples × {} outputs); \
             simulate fewer parameter sets at a time{}",
            human_bytes(limit),
            human_bytes(need),
            c.model.output_names().len(),
            if given {
                " or raise max_memory"
            } else {
                ", free memory, or set max_memory"
            }
        ),
    ))
}
