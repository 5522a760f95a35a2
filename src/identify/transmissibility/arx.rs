//! The frequency-domain ARX model of *Data interrogation for vehicle
//! suspensions* (§2.1.2, §3.3). Eq. 2 is missing from the text and Eq. 6 is
//! garbled; rigfit reads them as follows. Per line `k`, over the segments `s`,
//!
//! ```text
//! Eq. 5 (1st order, linear):    Y_s(k) = B(k)·U_s(k) + A₋₁(k)·Y_s(k−1) + A₁(k)·Y_s(k+1)
//! Eq. 6 (1st order, nonlinear): Y_s(k) = B(k)·U_s(k) + A₋₁(k)·Z_s(k/3) + A₁(k)·Z_s(3k)
//! ```
//!
//! where `Z_s` is the DFT of the cube `y(t)³` of the segment (the paper's
//! `Y³`, read as the spectrum of the cubed signal, which is what Eq. 9's
//! `cos³ωt = ¾cos ωt + ¼cos 3ωt` argues from) and `k/3` is rounded to the
//! nearest line. The coefficients are the least-squares solution
//! `p = D⁺Y = (DᴴD)⁻¹DᴴY` (Eq. 4, printed with `ᵀ`) with one row per segment.
//! The paper's features are `1 − |A_j(ω)|` ("like coherence", Fig. 8) and
//! `1 − |A_j^d/A_j^un|` between two states (Fig. 9).

use nalgebra::{DMatrix, DVector};
use rustfft::num_complex::Complex64;
use serde::Serialize;

use super::spectra::BlockSpectra;
use crate::identify::{IdentifyError, require_points};

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
/// [`IdentifyError::TooFewPoints`] with fewer segments than coefficients plus
/// two, [`IdentifyError::Numerical`] for a singular line.
pub fn arx(
    spec: &BlockSpectra,
    form: ArxForm,
    f_min: f64,
    f_max: f64,
) -> Result<Vec<ArxLine>, IdentifyError> {
    let bins = spec.freqs.len();
    let segs = spec.reference.len();
    require_points("segments for three complex ARX coefficients", 5, segs)?;
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
) -> Result<Vec<Complex64>, IdentifyError> {
    let (n, p) = (target.len(), cols.len());
    require_points("segments for the ARX coefficients", p + 2, n)?;
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
        .map_err(|reason| IdentifyError::Numerical {
            stage: "frequency-domain ARX",
            reason: reason.to_string(),
        })?;
    Ok((0..p)
        .map(|j| Complex64::new(x[j], x[p + j]) / scale[j])
        .collect())
}
