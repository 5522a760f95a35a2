//! Pre-calibration and identification on arrays: `ringdown`,
//! `fit_specimen`, `frf`, `rfs`, `idim` and `nimiso`, the functions `rigfit
//! ringdown`, `fit-specimen` and `identify ...` call, returning the report
//! their `--json` prints (as JSON text the Python layer parses). The
//! transmissibility methods and the impedance method are in their own files.

use numpy::PyReadonlyArray1;
use pyo3::prelude::*;

use crate::errors::{self, Kind};
use rigfit::identify::{IdentifyError, ringdown, specimen};

pub fn slice<'a>(x: &'a PyReadonlyArray1<'_, f64>) -> PyResult<&'a [f64]> {
    x.as_slice()
        .map_err(|e| errors::raise(Kind::Data, e.to_string()))
}

/// Three channels of one record.
pub fn three<'a>(r: &'a [PyReadonlyArray1<'_, f64>; 3]) -> PyResult<[&'a [f64]; 3]> {
    Ok([slice(&r[0])?, slice(&r[1])?, slice(&r[2])?])
}

pub fn slices<'a>(
    x: &'a PyReadonlyArray1<'_, f64>,
    y: &'a PyReadonlyArray1<'_, f64>,
) -> PyResult<(&'a [f64], &'a [f64])> {
    let bad = |e: numpy::NotContiguousError| errors::raise(Kind::Data, e.to_string());
    Ok((x.as_slice().map_err(bad)?, y.as_slice().map_err(bad)?))
}

/// The Python exception for an identification error: a bad option is a
/// campaign error, anything else a data error.
pub fn identify_error(e: &IdentifyError) -> PyErr {
    match e {
        IdentifyError::InvalidOption { .. } => errors::raise(Kind::Campaign, errors::chain(e)),
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
            .map_err(|e| identify_error(&e))?;
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
            .map_err(|e| identify_error(&e))?;
        Ok((
            serde_json::json!({ "fit": fit }).to_string(),
            fit.to_campaign_fragment().to_string(),
        ))
    })
}

/// The H1/H2 frequency response of output `y` to input `u` sampled at times
/// `t` (s), its coherence, and a modal fit of `modes` modes (none for 0), as
/// `rigfit identify frf` computes them. Returns the `--json` report, the
/// fragment, and the spectra as (freqs, h1 re, h1 im, h2 re, h2 im,
/// coherence).
#[pyfunction]
#[pyo3(signature = (t, u, y, *, response = "displacement", segment = None, modes = 1,
    f_min = None, f_max = None, min_coherence = 0.8, names = None, fixed = false))]
#[expect(
    clippy::too_many_arguments,
    reason = "the options of rigfit identify frf"
)]
pub fn frf_report(
    py: Python<'_>,
    t: PyReadonlyArray1<'_, f64>,
    u: PyReadonlyArray1<'_, f64>,
    y: PyReadonlyArray1<'_, f64>,
    response: &str,
    segment: Option<usize>,
    modes: usize,
    f_min: Option<f64>,
    f_max: Option<f64>,
    min_coherence: f64,
    names: Option<Vec<String>>,
    fixed: bool,
) -> PyResult<(String, String, [Vec<f64>; 6])> {
    use rigfit::identify::{columns, frf, modal};
    errors::guard(|| {
        let (t, u) = slices(&t, &u)?;
        let y = y
            .as_slice()
            .map_err(|e| errors::raise(Kind::Data, e.to_string()))?;
        let response = match response {
            "displacement" => modal::Response::Displacement,
            "velocity" => modal::Response::Velocity,
            "acceleration" => modal::Response::Acceleration,
            other => {
                return Err(errors::raise(
                    Kind::Campaign,
                    format!(
                        "response={other:?}: expected \"displacement\", \"velocity\" or \"acceleration\""
                    ),
                ));
            }
        };
        let names = names.unwrap_or_else(|| vec!["m".into(), "k".into(), "c".into()]);
        py.allow_threads(|| {
            let fs = 1.0 / columns::sample_interval(t).map_err(|e| identify_error(&e))?;
            let est = frf::estimate(u, y, fs, segment).map_err(|e| identify_error(&e))?;
            let fit = if modes > 0 {
                let opts = modal::ModalOptions {
                    modes,
                    f_min: f_min.unwrap_or(est.settings.resolution_hz),
                    f_max: f_max.unwrap_or(fs / 2.0),
                    response,
                    min_coherence,
                    iterations: 10,
                };
                Some(
                    modal::fit(&est.freqs, &est.h1, &est.coherence, &opts)
                        .map_err(|e| identify_error(&e))?,
                )
            } else {
                None
            };
            let report = serde_json::json!({
                "welch": est.settings, "modal": fit,
                "assumes": fit.as_ref().map(|_| frf::FORCE_INPUT),
            });
            let fragment = match &fit {
                Some(m) => m.to_campaign_fragment(&names, fixed),
                None => serde_json::json!({"params": {}}),
            };
            let spectra = [
                est.freqs.clone(),
                est.h1.iter().map(|h| h.re).collect(),
                est.h1.iter().map(|h| h.im).collect(),
                est.h2.iter().map(|h| h.re).collect(),
                est.h2.iter().map(|h| h.im).collect(),
                est.coherence.clone(),
            ];
            Ok((report.to_string(), fragment.to_string(), spectra))
        })
    })
}

