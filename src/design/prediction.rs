//! Prediction bands: a simulated output with the calibration's uncertainty
//! around it (`rigfit simulate --params result.json --bands N`). The run is
//! repeated at `N` draws of the fitted parameters ([`super::uncertainty`]) on
//! the CPU lanes, and at every sample each output's median and central 95 %
//! band over the draws are taken.

use std::path::Path;

use rayon::prelude::*;

use super::file::point_values;
use super::uncertainty::{Posterior, band};
use crate::campaign::{Campaign, CampaignError};
use crate::eval::simulate_histories;

/// One output's band at every sample.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputBand {
    /// The median over the draws.
    pub median: Vec<f64>,
    /// The band's lower end.
    pub lo: Vec<f64>,
    /// Its upper end.
    pub hi: Vec<f64>,
}

/// Each output's band over `draws` draws of `posterior` (seeded by `seed`)
/// for experiment `e` of campaign `c` (its values and step as they are set),
/// at `level` (0.95 for 95 %). `file` names the parameter file in a refusal
/// of a drawn value.
pub fn prediction_bands(
    c: &Campaign,
    e: usize,
    posterior: &Posterior,
    draws: usize,
    seed: u64,
    level: f64,
    file: &Path,
) -> Result<Vec<OutputBand>, CampaignError> {
    let drawn = posterior.draws(draws, seed);
    let mut runs = Vec::with_capacity(drawn.len());
    let mut scratch = c.clone();
    for d in &drawn {
        scratch.set_values(&point_values(&posterior.names, d), file, "")?;
        runs.push((scratch.base[e].clone(), scratch.base_offsets[e]));
    }
    // Draws sharing a clock offset advance together on the lanes.
    let mut groups: Vec<(u64, Vec<usize>)> = Vec::new();
    for (i, r) in runs.iter().enumerate() {
        match groups.iter_mut().find(|g| g.0 == r.1.to_bits()) {
            Some(g) => g.1.push(i),
            None => groups.push((r.1.to_bits(), vec![i])),
        }
    }
    let chunks: Vec<(f64, &[usize])> = groups
        .iter()
        .flat_map(|(off, ix)| ix.chunks(64).map(move |g| (f64::from_bits(*off), g)))
        .collect();
    let histories: Vec<_> = chunks
        .par_iter()
        .flat_map_iter(|&(offset, ix)| {
            let params: Vec<&[f64]> = ix.iter().map(|&i| runs[i].0.as_slice()).collect();
            simulate_histories(&c.problem, e, &params, offset)
        })
        .collect();
    let outputs = c.model.output_names().len();
    let samples = histories.first().map_or(0, |h| h.t.len());
    Ok((0..outputs)
        .map(|o| {
            let mut b = OutputBand {
                median: Vec::with_capacity(samples),
                lo: Vec::with_capacity(samples),
                hi: Vec::with_capacity(samples),
            };
            let mut at = vec![0.0; histories.len()];
            for k in 0..samples {
                for (v, h) in at.iter_mut().zip(&histories) {
                    *v = h.outputs[o][k];
                }
                let (m, lo, hi) = band(&at, level).unwrap_or((f64::NAN, f64::NAN, f64::NAN));
                b.median.push(m);
                b.lo.push(lo);
                b.hi.push(hi);
            }
            b
        })
        .collect())
}
