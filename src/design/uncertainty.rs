//! The calibration's uncertainty carried into a prediction: draws of the
//! fitted parameters from the polish's covariance.
//!
//! A finished job's `result.json` gives, for every fitted parameter, its value,
//! its scale (`"log"` or linear), its bounds and its standard error, and the
//! polish's correlation matrix of the fitted parameters. Together they are the
//! Gauss–Newton covariance `Σ = D R D` in each parameter's scale (the
//! logarithm for a log-scale parameter, whose scale-space error is its
//! standard error over its value), the same covariance the job's intervals
//! come from. A draw is `x + L z` in scale space (`L` the Cholesky factor of
//! `Σ`, `z` standard normal) mapped back, redrawn (up to
//! [`REDRAWS`] times, then clamped) where it leaves the parameter's bounds.
//!
//! A design variable that is also a fitted parameter (sweeping the adapter's
//! damping that the calibration fitted) is set by the design: the draws are of
//! the other parameters, from their marginal distribution (the rows and
//! columns of the design's parameters dropped from `Σ`).
//!
//! The draws assume what the covariance assumes (independent residuals of
//! equal variance, a model that can follow the record, a cost close to
//! quadratic over the interval); a parameter the data do not determine has
//! no finite interval and is refused, naming it.

use std::path::Path;

use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Deserialize;

/// Draws that leave a parameter's bounds are drawn again this many times,
/// then clamped to the bounds.
pub const REDRAWS: usize = 100;

/// The fitted parameters of a result and their covariance.
#[derive(Debug, Clone, PartialEq)]
pub struct Posterior {
    /// The fitted parameters' names, as a parameter file names them (`k1`,
    /// `test.k_lin`).
    pub names: Vec<String>,
    /// Their fitted values.
    pub values: Vec<f64>,
    /// Whether each is on a log scale.
    pub log: Vec<bool>,
    /// Each one's search bounds.
    pub bounds: Vec<[f64; 2]>,
    /// The covariance in scale space, `names.len()` square.
    pub covariance: DMatrix<f64>,
}

/// One parameter of `result.json`'s `parameters` list.
#[derive(Debug, Deserialize)]
struct ResultParameter {
    name: String,
    value: Option<f64>,
    #[serde(default)]
    free: bool,
    #[serde(default)]
    scale: Option<String>,
    #[serde(default)]
    bounds: Option<[f64; 2]>,
    #[serde(default)]
    std_error: Option<f64>,
    #[serde(default)]
    determined: Option<bool>,
}

/// `result.json`'s `polish`: the correlation's order and values.
#[derive(Debug, Deserialize)]
struct ResultPolish {
    genes: Vec<String>,
    correlation: Vec<Vec<Option<f64>>>,
}

/// The keys of `result.json` the posterior reads.
#[derive(Debug, Deserialize)]
struct ResultFile {
    parameters: Vec<ResultParameter>,
    polish: Option<ResultPolish>,
}

