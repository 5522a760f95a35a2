//! The experimental sensitivity functions of *Data interrogation for vehicle
//! suspensions* (§2.2, §3.4). Eq. 7a–c and 8a are missing from the text; rigfit
//! uses the forms of Yang et al. (2003, the paper's reference 12), which follow from `H = (K − ω²M + iωC)⁻¹` and
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
//! Without a load cell the paper takes the unsprung mass's input force from
//! the tire (Eq. 10's right-hand side), `F_1 = (K_1 + iωC_1)·(X_b − X_1)`, so the
//! receptances of the masses above the tire follow from transmissibilities to
//! the wheel pan: `H_j1 = T_j / ((K_1 + iωC_1)·(1 − T_1))` ([`tire_receptances`]).

use std::f64::consts::PI;

use rustfft::num_complex::Complex64;
use serde::Serialize;

use super::spectra::BlockSpectra;
use crate::identify::plot::{FIT, MEASURED, OTHER, Panel, Series, Style, line_over};
use crate::identify::psd::lines_in_band;
use crate::identify::{IdentifyError, require_points};

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
/// [`IdentifyError::TooFewPoints`] for no line in the band.
pub fn stiffness_change(
    freqs: &[f64],
    delta_h: &[Complex64],
    sensitivity: &[Complex64],
    band: (f64, f64),
) -> Result<StiffnessChange, IdentifyError> {
    let per_line: Vec<(f64, f64)> = (0..freqs.len())
        .filter(|&k| freqs[k] >= band.0 && freqs[k] <= band.1)
        .map(|k| (freqs[k], (delta_h[k] / sensitivity[k]).re))
        .filter(|(_, v)| v.is_finite())
        .collect();
    require_points("lines in the band", 1, per_line.len())?;
    let n = per_line.len() as f64;
    let mean = per_line.iter().map(|p| p.1).sum::<f64>() / n;
    let spread = (per_line.iter().map(|p| (p.1 - mean).powi(2)).sum::<f64>() / n).sqrt();
    Ok(StiffnessChange {
        per_line,
        mean,
        spread,
    })
}

/// Section 3.4 on a quarter car: the change of the strut's stiffness `K_12`
/// between a baseline and a changed record, each with the wheel pan, the
/// unsprung and the sprung mass as channels 0, 1, 2 of its block spectra.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StrutSensitivity {
    /// Eq. 8a over the band.
    pub change: StiffnessChange,
    /// Per line, for the figure (not in the JSON).
    #[serde(skip)]
    pub lines: StrutLines,
}

/// [`StrutSensitivity`]'s spectra, per line.
#[derive(Debug, Clone, PartialEq)]
pub struct StrutLines {
    /// Line frequencies (Hz).
    pub freqs: Vec<f64>,
    /// The baseline's `∂H11/∂K12 = −(H11 − H21)²` (Eq. 11 with the strut for the
    /// bolt), per line (m²/N²·N/m = m/N per N/m).
    pub sensitivity: Vec<Complex64>,
    /// `ΔH11` per line (m/N).
    pub delta_h: Vec<Complex64>,
}

impl StrutSensitivity {
    /// The campaign keys it suggests: with the strut stiffness before the
    /// change (`base_value`, N/m), `name` after it, a fixed value or a free
    /// parameter around it (half its value, or ten times the spread over the
    /// band where wider); without, none.
    pub fn to_campaign_fragment(
        &self,
        name: &str,
        base_value: Option<f64>,
        fixed: bool,
    ) -> serde_json::Value {
        let mut params = serde_json::Map::new();
        if let Some(k) = base_value {
            let v = k + self.change.mean;
            params.insert(
                name.to_string(),
                if fixed {
                    serde_json::json!(v)
                } else {
                    let w = (0.5 * v.abs()).max(10.0 * self.change.spread);
                    serde_json::json!({"min": (v - w).max(0.0), "max": v + w, "init": v})
                },
            );
        }
        serde_json::json!({ "params": params })
    }
}

/// [`StrutSensitivity`] from block spectra whose reference is the wheel pan
/// and whose responses are the unsprung and the sprung mass, with the tire's
/// `k1` (N/m) and `c1` (N·s/m), over `band` (Hz).
///
/// # Errors
/// [`IdentifyError::InvalidOption`] for spectra with other lines or fewer than
/// two responses; [`stiffness_change`]'s errors.
pub fn strut_sensitivity(
    base: &BlockSpectra,
    changed: &BlockSpectra,
    k1: f64,
    c1: f64,
    band: (f64, f64),
) -> Result<StrutSensitivity, IdentifyError> {
    if base.freqs != changed.freqs || base.responses.len() < 2 || changed.responses.len() < 2 {
        return Err(IdentifyError::InvalidOption {
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
        lines: StrutLines {
            freqs: base.freqs.clone(),
            sensitivity,
            delta_h,
        },
    })
}

/// Panels of Fig. 11: the sensitivity and the finite difference `ΔH11`
/// (magnitudes), and the stiffness change per line with its band mean.
pub fn sensitivity_figure(r: &StrutSensitivity, band: (f64, f64)) -> Vec<Panel> {
    let s = &r.lines;
    let ks = lines_in_band(&s.freqs, band);
    let line =
        |label: &str, f: &dyn Fn(usize) -> f64, color| line_over(label, &s.freqs, &ks, f, color);
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
                    points: r.change.per_line.clone(),
                    style: Style::Dots,
                    color: MEASURED,
                },
                line("band mean", &|_| r.change.mean, FIT),
            ],
        },
    ]
}
