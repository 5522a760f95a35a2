//! Nonlinear multiple-input / single-output analysis by the reverse path
//! (Bendat; *Non-linear signal analysis applied to surface wear condition monitoring in
//! reciprocating sliding testing machines*, §2 Eq. 1 and Fig. 2).
//!
//! A rig `m·ẍ + c·ẋ + k·x + a·g(x, ẋ) = F(t)` is read backwards: the measured
//! motion `x` is the "input" and the force `y = F` the "output", so that
//! `Y(f) = H(f)·X(f) + A(f)·V(f)` with `v = g(x, ẋ)` a chosen nonlinear input
//! (`x³`, `sgn ẋ`, `|ẋ|ẋ`, …). `H` is the linear impedance `k − mω² + iωc` and
//! `A` the nonlinear path, ideally the constant `a`. From Welch spectra (as in
//! [`super::frf`]; `S_ab = ⟨A*·B⟩`):
//!
//! ```text
//! L_xv = S_xv / S_xx                      v's part correlated with x
//! γ²_xv = |S_xv|² / (S_xx·S_vv)            (printed |S_xy|² in Eq. 1)
//! S_uu = S_vv·(1 − γ²_xv)                 u = v − L_xv·x, uncorrelated with x
//! S_uy = S_vy − L_xv*·S_xy
//! A    = S_uy / S_uu
//! H_o  = S_xy / S_xx                      the linear estimate ignoring v
//! H    = H_o − L_xv·A                     (printed "(S_xy/S_xx)·A" in Eq. 1)
//! ```
//!
//! The coherence the linear path explains is `γ²_xy = |S_xy|²/(S_xx·S_yy)`; the
//! nonlinear path adds `γ²_uy = |S_uy|²/(S_uu·S_yy)`; their sum is the multiple
//! coherence. `m, c, k` follow from `H` by least squares over a band
//! (`Re H = k − mω²`, `Im H = ωc`), and the nonlinear coefficient `a` is the
//! band's mean of `Re A`.

use std::f64::consts::PI;

use rustfft::num_complex::Complex64;
use serde::Serialize;

use super::frf::WelchSettings;
use super::lsq::least_squares;
use super::psd::{averaged_segments, check_rate, lines_in_band};
use super::signal::{derivative, sign};
use super::{IdentifyError, check_inputs, require_points};

/// The nonlinear input `v = g(x, ẋ)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Nonlinearity {
    /// `x³` (cubic stiffness, N/m³).
    Cubic,
    /// `sgn ẋ` (Coulomb friction, N).
    SignVelocity,
    /// `|ẋ|·ẋ` (quadratic damping, N·s²/m²).
    QuadraticDamping,
}

impl Nonlinearity {
    fn input(self, x: &[f64], v: &[f64]) -> Vec<f64> {
        match self {
            Nonlinearity::Cubic => x.iter().map(|x| x * x * x).collect(),
            Nonlinearity::SignVelocity => v.iter().map(|&v| sign(v)).collect(),
            Nonlinearity::QuadraticDamping => v.iter().map(|v| v.abs() * v).collect(),
        }
    }
}

/// Spectra of the reverse path on the one-sided bins.
#[derive(Debug, Clone, PartialEq)]
pub struct ReversePath {
    /// Bin frequencies (Hz).
    pub freqs: Vec<f64>,
    /// Linear path `H = H_o − L_xv·A` (force per displacement).
    pub h: Vec<Complex64>,
    /// Linear estimate ignoring the nonlinear input, `H_o`.
    pub h_o: Vec<Complex64>,
    /// Nonlinear path `A`.
    pub a: Vec<Complex64>,
    /// Coherence of the linear path `γ²_xy`.
    pub coherence_linear: Vec<f64>,
    /// Coherence the nonlinear path adds, `γ²_uy`.
    pub coherence_nonlinear: Vec<f64>,
    /// Welch settings.
    pub settings: WelchSettings,
}

/// Options of [`analyse`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NimisoOptions {
    /// Sample rate (Hz).
    pub sample_rate_hz: f64,
    /// Samples per segment (default from the data, ≥ 8 segments).
    pub segment_len: Option<usize>,
    /// The nonlinear input.
    pub nonlinearity: Nonlinearity,
    /// Band for the parameter fit (Hz).
    pub f_min: f64,
    /// Upper edge of that band (Hz).
    pub f_max: f64,
}

