//! `rigfit._rigfit`: the compiled half of the `rigfit` Python package. It
//! binds the library (campaigns, the job, the evaluators, identification);
//! the pure-Python half (`python/rigfit/`) gives it lmfit- and SciPy-shaped
//! objects.

mod campaign;
mod ensemble;
mod errors;
mod evaluator;
mod fit;
mod fitted;
mod grid;
mod identify;
mod impedance;
mod memory;
mod record;
mod report;
mod residuals;
mod save;
mod sim_memory;
mod sweep;
mod transmissibility;

use pyo3::prelude::*;

#[pymodule]
fn _rigfit(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // NumPy's C API is looked up on first use by running Python code; done
    // later (a job's first array, as it ends) a Ctrl-C landing in that code
    // failed the lookup, which rust-numpy treats as a bug. Done here, once.
    numpy::PyArray1::<f64>::zeros(m.py(), [0], false);
    m.add_class::<campaign::PyCampaign>()?;
    m.add_class::<ensemble::Objective>()?;
    m.add_class::<residuals::Residuals>()?;
    m.add_class::<record::PyRecord>()?;
    m.add_function(wrap_pyfunction!(record::record_of, m)?)?;
    m.add_function(wrap_pyfunction!(campaign::shipped_rigs, m)?)?;
    m.add_function(wrap_pyfunction!(fit::run_job, m)?)?;
    m.add_function(wrap_pyfunction!(ensemble::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(grid::simulate_grid, m)?)?;
    m.add_function(wrap_pyfunction!(identify::ringdown_report, m)?)?;
    m.add_function(wrap_pyfunction!(identify::specimen_report, m)?)?;
    m.add_function(wrap_pyfunction!(identify::frf_report, m)?)?;
    m.add_function(wrap_pyfunction!(identify::rfs_report, m)?)?;
    m.add_function(wrap_pyfunction!(identify::idim_report, m)?)?;
    m.add_function(wrap_pyfunction!(identify::nimiso_report, m)?)?;
    m.add_function(wrap_pyfunction!(transmissibility::arx_report, m)?)?;
    m.add_function(wrap_pyfunction!(transmissibility::sensitivity_report, m)?)?;
    m.add_function(wrap_pyfunction!(impedance::impedance_report, m)?)?;
    m.add_function(wrap_pyfunction!(report::report_html, m)?)?;
    m.add_function(wrap_pyfunction!(save::save_result, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep, m)?)?;
    Ok(())
}
