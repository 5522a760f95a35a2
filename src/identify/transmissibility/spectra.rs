//! Block spectra: each record cut into Hann-windowed segments with half overlap
//! and its mean removed (Table 2 of *Data interrogation for vehicle suspensions* gives the Welch settings: 100
//! averages, 50 % overlap, Hanning); `U_s(k)` is the reference channel's DFT in
//! segment `s` at line `k`, `Y_{c,s}(k)` each response channel's, `Z_s(k)` the
//! DFT of the first response's cube. Every method of
//! [`super`] reads them.

use rustfft::num_complex::Complex64;

use crate::identify::IdentifyError;
use crate::identify::frf::WelchSettings;
use crate::identify::psd::{averaged_segments, check_rate};

/// Segment DFTs of a reference channel and of response channels.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockSpectra {
    /// Line frequencies `k·fs/segment_len` (Hz).
    pub freqs: Vec<f64>,
    /// `U_s(k)`, by segment then line.
    pub reference: Vec<Vec<Complex64>>,
    /// `Y_{c,s}(k)`, by channel, segment, line.
    pub responses: Vec<Vec<Vec<Complex64>>>,
    /// `Z_s(k)`, the DFT of the first response channel's cube, by segment then line.
    pub cube: Vec<Vec<Complex64>>,
    /// The segmenting.
    pub settings: WelchSettings,
}

/// The segment length that gives `averages` Hann segments at 50 % overlap from
/// `samples` samples (Table 2 states the averages, not the length).
pub fn segment_for_averages(samples: usize, averages: usize) -> usize {
    2 * samples / (averages + 1)
}

/// Cuts `reference` and each of `responses` (same length, sampled at `fs` Hz)
/// into segments of `segment_len` samples (default as [`crate::identify::frf::estimate`])
/// and takes their DFTs.
///
/// # Errors
/// Mismatched or non-finite records, a non-positive rate, a segment shorter
/// than 16 samples, or fewer than two segments.
pub fn block_spectra(
    reference: &[f64],
    responses: &[&[f64]],
    fs: f64,
    segment_len: Option<usize>,
) -> Result<BlockSpectra, IdentifyError> {
    if responses.is_empty() {
        return Err(IdentifyError::InvalidOption {
            name: "output",
            reason: "give at least one response channel".into(),
        });
    }
    for y in responses {
        crate::identify::check_inputs("reference and response", reference, y)?;
    }
    check_rate(fs)?;
    let seg = averaged_segments(reference.len(), segment_len, 16, "samples for two segments")?;
    let (bins, fft) = (seg.bins(), seg.plan());
    let dft = |x: &[f64], s: usize, cube: bool| -> Vec<Complex64> {
        let mut b = if cube {
            seg.dft(&*fft, x, s, |d| d * d * d)
        } else {
            seg.dft(&*fft, x, s, |d| d)
        };
        b.truncate(bins);
        b
    };
    let segments = 0..seg.count;
    Ok(BlockSpectra {
        freqs: seg.freqs(fs),
        reference: segments.clone().map(|s| dft(reference, s, false)).collect(),
        responses: responses
            .iter()
            .map(|y| segments.clone().map(|s| dft(y, s, false)).collect())
            .collect(),
        cube: segments.map(|s| dft(responses[0], s, true)).collect(),
        settings: seg.settings(fs),
    })
}
