//! Transmissibility, the frequency-domain ARX model and the experimental
//! sensitivity functions of document 002 (§2.1.2 and §3.3; §2.2 and §3.4).
//!
//! **Block spectra.** Each record is cut into Hann-windowed segments with half
//! overlap and its mean removed (Table 2's Welch settings: 100 averages, 50 %
//! overlap, Hanning); `U_s(k)` is the reference channel's DFT in segment `s` at
//! line `k`, `Y_{c,s}(k)` each response channel's. The transmissibility to
//! channel `c` is `T_c = Σ_s U_s*·Y_{c,s} / Σ_s |U_s|²` (an H1 estimate with a
//! measured output as the input, the document's "transmissibility function
//! formulation"), with its coherence.
//!
//! **Frequency-domain ARX.** Eq. 2 is missing from the text and Eq. 6 is
//! garbled; rigfit reads them as follows. Per line `k`, over the segments `s`,
//!
//! ```text
//! Eq. 5 (1st order, linear):    Y_s(k) = B(k)·U_s(k) + A₋₁(k)·Y_s(k−1) + A₁(k)·Y_s(k+1)
//! Eq. 6 (1st order, nonlinear): Y_s(k) = B(k)·U_s(k) + A₋₁(k)·Z_s(k/3) + A₁(k)·Z_s(3k)
//! ```
//!
//! where `Z_s` is the DFT of the cube `y(t)³` of the segment (the document's
//! `Y³`, read as the spectrum of the cubed signal, which is what Eq. 9's
//! `cos³ωt = ¾cos ωt + ¼cos 3ωt` argues from) and `k/3` is rounded to the
//! nearest line. The coefficients are the least-squares solution
//! `p = D⁺Y = (DᴴD)⁻¹DᴴY` (Eq. 4, printed with `ᵀ`) with one row per segment.
//! The document's features are `1 − |A_j(ω)|` ("like coherence", Fig. 8) and
//! `1 − |A_j^d/A_j^un|` between two states (Fig. 9).
//!
//! **Low-order model of a transmissibility.** Between two points of a chain
//! of masses driven from one end, the element joining the reference node to
//! the next carries the inertia of every mass beyond it:
//! `Σ_j m_j·ẍ_j = k·(x_ref − x_1) + c·(ẋ_ref − ẋ_1)`. With the transmissibilities
//! `T_j` from the reference to each of those masses (accelerations, velocities
//! or displacements alike) this is, per line,
//!
//! ```text
//! −ω²·Σ_j m_j·T_j(ω) = (k + iωc)·(1 − T_1(ω))
//! ```
//!
//! linear in `k` and `c`, solved by least squares over the band with each line
//! weighted by its coherence. For one mass it is the SDOF transmissibility
//! `T = (k + iωc)/(k − mω² + iωc)`, whose zeros are the element's alone — the
//! document's reason to prefer transmissibility for locating a change.
//!
//! **Sensitivity functions.** Eq. 7a–c and 8a are missing from the text; rigfit
//! uses Yang's forms, which follow from `H = (K − ω²M + iωC)⁻¹` and
//! `∂H/∂p = −H·(∂Z/∂p)·H`, and reduce to the legible Eq. 11:
//!
//! ```text
//! ∂H_jk/∂K_mn = −(H_jm − H_jn)·(H_mk − H_nk)      (7a; Eq. 11 is j = k = m = 1, n = 3)
//! ∂H_jk/∂C_mn = iω·∂H_jk/∂K_mn                    (7b)
//! ∂H_jk/∂M_m  = ω²·H_jm·H_mk                       (7c)
//! H_0k = H_j0 = 0   (DOF 0 is the ground)           (7d)
//! ΔK_mn ≈ ΔH_jk / (∂H_jk/∂K_mn)                     (8a)
//! ```
//!
//! Without a load cell the document takes the unsprung mass's input force from
//! the tire (Eq. 10's right-hand side), `F_1 = (K_1 + iωC_1)·(X_b − X_1)`, so the
//! receptances of the masses above the tire follow from transmissibilities to
//! the wheel pan: `H_j1 = T_j / ((K_1 + iωC_1)·(1 − T_1))` ([`tire_receptances`]).

use std::f64::consts::PI;

use nalgebra::{DMatrix, DVector};
use rustfft::FftPlanner;
use rustfft::num_complex::Complex64;
use serde::Serialize;