/// Physical parameters from the two paths.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NimisoReport {
    /// Mass from `Re H` (kg).
    pub mass: f64,
    /// Stiffness from `Re H` (N/m).
    pub stiffness: f64,
    /// Damping from `Im H` (N·s/m).
    pub damping: f64,
    /// Mean of `Re A` over the band (the nonlinear coefficient).
    pub nonlinear_coefficient: f64,
    /// Spread (standard deviation) of `Re A` over the band.
    pub nonlinear_spread: f64,
    /// Mean coherence of the linear path over the band.
    pub mean_coherence_linear: f64,
    /// Mean coherence the nonlinear path adds over the band.
    pub mean_coherence_nonlinear: f64,
    /// Lines in the band.
    pub lines: usize,
    /// The nonlinear input used.
    pub nonlinearity: Nonlinearity,
    /// Welch settings.
    pub settings: WelchSettings,
}

/// Reverse-path analysis of motion `x` (m) and force `y` (N).
///
/// # Errors
/// Input errors, [`IdentifyError::InvalidOption`] for a bad rate, segment or band,
/// [`IdentifyError::TooFewPoints`] for a short record or a band of fewer than four
/// lines, and least-squares errors.
pub fn analyse(
    x: &[f64],
    y: &[f64],
    opts: &NimisoOptions,
) -> Result<(ReversePath, NimisoReport), IdentifyError> {
    check_inputs("motion and force", x, y)?;
    let fs = opts.sample_rate_hz;
    check_rate(fs)?;
    let vel = derivative(x, 1.0 / fs);
    let v = opts.nonlinearity.input(x, &vel);
    let seg = averaged_segments(
        x.len(),
        opts.segment_len,
        8,
        "samples for two averaged segments",
    )?;
    let (n_segments, bins, fft) = (seg.count, seg.bins(), seg.plan());
    let signals = [x, &v, y];
    // s[a][b][k] = ⟨A*·B⟩ (unnormalised; only ratios are used).
    let mut s = vec![vec![vec![Complex64::new(0.0, 0.0); bins]; 3]; 3];
    for part in 0..n_segments {
        let spectra: Vec<Vec<Complex64>> = signals
            .iter()
            .map(|sig| seg.dft(&*fft, sig, part, |d| d))
            .collect();
        for a in 0..3 {
            for b in 0..3 {
                for k in 0..bins {
                    s[a][b][k] += spectra[a][k].conj() * spectra[b][k];
                }
            }
        }
    }
    let (ix, iv, iy) = (0, 1, 2);
    let mut path = ReversePath {
        freqs: seg.freqs(fs),
        h: Vec::with_capacity(bins),
        h_o: Vec::with_capacity(bins),
        a: Vec::with_capacity(bins),
        coherence_linear: Vec::with_capacity(bins),
        coherence_nonlinear: Vec::with_capacity(bins),
        settings: seg.settings(fs),
    };
    #[expect(clippy::needless_range_loop, reason = "k indexes six spectra alike")]
    for k in 0..bins {
        let sxx = s[ix][ix][k].re;
        let svv = s[iv][iv][k].re;
        let syy = s[iy][iy][k].re;
        let (sxv, sxy, svy) = (s[ix][iv][k], s[ix][iy][k], s[iv][iy][k]);
        let l = sxv / sxx;
        let g_xv = (sxv.norm_sqr() / (sxx * svv)).min(1.0);
        let suu = svv * (1.0 - g_xv);
        let suy = svy - l.conj() * sxy;
        let a = suy / suu;
        let h_o = sxy / sxx;
        path.h.push(h_o - l * a);
        path.h_o.push(h_o);
        path.a.push(a);
        path.coherence_linear.push(sxy.norm_sqr() / (sxx * syy));
        path.coherence_nonlinear.push(suy.norm_sqr() / (suu * syy));
    }
    let band: Vec<usize> = lines_in_band(&path.freqs, (opts.f_min, opts.f_max))
        .into_iter()
        .filter(|&k| path.h[k].norm().is_finite() && path.a[k].norm().is_finite())
        .collect();
    require_points("lines in the fitted band", 4, band.len())?;
    let w2: Vec<f64> = band
        .iter()
        .map(|&k| (2.0 * PI * path.freqs[k]).powi(2))
        .collect();
    let re = least_squares(
        &[vec![1.0; band.len()], w2.iter().map(|w| -w).collect()],
        &band.iter().map(|&k| path.h[k].re).collect::<Vec<_>>(),
    )?;
    let im = least_squares(
        &[w2.iter().map(|w| w.sqrt()).collect()],
        &band.iter().map(|&k| path.h[k].im).collect::<Vec<_>>(),
    )?;
    let n = band.len() as f64;
    let a_re: Vec<f64> = band.iter().map(|&k| path.a[k].re).collect();
    let a_mean = a_re.iter().sum::<f64>() / n;
    let a_spread = (a_re.iter().map(|a| (a - a_mean).powi(2)).sum::<f64>() / n).sqrt();
    let mean = |v: &[f64]| band.iter().map(|&k| v[k]).sum::<f64>() / n;
    let report = NimisoReport {
        mass: re.coefficients[1].value,
        stiffness: re.coefficients[0].value,
        damping: im.coefficients[0].value,
        nonlinear_coefficient: a_mean,
        nonlinear_spread: a_spread,
        mean_coherence_linear: mean(&path.coherence_linear),
        mean_coherence_nonlinear: mean(&path.coherence_nonlinear),
        lines: band.len(),
        nonlinearity: opts.nonlinearity,
        settings: path.settings.clone(),
    };
    Ok((path, report))
}

