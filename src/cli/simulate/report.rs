//! `rigfit simulate --report FILE`: the page of the model against the
//! record (the report a job writes, with the sections that apply to one run
//! at fixed values: no search, no parameter table).

use std::path::Path;

use anyhow::Result;

use crate::cli::exit::BadInput;
use crate::cli::output::check_out_files;
use rigfit::campaign::Campaign;
use rigfit::eval::History;
use rigfit::model::modes::ModeReport;
use rigfit::report::html::input::{Column, FitCsv};
use rigfit::report::html::{build_record_report, is_rigfit_report};

/// Writes the page of experiment `e` of `c` simulated as `h` against its
/// record to `page`: never over one of the campaign's inputs, nor over a
/// file that is not a report rigfit wrote.
pub(super) fn write_page(page: &Path, c: &Campaign, e: usize, h: &History) -> Result<()> {
    let inputs: Vec<&Path> = c.inputs.iter().map(|p| p.as_path()).collect();
    check_out_files(&[("--report", page)], &inputs, true)?;
    if page.symlink_metadata().is_ok() && !is_rigfit_report(page) {
        return Err(BadInput(format!(
            "--report `{}` exists and is not a report rigfit wrote; expected a new file or an \
             earlier report (refusing to replace it)",
            page.display()
        ))
        .into());
    }
    let exp = &c.problem.experiments[e];
    let outputs = c.model.output_names();
    let n = h.t.len().min(exp.measured.len());
    let model = |o: usize| -> Vec<f64> {
        (0..n)
            .map(|k| h.outputs[o].get(k).copied().unwrap_or(f64::NAN))
            .collect()
    };
    let (name, unit) = outputs[exp.output].clone();
    let measured = exp.measured[..n].to_vec();
    let residual: Vec<f64> = model(exp.output)
        .iter()
        .zip(&measured)
        .map(|(m, x)| m - x)
        .collect();
    let mut columns = vec![Column {
        kind: "measured",
        name,
        unit: unit.clone(),
        values: measured,
    }];
    for (o, (name, unit)) in outputs.iter().enumerate() {
        columns.push(Column {
            kind: "model",
            name: name.clone(),
            unit: unit.clone(),
            values: model(o),
        });
    }
    columns.push(Column {
        kind: "residual",
        name: String::new(),
        unit,
        values: residual,
    });
    let csv = FitCsv {
        t: (0..n).map(|k| exp.t_first + k as f64 * exp.dt).collect(),
        columns,
        in_fit_window: (0..n).map(|k| exp.window.contains(&k)).collect(),
    };
    let lin = c.model.linearise(&c.base[e], &exp.drive);
    let hz: Vec<f64> = ModeReport::new(&lin)
        .map(|r| r.modes.iter().map(|m| m.frequency_hz).collect())
        .unwrap_or_default();
    let html = build_record_report(&exp.name, csv, &hz);
    rigfit::base::fsutil::atomic_write(page, html.as_bytes())
        .map_err(|err| anyhow::anyhow!("writing `{}`: {err}", page.display()))
}
