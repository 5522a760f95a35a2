//! A finished job's experiments as arrays in full precision: the columns of
//! each `<experiment>.csv` (which carries 7 significant digits) taken from
//! the job's outputs in memory, for `rigfit.FitResult`.

use numpy::IntoPyArray;
use numpy::ndarray::Array2;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use rigfit::campaign::Campaign;
use rigfit::job::JobSummary;

/// Experiment name → `{"t", "t_model", "measured", "model" (samples,
/// outputs), "residual", "in_fit_window"}`, the rows and columns of its CSV.
pub fn arrays<'py>(
    py: Python<'py>,
    c: &Campaign,
    summary: &JobSummary,
) -> PyResult<Bound<'py, PyDict>> {
    let all = PyDict::new(py);
    let n_out = c.model.output_names().len();
    for fit in &summary.experiments {
        let rows = fit.rows.clone();
        let n = rows.t_record.len();
        let flat: Vec<f64> = rows.model.into_iter().flatten().collect();
        let model = Array2::from_shape_vec((n, n_out), flat)
            .map_err(|e| {
                crate::errors::raise(
                    crate::errors::Kind::Error,
                    format!("{}: the model's outputs: {e}", fit.name),
                )
            })?
            .into_pyarray(py);
        let d = PyDict::new(py);
        d.set_item("t", rows.t_record.into_pyarray(py))?;
        d.set_item("t_model", rows.t_model.into_pyarray(py))?;
        d.set_item("measured", rows.measured.into_pyarray(py))?;
        d.set_item("model", model)?;
        d.set_item("residual", rows.residual.into_pyarray(py))?;
        d.set_item("in_fit_window", rows.in_fit_window.into_pyarray(py))?;
        all.set_item(&fit.name, d)?;
    }
    Ok(all)
}
