//! Per-experiment initial states (`experiments[].initial`): a run that starts
//! in motion.
//!
//! Each state named in an experiment's `"initial"` becomes an
//! experiment-scope parameter of the compiled rig, `initial_<state>` (default
//! 0), which the lowering reads as that state's initial value
//! ([`crate::compile::front::initial_param`]). The campaign's entry then turns
//! into that parameter's value in the experiment's own `params`: a number
//! (fixed), a range (free: the experiment's own gene, searched, polished and
//! given an interval like any other), or a number read from the data file.
//! Everything here runs before any work and names the campaign file and the
//! JSON path of anything wrong.

use std::collections::BTreeMap;
use std::path::Path;

use super::CampaignError;
use super::error::invalid;
use super::raw::{RawExperiment, RawInitial, RawInitialData, RawParam};
use super::resolve::check_value;
use crate::base::data::{Column, CsvSpec};
use crate::base::{Drive, ParamScope, Scale};
use crate::compile::front::{BASE_VELOCITY, initial_param};
use crate::model::compiled::CompiledRig;
use crate::record::lent::Lent;
use crate::rig::desc::{ParamDesc, RigDesc};

/// Declares `initial_<state>` for every state some experiment names, after
/// checking each name against the rig's `states`.
pub(crate) fn declare(
    file: &Path,
    experiments: &[RawExperiment],
    desc: &mut RigDesc,
    states: &[String],
) -> Result<(), CampaignError> {
    let mut wanted = vec![false; states.len()];
    for (e, x) in experiments.iter().enumerate() {
        for key in x.initial.keys() {
            let Some(k) = states.iter().position(|s| s == key) else {
                return Err(invalid(
                    file,
                    format!(
                        "experiments[{e}].initial.{}",
                        crate::base::text::echo_bare(key)
                    ),
                    format!("a state of rig '{}' ({})", desc.id, states.join(", ")),
                    crate::base::text::echo(key),
                ));
            };
            wanted[k] = true;
        }
    }
    for (state, _) in states.iter().zip(&wanted).filter(|(_, w)| **w) {
        let name = initial_param(state);
        if desc.params.iter().any(|p| p.name == name) {
            // The rig declares it itself.
            continue;
        }
        desc.params.push(ParamDesc {
            name,
            unit: if is_velocity(state) { "m/s" } else { "m" }.into(),
            doc: format!("initial value of state {state} (the experiment's \"initial\")"),
            scope: ParamScope::Experiment,
            default: Some(0.0),
            scale: Scale::Linear,
            domain: None,
        });
    }
    Ok(())
}

/// Experiment `e`'s `params` with its initial states added as
/// `initial_<state>` values: free ranges checked here (so messages name
/// `initial`), values from the data file read.
pub(crate) fn as_params(
    file: &Path,
    (dir, lent): (&Path, &Lent),
    e: usize,
    x: &RawExperiment,
) -> Result<BTreeMap<String, RawParam>, CampaignError> {
    let mut params = x.params.clone();
    for (state, raw) in &x.initial {
        let path = format!("experiments[{e}].initial.{state}");
        let name = initial_param(state);
        if params.contains_key(&name) {
            return Err(invalid(
                file,
                format!("experiments[{e}].params.{name}"),
                format!("the initial value of {state} given once (it is in {path})"),
                "both",
            ));
        }
        let value = match raw {
            RawInitial::Param(p) => {
                check_value(file, &path, p, None)?;
                match p {
                    RawParam::Fixed(v) if !v.is_finite() => {
                        return Err(invalid(file, path, "a finite number", v.to_string()));
                    }
                    other => other.clone(),
                }
            }
            RawInitial::Data(d) => RawParam::Fixed(from_data(
                file,
                (dir, lent),
                &path,
                x,
                d,
                is_velocity(state),
            )?),
        };
        params.insert(name, value);
    }
    Ok(params)
}

/// Refuses an initial value for a state the experiment's drive prescribes (a
/// node whose motion the drive sets is not integrated: its state's derivative
/// is the constant 0).
pub(crate) fn check_prescribed(
    file: &Path,
    rig: &CompiledRig,
    e: usize,
    x: &RawExperiment,
    drive: &Drive,
) -> Result<(), CampaignError> {
    let Some(p) = rig.program_for(drive) else {
        return Ok(());
    };
    let prog = &rig.lowered.programs[p];
    for state in x.initial.keys() {
        let Some(k) = rig.lowered.states.iter().position(|s| s == state) else {
            continue;
        };
        if matches!(
            prog.graph.ops[prog.deriv[k] as usize],
            crate::compile::Op::Const(_)
        ) {
            return Err(invalid(
                file,
                format!("experiments[{e}].initial.{state}"),
                "a state the drive leaves free (not one a drive prescribes)",
                format!(
                    "{state}, prescribed by the rig's \"{}\"-mode drive",
                    prog.mode
                ),
            ));
        }
    }
    Ok(())
}

