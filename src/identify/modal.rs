//! Modal fit of a measured frequency response: natural frequencies, damping
//! ratios and modal masses, stiffnesses and dampings (*Experimental
//! Investigations of Lubricated Bearing Stiffness*, "a two degree of freedom
//! model identified from frequency responses"; *A New Fatigue Testing Rig Based
//! on Inertial Forces*, §4.5 Eq. 9, an SDOF fit of `ω_n` and ζ; the
//! frequency-domain models of *Data interrogation for vehicle suspensions*).
//!
//! The response is turned into a receptance `H(iω)` (displacement per force:
//! a velocity response is divided by `iω`, an acceleration by `−ω²`) and fitted
//! over a band by a rational fraction in `s = iω/ω₀` (`ω₀` the band's geometric
//! centre, for conditioning):
//!
//! ```text
//! H(s) = (b₀ + b₁s + … + b_{2n−2}s^{2n−2}) / (a₀ + a₁s + … + a_{2n−1}s^{2n−1} + s^{2n})
//! ```
//!
//! for `n` modes. The coefficients solve the linearised least squares
//! `N(s_k) − H_k·D(s_k) ≈ 0` (Levy), re-weighted by `1/|D(s_k)|` of the previous
//! iterate (Sanathanan–Koerner) so that the converged fit minimises the error of
//! `H` itself, each line also weighted by its coherence. The poles `λ` are the
//! roots of `D` (eigenvalues of its companion matrix); for each pair
//! `ω_n = |λ|`, `ζ = −Re λ / |λ|`. With residue `r = N(λ)/D′(λ)` a mode of
//! receptance `1/(m(s² + 2ζω_n s + ω_n²))` has `r = 1/(2i·m·ω_d)`, so
//! `m = |1/(2i·ω_d·r)|` (the modal mass at the measured point, for a unit mode
//! shape there), `k = m·ω_n²`, `c = 2ζ·m·ω_n`. For one mode these are the
//! physical mass, stiffness and damping of an SDOF rig, the impedance form
//! `1/H = k − ω²m + iωc` of *Experimental Investigations of Lubricated Bearing
//! Stiffness*.

use std::f64::consts::PI;

use nalgebra::{DMatrix, DVector};
use rustfft::num_complex::Complex64;
use serde::Serialize;

use super::{IdentifyError, require_points};

/// What the measured response is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Response {
    /// Displacement (receptance).
    Displacement,
    /// Velocity (mobility).
    Velocity,
    /// Acceleration (accelerance).
    Acceleration,
}

/// Options of [`fit`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModalOptions {
    /// Number of modes in the band (1..=4).
    pub modes: usize,
    /// Lower edge of the band (Hz).
    pub f_min: f64,
    /// Upper edge of the band (Hz).
    pub f_max: f64,
    /// What the FRF's output is.
    pub response: Response,
    /// Lines whose coherence is below this are left out.
    pub min_coherence: f64,
    /// Sanathanan–Koerner iterations.
    pub iterations: usize,
}

/// One identified mode.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Mode {
    /// Natural frequency (Hz).
    pub natural_frequency_hz: f64,
    /// Damping ratio.
    pub damping_ratio: f64,
    /// Modal mass at the measured point (kg when the input is N and the output m).
    pub mass: f64,
    /// Modal stiffness `m·ω_n²` (N/m).
    pub stiffness: f64,
    /// Modal damping `2ζ·m·ω_n` (N·s/m).
    pub damping: f64,
    /// Phase of `1/(2i·ω_d·r)` (rad): 0 for a real (proportionally damped) mode.
    pub complexity_rad: f64,
    /// Whether the natural frequency lies inside the fitted band. A pole
    /// outside it is tested by no line near it: its frequency, damping and
    /// modal values rest on extrapolation (often the band's residual of
    /// modes beyond it), and [`ModalFit::warnings`] says so.
    pub in_band: bool,
}

/// The fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModalFit {
    /// Modes, by increasing frequency.
    pub modes: Vec<Mode>,
    /// Lines used.
    pub lines: usize,
    /// Relative RMS error `sqrt(Σ|H − Ĥ|² / Σ|H|²)` over the lines used.
    pub relative_error: f64,
    /// Scaling frequency ω₀ (rad/s).
    pub omega_ref: f64,
    /// Numerator coefficients in `s = iω/ω₀`.
    pub numerator: Vec<f64>,
    /// Denominator coefficients in `s`, monic (last = 1).
    pub denominator: Vec<f64>,
    /// What the fit cannot vouch for: each mode outside the fitted band.
    pub warnings: Vec<String>,
}

