//! The restoring-force surface of a base-excited single-degree-of-freedom rig
//! (*A New Fatigue Testing Rig Based on Inertial Forces*, §3.2 "Nonlinear Model
//! Selection", Eq. 3–4).
//!
//! With `x` the displacement of the mass relative to the base and `a` the base
//! acceleration, `m·ẍ + C(ẋ) + K(x) = −m·a`, so the restoring force
//!
//! ```text
//! f = −m·(a + ẍ) = C(ẋ) + K(x)
//! ```
//!
//! is known at every sample once `ẋ` and `ẍ` are formed from `x`. As in the
//! document, they come from finite differences (central differences for `ẋ`,
//! the three-point second difference for `ẍ`); an optional zero-phase
//! Butterworth low-pass on `x` and `a` first keeps the differences from
//! amplifying sensor noise. The first and last two samples (one-sided
//! differences) are dropped, and so is every sample at a velocity reversal
//! (its neighbours' velocities differ in sign): a Coulomb jump falls between
//! samples there, which spoils both its second difference and its `sgn ẋ`. Plotted over
//! `(x, ẋ)` the samples form the surface; its slices `ẋ ≈ 0` and `x ≈ 0` show `K` and `C`, which is how the paper chose its
//! terms (Fig. 7).

use serde::Serialize;

use super::columns::sample_interval;
use super::signal::{butter_lowpass, derivative, filtfilt, second_derivative};
use super::{IdentifyError, check_inputs, require_points};

/// How the surface is formed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RfsOptions {
    /// Mass of the moving body (kg), measured.
    pub mass: f64,
    /// Cut-off of the zero-phase low-pass applied to `x` and `a` (Hz); none when
    /// `None`.
    pub cutoff_hz: Option<f64>,
    /// Order of that Butterworth filter.
    pub filter_order: usize,
}

/// Samples of the restoring force over the phase plane.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Surface {
    /// Relative displacement `x` (m).
    pub x: Vec<f64>,
    /// Relative velocity `ẋ` (m/s).
    pub v: Vec<f64>,
    /// Restoring force `f = −m(a + ẍ)` (N).
    pub f: Vec<f64>,
    /// Sample rate (Hz).
    pub sample_rate_hz: f64,
    /// Mass used (kg).
    pub mass: f64,
    /// Samples left out at velocity reversals.
    pub reversals_dropped: usize,
}

impl Surface {
    /// Indices of the samples in the slice `|ẋ| ≤ frac·max|ẋ|` (the stiffness
    /// slice) or, with `velocity_slice`, `|x| ≤ frac·max|x|` (the damping slice).
    pub fn slice(&self, velocity_slice: bool, frac: f64) -> Vec<usize> {
        let axis = if velocity_slice { &self.x } else { &self.v };
        let max = axis.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        (0..axis.len())
            .filter(|&i| axis[i].abs() <= frac * max)
            .collect()
    }
}

/// Builds the restoring-force surface from times `t` (s), relative displacement
/// `x` (m) and base acceleration `a` (m/s²).
///
/// # Errors
/// Input errors, [`IdentifyError::NonUniformTime`], [`IdentifyError::InvalidOption`]
/// for a non-positive mass or a bad filter, [`IdentifyError::TooFewPoints`].
pub fn surface(
    t: &[f64],
    x: &[f64],
    a: &[f64],
    opts: &RfsOptions,
) -> Result<Surface, IdentifyError> {
    check_inputs("relative displacement", t, x)?;
    check_inputs("base acceleration", t, a)?;
    if !(opts.mass > 0.0 && opts.mass.is_finite()) {
        return Err(IdentifyError::InvalidOption {
            name: "mass",
            reason: format!("{} kg is not positive", opts.mass),
        });
    }
    require_points("samples", 16, t.len())?;
    let dt = sample_interval(t)?;
    let fs = 1.0 / dt;
    let (x, a) = match opts.cutoff_hz {
        Some(fc) => {
            let sections = butter_lowpass(opts.filter_order, fc, fs)?;
            (filtfilt(&sections, x)?, filtfilt(&sections, a)?)
        }
        None => (x.to_vec(), a.to_vec()),
    };
    let v = derivative(&x, dt);
    let acc = second_derivative(&x, dt);
    let n = x.len();
    // A sample whose neighbours' velocities differ in sign sits on a reversal:
    // a friction jump there falls between samples, so its second difference
    // and its sgn ẋ are both unreliable.
    let keep: Vec<usize> = (2..n - 2).filter(|&k| v[k - 1] * v[k + 1] > 0.0).collect();
    Ok(Surface {
        f: keep.iter().map(|&k| -opts.mass * (a[k] + acc[k])).collect(),
        x: keep.iter().map(|&k| x[k]).collect(),
        v: keep.iter().map(|&k| v[k]).collect(),
        sample_rate_hz: fs,
        mass: opts.mass,
        reversals_dropped: n - 4 - keep.len(),
    })
}
