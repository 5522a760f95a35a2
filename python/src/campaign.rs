//! `rigfit._rigfit.Campaign`: a campaign loaded and validated by the library,
//! as `rigfit check` validates it, with records lent from memory.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use pyo3::prelude::*;
use pyo3::types::PyBytes;
use serde_json::json;

use crate::errors::{self, Kind};
use crate::record::{Records, Source};
use rigfit::campaign::Campaign;

/// The sample interval (s) of the grid a campaign without its records stands
/// on ([`PyCampaign::pending`]): fine enough that no rig's stability rule
/// asks for more steps than one per sample.
const PENDING_DT: f64 = 1e-9;

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

/// Campaign text validated with `records` read in place of the files at
/// those paths, the GIL released.
fn validated(
    py: Python<'_>,
    json: &str,
    base_dir: &std::path::Path,
    origin: &str,
    records: &[(PathBuf, Source)],
) -> PyResult<PyCampaign> {
    let lent = crate::record::lent(py, records);
    let c = py
        .allow_threads(|| Campaign::from_str_lent(json, base_dir, origin, &lent, None))
        .map_err(|e| errors::campaign(&e))?;
    checked(c)
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
    /// messages name `origin`; `records` (path, a file's bytes or a
    /// `Record`) are read in place of the files at those paths.
    #[staticmethod]
    #[pyo3(signature = (json, base_dir, origin, records = Vec::new()))]
    fn from_text(
        py: Python<'_>,
        json: &str,
        base_dir: PathBuf,
        origin: &str,
        records: Records,
    ) -> PyResult<Self> {
        errors::guard(|| validated(py, json, &base_dir, origin, &records))
    }

    /// `from_text` keeping its records: every data file the text names
    /// (`experiments[].data.file`, `validation[].data.file`) that `records`
    /// does not lend is read once, through the library's reader and its
    /// limits, and lent, so the campaign is built from exactly the bytes
    /// returned: (the campaign, every (path, bytes) it was built from). A
    /// file that cannot be read is left to the library to refuse.
    #[staticmethod]
    #[pyo3(signature = (json, base_dir, origin, records = Vec::new()))]
    fn build(
        py: Python<'_>,
        json: &str,
        base_dir: PathBuf,
        origin: &str,
        records: Records,
    ) -> PyResult<(Self, Records)> {
        errors::guard(|| {
            let kept = kept_records(py, json, &base_dir, records);
            Ok((validated(py, json, &base_dir, origin, &kept)?, kept))
        })
    }

    /// Reads a campaign file (as `load`, its data files resolved against
    /// `base_dir`, the file's own folder) and [`PyCampaign::build`]s it.
    #[staticmethod]
    fn load_kept(py: Python<'_>, path: PathBuf, base_dir: PathBuf) -> PyResult<(Self, Records)> {
        let text = errors::guard(|| {
            rigfit::base::fsutil::read_description(&path).map_err(|e| {
                errors::campaign(&rigfit::campaign::CampaignError::Io {
                    file: path.clone(),
                    message: e.to_string(),
                })
            })
        })?;
        match path.to_str() {
            Some(origin) => Self::build(py, &text, base_dir, origin, Vec::new()),
            // A path that is no text cannot name itself in the messages as
            // `build` does; the library loads it (its records read again
            // where it is rebuilt).
            None => Ok((Self::load(py, path)?, Vec::new())),
        }
    }

    /// Validates campaign text whose records do not all exist yet: no record
    /// is read (each experiment stands on a two-sample grid of zeros, its
    /// drive column a zero force), so only its rig, parameters, genes and
    /// settings are checked; the Python layer refuses to fit or score it.
    #[staticmethod]
    fn pending(py: Python<'_>, json: &str, base_dir: PathBuf, origin: &str) -> PyResult<Self> {
        errors::guard(|| {
            // No experiment is named "" (names are non-empty): every one is
            // a bystander of the grid, its drive column not read.
            let grid = rigfit::campaign::SimulationGrid::Uniform {
                dt: PENDING_DT,
                samples: 2,
                drive_file: None,
                experiment: Some(String::new()),
            };
            let c = py
                .allow_threads(|| Campaign::from_str_for_simulation(json, &base_dir, origin, &grid))
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
            "path": c.path.to_string_lossy(), "inputs": c.inputs.iter().map(|p| p.to_string_lossy()).collect::<Vec<_>>(), "experiments": experiments, "genes": genes,
            "params": params, "outputs": model.output_names(), "warnings": c.warnings,
            "substeps": c.solver.substeps, "search_given": c.search_given,
            "population": c.search.population, "generations": c.search.generations,
            "seed": c.search.seed, "method": c.search.method.name(), "output": c.output,
        })
        .to_string()
    }
}

/// The data files `json` names, resolved against `base_dir`, with their
/// bytes: lent by `records`, else read once (a file that cannot be read is
/// left out, for the library to refuse by its rules). Records `json` does not
/// name are dropped.
fn kept_records(py: Python<'_>, json: &str, base_dir: &Path, records: Records) -> Records {
    let Ok(raw) = serde_json::from_str::<serde_json::Value>(json) else {
        return records;
    };
    let files = ["experiments", "validation"]
        .iter()
        .filter_map(|k| raw.get(*k).and_then(|v| v.as_array()))
        .flatten()
        .filter_map(|x| x.get("data")?.get("file")?.as_str());
    let mut kept: Records = Vec::new();
    for file in files {
        let path = base_dir.join(file);
        if kept.iter().any(|(p, _)| *p == path) {
            continue;
        }
        if let Some((_, b)) = records.iter().find(|(p, _)| *p == path) {
            kept.push((path, b.clone_ref(py)));
            continue;
        }
        let read = py.allow_threads(|| rigfit::base::fsutil::read_record(&path));
        if let Ok(bytes) = read {
            kept.push((path, Source::Bytes(PyBytes::new(py, &bytes).unbind())));
        }
    }
    kept
}

/// The shipped rigs: (id, the rig file's JSON text), as a campaign's `"rig"`
/// names them.
#[pyfunction]
pub fn shipped_rigs() -> Vec<(&'static str, &'static str)> {
    rigfit::rig::SHIPPED.to_vec()
}
