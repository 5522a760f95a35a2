//! An element's stiffness and damping from a low-order model of a
//! transmissibility. Between two points of a chain of masses driven from one end, the element joining the reference node to
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
//! `T = (k + iωc)/(k − mω² + iωc)`, whose zeros are the element's alone — why
//! *Data interrogation for vehicle suspensions* prefers transmissibility for
//! locating a change.

use std::f64::consts::PI;

use rustfft::num_complex::Complex64;
use serde::Serialize;

use crate::identify::lsq::least_squares;
use crate::identify::psd::lines_in_band;
use crate::identify::{IdentifyError, require_points};

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
/// [`IdentifyError::InvalidOption`] for masses that do not match the channels or
/// are not positive, [`IdentifyError::TooFewPoints`] for fewer than three lines,
/// and the least-squares errors.
pub fn element_fit(
    freqs: &[f64],
    transmissibilities: &[Vec<Complex64>],
    coherence: &[f64],
    masses: &[f64],
    band: (f64, f64),
    min_coherence: f64,
) -> Result<ElementFit, IdentifyError> {
    if masses.len() != transmissibilities.len() || masses.iter().any(|m| m.is_nan() || *m <= 0.0) {
        return Err(IdentifyError::InvalidOption {
            name: "mass",
            reason: format!(
                "give one positive mass (kg) per response channel: {} channel(s), masses {masses:?}",
                transmissibilities.len()
            ),
        });
    }
    let lines: Vec<usize> = lines_in_band(freqs, band)
        .into_iter()
        .filter(|&k| freqs[k] > 0.0)
        .filter(|&k| coherence[k] >= min_coherence)
        .filter(|&k| transmissibilities.iter().all(|t| t[k].norm().is_finite()))
        .collect();
    require_points("coherent lines in the band", 3, lines.len())?;
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
        stiffness: lin.coefficients[0].value,
        stiffness_std_error: lin.coefficients[0].std_error,
        damping: lin.coefficients[1].value,
        damping_std_error: lin.coefficients[1].std_error,
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
