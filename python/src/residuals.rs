//! The campaign's residual vector, for `scipy.optimize.least_squares` and
//! lmfit's `Minimizer`: the polish's own residuals
//! ([`rigfit::job::CampaignCost`] as a [`ResidualCost`]), every experiment's
//! fit window one after the other, each scaled by `√(w_e / (W · SS_tot,e))`,
//! so that their sum of squares is the cost the objective returns.

use std::sync::{Arc, Mutex};

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::campaign::PyCampaign;
use crate::errors::{self, Kind};
use rigfit::campaign::Campaign;
use rigfit::eval::{DIVERGED, Evaluator};
use rigfit::job::CampaignCost;
use rigfit::search::ResidualCost;

/// Residuals of parameter sets, one evaluator opened for every call.
#[pyclass(module = "rigfit._rigfit", frozen)]
pub struct Residuals {
    campaign: Arc<Campaign>,
    evaluator: Mutex<Option<Box<dyn Evaluator>>>,
    threads: usize,
    #[pyo3(get)]
    notes: Vec<String>,
}

/// Residuals in a vector: the fit windows' samples of every experiment.
fn length(c: &Campaign) -> usize {
    c.problem.experiments.iter().map(|x| x.window.len()).sum()
}

/// The residual vector of a run that blew up: every entry
/// `√(DIVERGED / N)`, so that its sum of squares is the objective's
/// [`DIVERGED`] cost, finite as `least_squares` requires.
fn diverged(n: usize) -> Vec<f64> {
    vec![(DIVERGED / n.max(1) as f64).sqrt(); n]
}

#[pymethods]
impl Residuals {
    #[new]
    #[pyo3(signature = (campaign, *, backend = None, precision = None, adapter = None, threads = 0))]
    fn new(
        py: Python<'_>,
        campaign: &PyCampaign,
        backend: Option<&str>,
        precision: Option<&str>,
        adapter: Option<String>,
        threads: usize,
    ) -> PyResult<Self> {
        errors::guard(|| {
            let c = campaign.inner.clone();
            let opened = crate::evaluator::open_named(
                py,
                &c,
                backend,
                precision,
                adapter.as_deref(),
                threads,
            )?;
            Ok(Self {
                campaign: c,
                evaluator: Mutex::new(Some(opened.evaluator)),
                threads,
                notes: opened.notes,
            })
        })
    }

    /// Residuals in a vector (the sum of the fit windows' samples).
    #[getter]
    fn size(&self) -> usize {
        length(&self.campaign)
    }

    /// Residual vectors of the rows of `theta` (S, P), one row each (S, N);
    /// also the notes to warn with (a move to the CPU).
    fn of<'py>(
        &self,
        py: Python<'py>,
        theta: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<(Bound<'py, PyArray2<f64>>, Vec<String>)> {
        errors::guard(|| {
            let c = &*self.campaign;
            let n = length(c);
            let s = theta.shape()[0];
            let bytes = (s as f64) * (n as f64) * 8.0;
            if let Some(free) = rigfit::job::memory::available_memory()
                && bytes > free
            {
                return Err(errors::raise(
                    Kind::Campaign,
                    format!(
                        "theta: {s} parameter set(s) of {n} residuals each need {:.1} GB, more \
                         than the {:.1} GB available now; pass fewer rows at a time",
                        bytes / 1e9,
                        free / 1e9
                    ),
                ));
            }
            let sets = crate::ensemble::genomes(c, theta.as_array())?;
            let (out, notes) = py.allow_threads(|| -> PyResult<_> {
                let mut slot = self
                    .evaluator
                    .lock()
                    .map_err(|_| errors::raise(Kind::Error, "the evaluator failed earlier"))?;
                let evaluator = slot
                    .take()
                    .ok_or_else(|| errors::raise(Kind::Error, "the evaluator failed earlier"))?;
                let mut cost = CampaignCost::new(c, evaluator, false, self.threads);
                let rows = cost.residuals(&sets);
                let notes: Vec<String> = cost.fallback_note().into_iter().collect();
                *slot = Some(cost.into_evaluator());
                let rows = rows.map_err(|e| errors::raise(Kind::Error, errors::chain(&e)))?;
                let mut out = Array2::<f64>::zeros((sets.len(), n));
                for (i, row) in rows.into_iter().enumerate() {
                    let row = row.filter(|r| r.len() == n && r.iter().all(|v| v.is_finite()));
                    let row = row.unwrap_or_else(|| diverged(n));
                    for (k, v) in row.into_iter().enumerate() {
                        out[[i, k]] = v;
                    }
                }
                Ok((out, notes))
            })?;
            Ok((out.into_pyarray(py), notes))
        })
    }
}
