//! Logarithmic decrement from the positive peaks of a ring-down.
//!
//! Peaks are local maxima over ±0.4 period whose height and position come from a
//! least-squares parabola over ±period/8 samples (averaging the noise; the
//! parabola's small shape bias is the same relative amount for every peak and
//! cancels in the ratios). Peaks are taken while above 5 % of the first one.

use std::f64::consts::PI;

use nalgebra::{Matrix3, Vector3};
use serde::Serialize;

/// Logarithmic-decrement results.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Decrement {
    /// Positive peaks used.
    pub n_peaks: usize,
    /// Peak separations `j`.
    pub separations: Vec<usize>,
    /// `ζ_j` for each separation.
    pub zeta_by_separation: Vec<f64>,
    /// Mean of `ζ_j`.
    pub zeta_mean: f64,
    /// Sample standard deviation of `ζ_j` (0 for one separation).
    pub zeta_std: f64,
    /// Smallest `ζ_j`.
    pub zeta_min: f64,
    /// Largest `ζ_j`.
    pub zeta_max: f64,
}

/// Positive peaks of `x − offset` as `(sample position, amplitude)`.
pub(crate) fn find_peaks(x: &[f64], offset: f64, period: f64) -> Vec<(f64, f64)> {
    let h = ((0.4 * period).round() as usize).max(1);
    let w = ((period / 8.0).round() as usize).clamp(1, h);
    let mut peaks: Vec<(f64, f64)> = Vec::new();
    let mut i = h;
    while i + h < x.len() {
        let top = x[i - h..=i + h]
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        if x[i] == top && x[i] > offset {
            let (u, amp) = refine(&x[i - w..=i + w], offset);
            if peaks.first().is_some_and(|first| amp < 0.05 * first.1) {
                break;
            }
            peaks.push((i as f64 + u * w as f64, amp));
            i += h;
        } else {
            i += 1;
        }
    }
    peaks
}

/// Vertex `(u in −1..1 half-windows, height above offset)` of the least-squares
/// parabola through `window` (centred on the peak sample).
fn refine(window: &[f64], offset: f64) -> (f64, f64) {
    let w = (window.len() / 2) as f64;
    let mut ata = Matrix3::zeros();
    let mut atb = Vector3::zeros();
    for (j, &y) in window.iter().enumerate() {
        let u = (j as f64 - w) / w;
        let row = Vector3::new(1.0, u, u * u);
        ata += row * row.transpose();
        atb += row * (y - offset);
    }
    let centre = window[window.len() / 2] - offset;
    match ata.lu().solve(&atb) {
        Some(c) if c[2] < 0.0 => {
            let u = (-c[1] / (2.0 * c[2])).clamp(-1.0, 1.0);
            (u, c[0] + c[1] * u + c[2] * u * u)
        }
        _ => (0.0, centre),
    }
}

pub(crate) fn log_decrement(
    peaks: &[(f64, f64)],
    cycles: &[f64],
    max_separations: usize,
) -> Decrement {
    let n = peaks.len();
    let k = max_separations.min(n - 1);
    let s = ((n - 1) / (2 * k)).max(1);
    let separations: Vec<usize> = (1..=k).map(|i| i * s).filter(|&j| j < n).collect();
    let zeta_by_separation: Vec<f64> = separations
        .iter()
        .map(|&j| {
            let deltas: Vec<f64> = (0..n - j)
                .filter(|&i| cycles[i + j] > cycles[i])
                .map(|i| (peaks[i].1 / peaks[i + j].1).ln() / (cycles[i + j] - cycles[i]))
                .collect();
            let delta = deltas.iter().sum::<f64>() / deltas.len().max(1) as f64;
            delta / (4.0 * PI * PI + delta * delta).sqrt()
        })
        .collect();
    let count = zeta_by_separation.len() as f64;
    let mean = zeta_by_separation.iter().sum::<f64>() / count;
    let var = if count > 1.0 {
        zeta_by_separation
            .iter()
            .map(|z| (z - mean).powi(2))
            .sum::<f64>()
            / (count - 1.0)
    } else {
        0.0
    };
    Decrement {
        n_peaks: n,
        zeta_min: zeta_by_separation
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min),
        zeta_max: zeta_by_separation
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max),
        separations,
        zeta_by_separation,
        zeta_mean: mean,
        zeta_std: var.sqrt(),
    }
}

/// Least-squares slope of `y` against `x`.
pub(crate) fn slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    sxy / sxx
}
