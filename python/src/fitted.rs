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
    for (exp, fit) in c.problem.experiments.iter().zip(&summary.experiments) {
        let hist = &fit.history;
        let offset = summary
            .params
            .get(&format!("{}.offset", exp.name))
            .copied()
            .unwrap_or(0.0);
        let n = hist.t.len().min(exp.force.len());
        let value = |o: usize, k: usize| {
            hist.outputs
                .get(o)
                .and_then(|h| h.get(k))
                .copied()
                .unwrap_or(f64::NAN)
        };
        let t: Vec<f64> = (0..n).map(|k| exp.t_first + k as f64 * exp.dt).collect();
        let t_model: Vec<f64> = t.iter().map(|t| t + offset).collect();
        let measured = exp.force[..n].to_vec();
        let residual: Vec<f64> = (0..n).map(|k| value(0, k) - exp.force[k]).collect();
        let window: Vec<bool> = (0..n).map(|k| exp.window.contains(&k)).collect();
        let flat: Vec<f64> = (0..n)
            .flat_map(|k| (0..n_out).map(move |o| value(o, k)))
            .collect();
        let model = Array2::from_shape_vec((n, n_out), flat)
            .expect("n × outputs values")
            .into_pyarray(py);
        let d = PyDict::new(py);
        d.set_item("t", t.into_pyarray(py))?;
        d.set_item("t_model", t_model.into_pyarray(py))?;
        d.set_item("measured", measured.into_pyarray(py))?;
        d.set_item("model", model)?;
        d.set_item("residual", residual.into_pyarray(py))?;
        d.set_item("in_fit_window", window.into_pyarray(py))?;
        all.set_item(&fit.name, d)?;
    }
    Ok(all)
}