use super::PrecalError;
use super::frf::WelchSettings;
use super::lsq::least_squares;
use super::psd::{Segments, averaged_segments};

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
/// into segments of `segment_len` samples (default as [`super::frf::estimate`])
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
) -> Result<BlockSpectra, PrecalError> {
    if responses.is_empty() {
        return Err(PrecalError::InvalidOption {
            name: "output",
            reason: "give at least one response channel".into(),
        });
    }
    for y in responses {
        super::check_inputs("reference and response", reference, y)?;
    }
    if !(fs > 0.0 && fs.is_finite()) {
        return Err(PrecalError::InvalidOption {
            name: "sample rate",
            reason: format!("{fs} Hz is not positive"),
        });
    }
    let Segments {
        len,
        step,
        count: n_segments,
        window,
    } = averaged_segments(reference.len(), segment_len, 16, "samples for two segments")?;
    let fft = FftPlanner::new().plan_fft_forward(len);
    let bins = len / 2 + 1;
    let dft = |x: &[f64], s: usize, cube: bool| -> Vec<Complex64> {
        let seg = &x[s * step..s * step + len];
        let mean = seg.iter().sum::<f64>() / len as f64;
        let mut b: Vec<Complex64> = seg
            .iter()
            .zip(&window)
            .map(|(v, w)| {
                let d = v - mean;
                Complex64::new(if cube { d * d * d } else { d } * w, 0.0)
            })
            .collect();
        fft.process(&mut b);
        b.truncate(bins);
        b
    };
    Ok(BlockSpectra {
        freqs: (0..bins).map(|k| k as f64 * fs / len as f64).collect(),
        reference: (0..n_segments).map(|s| dft(reference, s, false)).collect(),
        responses: responses
            .iter()
            .map(|y| (0..n_segments).map(|s| dft(y, s, false)).collect())
            .collect(),
        cube: (0..n_segments)
            .map(|s| dft(responses[0], s, true))
            .collect(),
        settings: WelchSettings {
            window: "hann",
            segment_len: len,
            n_segments,
            overlap: 0.5,
            sample_rate_hz: fs,
            resolution_hz: fs / len as f64,
        },
    })
}

impl BlockSpectra {
    /// `T_c(k)` and its coherence for response channel `c`.
    pub fn transmissibility(&self, c: usize) -> (Vec<Complex64>, Vec<f64>) {
        let y = &self.responses[c];
        (0..self.freqs.len())
            .map(|k| {
                let (mut uu, mut yy, mut uy) = (0.0, 0.0, Complex64::new(0.0, 0.0));
                for (us, ys) in self.reference.iter().zip(y) {
                    uu += us[k].norm_sqr();
                    yy += ys[k].norm_sqr();
                    uy += us[k].conj() * ys[k];
                }
                if uu > 0.0 && yy > 0.0 {
                    (uy / uu, (uy.norm_sqr() / (uu * yy)).min(1.0))
                } else {
                    (f64::NAN.into(), 0.0)
                }
            })
            .unzip()
    }
}

/// Which ARX form.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ArxForm {
    /// Eq. 5: the neighbouring lines `Y(k ∓ 1)`.
    Linear,
    /// Eq. 6: the cube's spectrum at `k/3` and `3k`.
    Cubic,
}

/// The ARX coefficients at one line.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ArxLine {
    /// Frequency (Hz).
    pub frequency_hz: f64,
    /// Exogenous coefficient `B(k)` as (re, im).
    pub b: (f64, f64),
    /// `A₋₁(k)` as (re, im).
    pub a_minus: (f64, f64),
    /// `A₁(k)` as (re, im); NaN where `3k` is above the Nyquist line.
    pub a_plus: (f64, f64),
    /// Share of `Σ_s |Y_s(k)|²` the model explains.
    pub explained: f64,
    /// `Σ_s |A₋₁·R₋₁,s|² / Σ_s |Y_s(k)|²`: the size of the first
    /// auto-regressive term against the response.
    pub share_minus: f64,
    /// The same for `A₁`.
    pub share_plus: f64,
}

fn pair(c: Complex64) -> (f64, f64) {
    (c.re, c.im)
}