impl Posterior {
    /// The posterior of the job whose `result.json` is `path`. Refused (the
    /// message says what is missing) where the file has no polish (a job run
    /// without one), or a fitted parameter has no finite standard error.
    pub fn from_result(path: &Path) -> Result<Self, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read: {e}"))?;
        let file: ResultFile = serde_json::from_str(&text).map_err(|e| {
            format!(
                "not a rigfit result.json with fitted parameters ({e}); the calibration's \
                 uncertainty needs the result of `rigfit run`"
            )
        })?;
        let Some(polish) = file.polish else {
            return Err(
                "the result has no polish (no covariance): run the job with its \
                        polish to carry its uncertainty"
                    .into(),
            );
        };
        let n = polish.genes.len();
        if n == 0 {
            return Err("the result has no fitted parameter".into());
        }
        if polish.correlation.len() != n || polish.correlation.iter().any(|r| r.len() != n) {
            return Err(format!(
                "polish.correlation is not {n} × {n}, the count of polish.genes"
            ));
        }
        let mut values = Vec::with_capacity(n);
        let mut log = Vec::with_capacity(n);
        let mut bounds = Vec::with_capacity(n);
        let mut scaled_error = Vec::with_capacity(n);
        for name in &polish.genes {
            let p = file
                .parameters
                .iter()
                .find(|p| &p.name == name && p.free)
                .ok_or_else(|| format!("fitted parameter '{name}' missing from parameters"))?;
            let value = p
                .value
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("fitted parameter '{name}' has no finite value"))?;
            let is_log = p.scale.as_deref() == Some("log");
            let se = match (p.std_error, p.determined) {
                (Some(se), Some(true) | None) if se.is_finite() && se >= 0.0 => se,
                _ => {
                    return Err(format!(
                        "fitted parameter '{name}' is not determined by the data (no finite \
                         interval in the result): its draws would be unbounded; fix it or \
                         calibrate it with a record that determines it"
                    ));
                }
            };
            let se = if is_log { se / value.abs() } else { se };
            values.push(value);
            log.push(is_log);
            bounds.push(p.bounds.unwrap_or([f64::NEG_INFINITY, f64::INFINITY]));
            scaled_error.push(se);
        }
        let mut covariance = DMatrix::zeros(n, n);
        for i in 0..n {
            for j in 0..n {
                let r = polish.correlation[i][j].ok_or_else(|| {
                    format!(
                        "the correlation of '{}' and '{}' is undefined (a parameter the data \
                         do not determine)",
                        polish.genes[i], polish.genes[j]
                    )
                })?;
                covariance[(i, j)] = scaled_error[i] * scaled_error[j] * r;
            }
        }
        Ok(Self {
            names: polish.genes,
            values,
            log,
            bounds,
            covariance,
        })
    }

    /// The marginal posterior of the parameters not named in `set` (those a
    /// design sets).
    pub fn without(&self, set: &[String]) -> Self {
        let keep: Vec<usize> = (0..self.names.len())
            .filter(|&i| !set.contains(&self.names[i]))
            .collect();
        let pick = |v: &[f64]| keep.iter().map(|&i| v[i]).collect::<Vec<_>>();
        Self {
            names: keep.iter().map(|&i| self.names[i].clone()).collect(),
            values: pick(&self.values),
            log: keep.iter().map(|&i| self.log[i]).collect(),
            bounds: keep.iter().map(|&i| self.bounds[i]).collect(),
            covariance: DMatrix::from_fn(keep.len(), keep.len(), |r, c| {
                self.covariance[(keep[r], keep[c])]
            }),
        }
    }

    /// `n` draws of the parameters (in their units, in [`Self::names`]'
    /// order), the same for the same seed. A covariance that is not positive
    /// definite (a parameter with no spread) is factored with a small
    /// diagonal added.
    pub fn draws(&self, n: usize, seed: u64) -> Vec<Vec<f64>> {
        let k = self.names.len();
        if k == 0 {
            return vec![Vec::new(); n];
        }
        let factor = cholesky(&self.covariance);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let scaled: Vec<f64> = (0..k)
            .map(|i| {
                if self.log[i] {
                    self.values[i].abs().ln()
                } else {
                    self.values[i]
                }
            })
            .collect();
        let back = |i: usize, s: f64| -> f64 {
            if self.log[i] {
                self.values[i].signum() * s.exp()
            } else {
                s
            }
        };
        let inside = |i: usize, v: f64| v >= self.bounds[i][0] && v <= self.bounds[i][1];
        (0..n)
            .map(|_| {
                let mut draw = Vec::new();
                for attempt in 0..=REDRAWS {
                    let z: Vec<f64> = (0..k).map(|_| standard_normal(&mut rng)).collect();
                    draw = (0..k)
                        .map(|i| {
                            let s: f64 = (0..=i).map(|j| factor[(i, j)] * z[j]).sum();
                            back(i, scaled[i] + s)
                        })
                        .collect();
                    if (0..k).all(|i| inside(i, draw[i])) {
                        break;
                    }
                    if attempt == REDRAWS {
                        for (i, v) in draw.iter_mut().enumerate() {
                            *v = v.clamp(self.bounds[i][0], self.bounds[i][1]);
                        }
                    }
                }
                draw
            })
            .collect()
    }
}

