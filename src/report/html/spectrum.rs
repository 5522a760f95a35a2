//! A residual's amplitude spectrum: Welch's average of Hann-windowed
//! periodograms (half-overlapping segments), scaled so that a sine of
//! amplitude `A` shows a peak of height `A` at its frequency.

use rustfft::FftPlanner;
use rustfft::num_complex::Complex;

/// The longest segment (samples): the frequency step is `1 / (SEGMENT·dt)`.
pub const SEGMENT: usize = 4096;

/// An amplitude spectrum.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Spectrum {
    /// Frequency of each bin (Hz), 0 to Nyquist.
    pub hz: Vec<f64>,
    /// Amplitude at each bin, in the signal's unit.
    pub amplitude: Vec<f64>,
}

/// The amplitude spectrum of `x` sampled every `dt` seconds; empty for
/// fewer than 8 samples or a step that is not positive. Each segment's
/// window-weighted mean is removed first.
pub fn amplitude_spectrum(x: &[f64], dt: f64) -> Spectrum {
    let n = x.len().min(SEGMENT);
    if n < 8 || dt <= 0.0 || !dt.is_finite() {
        return Spectrum::default();
    }
    let window: Vec<f64> = (0..n)
        .map(|k| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * k as f64 / n as f64).cos())
        .collect();
    let gain: f64 = window.iter().sum();
    let fft = FftPlanner::new().plan_fft_forward(n);
    let bins = n / 2 + 1;
    let mut power = vec![0.0; bins];
    let hop = (n / 2).max(1);
    let mut segments = 0usize;
    let mut buf = vec![Complex::new(0.0, 0.0); n];
    let mut start = 0;
    while start + n <= x.len() {
        let seg = &x[start..start + n];
        // The window-weighted mean: what is left has no DC at all.
        let mean = seg.iter().zip(&window).map(|(v, w)| v * w).sum::<f64>() / gain;
        for ((b, v), w) in buf.iter_mut().zip(seg).zip(&window) {
            *b = Complex::new((v - mean) * w, 0.0);
        }
        fft.process(&mut buf);
        for (p, b) in power.iter_mut().zip(&buf) {
            *p += b.norm_sqr();
        }
        segments += 1;
        start += hop;
    }
    let df = 1.0 / (n as f64 * dt);
    Spectrum {
        hz: (0..bins).map(|k| k as f64 * df).collect(),
        amplitude: power
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let one_sided = if k == 0 || 2 * k == n { 1.0 } else { 2.0 };
                one_sided * (p / segments as f64).sqrt() / gain
            })
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sine_shows_its_frequency_and_amplitude() {
        // 125 Hz, amplitude 3, sampled at 10 kHz for 2 s: a bin centre
        // (125 = 51.2 bins of 2.44 Hz is not: the Hann window's scalloping
        // loses at most 15 %).
        let (dt, f, a) = (1e-4, 125.0, 3.0);
        let x: Vec<f64> = (0..20_000)
            .map(|k| a * (2.0 * std::f64::consts::PI * f * k as f64 * dt).sin() + 7.0)
            .collect();
        let s = amplitude_spectrum(&x, dt);
        assert_eq!(s.hz.len(), SEGMENT / 2 + 1);
        assert!((s.hz[1] - 1.0 / (SEGMENT as f64 * dt)).abs() < 1e-12);
        let (k, peak) = s
            .amplitude
            .iter()
            .enumerate()
            .fold((0, 0.0), |b, (k, &v)| if v > b.1 { (k, v) } else { b });
        assert!((s.hz[k] - f).abs() <= s.hz[1], "peak at {} Hz", s.hz[k]);
        assert!(peak > 0.85 * a && peak < 1.01 * a, "peak {peak}");
        // The mean is gone and far bins are near zero.
        assert!(s.amplitude[0] < 1e-9 * a, "{}", s.amplitude[0]);
        assert!(s.amplitude[k + 20] < 1e-3 * a);
    }

    #[test]
    fn a_sine_on_a_bin_centre_has_its_exact_amplitude() {
        let (dt, a) = (1e-3, 0.5);
        let f = 64.0 / (SEGMENT as f64 * dt);
        let x: Vec<f64> = (0..3 * SEGMENT)
            .map(|k| a * (2.0 * std::f64::consts::PI * f * k as f64 * dt).cos())
            .collect();
        let s = amplitude_spectrum(&x, dt);
        assert!(
            (s.amplitude[64] - a).abs() < 1e-9 * a,
            "{}",
            s.amplitude[64]
        );
    }

    #[test]
    fn too_short_or_a_bad_step_gives_nothing() {
        assert!(amplitude_spectrum(&[1.0; 4], 1e-3).hz.is_empty());
        assert!(amplitude_spectrum(&[1.0; 100], 0.0).hz.is_empty());
    }
}