/// Eq. 5 or Eq. 6 at each line in `[f_min, f_max]` for the first response
/// channel, by least squares over the segments.
///
/// # Errors
/// [`PrecalError::TooFewPoints`] with fewer segments than coefficients plus
/// two, [`PrecalError::Numerical`] for a singular line.
pub fn arx(
    spec: &BlockSpectra,
    form: ArxForm,
    f_min: f64,
    f_max: f64,
) -> Result<Vec<ArxLine>, PrecalError> {
    let bins = spec.freqs.len();
    let segs = spec.reference.len();
    if segs < 5 {
        return Err(PrecalError::TooFewPoints {
            what: "segments for three complex ARX coefficients",
            needed: 5,
            found: segs,
        });
    }
    let y = &spec.responses[0];
    let mut out = vec![];
    for k in 1..bins - 1 {
        let f = spec.freqs[k];
        if f < f_min || f > f_max {
            continue;
        }
        let regressors: Vec<Option<Vec<Complex64>>> = match form {
            ArxForm::Linear => vec![
                Some(y.iter().map(|s| s[k - 1]).collect()),
                Some(y.iter().map(|s| s[k + 1]).collect()),
            ],
            ArxForm::Cubic => {
                let sub = ((k as f64) / 3.0).round() as usize;
                vec![
                    (sub >= 1).then(|| spec.cube.iter().map(|s| s[sub]).collect()),
                    (3 * k < bins).then(|| spec.cube.iter().map(|s| s[3 * k]).collect()),
                ]
            }
        };
        let mut cols: Vec<Vec<Complex64>> = vec![spec.reference.iter().map(|s| s[k]).collect()];
        let used: Vec<bool> = regressors.iter().map(Option::is_some).collect();
        cols.extend(regressors.into_iter().flatten());
        let target: Vec<Complex64> = y.iter().map(|s| s[k]).collect();
        let p = complex_least_squares(&cols, &target)?;
        let mut it = p.iter().copied();
        let b = it.next().unwrap_or_default();
        let nan = Complex64::new(f64::NAN, f64::NAN);
        let a_minus = if used[0] {
            it.next().unwrap_or(nan)
        } else {
            nan
        };
        let a_plus = if used[1] {
            it.next().unwrap_or(nan)
        } else {
            nan
        };
        let (mut e2, mut y2) = (0.0, 0.0);
        for (s, t) in target.iter().enumerate() {
            let fit: Complex64 = cols.iter().zip(&p).map(|(c, pj)| c[s] * pj).sum();
            e2 += (t - fit).norm_sqr();
            y2 += t.norm_sqr();
        }
        let term = |used_before: usize, present: bool| {
            if !present || y2 == 0.0 {
                return f64::NAN;
            }
            let j = 1 + used_before;
            cols[j].iter().map(|c| (c * p[j]).norm_sqr()).sum::<f64>() / y2
        };
        let share_minus = term(0, used[0]);
        let share_plus = term(usize::from(used[0]), used[1]);
        out.push(ArxLine {
            frequency_hz: f,
            b: pair(b),
            a_minus: pair(a_minus),
            a_plus: pair(a_plus),
            explained: if y2 > 0.0 { 1.0 - e2 / y2 } else { 0.0 },
            share_minus,
            share_plus,
        });
    }
    Ok(out)
}

/// `min Σ_s |t_s − Σ_j p_j·c_{j,s}|²` over complex `p`, as the real problem
/// `[Re C, −Im C; Im C, Re C]·[Re p; Im p] = [Re t; Im t]`, columns scaled.
fn complex_least_squares(
    cols: &[Vec<Complex64>],
    target: &[Complex64],
) -> Result<Vec<Complex64>, PrecalError> {
    let (n, p) = (target.len(), cols.len());
    if n < p + 2 {
        return Err(PrecalError::TooFewPoints {
            what: "segments for the ARX coefficients",
            needed: p + 2,
            found: n,
        });
    }
    let scale: Vec<f64> = cols
        .iter()
        .map(|c| {
            let s = c.iter().map(|v| v.norm_sqr()).sum::<f64>().sqrt();
            if s > 0.0 { s } else { 1.0 }
        })
        .collect();
    let a = DMatrix::from_fn(2 * n, 2 * p, |r, j| {
        let (s, im_row) = (r % n, r >= n);
        let (jj, im_col) = (j % p, j >= p);
        let v = cols[jj][s] / scale[jj];
        match (im_row, im_col) {
            (false, false) | (true, true) => v.re,
            (false, true) => -v.im,
            (true, false) => v.im,
        }
    });
    let rhs = DVector::from_fn(2 * n, |r, _| {
        if r < n {
            target[r].re
        } else {
            target[r - n].im
        }
    });
    let x = a
        .svd(true, true)
        .solve(&rhs, 1e-12)
        .map_err(|reason| PrecalError::Numerical {
            stage: "frequency-domain ARX",
            reason: reason.to_string(),
        })?;
    Ok((0..p)
        .map(|j| Complex64::new(x[j], x[p + j]) / scale[j])
        .collect())
}

