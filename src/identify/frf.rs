//! Frequency-response estimates H1 and H2 with coherence, from an input record
//! `u` (force) and an output record `y` (response), by Welch averaging
//! (*Experimental Investigations of Lubricated Bearing Stiffness*, "impact tests":
//! spectra averaged before the FRFs, coherence `γ² = |S_Fx|²/(S_FF·S_xx)`, 1 for
//! an undisturbed measurement; *Data interrogation for vehicle suspensions*,
//! §2.1.2, uses the same averaged spectra).
//!
//! Each segment has its mean removed and a Hann window applied; segments overlap
//! by half; `U_k`, `Y_k` are their DFTs (rustfft), and
//!
//! ```text
//! S_uu = ⟨|U|²⟩,  S_yy = ⟨|Y|²⟩,  S_uy = ⟨U*·Y⟩
//! H1 = S_uy / S_uu        (unbiased by noise on the output)
//! H2 = S_yy / S_uy*       (unbiased by noise on the input)
//! γ² = |S_uy|² / (S_uu·S_yy) = H1 / H2
//! ```
//!
//! The densities are one-sided and scaled as in [`crate::identify::psd`]. The
//! segment length defaults to the largest power of two giving at least eight
//! segments; a lightly damped mode needs a resolution `fs/segment_len` well
//! below its half-power bandwidth `2ζf_n`.

use rustfft::num_complex::Complex64;

pub use super::psd::WelchSettings;
use super::psd::{averaged_segments, check_rate};
use super::{IdentifyError, check_inputs};

/// What a modal fit of the FRF assumes of its input: the mass, stiffness and
/// damping it reports (and writes into a campaign fragment) are the rig's
/// only where the input is a force on the measured point.
pub const FORCE_INPUT: &str = "modal m, k and c assume the input column is a force (N) on \
    the measured point; for another input (a base motion, a drive voltage) they are not the \
    rig's mass, stiffness and damping, only f_n and ζ are";

/// Frequency-response estimates on the one-sided bins `k·fs/segment_len`.
#[derive(Debug, Clone, PartialEq)]
pub struct Frf {
    /// Bin frequencies (Hz).
    pub freqs: Vec<f64>,
    /// H1 = S_uy / S_uu (output unit per input unit).
    pub h1: Vec<Complex64>,
    /// H2 = S_yy / S_yu.
    pub h2: Vec<Complex64>,
    /// Ordinary coherence γ² in [0, 1].
    pub coherence: Vec<f64>,
    /// Input auto-spectral density (input unit² / Hz).
    pub s_uu: Vec<f64>,
    /// Output auto-spectral density (output unit² / Hz).
    pub s_yy: Vec<f64>,
    /// The averaging used.
    pub settings: WelchSettings,
}

/// Estimates H1, H2 and the coherence from `u` and `y` sampled at `fs` (Hz).
///
/// # Errors
/// Input errors, [`IdentifyError::InvalidOption`] for a non-positive rate or a
/// segment shorter than 8 samples, [`IdentifyError::TooFewPoints`] for fewer than
/// two segments.
pub fn estimate(
    u: &[f64],
    y: &[f64],
    fs: f64,
    segment_len: Option<usize>,
) -> Result<Frf, IdentifyError> {
    check_inputs("input and output", u, y)?;
    check_rate(fs)?;
    let seg = averaged_segments(u.len(), segment_len, 8, "samples for two averaged segments")?;
    let (len, n_segments, bins) = (seg.len, seg.count, seg.bins());
    let w2: f64 = seg.window.iter().map(|w| w * w).sum();
    let fft = seg.plan();
    let (mut suu, mut syy) = (vec![0.0; bins], vec![0.0; bins]);
    let mut suy = vec![Complex64::new(0.0, 0.0); bins];
    for s in 0..n_segments {
        let bu = seg.dft(&*fft, u, s, |d| d);
        let by = seg.dft(&*fft, y, s, |d| d);
        for k in 0..bins {
            suu[k] += bu[k].norm_sqr();
            syy[k] += by[k].norm_sqr();
            suy[k] += bu[k].conj() * by[k];
        }
    }
    let norm = 1.0 / (fs * w2 * n_segments as f64);
    let one_sided = |k: usize| {
        if k == 0 || (len % 2 == 0 && k == bins - 1) {
            norm
        } else {
            2.0 * norm
        }
    };
    let mut out = Frf {
        freqs: seg.freqs(fs),
        h1: Vec::with_capacity(bins),
        h2: Vec::with_capacity(bins),
        coherence: Vec::with_capacity(bins),
        s_uu: Vec::with_capacity(bins),
        s_yy: Vec::with_capacity(bins),
        settings: seg.settings(fs),
    };
    for k in 0..bins {
        let c = one_sided(k);
        let (puu, pyy, puy) = (suu[k] * c, syy[k] * c, suy[k] * c);
        out.h1.push(if puu > 0.0 {
            puy / puu
        } else {
            f64::NAN.into()
        });
        out.h2.push(if puy.norm_sqr() > 0.0 {
            Complex64::from(pyy) / puy.conj()
        } else {
            f64::NAN.into()
        });
        out.coherence.push(if puu > 0.0 && pyy > 0.0 {
            (puy.norm_sqr() / (puu * pyy)).min(1.0)
        } else {
            0.0
        });
        out.s_uu.push(puu);
        out.s_yy.push(pyy);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// A first-order digital filter `y[n] = b·u[n] + a·y[n−1]` has the exact
    /// response `b / (1 − a·e^{−iω})`; white input makes H1 and H2 match it.
    #[test]
    fn recovers_a_known_digital_filter() {
        let mut state = 12345u64;
        let mut rand = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let u: Vec<f64> = (0..65536).map(|_| rand()).collect();
        let (b, a) = (0.3, 0.8);
        let mut y = vec![0.0; u.len()];
        for n in 0..u.len() {
            y[n] = b * u[n] + if n > 0 { a * y[n - 1] } else { 0.0 };
        }
        let fs = 1000.0;
        let frf = estimate(&u, &y, fs, Some(512)).unwrap();
        for k in (5..250).step_by(10) {
            let w = 2.0 * PI * frf.freqs[k] / fs;
            let exact = Complex64::new(b, 0.0) / (1.0 - a * Complex64::from_polar(1.0, -w));
            assert!((frf.h1[k] - exact).norm() < 0.02 * exact.norm(), "{k}");
            assert!((frf.h2[k] - exact).norm() < 0.03 * exact.norm(), "{k}");
            assert!(frf.coherence[k] > 0.99, "{k}: {}", frf.coherence[k]);
        }
    }
}
