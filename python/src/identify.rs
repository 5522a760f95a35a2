//! Pre-calibration on arrays: `ringdown` and `fit_specimen`, the functions
//! `rigfit ringdown` and `rigfit fit-specimen` call, returning the report
//! their `--json` prints (as JSON text the Python layer parses).

use numpy::PyReadonlyArray1;
use pyo3::prelude::*;

use crate::errors::{self, Kind};
use rigfit::identify::{PrecalError, ringdown, specimen};

fn slices<'a>(
    x: &'a PyReadonlyArray1<'_, f64>,
    y: &'a PyReadonlyArray1<'_, f64>,
) -> PyResult<(&'a [f64], &'a [f64])> {
    let bad = |e: numpy::NotContiguousError| errors::raise(Kind::Data, e.to_string());
    Ok((x.as_slice().map_err(bad)?, y.as_slice().map_err(bad)?))
}

fn precal(e: &PrecalError) -> PyErr {
    match e {
        PrecalError::InvalidOption { .. } => errors::raise(Kind::Campaign, errors::chain(e)),
        _ => errors::raise(Kind::Data, errors::chain(e)),
    }
}

/// Frequency and damping of a free ring-down `f` at times `t` (s); with the
/// load cell's mass `m1` (kg) or stiffness `k1` (N/m) also the other and
/// the post-fracture damping. `start`: the ring's start time (s; default:
/// found).
#[pyfunction]
#[pyo3(signature = (t, f, *, m1 = None, k1 = None, start = None))]
pub fn ringdown_report(
    py: Python<'_>,
    t: PyReadonlyArray1<'_, f64>,
    f: PyReadonlyArray1<'_, f64>,
    m1: Option<f64>,
    k1: Option<f64>,
    start: Option<f64>,
) -> PyResult<(String, String)> {
    errors::guard(|| {
        let (t, f) = slices(&t, &f)?;
        let opts = ringdown::RingdownOptions {
            m1,
            k1,
            start,
            ..ringdown::RingdownOptions::default()
        };
        let r = py
            .allow_threads(|| ringdown::analyse(t, f, &opts))
            .map_err(|e| precal(&e))?;
        Ok((
            serde_json::json!({ "ringdown": r }).to_string(),
            r.to_campaign_fragment().to_string(),
        ))
    })
}

/// The specimen law (linear, then a polynomial of `degree`) fitted to
/// quasi-static elongation `e` (m) and force `f` (N).
#[pyfunction]
#[pyo3(signature = (e, f, *, degree = 3))]
pub fn specimen_report(
    py: Python<'_>,
    e: PyReadonlyArray1<'_, f64>,
    f: PyReadonlyArray1<'_, f64>,
    degree: usize,
) -> PyResult<(String, String)> {
    errors::guard(|| {
        let (e, f) = slices(&e, &f)?;
        let opts = specimen::SpecimenFitOptions {
            degree,
            ..specimen::SpecimenFitOptions::default()
        };
        let fit = py
            .allow_threads(|| specimen::fit(e, f, &opts))
            .map_err(|e| precal(&e))?;
        Ok((
            serde_json::json!({ "fit": fit }).to_string(),
            fit.to_campaign_fragment().to_string(),
        ))
    })
}