/// The restoring-force surface of a single-degree-of-freedom record
/// (displacement `x`, acceleration `accel` at times `t`, the known `mass`)
/// and the direct parameter estimate of `terms` on it, as `rigfit identify
/// rfs` computes them. Terms by the CLI's names (`linear`, `cubic`,
/// `power-stiffness`, `viscous`, `cubic-damping`, `power-damping`,
/// `coulomb`).
#[pyfunction]
#[pyo3(signature = (t, x, accel, *, mass, terms = None, alpha = None, beta = None,
    cutoff = None, filter_order = 4, fixed = false))]
#[expect(
    clippy::too_many_arguments,
    reason = "the options of rigfit identify rfs"
)]
pub fn rfs_report(
    py: Python<'_>,
    t: PyReadonlyArray1<'_, f64>,
    x: PyReadonlyArray1<'_, f64>,
    accel: PyReadonlyArray1<'_, f64>,
    mass: f64,
    terms: Option<Vec<String>>,
    alpha: Option<f64>,
    beta: Option<f64>,
    cutoff: Option<f64>,
    filter_order: usize,
    fixed: bool,
) -> PyResult<(String, String)> {
    use rigfit::identify::dpe::{self, DpeOptions, GridOptions, Term};
    use rigfit::identify::rfs::{self, RfsOptions};
    errors::guard(|| {
        let (t, x) = slices(&t, &x)?;
        let accel = accel
            .as_slice()
            .map_err(|e| errors::raise(Kind::Data, e.to_string()))?;
        let names = terms.unwrap_or_else(|| vec!["linear".into(), "viscous".into()]);
        let terms = names
            .iter()
            .map(|n| {
                Ok(match n.as_str() {
                    "linear" => Term::Linear,
                    "cubic" => Term::Cubic,
                    "power-stiffness" => Term::PowerStiffness,
                    "viscous" => Term::Viscous,
                    "cubic-damping" => Term::CubicDamping,
                    "power-damping" => Term::PowerDamping,
                    "coulomb" => Term::Coulomb,
                    other => {
                        return Err(errors::raise(
                            Kind::Campaign,
                            format!(
                                "terms: {other:?} is not a term; expected linear, cubic, \
                                 power-stiffness, viscous, cubic-damping, power-damping or coulomb"
                            ),
                        ));
                    }
                })
            })
            .collect::<PyResult<Vec<Term>>>()?;
        let options = RfsOptions {
            mass,
            cutoff_hz: cutoff,
            filter_order,
        };
        let opts = DpeOptions {
            terms,
            alpha,
            beta,
            grid: GridOptions::default(),
        };
        py.allow_threads(|| {
            let surface = rfs::surface(t, x, accel, &options).map_err(|e| identify_error(&e))?;
            let r = dpe::estimate(&surface, &opts).map_err(|e| identify_error(&e))?;
            Ok((
                serde_json::json!({ "dpe": r }).to_string(),
                r.to_campaign_fragment(fixed, &opts.grid).to_string(),
            ))
        })
    })
}