fn poly(c: &[f64], s: Complex64) -> Complex64 {
    c.iter()
        .rev()
        .fold(Complex64::new(0.0, 0.0), |acc, &a| acc * s + a)
}

impl ModalFit {
    /// The fitted receptance at `f` (Hz).
    pub fn receptance(&self, f: f64) -> Complex64 {
        let s = Complex64::new(0.0, 2.0 * PI * f / self.omega_ref);
        poly(&self.numerator, s) / poly(&self.denominator, s)
    }

    /// The fitted response of the measured kind at `f` (Hz).
    pub fn response(&self, f: f64, kind: Response) -> Complex64 {
        self.receptance(f) * to_receptance_factor(f, kind).inv()
    }
}

/// The factor that turns a response of `kind` into a receptance at `f` (Hz).
fn to_receptance_factor(f: f64, kind: Response) -> Complex64 {
    let iw = Complex64::new(0.0, 2.0 * PI * f);
    match kind {
        Response::Displacement => Complex64::new(1.0, 0.0),
        Response::Velocity => iw.inv(),
        Response::Acceleration => (iw * iw).inv(),
    }
}

fn validate(o: &ModalOptions) -> Result<(), IdentifyError> {
    if !(1..=4).contains(&o.modes) {
        return Err(IdentifyError::InvalidOption {
            name: "modes",
            reason: format!("{} is outside 1..=4", o.modes),
        });
    }
    if !(o.f_min > 0.0 && o.f_max > o.f_min && o.f_max.is_finite()) {
        return Err(IdentifyError::InvalidOption {
            name: "band",
            reason: format!("{} … {} Hz is not a band above 0", o.f_min, o.f_max),
        });
    }
    Ok(())
}

