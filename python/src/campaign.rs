//! `rigfit._rigfit.Campaign`: a campaign loaded and validated by the library,
//! as `rigfit check` validates it, with records lent from memory.

use std::path::PathBuf;
use std::sync::Arc;

use pyo3::prelude::*;
use pyo3::types::PyBytes;
use serde_json::json;

use crate::errors::{self, Kind};
use rigfit::campaign::Campaign;

/// A validated campaign (immutable; `set_data` builds a new one).
#[pyclass(module = "rigfit._rigfit", name = "Campaign", frozen)]
pub struct PyCampaign {
    pub inner: Arc<Campaign>,
}

/// The checks `rigfit check` adds to loading: every expression law finite
/// over the rig's reach at the campaign's bounds.
fn checked(c: Campaign) -> PyResult<PyCampaign> {
    for e in 0..c.problem.experiments.len() {
        let (lo, hi) = c.bounds(e);
        let file = format!("{} (rig {})", c.path.display(), c.model.id());
        rigfit::compile::front::finite::check_laws(&c.model.desc, &file, &[&lo, &hi])
            .map_err(|e| errors::raise(Kind::Campaign, errors::chain(&e)))?;
    }
    Ok(PyCampaign { inner: Arc::new(c) })
}

#[pymethods]
impl PyCampaign {
    /// Reads and validates a campaign file.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        errors::guard(|| {
            let c = py
                .allow_threads(|| Campaign::load(&path))
                .map_err(|e| errors::campaign(&e))?;
            checked(c)
        })
    }

    /// Validates campaign text: relative paths resolve against `base_dir`,
    /// messages name `origin`; `records` (path, CSV bytes) are read in place
    /// of the files at those paths.
    #[staticmethod]
    #[pyo3(signature = (json, base_dir, origin, records = Vec::new()))]
    fn from_text(
        py: Python<'_>,
        json: &str,
        base_dir: PathBuf,
        origin: &str,
        records: Vec<(PathBuf, Bound<'_, PyBytes>)>,
    ) -> PyResult<Self> {
        errors::guard(|| {
            let lent: Vec<(PathBuf, Vec<u8>)> = records
                .iter()
                .map(|(p, b)| (p.clone(), b.as_bytes().to_vec()))
                .collect();
            let c = py
                .allow_threads(|| {
                    rigfit::base::records::with_records(&lent, || {
                        Campaign::from_str(json, &base_dir, origin)
                    })
                })
                .map_err(|e| errors::campaign(&e))?;
            checked(c)
        })
    }

    /// The campaign's text as it was validated.
    #[getter]
    fn raw_json(&self) -> String {
        self.inner.raw_json.clone()
    }

    /// Everything the Python layer shows, as JSON text.
    fn info(&self) -> String {
        let c = &*self.inner;
        let model = &c.model;
        let experiments: Vec<_> = c
            .problem
            .experiments
            .iter()
            .enumerate()
            .map(|(e, x)| {
                json!({
                    "name": x.name, "samples": x.window.end, "dt": x.dt, "t_first": x.t_first,
                    "fit_window": [x.window.start, x.window.end], "weight": x.weight,
                    "values": c.base[e], "offset": c.base_offsets[e],
                })
            })
            .collect();
        let genes: Vec<_> = c
            .genes
            .iter()
            .map(|g| {
                json!({
                    "name": g.name, "lower": g.lower, "upper": g.upper,
                    "scale": format!("{:?}", g.scale).to_lowercase(), "init": g.init,
                    "unit": g.unit,
                    "experiment": g.experiment.map(|e| c.experiment_names()[e].to_string()),
                })
            })
            .collect();
        let params: Vec<_> = model
            .params()
            .iter()
            .map(|p| json!({"name": p.name, "unit": p.unit, "doc": p.doc, "default": p.default}))
            .collect();
        json!({
            "name": c.name, "description": c.description, "rig": model.id(),
            "path": c.path, "inputs": c.inputs, "experiments": experiments, "genes": genes,
            "params": params, "outputs": model.output_names(), "warnings": c.warnings,
            "substeps": c.solver.substeps, "search_given": c.search_given,
            "population": c.search.population, "generations": c.search.generations,
            "seed": c.search.seed, "method": c.search.method.name(), "output": c.output,
        })
        .to_string()
    }
}

/// CSV text of named columns (the header, then one row per sample), each
/// number written so that it reads back as the same bits.
#[pyfunction]
pub fn record_csv<'py>(
    py: Python<'py>,
    names: Vec<String>,
    columns: Vec<numpy::PyReadonlyArray1<'py, f64>>,
) -> PyResult<Bound<'py, PyBytes>> {
    use std::fmt::Write as _;
    let cols: Vec<&[f64]> = columns
        .iter()
        .map(|c| c.as_slice())
        .collect::<Result<_, _>>()
        .map_err(|e| errors::raise(Kind::Data, e.to_string()))?;
    let n = cols.first().map_or(0, |c| c.len());
    if names.len() != cols.len() || cols.iter().any(|c| c.len() != n) {
        return Err(errors::raise(
            Kind::Data,
            "expected one name per column and columns of one length",
        ));
    }
    let mut s = String::with_capacity(n * cols.len() * 16);
    s.push_str(&names.join(","));
    s.push('\n');
    for k in 0..n {
        for (j, c) in cols.iter().enumerate() {
            if j > 0 {
                s.push(',');
            }
            let _ = write!(s, "{:e}", c[k]);
        }
        s.push('\n');
    }
    Ok(PyBytes::new(py, s.as_bytes()))
}

/// The shipped rigs: (id, the rig file's JSON text), as a campaign's `"rig"`
/// names them.
#[pyfunction]
pub fn shipped_rigs() -> Vec<(&'static str, &'static str)> {
    rigfit::rig::SHIPPED.to_vec()
}
