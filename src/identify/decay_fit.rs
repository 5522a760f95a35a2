//! Levenberg–Marquardt fit of a free damped oscillation
//! `x(t) = A·e^{−σt}·cos(ω_d·t + φ) + c` to a ring-down.
//!
//! The amplitude and phase are carried as `C = A cos φ`, `S = −A sin φ`, so the
//! model `e^{−σt}(C cos ω_d t + S sin ω_d t) + c` is linear in `C, S, c`; those
//! three start from a linear least-squares solve with the initial `σ, ω_d`, then
//! all five are refined together with Marquardt's diagonal scaling.

use nalgebra::{Matrix3, Matrix5, Vector3, Vector5};
use serde::Serialize;

use super::{IdentifyError, r_squared};

const MAX_ITERATIONS: usize = 200;

/// A fitted damped oscillation (times from the start of the free ringing).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DecayFit {
    /// Initial amplitude `A` (signal unit, N).
    pub amplitude: f64,
    /// Phase `φ` (rad).
    pub phase: f64,
    /// Constant offset `c` (N).
    pub offset: f64,
    /// Decay rate `σ = ζ·ω_n` (1/s).
    pub decay_rate: f64,
    /// Damped angular frequency `ω_d` (rad/s).
    pub omega_d: f64,
    /// Undamped angular frequency `ω_n = sqrt(ω_d² + σ²)` (rad/s).
    pub omega_n: f64,
    /// Damping ratio `ζ = σ/ω_n`.
    pub zeta: f64,
    /// R² of the fit over the samples of free ringing.
    pub r2: f64,
    /// Root-mean-square residual (N).
    pub rmse: f64,
    /// Levenberg–Marquardt iterations used.
    pub iterations: usize,
    /// Whether the relative SSE change fell below 1e-12 before the iteration cap.
    pub converged: bool,
}

/// Fits the decay to samples `x` at times `t` (s, from 0), starting from
/// `omega_d` (rad/s) and `decay_rate` (1/s).
pub(crate) fn fit_decay(
    t: &[f64],
    x: &[f64],
    omega_d: f64,
    decay_rate: f64,
) -> Result<DecayFit, IdentifyError> {
    let linear =
        linear_part(t, x, decay_rate, omega_d).ok_or_else(|| IdentifyError::Numerical {
            stage: "ring-down fit start",
            reason: "singular linear system".into(),
        })?;
    let mut p = Vector5::new(linear[0], linear[1], decay_rate, omega_d, linear[2]);
    let mut sse = sse_of(t, x, &p);
    let mut lambda = 1e-3;
    let mut iterations = 0;
    let mut converged = false;
    while iterations < MAX_ITERATIONS {
        iterations += 1;
        let (jtj, jtr) = normal_equations(t, x, &p);
        let mut improved = false;
        for _ in 0..20 {
            let mut a = jtj;
            for i in 0..5 {
                a[(i, i)] += lambda * jtj[(i, i)].max(1e-300);
            }
            let Some(step) = a.lu().solve(&jtr) else {
                lambda *= 10.0;
                continue;
            };
            let trial = p + step;
            let trial_sse = sse_of(t, x, &trial);
            if trial_sse.is_finite() && trial_sse <= sse {
                let change = (sse - trial_sse) / sse.max(f64::MIN_POSITIVE);
                p = trial;
                sse = trial_sse;
                lambda = (lambda / 3.0).max(1e-12);
                improved = true;
                converged = change < 1e-12;
                break;
            }
            lambda *= 4.0;
        }
        if !improved || converged {
            converged = true;
            break;
        }
    }
    let (c, s, sigma, omega, offset) = (p[0], p[1], p[2], p[3], p[4]);
    let omega_n = (omega * omega + sigma * sigma).sqrt();
    Ok(DecayFit {
        amplitude: c.hypot(s),
        phase: (-s).atan2(c),
        offset,
        decay_rate: sigma,
        omega_d: omega,
        omega_n,
        zeta: sigma / omega_n,
        r2: r_squared(sse, x),
        rmse: (sse / x.len() as f64).sqrt(),
        iterations,
        converged,
    })
}

fn model(t: f64, p: &Vector5<f64>) -> (f64, [f64; 5]) {
    let e = (-p[2] * t).exp();
    let (sin, cos) = (p[3] * t).sin_cos();
    let osc = p[0] * cos + p[1] * sin;
    let value = e * osc + p[4];
    let grad = [
        e * cos,
        e * sin,
        -t * e * osc,
        t * e * (p[1] * cos - p[0] * sin),
        1.0,
    ];
    (value, grad)
}

fn sse_of(t: &[f64], x: &[f64], p: &Vector5<f64>) -> f64 {
    t.iter()
        .zip(x)
        .map(|(&ti, &xi)| (xi - model(ti, p).0).powi(2))
        .sum()
}

fn normal_equations(t: &[f64], x: &[f64], p: &Vector5<f64>) -> (Matrix5<f64>, Vector5<f64>) {
    let mut jtj = Matrix5::zeros();
    let mut jtr = Vector5::zeros();
    for (&ti, &xi) in t.iter().zip(x) {
        let (value, g) = model(ti, p);
        let g = Vector5::from(g);
        jtj += g * g.transpose();
        jtr += g * (xi - value);
    }
    (jtj, jtr)
}

/// `C, S, c` by linear least squares with `σ, ω_d` fixed.
fn linear_part(t: &[f64], x: &[f64], sigma: f64, omega: f64) -> Option<Vector3<f64>> {
    let mut ata = Matrix3::zeros();
    let mut atb = Vector3::zeros();
    for (&ti, &xi) in t.iter().zip(x) {
        let e = (-sigma * ti).exp();
        let (sin, cos) = (omega * ti).sin_cos();
        let row = Vector3::new(e * cos, e * sin, 1.0);
        ata += row * row.transpose();
        atb += row * xi;
    }
    ata.lu().solve(&atb)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_a_clean_decay() {
        let (sigma, omega) = (58.0, 2.0 * std::f64::consts::PI * 5190.0);
        let t: Vec<f64> = (0..10_000).map(|i| i as f64 * 1e-6).collect();
        let x: Vec<f64> = t
            .iter()
            .map(|&t| 5000.0 * (-sigma * t).exp() * (omega * t + 0.3).cos() + 12.0)
            .collect();
        let fit = fit_decay(&t, &x, omega * 1.001, sigma * 1.2).unwrap();
        assert!((fit.decay_rate - sigma).abs() < 1e-6 * sigma, "{fit:?}");
        assert!((fit.omega_d - omega).abs() < 1e-6 * omega);
        assert!((fit.phase - 0.3).abs() < 1e-6 && (fit.offset - 12.0).abs() < 1e-6);
        assert!(fit.r2 > 0.999_999);
    }
}