/// Fits `opts.modes` modes to the response `h` at `freqs` (Hz), weighting each
/// line by its `coherence`.
///
/// # Errors
/// [`IdentifyError::InvalidOption`] for bad options, [`IdentifyError::TooFewPoints`]
/// for too few coherent lines in the band, [`IdentifyError::Numerical`] when the
/// fit has fewer stable, oscillating poles than modes asked for.
pub fn fit(
    freqs: &[f64],
    h: &[Complex64],
    coherence: &[f64],
    opts: &ModalOptions,
) -> Result<ModalFit, IdentifyError> {
    validate(opts)?;
    let lines: Vec<(f64, Complex64, f64)> = (0..freqs.len())
        .filter(|&k| freqs[k] >= opts.f_min && freqs[k] <= opts.f_max)
        .filter(|&k| coherence[k] >= opts.min_coherence && h[k].norm().is_finite())
        .map(|k| {
            (
                freqs[k],
                h[k] * to_receptance_factor(freqs[k], opts.response),
                coherence[k],
            )
        })
        .collect();
    let n = opts.modes;
    let nb = 2 * n - 1;
    let na = 2 * n;
    let unknowns = nb + na;
    require_points(
        "coherent lines in the band",
        unknowns.div_ceil(2) + 1,
        lines.len(),
    )?;
    let omega_ref = 2.0 * PI * (opts.f_min * opts.f_max).sqrt();
    let s: Vec<Complex64> = lines
        .iter()
        .map(|(f, _, _)| Complex64::new(0.0, 2.0 * PI * f / omega_ref))
        .collect();
    // Receptances are tiny numbers; fit H/scale and scale the numerator back.
    let scale = lines.iter().map(|l| l.1.norm()).fold(0.0, f64::max);
    let mut num = vec![0.0; nb];
    let mut den = vec![1.0; na + 1];
    let mut weight = vec![1.0; lines.len()];
    for _ in 0..opts.iterations.max(1) {
        let rows = 2 * lines.len();
        let mut a = DMatrix::zeros(rows, unknowns);
        let mut rhs = DVector::zeros(rows);
        for (k, ((_, hk, g), sk)) in lines.iter().zip(&s).enumerate() {
            let hk = hk / scale;
            let w = weight[k] * g;
            let mut p = Complex64::new(1.0, 0.0);
            for j in 0..na {
                if j < nb {
                    a[(2 * k, j)] = w * p.re;
                    a[(2 * k + 1, j)] = w * p.im;
                }
                let t = -hk * p;
                a[(2 * k, nb + j)] = w * t.re;
                a[(2 * k + 1, nb + j)] = w * t.im;
                p *= sk;
            }
            let r = hk * p;
            rhs[2 * k] = w * r.re;
            rhs[2 * k + 1] = w * r.im;
        }
        let theta =
            a.svd(true, true)
                .solve(&rhs, 1e-14)
                .map_err(|reason| IdentifyError::Numerical {
                    stage: "rational-fraction fit",
                    reason: reason.to_string(),
                })?;
        num = theta.as_slice()[..nb].to_vec();
        den[..na].copy_from_slice(&theta.as_slice()[nb..]);
        for (w, sk) in weight.iter_mut().zip(&s) {
            let d = poly(&den, *sk).norm();
            *w = if d > 0.0 { 1.0 / d } else { 1.0 };
        }
    }
    for b in &mut num {
        *b *= scale;
    }
    // Roots of the monic denominator: eigenvalues of its companion matrix.
    let companion = DMatrix::from_fn(na, na, |i, j| {
        if i == 0 {
            -den[na - 1 - j]
        } else if i == j + 1 {
            1.0
        } else {
            0.0
        }
    });
    let dden: Vec<f64> = (1..=na).map(|j| j as f64 * den[j]).collect();
    let mut modes: Vec<Mode> = companion
        .complex_eigenvalues()
        .iter()
        .filter(|l| l.im > 0.0 && l.re < 0.0)
        .map(|&l| {
            let lam = l * omega_ref;
            let wn = lam.norm();
            let zeta = -lam.re / wn;
            let wd = lam.im;
            let r = poly(&num, l) / poly(&dden, l) * omega_ref;
            let mc = (Complex64::new(0.0, 2.0 * wd) * r).inv();
            let m = mc.norm();
            Mode {
                natural_frequency_hz: wn / (2.0 * PI),
                damping_ratio: zeta,
                mass: m,
                stiffness: m * wn * wn,
                damping: 2.0 * zeta * m * wn,
                complexity_rad: mc.arg(),
                in_band: (opts.f_min..=opts.f_max).contains(&(wn / (2.0 * PI))),
            }
        })
        .collect();
    if modes.len() < n {
        return Err(IdentifyError::Numerical {
            stage: "modal fit",
            reason: format!(
                "{} stable oscillating pole pair(s) found for {n} mode(s); try another band or fewer modes",
                modes.len()
            ),
        });
    }
    modes.sort_by(|a, b| a.natural_frequency_hz.total_cmp(&b.natural_frequency_hz));
    let warnings = out_of_band(&modes, opts);
    let mut out = ModalFit {
        modes,
        lines: lines.len(),
        relative_error: 0.0,
        omega_ref,
        numerator: num,
        denominator: den,
        warnings,
    };
    let (mut e2, mut h2) = (0.0, 0.0);
    for (f, hk, _) in &lines {
        e2 += (hk - out.receptance(*f)).norm_sqr();
        h2 += hk.norm_sqr();
    }
    out.relative_error = (e2 / h2).sqrt();
    Ok(out)
}

/// One warning per mode whose natural frequency lies outside the band the
/// lines were taken from: the fit places such a pole to shape the band's
/// response, and no line near it tests its frequency, damping or mass.
fn out_of_band(modes: &[Mode], opts: &ModalOptions) -> Vec<String> {
    modes
        .iter()
        .enumerate()
        .filter(|(_, m)| !m.in_band)
        .map(|(i, m)| {
            let f = m.natural_frequency_hz;
            let side = if f < opts.f_min { "below" } else { "above" };
            format!(
                "mode {}: f_n = {f:.4} Hz lies {side} the fitted band {} … {} Hz; no line of the \
                 band is near it, so its frequency, damping and modal mass, stiffness and damping \
                 rest on extrapolation (with noise, or modes beyond the band, often the band's \
                 residual rather than a resonance): widen the band to take in the resonance, or \
                 fit fewer modes",
                i + 1,
                opts.f_min,
                opts.f_max
            )
        })
        .collect()
}

