//! The impedance method on arrays: `rigfit identify impedance`, the 2 × 2
//! impedance and receptance matrices of a point mass from an impact in x and
//! one in y, with K, C and M fitted, returning the report its `--json`
//! prints and the fragment (as JSON text).

use numpy::PyReadonlyArray1;
use pyo3::prelude::*;

use crate::errors;
use crate::identify::{identify_error, slice, three};
use rigfit::identify::columns;
use rigfit::identify::impedance::{self, ImpactRecord};

/// K, C and M (unless `mass`, kg, is given) fitted over `f_min`..`f_max`
/// (Hz) to the matrices of the impacts `x_impact` and `y_impact`, each
/// (hammer force in N, x and y displacement in m) sampled at times `t` (s).
#[pyfunction]
#[pyo3(signature = (t, x_impact, y_impact, *, f_min, f_max, mass = None, fixed = false))]
#[expect(
    clippy::too_many_arguments,
    reason = "the options of rigfit identify impedance"
)]
pub fn impedance_report(
    py: Python<'_>,
    t: PyReadonlyArray1<'_, f64>,
    x_impact: [PyReadonlyArray1<'_, f64>; 3],
    y_impact: [PyReadonlyArray1<'_, f64>; 3],
    f_min: f64,
    f_max: f64,
    mass: Option<f64>,
    fixed: bool,
) -> PyResult<(String, String)> {
    errors::guard(|| {
        let t = slice(&t)?;
        let ([f1, x1, y1], [f2, x2, y2]) = (three(&x_impact)?, three(&y_impact)?);
        let x_impact = ImpactRecord {
            force: f1,
            x: x1,
            y: y1,
        };
        let y_impact = ImpactRecord {
            force: f2,
            x: x2,
            y: y2,
        };
        py.allow_threads(|| {
            let fs = 1.0 / columns::sample_interval(t).map_err(|e| identify_error(&e))?;
            let m = impedance::matrices(x_impact, y_impact, fs).map_err(|e| identify_error(&e))?;
            let fit = impedance::fit(&m, (f_min, f_max), mass).map_err(|e| identify_error(&e))?;
            Ok((
                serde_json::json!({"impedance": fit}).to_string(),
                fit.to_campaign_fragment(fixed).to_string(),
            ))
        })
    })
}
