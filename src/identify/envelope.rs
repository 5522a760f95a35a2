//! Decay rate of a ringdown from its analytic-signal envelope, in a band
//! around the chosen spectral peak.
//!
//! The record (mean removed) is zero-padded to a power of two at least twice
//! its length and transformed; only the positive-frequency bins inside
//! `f_peak ± band` are kept (doubled), which is both the band-pass that isolates
//! one mode of a record with several and the Hilbert transform. The inverse
//! transform is the analytic signal `z(t)`, and `|z(t)|` the envelope
//! `A·e^{−σt}` of that mode, whatever the number of samples per cycle: unlike
//! picked peaks, it does not sample the oscillation's crest. A straight line
//! fitted to `ln |z|` gives `σ`, and `ζ = σ / ω_n` with `ω_n = 2π·f_peak`
//! (refined by the caller when the fit gives a better one). The first and last
//! `2/band` seconds are left out, where the band-pass rings in and out, and so is
//! everything after the envelope has fallen below 5 % of its start.

use std::f64::consts::PI;

use rustfft::FftPlanner;
use rustfft::num_complex::Complex64;
use serde::Serialize;

use super::{IdentifyError, r_squared};

/// The envelope's decay.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EnvelopeDecay {
    /// Damping ratio `σ/ω_n`.
    pub zeta: f64,
    /// Decay rate σ (1/s).
    pub sigma: f64,
    /// The pass band `(low, high)` (Hz).
    pub band_hz: (f64, f64),
    /// Samples in the straight-line fit.
    pub samples_fitted: usize,
    /// R² of the straight line through `ln |z|`.
    pub r2: f64,
}

/// Envelope decay of `x` sampled at `fs` (Hz) in `f_peak ± band` (Hz).
///
/// # Errors
/// [`IdentifyError::InvalidOption`] for a band that does not fit below the Nyquist
/// rate, [`IdentifyError::TooShortRingdown`] when fewer than 16 samples remain for
/// the fit.
pub fn envelope_decay(
    x: &[f64],
    fs: f64,
    f_peak: f64,
    band: f64,
) -> Result<EnvelopeDecay, IdentifyError> {
    let (lo, hi) = ((f_peak - band).max(0.0), f_peak + band);
    if !(band > 0.0 && hi < fs / 2.0) {
        return Err(IdentifyError::InvalidOption {
            name: "envelope band",
            reason: format!("{lo:.4} … {hi:.4} Hz does not fit below half the sample rate"),
        });
    }
    let n = x.len();
    let len = (2 * n).next_power_of_two();
    let mean = x.iter().sum::<f64>() / n as f64;
    let mut buf: Vec<Complex64> = x
        .iter()
        .map(|v| Complex64::new(v - mean, 0.0))
        .chain(std::iter::repeat_n(Complex64::new(0.0, 0.0), len - n))
        .collect();
    let mut planner = FftPlanner::new();
    planner.plan_fft_forward(len).process(&mut buf);
    let df = fs / len as f64;
    for (k, b) in buf.iter_mut().enumerate() {
        let f = k as f64 * df;
        *b = if k < len / 2 && f >= lo && f <= hi {
            *b * 2.0
        } else {
            Complex64::new(0.0, 0.0)
        };
    }
    planner.plan_fft_inverse(len).process(&mut buf);
    let env: Vec<f64> = buf[..n].iter().map(|z| z.norm() / len as f64).collect();
    let margin = ((2.0 / band) * fs).ceil() as usize;
    let start = margin.min(n);
    let floor = 0.05 * env.get(start).copied().unwrap_or(0.0);
    let end = (start..n.saturating_sub(margin))
        .find(|&i| env[i] < floor)
        .unwrap_or(n.saturating_sub(margin));
    if end < start + 16 {
        return Err(IdentifyError::TooShortRingdown {
            what: "envelope samples between the band-pass edges",
            needed: 16,
            found: end.saturating_sub(start),
        });
    }
    let ts: Vec<f64> = (start..end).map(|i| i as f64 / fs).collect();
    let ys: Vec<f64> = (start..end)
        .map(|i| env[i].max(f64::MIN_POSITIVE).ln())
        .collect();
    let m = ts.len() as f64;
    let (tm, ym) = (ts.iter().sum::<f64>() / m, ys.iter().sum::<f64>() / m);
    let sxy: f64 = ts.iter().zip(&ys).map(|(t, y)| (t - tm) * (y - ym)).sum();
    let sxx: f64 = ts.iter().map(|t| (t - tm).powi(2)).sum();
    let slope = sxy / sxx;
    let sse: f64 = ts
        .iter()
        .zip(&ys)
        .map(|(t, y)| (y - ym - slope * (t - tm)).powi(2))
        .sum();
    let sigma = -slope;
    Ok(EnvelopeDecay {
        zeta: sigma / (2.0 * PI * f_peak),
        sigma,
        band_hz: (lo, hi),
        samples_fitted: ts.len(),
        r2: r_squared(sse, &ys),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Six samples per cycle, a second mode nearby, and a very light damping:
    /// the case where picked peaks mislead.
    #[test]
    fn light_damping_at_six_samples_per_cycle_with_a_second_mode() {
        let (fs, f1, zeta) = (1280.0, 212.0, 0.0009);
        let w1 = 2.0 * PI * f1;
        let x: Vec<f64> = (0..12_800)
            .map(|i| {
                let t = i as f64 / fs;
                (-zeta * w1 * t).exp() * (w1 * (1.0 - zeta * zeta).sqrt() * t + 0.3).cos()
                    + 0.3 * (-0.01 * 2.0 * PI * 90.0 * t).exp() * (2.0 * PI * 90.0 * t).cos()
            })
            .collect();
        let e = envelope_decay(&x, fs, f1, 60.0).unwrap();
        assert!((e.zeta / zeta - 1.0).abs() < 0.02, "{e:?}");
        assert!(e.r2 > 0.999, "{e:?}");
    }
}
