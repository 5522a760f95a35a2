//! Linear least squares with standard errors, shared by the identification
//! tools.
//!
//! The columns are scaled to unit norm before the solve (the coefficients of
//! *A New Fatigue Testing Rig Based on Inertial Forces* span 10² to 10¹³), the scaled
//! problem is solved by SVD (nalgebra), and the coefficients are unscaled. Standard
//! errors come from
//! `σ̂²·(AᵀA)⁻¹` with `σ̂² = SSE / (n − p)`, i.e. white, equal-variance residuals.

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use super::{IdentifyError, r_squared, require_points};

/// A least-squares fit `y ≈ Σ θ_j·column_j`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LinearFit {
    /// The coefficients `θ_j` with their standard errors, in the order of
    /// the columns.
    pub coefficients: Vec<Coefficient>,
    /// Sum of squared residuals.
    pub sse: f64,
    /// Root-mean-square residual.
    pub rms: f64,
    /// Coefficient of determination of the fit.
    pub r2: f64,
    /// Rows used.
    pub rows: usize,
    /// Ratio of the largest to the smallest singular value of the scaled matrix.
    pub condition: f64,
}

/// One coefficient `θ_j` of a [`LinearFit`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Coefficient {
    /// The estimate.
    pub value: f64,
    /// Its standard error.
    pub std_error: f64,
}

impl Coefficient {
    /// Standard error relative to the coefficient's magnitude.
    pub fn relative_error(&self) -> f64 {
        self.std_error / self.value.abs()
    }
}

/// Solves `min Σ (y − Σ θ_j c_j)²` over the rows.
///
/// # Errors
/// [`IdentifyError::LengthMismatch`] for a column of the wrong length,
/// [`IdentifyError::TooFewPoints`] for no more rows than columns, and
/// [`IdentifyError::Numerical`] when a column is zero or the columns are
/// dependent.
pub fn least_squares(columns: &[Vec<f64>], y: &[f64]) -> Result<LinearFit, IdentifyError> {
    let n = y.len();
    let p = columns.len();
    if let Some(c) = columns.iter().find(|c| c.len() != n) {
        return Err(IdentifyError::LengthMismatch {
            what: "regressor column",
            x_len: c.len(),
            y_len: n,
        });
    }
    require_points("rows for the least-squares fit", p + 1, n)?;
    let norms: Vec<f64> = columns
        .iter()
        .map(|c| c.iter().map(|v| v * v).sum::<f64>().sqrt())
        .collect();
    if let Some(j) = norms.iter().position(|&s| !(s > 0.0 && s.is_finite())) {
        return Err(IdentifyError::Numerical {
            stage: "least squares",
            reason: format!("regressor {} is zero or not finite", j + 1),
        });
    }
    if y.iter().all(|v| *v == 0.0) || y.iter().any(|v| !v.is_finite()) {
        return Err(IdentifyError::Numerical {
            stage: "least squares",
            reason: "the fitted quantity is zero at every row, or not finite: nothing to fit"
                .into(),
        });
    }
    let a = DMatrix::from_fn(n, p, |i, j| columns[j][i] / norms[j]);
    let b = DVector::from_column_slice(y);
    let svd = a.clone().svd(true, true);
    let s_max = svd.singular_values.max();
    let s_min = svd.singular_values.min();
    if s_min.is_nan() || s_min <= 1e-13 * s_max {
        return Err(IdentifyError::Numerical {
            stage: "least squares",
            reason: format!(
                "the regressors are linearly dependent (singular values {s_max:e} … {s_min:e})"
            ),
        });
    }
    let theta = svd
        .solve(&b, 0.0)
        .map_err(|reason| IdentifyError::Numerical {
            stage: "least squares",
            reason: reason.to_string(),
        })?;
    let resid = &b - &a * &theta;
    let sse = resid.norm_squared();
    let sigma2 = sse / (n - p) as f64;
    let v_t = svd.v_t.as_ref().expect("SVD with V requested");
    let coefficients = (0..p)
        .map(|j| {
            let var: f64 = (0..p)
                .map(|k| (v_t[(k, j)] / svd.singular_values[k]).powi(2))
                .sum();
            Coefficient {
                value: theta[j] / norms[j],
                std_error: (sigma2 * var).sqrt() / norms[j],
            }
        })
        .collect();
    let fit = LinearFit {
        coefficients,
        sse,
        rms: (sse / n as f64).sqrt(),
        r2: r_squared(sse, y),
        rows: n,
        condition: s_max / s_min,
    };
    // A result that is not a finite number is no result: refused, never
    // reported or written into a campaign fragment.
    let values = fit.coefficients.iter().map(|c| c.value);
    let numbers = values.chain(fit.coefficients.iter().map(|c| c.std_error));
    if let Some(bad) = numbers.chain([fit.sse, fit.r2]).find(|v| !v.is_finite()) {
        return Err(IdentifyError::Numerical {
            stage: "least squares",
            reason: format!("the fit is not finite ({bad} among its results)"),
        });
    }
    Ok(fit)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_a_line_with_its_textbook_standard_errors() {
        let x: Vec<f64> = (0..10).map(f64::from).collect();
        let noise = [0.1, -0.2, 0.05, 0.0, 0.15, -0.1, -0.05, 0.2, -0.15, 0.0];
        let y: Vec<f64> = x
            .iter()
            .zip(noise)
            .map(|(x, e)| 1e6 * (2.0 + 3.0 * x) + e)
            .collect();
        let fit = least_squares(&[vec![1e6; 10], x.iter().map(|x| 1e6 * x).collect()], &y).unwrap();
        assert!((fit.coefficients[0].value - 2.0).abs() < 1e-6);
        assert!((fit.coefficients[1].value - 3.0).abs() < 1e-7);
        // Closed form for a straight line: se(slope) = σ̂ / sqrt(Σ(x − x̄)²) / 1e6.
        let sxx: f64 = x.iter().map(|x| (x - 4.5f64).powi(2)).sum();
        let se = (fit.sse / 8.0).sqrt() / sxx.sqrt() / 1e6;
        assert!((fit.coefficients[1].std_error - se).abs() < 1e-6 * se);
        assert!(least_squares(&[x.clone(), x.iter().map(|v| 2.0 * v).collect()], &y).is_err());
    }
}
