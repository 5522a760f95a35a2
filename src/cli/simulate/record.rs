//! The files a simulation writes: a synthetic record laid out as the
//! campaign reads it ([`record_layout`], [`write_record`]: its columns, each
//! measured channel with its noise), or the history without noise
//! ([`history_csv`]).

use std::fmt::Write as _;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::cli::exit::BadInput;
use rigfit::base::data::Column;
use rigfit::base::noise::gaussian;
use rigfit::base::text::echo;
use rigfit::campaign::Campaign;
use rigfit::campaign::raw::RawData;
use rigfit::design::prediction::OutputBand;
use rigfit::eval::History;

/// What one column of a synthetic record holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Cell {
    Time,
    /// Measured channel `j` (in the order of [`Channel`]s).
    Measured(usize),
    Drive,
    /// A column between two the campaign reads by position: zeros.
    Unused,
}

/// One measured column of a synthetic record: the output, its noise (the
/// output's unit) and the campaign's multiplier to that unit.
pub(super) struct Channel {
    pub(super) output: usize,
    pub(super) sigma: f64,
    pub(super) scale: f64,
}

/// The record's columns in order, each with its header, placed where the
/// campaign's `data` reads them: by name, or at a 0-based position.
/// `measured`: each channel's column and default header.
pub(super) fn record_layout(
    data: &RawData,
    measured: &[(Column, String)],
    drive: Option<&Column>,
) -> Result<Vec<(String, Cell)>, BadInput> {
    let time = data.time_column.clone().unwrap_or(Column::Index(0));
    let mut wanted = vec![(time, "t_s".to_string(), Cell::Time)];
    for (j, (column, header)) in measured.iter().enumerate() {
        wanted.push((column.clone(), header.clone(), Cell::Measured(j)));
    }
    if let Some(d) = drive {
        wanted.push((d.clone(), "drive".into(), Cell::Drive));
    }
    let width = wanted
        .iter()
        .map(|(c, ..)| match c {
            Column::Index(i) => i + 1,
            Column::Name(_) => 0,
        })
        .max()
        .unwrap_or(0)
        .max(wanted.len());
    if width > 64 {
        return Err(BadInput(format!(
            "the campaign reads a column at position {}: expected positions below 64 for a \
             record rigfit simulate writes; name the columns instead",
            width - 1
        )));
    }
    let mut slots: Vec<Option<(String, Cell)>> = vec![None; width];
    for (c, default, cell) in &wanted {
        if let Column::Index(i) = c {
            if let Some((_, other)) = &slots[*i] {
                return Err(BadInput(format!(
                    "the campaign reads its {other:?} and {cell:?} columns both at position {i}; \
                     expected one column per position"
                )));
            }
            slots[*i] = Some((default.clone(), *cell));
        }
    }
    for (c, _, cell) in &wanted {
        if let Column::Name(name) = c {
            if name.contains([',', ';', '\t', '"', '\n', '\r']) {
                return Err(BadInput(format!(
                    "column name {}: expected a name without separators, quotes or line breaks \
                     for a record rigfit simulate writes",
                    echo(name)
                )));
            }
            let free = slots
                .iter()
                .position(Option::is_none)
                .expect("as many slots as columns");
            slots[free] = Some((name.clone(), *cell));
        }
    }
    Ok(slots
        .into_iter()
        .enumerate()
        .map(|(i, s)| s.unwrap_or_else(|| (format!("unused_{i}"), Cell::Unused)))
        .collect())
}

/// Significant digits that keep the rounding of a noisy value well below the
/// noise: at least the 7 the shipped records carry.
pub(super) fn digits(peak: f64, sigma: f64) -> usize {
    if sigma > 0.0 && peak > 0.0 {
        ((peak / sigma).log10().ceil() as usize + 3).clamp(7, 17)
    } else {
        17
    }
}

/// Writes the synthetic record's header and rows: the record's time, each
/// measured channel with its noise, the drive column, each in the unit the
/// campaign reads it in.
#[expect(
    clippy::too_many_arguments,
    reason = "one row writer, every part named"
)]
pub(super) fn write_record(
    s: &mut String,
    layout: &[(String, Cell)],
    h: &History,
    exp: &rigfit::eval::ExperimentData,
    data: &RawData,
    channels: &[Channel],
    seed: u64,
    drive: Option<&(&Column, Vec<f64>)>,
) {
    let names: Vec<&str> = layout.iter().map(|(n, _)| n.as_str()).collect();
    *s += &names.join(",");
    s.push('\n');
    let precision: Vec<usize> = channels
        .iter()
        .map(|ch| {
            let peak = h.outputs[ch.output]
                .iter()
                .fold(0.0_f64, |m, f| m.max(f.abs()));
            digits(peak, ch.sigma) - 1
        })
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut noisy = vec![0.0; channels.len()];
    for k in 0..h.t.len() {
        let t = exp.t_first + k as f64 * exp.dt;
        // One draw per sample and channel whatever the layout, so a seed
        // gives one noise.
        for (v, ch) in noisy.iter_mut().zip(channels) {
            *v = h.outputs[ch.output][k] + ch.sigma * gaussian(&mut rng);
        }
        for (i, (_, cell)) in layout.iter().enumerate() {
            if i > 0 {
                s.push(',');
            }
            let _ = match *cell {
                Cell::Time => write!(s, "{:.9e}", t / data.time_scale),
                Cell::Measured(j) => {
                    let p = precision[j];
                    write!(s, "{:.p$e}", noisy[j] / channels[j].scale)
                }
                Cell::Drive => write!(s, "{:e}", drive.map_or(0.0, |d| d.1[k])),
                Cell::Unused => write!(s, "0"),
            };
        }
        s.push('\n');
    }
}

/// The history without noise: `t_s`, every output and state by the rig's own
/// names, then the drive column by the campaign's name for it, then each
/// output's prediction band (median, lo, hi) where `bands` holds them.
pub(super) fn history_csv(
    c: &Campaign,
    h: &History,
    drive: Option<&(&Column, Vec<f64>)>,
    bands: Option<&[OutputBand]>,
) -> String {
    let mut s = String::from("t_s");
    let mut names = vec!["t_s".to_string()];
    for (name, unit) in c.model.output_names() {
        names.push(format!("{name}_{unit}"));
    }
    names.extend(c.model.state_names().iter().map(ToString::to_string));
    for n in &names[1..] {
        let _ = write!(s, ",{n}");
    }
    if let Some((col, _)) = drive {
        let name = match col {
            Column::Name(n) if !names.contains(n) && !n.contains([',', '"', '\n', '\r']) => {
                n.clone()
            }
            Column::Name(n) => format!("drive_{}", n.replace([',', '"', '\n', '\r'], "_")),
            Column::Index(_) => "drive".into(),
        };
        let _ = write!(s, ",{name}");
    }
    if bands.is_some() {
        for (name, unit) in c.model.output_names() {
            for end in ["median", "lo", "hi"] {
                let _ = write!(s, ",{name}_{unit}.{end}");
            }
        }
    }
    s.push('\n');
    for k in 0..h.t.len() {
        let _ = write!(s, "{:.9e}", h.t[k]);
        for o in h.outputs.iter().chain(&h.states) {
            let _ = write!(s, ",{:.9e}", o[k]);
        }
        if let Some((_, d)) = drive {
            let _ = write!(s, ",{:e}", d[k]);
        }
        for b in bands.unwrap_or_default() {
            let _ = write!(s, ",{:.9e},{:.9e},{:.9e}", b.median[k], b.lo[k], b.hi[k]);
        }
        s.push('\n');
    }
    s
}