impl ModalFit {
    /// The campaign fragment: for each mode its mass, stiffness and damping under
    /// `names` (three per mode; with three names and several modes, the mode's
    /// number is appended). Free with `init` at the estimate and bounds ±50 %,
    /// or plain numbers with `fixed`.
    pub fn to_campaign_fragment(&self, names: &[String], fixed: bool) -> serde_json::Value {
        let mut params = serde_json::Map::new();
        for (i, m) in self.modes.iter().enumerate() {
            for (j, value) in [m.mass, m.stiffness, m.damping].into_iter().enumerate() {
                let name = match names.get(3 * i + j) {
                    Some(n) if names.len() == 3 * self.modes.len() => n.clone(),
                    _ => format!(
                        "{}{}",
                        names.get(j).map_or(["m", "k", "c"][j], |s| s.as_str()),
                        i + 1
                    ),
                };
                let entry = if fixed {
                    serde_json::json!(value)
                } else {
                    serde_json::json!({"min": 0.5 * value, "max": 1.5 * value, "init": value})
                };
                params.insert(name, entry);
            }
        }
        serde_json::json!({ "params": params })
    }
}

/// Panels of the FRF figure: magnitude (dB) and phase of H1, H2 and the fit,
/// and the coherence, against frequency.
pub fn figure(
    est: &super::frf::Frf,
    fit: Option<&ModalFit>,
    kind: Response,
) -> Vec<super::plot::Panel> {
    use super::plot::{FIT, MEASURED, OTHER, Panel, Series, Style};
    let lines = 1..est.freqs.len();
    let db = |h: Complex64| 20.0 * h.norm().log10();
    let deg = |h: Complex64| h.arg().to_degrees();
    let series = |label: &str, f: &dyn Fn(usize) -> f64, style, color| Series {
        label: label.into(),
        points: lines.clone().map(|k| (est.freqs[k], f(k))).collect(),
        style,
        color,
    };
    let fitted = |k: usize| fit.map_or(f64::NAN.into(), |m| m.response(est.freqs[k], kind));
    let mut mag = vec![
        series("H1", &|k| db(est.h1[k]), Style::Line, MEASURED),
        series("H2", &|k| db(est.h2[k]), Style::Line, OTHER),
    ];
    let mut phase = vec![
        series("H1", &|k| deg(est.h1[k]), Style::Line, MEASURED),
        series("H2", &|k| deg(est.h2[k]), Style::Line, OTHER),
    ];
    if fit.is_some() {
        mag.push(series("modal fit", &|k| db(fitted(k)), Style::Line, FIT));
        phase.push(series("modal fit", &|k| deg(fitted(k)), Style::Line, FIT));
    }
    vec![
        Panel {
            caption: "magnitude".into(),
            x_desc: "frequency (Hz)".into(),
            y_desc: "|H| (dB)".into(),
            series: mag,
        },
        Panel {
            caption: "phase".into(),
            x_desc: "frequency (Hz)".into(),
            y_desc: "phase (°)".into(),
            series: phase,
        },
        Panel {
            caption: "coherence".into(),
            x_desc: "frequency (Hz)".into(),
            y_desc: "γ²".into(),
            series: vec![series("γ²", &|k| est.coherence[k], Style::Line, FIT)],
        },
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_two_mode_receptance_is_recovered() {
        // Two modes, real mode shapes: H = Σ 1/(m_i(s² + 2ζ_i ω_i s + ω_i²)).
        let modes = [(12.0, 0.02, 3.0), (31.0, 0.05, 1.5)];
        let freqs: Vec<f64> = (1..400).map(|k| k as f64 * 0.1).collect();
        let h: Vec<Complex64> = freqs
            .iter()
            .map(|f| {
                let s = Complex64::new(0.0, 2.0 * PI * f);
                modes
                    .iter()
                    .map(|&(fn_, z, m)| {
                        let w = 2.0 * PI * fn_;
                        (m * (s * s + 2.0 * z * w * s + w * w)).inv()
                    })
                    .sum()
            })
            .collect();
        let opts = ModalOptions {
            modes: 2,
            f_min: 2.0,
            f_max: 39.0,
            response: Response::Displacement,
            min_coherence: 0.0,
            iterations: 8,
        };
        let fit = fit(&freqs, &h, &vec![1.0; freqs.len()], &opts).unwrap();
        for (m, &(fn_, z, mass)) in fit.modes.iter().zip(&modes) {
            assert!((m.natural_frequency_hz - fn_).abs() < 1e-6 * fn_, "{m:?}");
            assert!((m.damping_ratio - z).abs() < 1e-6 * z, "{m:?}");
            assert!((m.mass - mass).abs() < 1e-5 * mass, "{m:?}");
            assert!(m.complexity_rad.abs() < 1e-5);
        }
        assert!(fit.relative_error < 1e-8);
    }
}
