//! Signal conditioning shared by the identification tools: a Butterworth
//! low-pass run forward and backward (zero phase), central differences and
//! decimation.
//!
//! The filter is the analog Butterworth prototype mapped by the bilinear
//! transform with the cut-off pre-warped, as second-order sections (plus one
//! first-order section for an odd order). The zero-phase pass pads each end with
//! its odd reflection over `3·(2·sections + 1)` samples and starts every section
//! in its steady state for the first padded sample, as `scipy.signal.sosfiltfilt`
//! does, so a record's ends are not pulled towards zero.

use std::f64::consts::PI;

use super::{IdentifyError, require_points};

/// One section `H(z) = (b0 + b1 z⁻¹ + b2 z⁻²) / (1 + a1 z⁻¹ + a2 z⁻²)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Section {
    /// Numerator `b0, b1, b2`.
    pub b: [f64; 3],
    /// Denominator `a1, a2` (`a0 = 1`).
    pub a: [f64; 2],
}

impl Section {
    fn dc_gain(&self) -> f64 {
        (self.b[0] + self.b[1] + self.b[2]) / (1.0 + self.a[0] + self.a[1])
    }
}

fn check_lowpass(order: usize, fc: f64, fs: f64) -> Result<(), IdentifyError> {
    if !(1..=8).contains(&order) {
        return Err(IdentifyError::InvalidOption {
            name: "filter order",
            reason: format!("{order} is outside 1..=8"),
        });
    }
    if !(fc > 0.0 && fc < fs / 2.0) {
        return Err(IdentifyError::InvalidOption {
            name: "cut-off",
            reason: format!("{fc} Hz is not between 0 and half the sample rate {fs} Hz"),
        });
    }
    Ok(())
}

/// Sections of a low-pass from the analog prototype's poles in the upper half
/// plane (`(re, im)` for a unit cut-off; `im = 0` for the real pole of an odd
/// order), mapped by the bilinear transform with the cut-off `fc` pre-warped;
/// each section has unit gain at DC, and the first is scaled by `dc_gain`.
fn bilinear_lowpass(poles: &[(f64, f64)], fc: f64, fs: f64, dc_gain: f64) -> Vec<Section> {
    let k = 2.0 * fs;
    let wa = k * (PI * fc / fs).tan();
    let mut out: Vec<Section> = poles
        .iter()
        .map(|&(re, im)| {
            let (re, im) = (re * wa, im * wa);
            if im == 0.0 {
                // s − re, one real pole.
                let a0 = k - re;
                let g = -re / a0;
                Section {
                    b: [g, g, 0.0],
                    a: [(-re - k) / a0, 0.0],
                }
            } else {
                let p2 = re * re + im * im;
                let a0 = k * k - 2.0 * re * k + p2;
                let g = p2 / a0;
                Section {
                    b: [g, 2.0 * g, g],
                    a: [
                        (2.0 * p2 - 2.0 * k * k) / a0,
                        (k * k + 2.0 * re * k + p2) / a0,
                    ],
                }
            }
        })
        .collect();
    if let Some(first) = out.first_mut() {
        for b in &mut first.b {
            *b *= dc_gain;
        }
    }
    out
}

/// Butterworth low-pass of `order` (1..=8) with cut-off `fc` (Hz, −3 dB) at
/// sample rate `fs` (Hz).
///
/// # Errors
/// [`IdentifyError::InvalidOption`] for an order outside 1..=8 or a cut-off not
/// strictly between 0 and `fs/2`.
pub fn butter_lowpass(order: usize, fc: f64, fs: f64) -> Result<Vec<Section>, IdentifyError> {
    check_lowpass(order, fc, fs)?;
    let mut poles: Vec<(f64, f64)> = (0..order / 2)
        .map(|i| {
            // Angle from the negative real axis.
            let theta = PI * (2 * i + 1) as f64 / (2 * order) as f64;
            (-theta.sin(), theta.cos())
        })
        .collect();
    if order % 2 == 1 {
        poles.push((-1.0, 0.0));
    }
    Ok(bilinear_lowpass(&poles, fc, fs, 1.0))
}

