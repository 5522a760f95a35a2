//! Welch power spectral density and its peak, for the ring-down analysis.
//!
//! Settings: Hann window, 50 % overlap, the mean removed from each segment, a
//! one-sided density `P(f) = 2|X(f)|² / (fs·Σw²)` (N²/Hz) averaged over segments.
//! The segment length is chosen from the data unless given: the largest power of
//! two that still gives at least [`MIN_SEGMENTS`] segments (at least
//! [`MIN_SEGMENT_LEN`] samples). The resolution is `Δf = fs / segment_len`; the
//! peak is located between bins by a parabola through the logarithm of the
//! three highest bins (exact for a Gaussian-like main lobe, good for Hann).

use std::f64::consts::PI;

use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlanner};
use serde::Serialize;

use super::IdentifyError;

/// Segments the automatic segment length aims for.
pub const MIN_SEGMENTS: usize = 8;
/// Shortest segment accepted (samples).
pub const MIN_SEGMENT_LEN: usize = 64;

/// A one-sided power spectral density.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Psd {
    /// Bin frequencies `k·Δf` (Hz).
    pub freqs: Vec<f64>,
    /// Density (signal unit² per Hz).
    pub density: Vec<f64>,
    /// Window name (`"hann"`).
    pub window: &'static str,
    /// Samples per segment.
    pub segment_len: usize,
    /// Number of averaged segments.
    pub n_segments: usize,
    /// Overlap between segments (fraction).
    pub overlap: f64,
    /// Frequency resolution `fs / segment_len` (Hz).
    pub resolution_hz: f64,
}

impl Psd {
    /// The highest bin at or above `f_min` (Hz) and its parabolically interpolated
    /// frequency: `(bin frequency, interpolated frequency)`.
    pub fn peak(&self, f_min: f64) -> Option<(f64, f64)> {
        let n = self.density.len();
        let first = self.freqs.iter().position(|&f| f >= f_min)?.max(1);
        let k = (first..n).max_by(|&a, &b| self.density[a].total_cmp(&self.density[b]))?;
        let bin = self.freqs[k];
        if k == 0 || k + 1 >= n || self.density[k] <= 0.0 {
            return Some((bin, bin));
        }
        let tiny = f64::MIN_POSITIVE;
        let (a, b, c) = (
            self.density[k - 1].max(tiny).ln(),
            self.density[k].ln(),
            self.density[k + 1].max(tiny).ln(),
        );
        let denom = a - 2.0 * b + c;
        let shift = if denom < 0.0 {
            0.5 * (a - c) / denom
        } else {
            0.0
        };
        Some((bin, bin + shift.clamp(-0.5, 0.5) * self.resolution_hz))
    }
}

/// How the spectra of an averaged estimate were cut and averaged.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WelchSettings {
    /// Window (`"hann"`).
    pub window: &'static str,
    /// Samples per segment.
    pub segment_len: usize,
    /// Segments averaged.
    pub n_segments: usize,
    /// Overlap (fraction).
    pub overlap: f64,
    /// Sample rate (Hz).
    pub sample_rate_hz: f64,
    /// Resolution `fs / segment_len` (Hz).
    pub resolution_hz: f64,
}

/// Refuses a sample rate `fs` (Hz) that is not positive and finite.
pub(crate) fn check_rate(fs: f64) -> Result<(), IdentifyError> {
    if fs > 0.0 && fs.is_finite() {
        Ok(())
    } else {
        Err(IdentifyError::InvalidOption {
            name: "sample rate",
            reason: format!("{fs} Hz is not positive"),
        })
    }
}

/// The lines `k ≥ 1` of `freqs` inside `band` (Hz): the DC line never counts.
pub(crate) fn lines_in_band(freqs: &[f64], band: (f64, f64)) -> Vec<usize> {
    (1..freqs.len())
        .filter(|&k| freqs[k] >= band.0 && freqs[k] <= band.1)
        .collect()
}

/// The DFT (all `seg.len()` lines) of `seg` with its mean removed, mapped by
/// `f`, and multiplied by `window`.
pub(crate) fn segment_dft(
    fft: &dyn Fft<f64>,
    seg: &[f64],
    window: &[f64],
    f: impl Fn(f64) -> f64,
) -> Vec<Complex64> {
    let mean = seg.iter().sum::<f64>() / seg.len() as f64;
    let mut buf: Vec<Complex64> = seg
        .iter()
        .zip(window)
        .map(|(v, w)| Complex64::new(f(v - mean) * w, 0.0))
        .collect();
    fft.process(&mut buf);
    buf
}

/// The automatic segment length for `n` samples (see the module docs).
pub fn auto_segment_len(n: usize) -> usize {
    // K segments at 50 % overlap span (K + 1)·L/2 samples.
    let target = 2 * n / (MIN_SEGMENTS + 1);
    let mut len = MIN_SEGMENT_LEN;
    while len * 2 <= target {
        len *= 2;
    }
    len
}

/// The Hann window of `len` samples (periodic form, as every estimator here
/// uses it).
pub fn hann(len: usize) -> Vec<f64> {
    (0..len)
        .map(|i| 0.5 - 0.5 * (2.0 * PI * i as f64 / len as f64).cos())
        .collect()
}

/// A record of `n` samples cut for an averaged spectral estimate: segments of
/// `len` samples at 50 % overlap (`step = len/2`), `count` of them, and the
/// Hann window.
#[derive(Debug, Clone)]
pub struct Segments {
    /// Samples per segment.
    pub len: usize,
    /// Samples between segment starts.
    pub step: usize,
    /// Whole segments in the record.
    pub count: usize,
    /// The Hann window.
    pub window: Vec<f64>,
}