/// The element between the reference node and the first response node.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ElementFit {
    /// Stiffness `k` (N/m when the masses are in kg).
    pub stiffness: f64,
    /// Its standard error.
    pub stiffness_std_error: f64,
    /// Damping `c` (N·s/m).
    pub damping: f64,
    /// Its standard error.
    pub damping_std_error: f64,
    /// The masses carried, first the one across the element (kg).
    pub masses: Vec<f64>,
    /// Lines used.
    pub lines: usize,
    /// `sqrt(Σ|T_1 − T̂_1|² / Σ|T_1|²)` over the lines used.
    pub relative_error: f64,
    /// R² of the linear least squares.
    pub r2: f64,
}

impl ElementFit {
    /// The model transmissibility to the first node at `f` (Hz), given the
    /// measured transmissibilities `beyond` to the other carried masses there:
    /// `T̂_1 = (k + iωc + ω²·Σ_{j≥2} m_j·T_j) / (k + iωc − ω²·m_1)`.
    pub fn model(&self, f: f64, beyond: &[Complex64]) -> Complex64 {
        let w = 2.0 * PI * f;
        let kc = Complex64::new(self.stiffness, w * self.damping);
        let carried: Complex64 = self.masses[1..]
            .iter()
            .zip(beyond)
            .map(|(m, t)| m * t)
            .sum();
        (kc + w * w * carried) / (kc - w * w * self.masses[0])
    }

    /// `{"params": {k_name, c_name}}`: free with `init` at the estimate and
    /// bounds ±50 % (or ten standard errors when wider; never below 0), or
    /// plain numbers with `fixed`.
    pub fn to_campaign_fragment(&self, names: [&str; 2], fixed: bool) -> serde_json::Value {
        let mut params = serde_json::Map::new();
        for (name, v, se) in [
            (names[0], self.stiffness, self.stiffness_std_error),
            (names[1], self.damping, self.damping_std_error),
        ] {
            let entry = if fixed {
                serde_json::json!(v)
            } else {
                let w = (0.5 * v.abs()).max(10.0 * se);
                serde_json::json!({"min": (v - w).max(0.0), "max": v + w, "init": v})
            };
            params.insert(name.into(), entry);
        }
        serde_json::json!({ "params": params })
    }
}