/// The lower Cholesky factor of `c`, with a diagonal of 1e-12 × the largest
/// variance added (and grown) until it factors.
fn cholesky(c: &DMatrix<f64>) -> DMatrix<f64> {
    let scale = c
        .diagonal()
        .iter()
        .fold(0.0_f64, |m, v| m.max(*v))
        .max(1e-300);
    let mut jitter = 0.0;
    loop {
        let mut m = c.clone();
        for i in 0..m.nrows() {
            m[(i, i)] += jitter;
        }
        if let Some(ch) = m.cholesky() {
            return ch.l();
        }
        jitter = if jitter == 0.0 {
            1e-12 * scale
        } else {
            jitter * 10.0
        };
    }
}

/// A standard normal draw (Box–Muller).
fn standard_normal(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>();
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// The median and the central `level` band (`[lo, hi]` at the `(1 − level)/2`
/// and `(1 + level)/2` quantiles, linear between order statistics) of the
/// finite values; `None` where fewer than two are finite.
pub fn band(values: &[f64], level: f64) -> Option<(f64, f64, f64)> {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.len() < 2 {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let q = |p: f64| {
        let h = p * (v.len() - 1) as f64;
        let i = h.floor() as usize;
        let f = h - i as f64;
        if i + 1 < v.len() {
            v[i] + f * (v[i + 1] - v[i])
        } else {
            v[i]
        }
    };
    Some((q(0.5), q((1.0 - level) / 2.0), q((1.0 + level) / 2.0)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn posterior() -> Posterior {
        let se = [0.1, 2.0];
        let r = 0.6;
        Posterior {
            names: vec!["k".into(), "c".into()],
            values: vec![100.0, 10.0],
            log: vec![true, false],
            bounds: vec![[1.0, 1e4], [0.0, 100.0]],
            covariance: DMatrix::from_row_slice(
                2,
                2,
                &[
                    se[0] * se[0],
                    r * se[0] * se[1],
                    r * se[0] * se[1],
                    se[1] * se[1],
                ],
            ),
        }
    }

    #[test]
    fn draws_have_the_covariance_in_scale_space() {
        let p = posterior();
        let d = p.draws(40_000, 3);
        let a: Vec<f64> = d.iter().map(|x| x[0].ln()).collect();
        let b: Vec<f64> = d.iter().map(|x| x[1]).collect();
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let (ma, mb) = (mean(&a), mean(&b));
        let cov = |x: &[f64], mx: f64, y: &[f64], my: f64| {
            x.iter()
                .zip(y)
                .map(|(x, y)| (x - mx) * (y - my))
                .sum::<f64>()
                / x.len() as f64
        };
        assert!((ma - 100f64.ln()).abs() < 3e-3, "{ma}");
        assert!((mb - 10.0).abs() < 0.05, "{mb}");
        assert!((cov(&a, ma, &a, ma).sqrt() - 0.1).abs() < 2e-3);
        assert!((cov(&b, mb, &b, mb).sqrt() - 2.0).abs() < 0.04);
        let rho = cov(&a, ma, &b, mb) / (0.1 * 2.0);
        assert!((rho - 0.6).abs() < 0.02, "{rho}");
        assert_eq!(d, p.draws(40_000, 3), "the same seed, the same draws");
        assert_ne!(d[..10], p.draws(10, 4)[..]);
    }

    #[test]
    fn draws_stay_in_bounds_and_marginals_drop_the_design() {
        let mut p = posterior();
        p.bounds[1] = [9.5, 10.5];
        assert!(
            p.draws(2000, 1)
                .iter()
                .all(|x| (9.5..=10.5).contains(&x[1]))
        );
        let m = p.without(&["k".to_string()]);
        assert_eq!(m.names, vec!["c".to_string()]);
        assert_eq!(m.covariance[(0, 0)], 4.0);
    }

    #[test]
    fn band_is_the_median_and_central_quantiles() {
        let v: Vec<f64> = (0..=100).map(f64::from).collect();
        let (m, lo, hi) = band(&v, 0.95).expect("a band");
        for (found, exact) in [(m, 50.0), (lo, 2.5), (hi, 97.5)] {
            assert!((found - exact).abs() < 1e-12, "{found} against {exact}");
        }
        assert_eq!(band(&[1.0, f64::NAN], 0.95), None);
    }
}