impl Segments {
    /// The one-sided lines: `len/2 + 1`.
    pub fn bins(&self) -> usize {
        self.len / 2 + 1
    }

    /// The one-sided line frequencies `k·fs/len` (Hz).
    pub fn freqs(&self, fs: f64) -> Vec<f64> {
        (0..self.bins())
            .map(|k| k as f64 * fs / self.len as f64)
            .collect()
    }

    /// A forward FFT of one segment's length.
    pub fn plan(&self) -> std::sync::Arc<dyn Fft<f64>> {
        FftPlanner::new().plan_fft_forward(self.len)
    }

    /// The DFT of segment `s` of `x` ([`segment_dft`] with `f`).
    pub(crate) fn dft(
        &self,
        fft: &dyn Fft<f64>,
        x: &[f64],
        s: usize,
        f: impl Fn(f64) -> f64,
    ) -> Vec<Complex64> {
        let start = s * self.step;
        segment_dft(fft, &x[start..start + self.len], &self.window, f)
    }

    /// The settings of an estimate at `fs` (Hz) averaged over every segment.
    pub fn settings(&self, fs: f64) -> WelchSettings {
        WelchSettings {
            window: "hann",
            segment_len: self.len,
            n_segments: self.count,
            overlap: 0.5,
            sample_rate_hz: fs,
            resolution_hz: fs / self.len as f64,
        }
    }
}

/// Cuts `n` samples into at least two overlapping segments of `segment_len`
/// samples (chosen from the data when `None`; at least `min_len`).
///
/// # Errors
/// [`IdentifyError::InvalidOption`] for a segment shorter than `min_len`;
/// [`IdentifyError::TooFewPoints`] (`what` names the samples) when two segments
/// do not fit.
pub fn averaged_segments(
    n: usize,
    segment_len: Option<usize>,
    min_len: usize,
    what: &'static str,
) -> Result<Segments, IdentifyError> {
    let len = segment_len.unwrap_or_else(|| auto_segment_len(n));
    if len < min_len {
        return Err(IdentifyError::InvalidOption {
            name: "segment length",
            reason: format!("{len} samples is too short"),
        });
    }
    let step = len / 2;
    let count = if n >= len { (n - len) / step + 1 } else { 0 };
    if count < 2 {
        return Err(IdentifyError::TooFewPoints {
            what,
            needed: len + step,
            found: n,
        });
    }
    Ok(Segments {
        len,
        step,
        count,
        window: hann(len),
    })
}

/// Welch PSD of `x` sampled at `fs` (Hz); `segment_len` `None` picks it from the
/// data.
///
/// # Errors
/// [`IdentifyError::TooShortRingdown`] when `x` holds fewer samples than one
/// segment; [`IdentifyError::InvalidOption`] for a segment shorter than 4 samples or
/// a non-positive `fs`.
pub fn welch(x: &[f64], fs: f64, segment_len: Option<usize>) -> Result<Psd, IdentifyError> {
    check_rate(fs)?;
    let len = segment_len.unwrap_or_else(|| auto_segment_len(x.len()));
    if len < 4 {
        return Err(IdentifyError::InvalidOption {
            name: "segment_len",
            reason: format!("{len} samples is too short"),
        });
    }
    if x.len() < len {
        return Err(IdentifyError::TooShortRingdown {
            what: "samples for one PSD segment",
            needed: len,
            found: x.len(),
        });
    }
    let step = len / 2;
    let n_segments = (x.len() - len) / step + 1;
    let window = hann(len);
    let w2: f64 = window.iter().map(|w| w * w).sum();
    let fft = FftPlanner::new().plan_fft_forward(len);
    let bins = len / 2 + 1;
    let mut acc = vec![0.0; bins];
    for s in 0..n_segments {
        let buf = segment_dft(&*fft, &x[s * step..s * step + len], &window, |d| d);
        for (a, b) in acc.iter_mut().zip(&buf) {
            *a += b.norm_sqr();
        }
    }
    let norm = 1.0 / (fs * w2 * n_segments as f64);
    let density = acc
        .iter()
        .enumerate()
        .map(|(k, a)| {
            let one_sided = if k == 0 || (len.is_multiple_of(2) && k == bins - 1) {
                1.0
            } else {
                2.0
            };
            a * norm * one_sided
        })
        .collect();
    let resolution_hz = fs / len as f64;
    Ok(Psd {
        freqs: (0..bins).map(|k| k as f64 * resolution_hz).collect(),
        density,
        window: "hann",
        segment_len: len,
        n_segments,
        overlap: 0.5,
        resolution_hz,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sine_peak_is_found_between_bins() {
        let fs = 100_000.0;
        let f0 = 5_190.0;
        let x: Vec<f64> = (0..20_000)
            .map(|i| (2.0 * PI * f0 * i as f64 / fs).sin())
            .collect();
        let psd = welch(&x, fs, None).unwrap();
        assert_eq!(psd.segment_len, 4096);
        assert!(psd.n_segments >= MIN_SEGMENTS);
        let (_, f) = psd.peak(10.0).unwrap();
        assert!((f - f0).abs() < 0.1 * psd.resolution_hz, "{f}");
        // Parseval: the density integrates to the variance (0.5).
        let power: f64 = psd.density.iter().sum::<f64>() * psd.resolution_hz;
        assert!((power - 0.5).abs() < 0.01, "{power}");
    }
}