/// Fits `k` and `c` of the element from the reference to the first of
/// `transmissibilities` (one per carried mass, on `freqs`), weighting each line
/// of `[f_min, f_max]` by the first channel's `coherence` and leaving out lines
/// below `min_coherence`.
///
/// # Errors
/// [`PrecalError::InvalidOption`] for masses that do not match the channels or
/// are not positive, [`PrecalError::TooFewPoints`] for fewer than three lines,
/// and the least-squares errors.
pub fn element_fit(
    freqs: &[f64],
    transmissibilities: &[Vec<Complex64>],
    coherence: &[f64],
    masses: &[f64],
    band: (f64, f64),
    min_coherence: f64,
) -> Result<ElementFit, PrecalError> {
    if masses.len() != transmissibilities.len() || masses.iter().any(|m| m.is_nan() || *m <= 0.0) {
        return Err(PrecalError::InvalidOption {
            name: "mass",
            reason: format!(
                "give one positive mass (kg) per response channel: {} channel(s), masses {masses:?}",
                transmissibilities.len()
            ),
        });
    }
    let lines: Vec<usize> = (0..freqs.len())
        .filter(|&k| freqs[k] > 0.0 && freqs[k] >= band.0 && freqs[k] <= band.1)
        .filter(|&k| coherence[k] >= min_coherence)
        .filter(|&k| transmissibilities.iter().all(|t| t[k].norm().is_finite()))
        .collect();
    if lines.len() < 3 {
        return Err(PrecalError::TooFewPoints {
            what: "coherent lines in the band",
            needed: 3,
            found: lines.len(),
        });
    }
    let (mut ck, mut cc, mut rhs) = (vec![], vec![], vec![]);
    for &k in &lines {
        let w = 2.0 * PI * freqs[k];
        let g = coherence[k];
        let d = Complex64::new(1.0, 0.0) - transmissibilities[0][k];
        let l: Complex64 = -w
            * w
            * masses
                .iter()
                .zip(transmissibilities)
                .map(|(m, t)| m * t[k])
                .sum::<Complex64>();
        // (k + iωc)·d = l, split into real and imaginary rows.
        ck.extend([g * d.re, g * d.im]);
        cc.extend([-g * w * d.im, g * w * d.re]);
        rhs.extend([g * l.re, g * l.im]);
    }
    let lin = least_squares(&[ck, cc], &rhs)?;
    let mut out = ElementFit {
        stiffness: lin.coefficients[0],
        stiffness_std_error: lin.std_errors[0],
        damping: lin.coefficients[1],
        damping_std_error: lin.std_errors[1],
        masses: masses.to_vec(),
        lines: lines.len(),
        relative_error: 0.0,
        r2: lin.r2,
    };
    let (mut e2, mut t2) = (0.0, 0.0);
    for &k in &lines {
        let beyond: Vec<Complex64> = transmissibilities[1..].iter().map(|t| t[k]).collect();
        e2 += (transmissibilities[0][k] - out.model(freqs[k], &beyond)).norm_sqr();
        t2 += transmissibilities[0][k].norm_sqr();
    }
    out.relative_error = (e2 / t2).sqrt();
    Ok(out)
}

/// Eq. 7a: `∂H_jk/∂K_mn = −(H_jm − H_jn)·(H_mk − H_nk)`, with `h(a, b)` the
/// receptance between DOFs `a` and `b` (1-based) and DOF 0 the ground (Eq. 7d).
pub fn stiffness_sensitivity(
    h: &dyn Fn(usize, usize) -> Complex64,
    j: usize,
    k: usize,
    m: usize,
    n: usize,
) -> Complex64 {
    let hh = |a: usize, b: usize| {
        if a == 0 || b == 0 {
            Complex64::new(0.0, 0.0)
        } else {
            h(a, b)
        }
    };
    -(hh(j, m) - hh(j, n)) * (hh(m, k) - hh(n, k))
}

/// Eq. 7b: `∂H_jk/∂C_mn = iω·∂H_jk/∂K_mn` at `omega` (rad/s).
pub fn damping_sensitivity(
    h: &dyn Fn(usize, usize) -> Complex64,
    j: usize,
    k: usize,
    m: usize,
    n: usize,
    omega: f64,
) -> Complex64 {
    Complex64::new(0.0, omega) * stiffness_sensitivity(h, j, k, m, n)
}

/// Eq. 7c: `∂H_jk/∂M_m = ω²·H_jm·H_mk` at `omega` (rad/s).
pub fn mass_sensitivity(
    h: &dyn Fn(usize, usize) -> Complex64,
    j: usize,
    k: usize,
    m: usize,
    omega: f64,
) -> Complex64 {
    omega * omega * h(j, m) * h(m, k)
}

/// The receptances `H_j1 = X_j/F_1` of the masses above a tire from their
/// transmissibilities `T_j` to the wheel pan, with the tire force of Eq. 10,
/// `F_1 = (K_1 + iωC_1)·(X_b − X_1)`: `H_j1 = T_j / ((K_1 + iωC_1)·(1 − T_1))`.
/// `t[0]` is the unsprung mass's.
pub fn tire_receptances(t: &[Complex64], k1: f64, c1: f64, f: f64) -> Vec<Complex64> {
    let kt = Complex64::new(k1, 2.0 * PI * f * c1);
    let den = kt * (Complex64::new(1.0, 0.0) - t[0]);
    t.iter().map(|tj| tj / den).collect()
}

/// Eq. 8a over a band: the stiffness change `Re(ΔH/S)` per line, its mean
/// and standard deviation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StiffnessChange {
    /// Per line: (frequency (Hz), `Re(ΔH/S)`).
    pub per_line: Vec<(f64, f64)>,
    /// Mean over the band.
    pub mean: f64,
    /// Standard deviation over the band.
    pub spread: f64,
}

