//! The picture `rigfit sweep --picture` draws of one metric: the Sobol
//! indices of drawn points, a heat map over two grid variables, or else a
//! line (with its band, where the sweep carries the calibration's
//! uncertainty) over the first variable for each combination of the others.

use super::file::Sweep;
use super::picture::{BandLine, IndexBar, band_svg, heat_map_svg, indices_svg};
use super::points::Points;
use super::run::Table;
use super::sensitivity::{IndexTable, sobol_table};
use crate::report::plots::PlotError;

/// Most lines one picture draws (combinations of the variables after the
/// first).
pub const MAX_LINES: usize = 12;

/// Why the sweep cannot be drawn, before it runs.
pub fn check(sweep: &Sweep) -> Result<(), String> {
    match &sweep.points {
        Points::Drawn(d) if !d.indices => Err(
            "a picture of drawn points is their Sobol indices; ask for them with \"sampling\": \
             {…, \"indices\": true}"
                .into(),
        ),
        Points::Drawn(_) => Ok(()),
        Points::Grid(g) if g.axes.len() == 2 => Ok(()),
        Points::Grid(g) => {
            let lines: usize = g.axes[1..].iter().map(Vec::len).product();
            if lines > MAX_LINES {
                Err(format!(
                    "the variables after the first make {lines} combinations, one line each; a \
                     picture draws at most {MAX_LINES} (sweep fewer values, or draw from the CSV)"
                ))
            } else {
                Ok(())
            }
        }
    }
}

/// Whether a grid reads better on a log axis: positive values spanning more
/// than a decade.
fn logarithmic(values: &[f64]) -> bool {
    let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    values.len() >= 3 && lo > 0.0 && hi / lo > 10.0
}

/// A design variable's axis label: its name and the rig parameter's unit
/// (`c4 (N·s/m)`; `v05.velocity` reads `velocity`'s).
pub fn variable_label(sweep: &Sweep, name: &str) -> String {
    let param = name.rsplit('.').next().unwrap_or(name);
    match sweep
        .campaign
        .model
        .desc
        .params
        .iter()
        .find(|p| p.name == param)
    {
        Some(p) if !p.unit.is_empty() && p.unit != "1" => format!("{name} ({})", p.unit),
        _ => name.to_string(),
    }
}

/// A metric's axis label: its name and unit (the output's for a peak, an
/// RMS…; s for times, Hz for a frequency; none for a ratio or a formula).
pub fn metric_label(sweep: &Sweep, metric: usize) -> String {
    use super::metrics::MetricKind as K;
    let m = &sweep.metrics[metric];
    let output_unit = || sweep.campaign.model.output_names()[m.output].1.clone();
    let unit = match m.kind {
        K::Peak | K::Max | K::Min | K::Mean | K::Rms => Some(output_unit()),
        K::RiseTime | K::SettlingTime | K::FirstCrossing => Some("s".to_string()),
        K::RingingHz => Some("Hz".to_string()),
        K::Energy => Some(format!("{}²·s", output_unit())),
        K::Overshoot | K::Ringing | K::Expression => None,
    };
    match unit {
        Some(u) => format!("{} ({u})", m.name),
        None => m.name.clone(),
    }
}

/// The SVG of metric `metric` (an index into the sweep's metrics); `indices`
/// the sweep's Sobol indices where the caller has them already (computed
/// here otherwise).
pub fn picture(
    sweep: &Sweep,
    table: &Table,
    metric: usize,
    indices: Option<&IndexTable>,
) -> Result<String, PlotError> {
    let failed = |message: String| PlotError {
        path: "--picture".into(),
        message,
    };
    check(sweep).map_err(failed)?;
    let name = &table.metrics[metric];
    let experiment = &sweep.campaign.problem.experiments[sweep.experiment].name;
    let title = format!("{name} of {experiment}");
    let value = |r: usize| table.rows[r].metrics[metric].unwrap_or(f64::NAN);
    match &sweep.points {
        Points::Drawn(_) => {
            let computed;
            let ix = match indices {
                Some(ix) => ix,
                None => {
                    computed = sobol_table(sweep, table).map_err(failed)?;
                    &computed
                }
            };
            let indices = ix.metrics[metric]
                .1
                .as_ref()
                .map_err(|why| failed(format!("{name}: {why}")))?;
            let bars: Vec<IndexBar<'_>> = sweep
                .variables
                .iter()
                .zip(indices)
                .map(|(v, x)| IndexBar {
                    name: v,
                    first: x.first,
                    first_95: x.first_95,
                    total: x.total,
                    total_95: x.total_95,
                })
                .collect();
            indices_svg(&format!("Sobol indices: {title}"), name, &bars)
        }
        Points::Grid(g) if g.axes.len() == 2 => {
            let (ys, xs) = (&g.axes[0], &g.axes[1]);
            let z: Vec<Vec<f64>> = (0..ys.len())
                .map(|i| (0..xs.len()).map(|j| value(i * xs.len() + j)).collect())
                .collect();
            heat_map_svg(
                &title,
                &variable_label(sweep, &sweep.variables[1]),
                &variable_label(sweep, &sweep.variables[0]),
                &metric_label(sweep, metric),
                xs,
                ys,
                &z,
                logarithmic(xs),
                logarithmic(ys),
                None,
            )
        }
        Points::Grid(g) => {
            let x = &g.axes[0];
            let rest: usize = g.axes[1..].iter().map(Vec::len).product();
            let band_of = |r: usize, pick: fn(&super::run::Band) -> f64| {
                table.rows[r]
                    .bands
                    .get(metric)
                    .copied()
                    .flatten()
                    .map_or(f64::NAN, |b| pick(&b))
            };
            let mut labels = Vec::new();
            let mut mids = Vec::new();
            let mut los = Vec::new();
            let mut his = Vec::new();
            for c in 0..rest {
                let rows: Vec<usize> = (0..x.len()).map(|i| i * rest + c).collect();
                let values = &table.rows[c].values;
                labels.push(if g.axes.len() == 1 {
                    name.clone()
                } else {
                    sweep.variables[1..]
                        .iter()
                        .zip(&values[1..])
                        .map(|(n, v)| format!("{n} = {v}"))
                        .collect::<Vec<_>>()
                        .join(", ")
                });
                mids.push(rows.iter().map(|&r| value(r)).collect::<Vec<f64>>());
                los.push(
                    rows.iter()
                        .map(|&r| band_of(r, |b| b.lo))
                        .collect::<Vec<f64>>(),
                );
                his.push(
                    rows.iter()
                        .map(|&r| band_of(r, |b| b.hi))
                        .collect::<Vec<f64>>(),
                );
            }
            let lines: Vec<BandLine<'_>> = (0..rest)
                .map(|c| BandLine {
                    label: &labels[c],
                    x,
                    mid: &mids[c],
                    lo: table.banded.then_some(los[c].as_slice()),
                    hi: table.banded.then_some(his[c].as_slice()),
                })
                .collect();
            let title = if table.banded {
                format!("{title}, 95 % band of the calibration")
            } else {
                title
            };
            band_svg(
                &title,
                &variable_label(sweep, &sweep.variables[0]),
                &metric_label(sweep, metric),
                logarithmic(x),
                &lines,
            )
        }
    }
}