/// Whether `state` is a velocity (`v_<node>`, or the base's velocity under
/// base acceleration), not a displacement.
fn is_velocity(state: &str) -> bool {
    state.starts_with("v_") || state == BASE_VELOCITY
}

/// The initial value from the data file (see [`RawInitialData`]).
fn from_data(
    file: &Path,
    (dir, lent): (&Path, &Lent),
    path: &str,
    x: &RawExperiment,
    d: &RawInitialData,
    velocity: bool,
) -> Result<f64, CampaignError> {
    if !(d.scale.is_finite() && d.scale != 0.0) {
        return Err(invalid(
            file,
            format!("{path}.scale"),
            "a finite, non-zero multiplier",
            d.scale.to_string(),
        ));
    }
    let slope = d.slope.unwrap_or(velocity);
    let min = if slope { 2 } else { 1 };
    let samples = d.samples.unwrap_or(if slope { 3 } else { 1 });
    if samples < min {
        return Err(invalid(
            file,
            format!("{path}.samples"),
            format!(
                "at least {min} sample(s) for a {}",
                if slope { "slope" } else { "value" }
            ),
            samples.to_string(),
        ));
    }
    let data_file = dir.join(&x.data.file);
    let spec = CsvSpec {
        time: x.data.time_column.clone().unwrap_or(Column::Index(0)),
        force: d.column.clone(),
        time_scale: x.data.time_scale,
        force_scale: d.scale,
        encoding: x.data.encoding,
        decimal: x.data.decimal,
    };
    let data_err = |source| CampaignError::Data {
        file: file.to_path_buf(),
        path: format!("{path}.column"),
        source: Box::new(source),
    };
    let loan = lent.read(&data_file).map_err(|err| {
        data_err(crate::base::data::DataError::Io {
            file: data_file.clone(),
            message: err.to_string(),
        })
    })?;
    // Read in the record's own format, as its measured channels are.
    let mut record = super::record_file::Shared::default();
    record.hold(loan);
    let (series, _) =
        super::record_file::read(&mut record, &data_file, &x.data, &spec).map_err(data_err)?;
    if series.force.len() < samples {
        return Err(invalid(
            file,
            format!("{path}.samples"),
            format!("at most the record's {} samples", series.force.len()),
            samples.to_string(),
        ));
    }
    let (value, per_sample) = start_fit(&series.force[..samples]);
    Ok(if slope { per_sample / series.dt } else { value })
}

/// Value and slope (per sample) at the first of `xs` of the least-squares
/// polynomial of degree `min(2, len − 1)` through them at `0, 1, …`.
pub(crate) fn start_fit(xs: &[f64]) -> (f64, f64) {
    let deg = (xs.len() - 1).min(2);
    let m = deg + 1;
    // Normal equations A c = b, A[i][j] = Σ u^(i+j), b[i] = Σ u^i x.
    let mut a = vec![vec![0.0; m + 1]; m];
    for (k, &x) in xs.iter().enumerate() {
        let u = k as f64;
        for (i, row) in a.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().take(m).enumerate() {
                *v += u.powi((i + j) as i32);
            }
            row[m] += u.powi(i as i32) * x;
        }
    }
    // Gauss–Jordan elimination with partial pivoting.
    for c in 0..m {
        let p = (c..m)
            .max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))
            .expect("a row");
        a.swap(c, p);
        let pivot = a[c].clone();
        for (r, row) in a.iter_mut().enumerate() {
            if r != c {
                let f = row[c] / pivot[c];
                for (v, pv) in row.iter_mut().zip(&pivot).skip(c) {
                    *v -= f * pv;
                }
            }
        }
    }
    let coef: Vec<f64> = (0..m).map(|i| a[i][m] / a[i][i]).collect();
    (coef[0], coef.get(1).copied().unwrap_or(0.0))
}

#[cfg(test)]
mod tests {
    use super::start_fit;

    #[test]
    fn start_fit_is_exact_for_quadratics_and_takes_the_first_sample_alone() {
        let q = |u: f64| 0.5 - 0.25 * u + 0.125 * u * u;
        let xs: Vec<f64> = (0..3).map(|k| q(k as f64)).collect();
        let (v, s) = start_fit(&xs);
        assert!((v - 0.5).abs() < 1e-14 && (s + 0.25).abs() < 1e-14);
        // The one-sided second-order difference.
        assert!((s - (-3.0 * xs[0] + 4.0 * xs[1] - xs[2]) / 2.0).abs() < 1e-14);
        let xs: Vec<f64> = (0..7).map(|k| q(k as f64)).collect();
        let (v, s) = start_fit(&xs);
        assert!((v - 0.5).abs() < 1e-12 && (s + 0.25).abs() < 1e-12);
        assert_eq!(start_fit(&[3.5]), (3.5, 0.0));
        let (v, s) = start_fit(&[1.0, 3.0]);
        assert!((v - 1.0).abs() < 1e-15 && (s - 2.0).abs() < 1e-15);
    }
}