/// Chebyshev type I low-pass of `order` (1..=8), pass-band ripple `ripple_db`
/// (dB) up to `fc` (Hz), at sample rate `fs` (Hz). An even order has the gain
/// `10^(−ripple/20)` at DC, as usual for this filter.
///
/// # Errors
/// As [`butter_lowpass`], and for a non-positive ripple.
pub fn cheby1_lowpass(
    order: usize,
    ripple_db: f64,
    fc: f64,
    fs: f64,
) -> Result<Vec<Section>, IdentifyError> {
    check_lowpass(order, fc, fs)?;
    if ripple_db.is_nan() || ripple_db <= 0.0 {
        return Err(IdentifyError::InvalidOption {
            name: "ripple",
            reason: format!("{ripple_db} dB is not positive"),
        });
    }
    let eps = (10f64.powf(ripple_db / 10.0) - 1.0).sqrt();
    let mu = (1.0 / eps).asinh() / order as f64;
    let mut poles: Vec<(f64, f64)> = (0..order / 2)
        .map(|i| {
            let theta = PI * (2 * i + 1) as f64 / (2 * order) as f64;
            (-mu.sinh() * theta.sin(), mu.cosh() * theta.cos())
        })
        .collect();
    if order % 2 == 1 {
        poles.push((-mu.sinh(), 0.0));
    }
    let dc = if order.is_multiple_of(2) {
        10f64.powf(-ripple_db / 20.0)
    } else {
        1.0
    };
    Ok(bilinear_lowpass(&poles, fc, fs, dc))
}

/// Runs the sections over `x` (direct form II transposed), each started in its
/// steady state for a constant input equal to `x[0]`.
pub fn filter(sections: &[Section], x: &[f64]) -> Vec<f64> {
    let mut y = x.to_vec();
    let mut level = x.first().copied().unwrap_or(0.0);
    for s in sections {
        let g = s.dc_gain();
        let out = g * level;
        let mut z2 = s.b[2] * level - s.a[1] * out;
        let mut z1 = s.b[1] * level - s.a[0] * out + z2;
        for v in y.iter_mut() {
            let xin = *v;
            let yout = s.b[0] * xin + z1;
            z1 = s.b[1] * xin - s.a[0] * yout + z2;
            z2 = s.b[2] * xin - s.a[1] * yout;
            *v = yout;
        }
        level = out;
    }
    y
}

/// Zero-phase filtering: forward, then backward, with odd-reflection padding
/// (see the module docs).
///
/// # Errors
/// [`IdentifyError::TooFewPoints`] when `x` is not longer than the padding.
pub fn filtfilt(sections: &[Section], x: &[f64]) -> Result<Vec<f64>, IdentifyError> {
    let pad = 3 * (2 * sections.len() + 1);
    require_points("samples to filter", pad + 1, x.len())?;
    let n = x.len();
    let mut ext = Vec::with_capacity(n + 2 * pad);
    ext.extend((1..=pad).rev().map(|i| 2.0 * x[0] - x[i]));
    ext.extend_from_slice(x);
    ext.extend((1..=pad).map(|i| 2.0 * x[n - 1] - x[n - 1 - i]));
    let mut y = filter(sections, &ext);
    y.reverse();
    let mut y = filter(sections, &y);
    y.reverse();
    Ok(y[pad..pad + n].to_vec())
}

/// First derivative by central differences `(x[k+1] − x[k−1]) / 2dt`, one-sided
/// at the two ends.
pub fn derivative(x: &[f64], dt: f64) -> Vec<f64> {
    let n = x.len();
    if n < 2 {
        return vec![0.0; n];
    }
    (0..n)
        .map(|k| {
            let (lo, hi) = (k.saturating_sub(1), (k + 1).min(n - 1));
            (x[hi] - x[lo]) / ((hi - lo) as f64 * dt)
        })
        .collect()
}

/// Second derivative `(x[k+1] − 2x[k] + x[k−1]) / dt²`, with the ends copied from
/// their neighbours.
pub fn second_derivative(x: &[f64], dt: f64) -> Vec<f64> {
    let n = x.len();
    if n < 3 {
        return vec![0.0; n];
    }
    let mut out = vec![0.0; n];
    for k in 1..n - 1 {
        out[k] = (x[k + 1] - 2.0 * x[k] + x[k - 1]) / (dt * dt);
    }
    out[0] = out[1];
    out[n - 1] = out[n - 2];
    out
}

/// Every `factor`-th sample from `first` on.
pub fn downsample(x: &[f64], first: usize, factor: usize) -> Vec<f64> {
    x.iter()
        .skip(first)
        .step_by(factor.max(1))
        .copied()
        .collect()
}

/// Decimation by `factor` as the usual `decimate` does it: a zero-phase
/// Chebyshev type I low-pass (order 8, 0.05 dB ripple, pass band up to
/// `0.8·(fs/2)/factor`), then every `factor`-th sample, placed so that the last
/// sample is kept.
///
/// # Errors
/// [`IdentifyError::InvalidOption`] for a factor below 2,
/// [`IdentifyError::TooFewPoints`] for a record shorter than the filter's padding.
pub fn decimate(x: &[f64], factor: usize) -> Result<Vec<f64>, IdentifyError> {
    if factor < 2 {
        return Err(IdentifyError::InvalidOption {
            name: "decimation",
            reason: format!("factor {factor} is below 2"),
        });
    }
    // Normalised to fs = 2: the pass band ends at 0.8/factor of the Nyquist rate.
    let sections = cheby1_lowpass(8, 0.05, 0.8 / factor as f64, 2.0)?;
    let y = filtfilt(&sections, x)?;
    let first = (y.len() - 1) % factor;
    Ok(downsample(&y, first, factor))
}