/// Eq. 8a: `ΔK ≈ ΔH/S` at each line of `freqs` in `band` (Hz), from the
/// finite difference `delta_h` and the baseline sensitivity `sensitivity`.
///
/// # Errors
/// [`PrecalError::TooFewPoints`] for no line in the band.
pub fn stiffness_change(
    freqs: &[f64],
    delta_h: &[Complex64],
    sensitivity: &[Complex64],
    band: (f64, f64),
) -> Result<StiffnessChange, PrecalError> {
    let per_line: Vec<(f64, f64)> = (0..freqs.len())
        .filter(|&k| freqs[k] >= band.0 && freqs[k] <= band.1)
        .map(|k| (freqs[k], (delta_h[k] / sensitivity[k]).re))
        .filter(|(_, v)| v.is_finite())
        .collect();
    if per_line.is_empty() {
        return Err(PrecalError::TooFewPoints {
            what: "lines in the band",
            needed: 1,
            found: 0,
        });
    }
    let n = per_line.len() as f64;
    let mean = per_line.iter().map(|p| p.1).sum::<f64>() / n;
    let spread = (per_line.iter().map(|p| (p.1 - mean).powi(2)).sum::<f64>() / n).sqrt();
    Ok(StiffnessChange {
        per_line,
        mean,
        spread,
    })
}

/// Panels of the transmissibility figure: magnitude (dB) and phase of the
/// measured `T_1` with the element model, and the coherence beside the ARX
/// feature `1 − |A_j|` of the linear model (Fig. 7–8).
pub fn figure(
    freqs: &[f64],
    transmissibilities: &[Vec<Complex64>],
    coherence: &[f64],
    fit: Option<&ElementFit>,
    arx_lines: &[ArxLine],
    band: (f64, f64),
) -> Vec<super::plot::Panel> {
    use super::plot::{FIT, MEASURED, OTHER, Panel, Series, Style, THIRD};
    let ks: Vec<usize> = (1..freqs.len())
        .filter(|&k| freqs[k] >= band.0 && freqs[k] <= band.1)
        .collect();
    let t = &transmissibilities[0];
    let model = |k: usize| {
        let beyond: Vec<Complex64> = transmissibilities[1..].iter().map(|t| t[k]).collect();
        fit.map_or(f64::NAN.into(), |e| e.model(freqs[k], &beyond))
    };
    let series = |label: &str, f: &dyn Fn(usize) -> f64, color| Series {
        label: label.into(),
        points: ks.iter().map(|&k| (freqs[k], f(k))).collect(),
        style: Style::Line,
        color,
    };
    let db = |c: Complex64| 20.0 * c.norm().log10();
    let deg = |c: Complex64| c.arg().to_degrees();
    let mut mag = vec![series("measured T", &|k| db(t[k]), MEASURED)];
    let mut phase = vec![series("measured T", &|k| deg(t[k]), MEASURED)];
    if fit.is_some() {
        mag.push(series("element model", &|k| db(model(k)), FIT));
        phase.push(series("element model", &|k| deg(model(k)), FIT));
    }
    let feature = |label: &str, pick: &dyn Fn(&ArxLine) -> (f64, f64), color| Series {
        label: label.into(),
        points: arx_lines
            .iter()
            .map(|l| {
                let (re, im) = pick(l);
                (l.frequency_hz, 1.0 - re.hypot(im))
            })
            .collect(),
        style: Style::Line,
        color,
    };
    vec![
        Panel {
            caption: "transmissibility magnitude".into(),
            x_desc: "frequency (Hz)".into(),
            y_desc: "dB".into(),
            series: mag,
        },
        Panel {
            caption: "transmissibility phase".into(),
            x_desc: "frequency (Hz)".into(),
            y_desc: "degrees".into(),
            series: phase,
        },
        Panel {
            caption: "coherence and ARX features 1 − |A_j|".into(),
            x_desc: "frequency (Hz)".into(),
            y_desc: "".into(),
            series: vec![
                series("coherence", &|k| coherence[k], MEASURED),
                feature("1 − |A₋₁|", &|l| l.a_minus, OTHER),
                feature("1 − |A₁|", &|l| l.a_plus, THIRD),
            ],
        },
    ]
}

