//! The transmissibility methods on arrays: `rigfit identify arx` (the element
//! between two measured points, and the ARX lines) and `rigfit identify
//! sensitivity` (a quarter car's strut stiffness change), returning the
//! report their `--json` prints and the fragment (as JSON text).

use numpy::PyReadonlyArray1;
use pyo3::prelude::*;

use crate::errors::{self, Kind};
use crate::identify::{identify_error, slice, three};
use rigfit::identify::columns;
use rigfit::identify::transmissibility::{self as tr, ArxForm};

/// The transmissibility of the response channels `ys` (the node across the
/// element first, then every node it carries, with their `mass`es in kg) to
/// the reference `u` at times `t` (s), the element's stiffness and damping
/// fitted over `f_min`..`f_max` (Hz), and the ARX lines of `form`, as
/// `rigfit identify arx` computes them. Returns the `--json` report, the
/// fragment, and the spectra: the line frequencies, the transmissibilities'
/// real and imaginary parts and the coherences, by channel.
#[pyfunction]
#[pyo3(signature = (t, u, ys, *, mass, f_min, f_max, names = None, form = "linear",
    segment = None, min_coherence = 0.9, fixed = false))]
#[expect(
    clippy::too_many_arguments,
    reason = "the options of rigfit identify arx"
)]
pub fn arx_report(
    py: Python<'_>,
    t: PyReadonlyArray1<'_, f64>,
    u: PyReadonlyArray1<'_, f64>,
    ys: Vec<PyReadonlyArray1<'_, f64>>,
    mass: Vec<f64>,
    f_min: f64,
    f_max: f64,
    names: Option<Vec<String>>,
    form: &str,
    segment: Option<usize>,
    min_coherence: f64,
    fixed: bool,
) -> PyResult<(String, String, ArxSpectra)> {
    errors::guard(|| {
        let names = names.unwrap_or_else(|| vec!["k2".into(), "c2".into()]);
        if names.len() != 2 {
            return Err(errors::raise(
                Kind::Campaign,
                format!(
                    "names takes the stiffness and the damping name, found {}",
                    names.len()
                ),
            ));
        }
        let form = match form {
            "linear" => ArxForm::Linear,
            "cubic" => ArxForm::Cubic,
            other => {
                return Err(errors::raise(
                    Kind::Campaign,
                    format!("form={other:?}: expected \"linear\" or \"cubic\""),
                ));
            }
        };
        let (t, u) = (slice(&t)?, slice(&u)?);
        let ys = ys.iter().map(slice).collect::<PyResult<Vec<&[f64]>>>()?;
        py.allow_threads(|| {
            let fs = 1.0 / columns::sample_interval(t).map_err(|e| identify_error(&e))?;
            let spec = tr::block_spectra(u, &ys, fs, segment).map_err(|e| identify_error(&e))?;
            let (ts, coherences): (Vec<_>, Vec<_>) =
                (0..ys.len()).map(|c| spec.transmissibility(c)).unzip();
            let band = (f_min, f_max);
            let lines = tr::arx(&spec, form, band.0, band.1).map_err(|e| identify_error(&e))?;
            let fit = tr::element_fit(&spec.freqs, &ts, &coherences[0], &mass, band, min_coherence)
                .map_err(|e| identify_error(&e))?;
            let report = serde_json::json!({"welch": spec.settings, "element": fit, "arx": lines});
            let fragment = fit.to_campaign_fragment([&names[0], &names[1]], fixed);
            let spectra = ArxSpectra {
                freqs: spec.freqs.clone(),
                re: ts
                    .iter()
                    .map(|t| t.iter().map(|h| h.re).collect())
                    .collect(),
                im: ts
                    .iter()
                    .map(|t| t.iter().map(|h| h.im).collect())
                    .collect(),
                coherence: coherences,
            };
            Ok((report.to_string(), fragment.to_string(), spectra))
        })
    })
}

/// The transmissibilities of `arx_report`, by channel then line.
#[derive(IntoPyObject)]
pub struct ArxSpectra {
    freqs: Vec<f64>,
    re: Vec<Vec<f64>>,
    im: Vec<Vec<f64>>,
    coherence: Vec<Vec<f64>>,
}

/// The change of a quarter car's strut stiffness between the records `base`
/// and `changed`, each (wheel pan, unsprung mass, sprung mass) sampled at
/// times `t` (s), from the tire's `k1` (N/m) and `c1` (N·s/m), averaged over
/// `f_min`..`f_max` (Hz), as `rigfit identify sensitivity` computes it.
/// Returns the `--json` report and the fragment (`name` after the change,
/// when `base_value` gives it before).
#[pyfunction]
#[pyo3(signature = (t, base, changed, *, k1, f_min, f_max, c1 = 0.0, segment = None,
    name = "k2", base_value = None, fixed = false))]
#[expect(
    clippy::too_many_arguments,
    reason = "the options of rigfit identify sensitivity"
)]
pub fn sensitivity_report(
    py: Python<'_>,
    t: PyReadonlyArray1<'_, f64>,
    base: [PyReadonlyArray1<'_, f64>; 3],
    changed: [PyReadonlyArray1<'_, f64>; 3],
    k1: f64,
    f_min: f64,
    f_max: f64,
    c1: f64,
    segment: Option<usize>,
    name: &str,
    base_value: Option<f64>,
    fixed: bool,
) -> PyResult<(String, String)> {
    errors::guard(|| {
        let t = slice(&t)?;
        let (base, changed) = (three(&base)?, three(&changed)?);
        py.allow_threads(|| {
            let fs = 1.0 / columns::sample_interval(t).map_err(|e| identify_error(&e))?;
            let spectra = |[u, y1, y2]: [&[f64]; 3]| {
                tr::block_spectra(u, &[y1, y2], fs, segment).map_err(|e| identify_error(&e))
            };
            let (base, changed) = (spectra(base)?, spectra(changed)?);
            let r = tr::strut_sensitivity(&base, &changed, k1, c1, (f_min, f_max))
                .map_err(|e| identify_error(&e))?;
            Ok((
                serde_json::json!({"welch": base.settings, "sensitivity": r}).to_string(),
                r.to_campaign_fragment(name, base_value, fixed).to_string(),
            ))
        })
    })
}
