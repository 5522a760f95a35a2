//! `rigfit inspect`: what a record file holds — its format, its channels with
//! their lengths, units and sample rates — so a campaign's column keys can be
//! written from it.

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use super::exit::BadInput;
use super::output::Output;
use rigfit::base::text::{echo_bare, number};
use rigfit::record::{Channel, Format, Record};

/// `rigfit inspect`.
#[derive(Debug, Args)]
pub struct InspectArgs {
    /// A record file: CSV, NI TDMS (.tdms), HDF5 (.h5), MATLAB MAT-file (v5 or
    /// v7.3, .mat) or universal file dataset 58 (.uff, .unv).
    pub file: PathBuf,
    /// Read it as this format instead of telling it from its first bytes and
    /// its extension: csv, tdms, hdf5, mat or uff.
    #[arg(long)]
    pub format: Option<String>,
}

/// Lists the channels of a record file (or, with `--json`, writes them as
/// one JSON object).
pub fn inspect(args: &InspectArgs, out: &Output) -> Result<()> {
    let stated = match &args.format {
        None => None,
        Some(f) => Some(f.parse::<Format>().map_err(|names| {
            BadInput(format!("invalid --format: expected {names}, found {f:?}"))
        })?),
    };
    let bytes = rigfit::base::fsutil::read_record(&args.file)
        .map_err(|e| BadInput(format!("{}: cannot read: {e}", args.file.display())))?;
    let format = Format::of(&args.file, &bytes, stated);
    let record = rigfit::record::detect::read_any(format, &bytes, &args.file)
        .map_err(|e| BadInput(e.to_string()))?;
    out.json(&serde_json::json!({
        "file": args.file.display().to_string(),
        "format": format.key(),
        "bytes": bytes.len(),
        "channels": record.channels.iter().enumerate().map(|(i, c)| {
            let (min, max) = range(&c.values);
            serde_json::json!({
                "index": i,
                "name": c.name,
                "unit": c.unit,
                "samples": c.values.len(),
                "start_s": c.timing.map(|w| w.start),
                "increment_s": c.timing.map(|w| w.increment),
                "rate_hz": c.timing.map(|w| 1.0 / w.increment),
                "min": min,
                "max": max,
            })
        }).collect::<Vec<_>>(),
        "campaign_data": campaign_data(&args.file, format, stated.is_some(), &record),
    }))?;
    out.say(|| table(&args.file, format, &record));
    Ok(())
}

/// The finite values' least and greatest (none when none is finite).
fn range(values: &[f64]) -> (Option<f64>, Option<f64>) {
    let finite = values.iter().copied().filter(|v| v.is_finite());
    let min = finite.clone().reduce(f64::min);
    (min, finite.reduce(f64::max))
}

/// The channel that reads as a record's time: one whose unit is seconds or
/// whose name says time, with strictly increasing values.
fn time_channel(record: &Record) -> Option<usize> {
    let says_time = |c: &Channel| {
        let unit = c.unit.as_deref().map(rigfit::record::units::normal);
        let last = c
            .name
            .rsplit(['/', '.'])
            .next()
            .unwrap_or_default()
            .to_ascii_lowercase();
        matches!(unit.as_deref(), Some("s" | "ms" | "µs" | "us"))
            || last == "t"
            || last.starts_with("t_")
            || last.starts_with("time")
    };
    record.channels.iter().position(|c| {
        says_time(c) && c.values.len() > 1 && c.values.windows(2).all(|w| w[1] > w[0])
    })
}

/// The `"data"` object a campaign would read the record with: the time
/// column found, or the first channel with waveform timing; the measured
/// column left for the user to choose where several could be it.
fn campaign_data(
    file: &std::path::Path,
    format: Format,
    stated: bool,
    record: &Record,
) -> serde_json::Value {
    let time = time_channel(record);
    let measured = record
        .channels
        .iter()
        .enumerate()
        .position(|(i, c)| Some(i) != time && (time.is_some() || c.timing.is_some()));
    let mut data = serde_json::Map::new();
    let name = file.file_name().map(|n| n.to_string_lossy().into_owned());
    data.insert("file".into(), name.unwrap_or_default().into());
    if stated {
        data.insert("format".into(), format.key().into());
    }
    if let Some(t) = time {
        data.insert("time_column".into(), record.channels[t].name.clone().into());
    }
    if let Some(m) = measured {
        data.insert("column".into(), record.channels[m].name.clone().into());
    }
    serde_json::Value::Object(data)
}

/// The human listing: one line per channel, then the campaign's keys.
fn table(file: &std::path::Path, format: Format, record: &Record) -> String {
    let mut s = format!(
        "{}: {format}, {} channel(s)\n",
        file.display(),
        record.channels.len()
    );
    let rows: Vec<[String; 6]> = record
        .channels
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let (min, max) = range(&c.values);
            let shown = |v: Option<f64>| v.map_or("-".into(), number);
            let timing = c.timing.map_or("-".into(), |w| {
                format!(
                    "{} Hz from {} s",
                    number(1.0 / w.increment),
                    number(w.start)
                )
            });
            [
                format!("#{i}"),
                echo_bare(&c.name),
                c.unit.as_deref().map_or("-".into(), echo_bare),
                c.values.len().to_string(),
                timing,
                format!("{} .. {}", shown(min), shown(max)),
            ]
        })
        .collect();
    let head = ["", "channel", "unit", "samples", "timing", "range"];
    let widths: Vec<usize> = (0..6)
        .map(|j| {
            rows.iter()
                .map(|r| r[j].chars().count())
                .chain([head[j].len()])
                .max()
                .unwrap_or(0)
        })
        .collect();
    for row in std::iter::once(head.map(String::from)).chain(rows) {
        let mut line = String::from(" ");
        for (cell, w) in row.iter().zip(&widths) {
            let _ = write!(line, " {cell:<w$}");
        }
        s += line.trim_end();
        s += "\n";
    }
    let data = campaign_data(file, format, false, record);
    let _ = write!(
        s,
        "A campaign reads it with \"data\": {data} (columns by name, by 0-based index, or by \
         the last part of the name when no other channel ends alike; a channel with its own \
         timing needs no \"time_column\")."
    );
    s
}