/// Section 3.4 on a quarter car: the change of the strut's stiffness `K_12`
/// between a baseline and a changed record, each with the wheel pan, the
/// unsprung and the sprung mass as channels 0, 1, 2 of its block spectra.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StrutSensitivity {
    /// Eq. 8a over the band.
    pub change: StiffnessChange,
    /// Line frequencies (Hz).
    #[serde(skip)]
    pub freqs: Vec<f64>,
    /// The baseline's `∂H11/∂K12 = −(H11 − H21)²` (Eq. 11 with the strut for the
    /// bolt), per line (m²/N²·N/m = m/N per N/m).
    #[serde(skip)]
    pub sensitivity: Vec<Complex64>,
    /// `ΔH11` per line (m/N).
    #[serde(skip)]
    pub delta_h: Vec<Complex64>,
}

/// [`StrutSensitivity`] from block spectra whose reference is the wheel pan
/// and whose responses are the unsprung and the sprung mass, with the tire's
/// `k1` (N/m) and `c1` (N·s/m), over `band` (Hz).
///
/// # Errors
/// [`PrecalError::InvalidOption`] for spectra with other lines or fewer than
/// two responses; [`stiffness_change`]'s errors.
pub fn strut_sensitivity(
    base: &BlockSpectra,
    changed: &BlockSpectra,
    k1: f64,
    c1: f64,
    band: (f64, f64),
) -> Result<StrutSensitivity, PrecalError> {
    if base.freqs != changed.freqs || base.responses.len() < 2 || changed.responses.len() < 2 {
        return Err(PrecalError::InvalidOption {
            name: "records",
            reason: "both records need the wheel pan, the unsprung and the sprung mass, at the same rate and segment length".into(),
        });
    }
    let receptances = |spec: &BlockSpectra| -> Vec<Vec<Complex64>> {
        let (t1, _) = spec.transmissibility(0);
        let (t2, _) = spec.transmissibility(1);
        (0..spec.freqs.len())
            .map(|k| tire_receptances(&[t1[k], t2[k]], k1, c1, spec.freqs[k]))
            .collect()
    };
    let (hb, hc) = (receptances(base), receptances(changed));
    // Only H11 and H21 are measured; H12 = H21 by reciprocity.
    let sensitivity: Vec<Complex64> = hb
        .iter()
        .map(|h| {
            let rec = |a: usize, b: usize| if (a, b) == (1, 1) { h[0] } else { h[1] };
            stiffness_sensitivity(&rec, 1, 1, 1, 2)
        })
        .collect();
    let delta_h: Vec<Complex64> = hc.iter().zip(&hb).map(|(c, b)| c[0] - b[0]).collect();
    let change = stiffness_change(&base.freqs, &delta_h, &sensitivity, band)?;
    Ok(StrutSensitivity {
        change,
        freqs: base.freqs.clone(),
        sensitivity,
        delta_h,
    })
}

/// Panels of Fig. 11: the sensitivity and the finite difference `ΔH11`
/// (magnitudes), and the stiffness change per line with its band mean.
pub fn sensitivity_figure(s: &StrutSensitivity, band: (f64, f64)) -> Vec<super::plot::Panel> {
    use super::plot::{FIT, MEASURED, OTHER, Panel, Series, Style};
    let ks: Vec<usize> = (1..s.freqs.len())
        .filter(|&k| s.freqs[k] >= band.0 && s.freqs[k] <= band.1)
        .collect();
    let line = |label: &str, f: &dyn Fn(usize) -> f64, color| Series {
        label: label.into(),
        points: ks.iter().map(|&k| (s.freqs[k], f(k))).collect(),
        style: Style::Line,
        color,
    };
    vec![
        Panel {
            caption: "sensitivity and finite difference".into(),
            x_desc: "frequency (Hz)".into(),
            y_desc: "log10 magnitude".into(),
            series: vec![
                line(
                    "|∂H11/∂K12| (m/N per N/m)",
                    &|k| s.sensitivity[k].norm().log10(),
                    FIT,
                ),
                line("|ΔH11| (m/N)", &|k| s.delta_h[k].norm().log10(), OTHER),
            ],
        },
        Panel {
            caption: "stiffness change ΔK12 = ΔH11 / (∂H11/∂K12)".into(),
            x_desc: "frequency (Hz)".into(),
            y_desc: "N/m".into(),
            series: vec![
                Series {
                    label: "per line".into(),
                    points: s.change.per_line.clone(),
                    style: Style::Dots,
                    color: MEASURED,
                },
                line("band mean", &|_| s.change.mean, FIT),
            ],
        },
    ]
}