/// `sgn(v)` with `sgn(0) = 0` (and 0 for NaN), unlike [`f64::signum`].
pub(crate) fn sign(v: f64) -> f64 {
    if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Gain of the cascade at frequency `f` (Hz).
    fn gain(sections: &[Section], f: f64, fs: f64) -> f64 {
        let w = 2.0 * PI * f / fs;
        let z1 = (w.cos(), -w.sin());
        let z2 = ((2.0 * w).cos(), -(2.0 * w).sin());
        sections
            .iter()
            .map(|s| {
                let num = (
                    s.b[0] + s.b[1] * z1.0 + s.b[2] * z2.0,
                    s.b[1] * z1.1 + s.b[2] * z2.1,
                );
                let den = (
                    1.0 + s.a[0] * z1.0 + s.a[1] * z2.0,
                    s.a[0] * z1.1 + s.a[1] * z2.1,
                );
                (num.0.hypot(num.1)) / (den.0.hypot(den.1))
            })
            .product()
    }

    #[test]
    fn butterworth_is_half_power_at_the_cutoff_and_flat_below() {
        for order in 1..=8 {
            let s = butter_lowpass(order, 100.0, 1000.0).unwrap();
            assert!((gain(&s, 0.0, 1000.0) - 1.0).abs() < 1e-12);
            assert!(
                (gain(&s, 100.0, 1000.0) - 0.5f64.sqrt()).abs() < 1e-9,
                "{order}"
            );
            assert!(gain(&s, 300.0, 1000.0) < 0.5f64.sqrt().powi(order as i32));
        }
        assert!(butter_lowpass(0, 10.0, 100.0).is_err());
        // Chebyshev I: equiripple pass band down to −0.05 dB at the edge.
        for order in [4, 7, 8] {
            let s = cheby1_lowpass(order, 0.05, 40.0, 1000.0).unwrap();
            let edge = 10f64.powf(-0.05 / 20.0);
            assert!((gain(&s, 40.0, 1000.0) - edge).abs() < 1e-9, "{order}");
            for f in [0.0, 10.0, 20.0, 30.0, 39.0] {
                let g = gain(&s, f, 1000.0);
                assert!(g <= 1.0 + 1e-12 && g >= edge - 1e-12, "{order} {f}: {g}");
            }
        }
        // Order 8 (the decimation filter) stops 100 Hz by more than 40 dB.
        assert!(
            gain(
                &cheby1_lowpass(8, 0.05, 40.0, 1000.0).unwrap(),
                100.0,
                1000.0
            ) < 0.01
        );
        assert!(butter_lowpass(4, 60.0, 100.0).is_err());
    }

    #[test]
    fn filtfilt_keeps_a_slow_signal_and_its_ends() {
        let fs = 1000.0;
        let x: Vec<f64> = (0..2000)
            .map(|i| {
                3.0 + (2.0 * PI * 2.0 * i as f64 / fs).sin()
                    + 0.5 * (2.0 * PI * 400.0 * i as f64 / fs).sin()
            })
            .collect();
        let s = butter_lowpass(4, 100.0, fs).unwrap();
        let y = filtfilt(&s, &x).unwrap();
        // Inside, the fast component is gone. The odd reflection pins each end to
        // the raw end value, so there the fast component's value may remain (at
        // most its amplitude 0.5), but nothing is pulled towards zero (3).
        for (i, v) in y.iter().enumerate() {
            let slow = 3.0 + (2.0 * PI * 2.0 * i as f64 / fs).sin();
            let tol = if (50..1950).contains(&i) { 1e-3 } else { 0.5 };
            assert!((v - slow).abs() < tol, "{i}: {v} vs {slow}");
        }
    }

    #[test]
    fn differences_are_exact_for_a_parabola() {
        let dt = 0.01;
        let x: Vec<f64> = (0..50).map(|i| (i as f64 * dt).powi(2)).collect();
        let v = derivative(&x, dt);
        let a = second_derivative(&x, dt);
        for k in 1..49 {
            assert!((v[k] - 2.0 * k as f64 * dt).abs() < 1e-12);
            assert!((a[k] - 2.0).abs() < 1e-9);
        }
        assert_eq!(downsample(&[0.0, 1.0, 2.0, 3.0, 4.0], 1, 2), vec![1.0, 3.0]);
    }
}