/// The inverse-model least squares of `rigfit identify idim`: mass, viscous
/// and Coulomb friction and offset from a position `q` (m) and a force
/// `force` (its unit times `gain` in N) sampled at `sample_rate` (Hz), or at
/// the times `t` (s).
#[pyfunction]
#[pyo3(signature = (q, force, *, sample_rate = None, t = None, gain = 1.0, cutoff = 100.0,
    filter_order = 4, decimation = 10, fixed = false))]
#[expect(
    clippy::too_many_arguments,
    reason = "the options of rigfit identify idim"
)]
pub fn idim_report(
    py: Python<'_>,
    q: PyReadonlyArray1<'_, f64>,
    force: PyReadonlyArray1<'_, f64>,
    sample_rate: Option<f64>,
    t: Option<PyReadonlyArray1<'_, f64>>,
    gain: f64,
    cutoff: f64,
    filter_order: usize,
    decimation: usize,
    fixed: bool,
) -> PyResult<(String, String)> {
    use rigfit::identify::{columns, idim};
    errors::guard(|| {
        let (q, force) = slices(&q, &force)?;
        let tau: Vec<f64> = force.iter().map(|v| gain * v).collect();
        let fs = match (&t, sample_rate) {
            (Some(t), None) => {
                let t = t
                    .as_slice()
                    .map_err(|e| errors::raise(Kind::Data, e.to_string()))?;
                1.0 / columns::sample_interval(t).map_err(|e| identify_error(&e))?
            }
            (None, Some(fs)) => fs,
            _ => {
                return Err(errors::raise(
                    Kind::Campaign,
                    "give the sample rate (sample_rate=) or the times (t=), one of them",
                ));
            }
        };
        let opts = idim::IdimOptions {
            sample_rate_hz: fs,
            cutoff_hz: cutoff,
            filter_order,
            decimation,
            border: 49,
        };
        let r = py
            .allow_threads(|| idim::estimate(q, &tau, &opts))
            .map_err(|e| identify_error(&e))?;
        Ok((
            serde_json::json!({ "idim": r }).to_string(),
            r.to_campaign_fragment(fixed).to_string(),
        ))
    })
}

/// The reverse-path nonlinear MISO analysis of `rigfit identify nimiso`:
/// motion `x` (m) and force `f` (N) at times `t` (s), the nonlinearity
/// (`cubic`, `sign-velocity`, `quadratic-damping`) and the fitted band
/// `f_min`..`f_max` (Hz).
#[pyfunction]
#[pyo3(signature = (t, x, f, *, f_min, f_max, nonlinear = "cubic", segment = None, fixed = false))]
#[expect(
    clippy::too_many_arguments,
    reason = "the options of rigfit identify nimiso"
)]
pub fn nimiso_report(
    py: Python<'_>,
    t: PyReadonlyArray1<'_, f64>,
    x: PyReadonlyArray1<'_, f64>,
    f: PyReadonlyArray1<'_, f64>,
    f_min: f64,
    f_max: f64,
    nonlinear: &str,
    segment: Option<usize>,
    fixed: bool,
) -> PyResult<(String, String)> {
    use rigfit::identify::{columns, nimiso};
    errors::guard(|| {
        let (t, x) = slices(&t, &x)?;
        let f = f
            .as_slice()
            .map_err(|e| errors::raise(Kind::Data, e.to_string()))?;
        let (nonlinearity, name) = match nonlinear {
            "cubic" => (nimiso::Nonlinearity::Cubic, "k3"),
            "sign-velocity" => (nimiso::Nonlinearity::SignVelocity, "f_c"),
            "quadratic-damping" => (nimiso::Nonlinearity::QuadraticDamping, "c2"),
            other => {
                return Err(errors::raise(
                    Kind::Campaign,
                    format!(
                        "nonlinear={other:?}: expected \"cubic\", \"sign-velocity\" or \
                         \"quadratic-damping\""
                    ),
                ));
            }
        };
        py.allow_threads(|| {
            let fs = 1.0 / columns::sample_interval(t).map_err(|e| identify_error(&e))?;
            let opts = nimiso::NimisoOptions {
                sample_rate_hz: fs,
                segment_len: segment,
                nonlinearity,
                f_min,
                f_max,
            };
            let (_, r) = nimiso::analyse(x, f, &opts).map_err(|e| identify_error(&e))?;
            Ok((
                serde_json::json!({ "nimiso": r }).to_string(),
                r.to_campaign_fragment(name, fixed).to_string(),
            ))
        })
    })
}