impl NimisoReport {
    /// The campaign fragment: `m`, `c`, `k` and the nonlinear coefficient under
    /// `nonlinear_name`, free with `init` at the estimate and bounds ±50 %, or
    /// plain numbers with `fixed`.
    pub fn to_campaign_fragment(&self, nonlinear_name: &str, fixed: bool) -> serde_json::Value {
        let mut params = serde_json::Map::new();
        for (name, value) in [
            ("m", self.mass),
            ("c", self.damping),
            ("k", self.stiffness),
            (nonlinear_name, self.nonlinear_coefficient),
        ] {
            let entry = if fixed {
                serde_json::json!(value)
            } else {
                let w = 0.5 * value.abs();
                serde_json::json!({"min": value - w, "max": value + w, "init": value})
            };
            params.insert(name.into(), entry);
        }
        serde_json::json!({ "params": params })
    }
}

/// Panels of the reverse-path figure: the linear path's real and imaginary
/// parts with the fitted `k − mω²` and `ωc`, the nonlinear path `Re A` with its
/// band mean, and the coherence of each path.
pub fn figure(
    path: &ReversePath,
    report: &NimisoReport,
    band: (f64, f64),
) -> Vec<super::plot::Panel> {
    use super::plot::{FIT, MEASURED, OTHER, Panel, THIRD, line_over};
    let ks = lines_in_band(&path.freqs, band);
    let series =
        |label: &str, f: &dyn Fn(usize) -> f64, color| line_over(label, &path.freqs, &ks, f, color);
    let w = |k: usize| 2.0 * PI * path.freqs[k];
    vec![
        Panel {
            caption: "linear path H (force per displacement)".into(),
            x_desc: "frequency (Hz)".into(),
            y_desc: "N/m".into(),
            series: vec![
                series("Re H", &|k| path.h[k].re, MEASURED),
                series(
                    "k − mω²",
                    &|k| report.stiffness - report.mass * w(k).powi(2),
                    FIT,
                ),
                series("Im H", &|k| path.h[k].im, OTHER),
                series("ωc", &|k| w(k) * report.damping, THIRD),
            ],
        },
        Panel {
            caption: "nonlinear path A".into(),
            x_desc: "frequency (Hz)".into(),
            y_desc: "Re A".into(),
            series: vec![
                series("Re A", &|k| path.a[k].re, MEASURED),
                series("band mean", &|_| report.nonlinear_coefficient, FIT),
            ],
        },
        Panel {
            caption: "coherence of each path".into(),
            x_desc: "frequency (Hz)".into(),
            y_desc: "γ²".into(),
            series: vec![
                series("linear γ²_xy", &|k| path.coherence_linear[k], FIT),
                series("nonlinear γ²_uy", &|k| path.coherence_nonlinear[k], OTHER),
                series(
                    "sum",
                    &|k| path.coherence_linear[k] + path.coherence_nonlinear[k],
                    MEASURED,
                ),
            ],
        },
    ]
}
