//! `rigfit ringdown`, a pre-calibration command: the frequency and damping of
//! a free ringdown (a hammer impact, a release, the load cell after a
//! fracture), pinned down before the rig is searched.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use super::exit::BadInput;
use super::fragment::{Figure, Files, Findings};
use super::output::Output;
use super::record::{Record, in_file, read_two_columns};
use rigfit::identify::csv_input::TwoColumns;
use rigfit::identify::ringdown::{self, DEFAULT_NAMES, RingdownOptions};

/// `rigfit ringdown`.
#[derive(Debug, Args)]
pub struct RingdownArgs {
    /// CSV record: time (s) and the ringing signal (force in N, or any motion);
    /// two columns unless --time or --signal choose among more.
    pub data: PathBuf,
    /// Time column (s), by header name or 1-based position (default: 1).
    #[arg(long)]
    pub time: Option<String>,
    /// Ringing signal column, by header name or 1-based position (default: 2).
    #[arg(long)]
    pub signal: Option<String>,
    /// Mass of the ringing mode (kg; m1, the load cell, on the tensile rig):
    /// with it, the stiffness follows from the frequency.
    #[arg(long, visible_alias = "mass")]
    pub m1: Option<f64>,
    /// Stiffness of the ringing mode (N/m; k1 on the tensile rig), held fixed
    /// in the damping fit.
    #[arg(long, visible_alias = "stiffness")]
    pub k1: Option<f64>,
    /// Campaign names of the ringing mode's stiffness and damping, as the
    /// fragment writes them.
    #[arg(long, value_delimiter = ',', default_values_t = DEFAULT_NAMES.map(String::from))]
    pub names: Vec<String>,
    /// Start of the free ringing (s; default: the start of the largest drop, e.g. a fracture).
    #[arg(long)]
    pub start: Option<f64>,
    /// Write the campaign fragment (JSON) here.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write the figure (SVG) here: the ringing with its fitted decay and envelope,
    /// and the peaks' decay against each estimator's.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Replace the --out and --svg files when they exist (never the data file).
    #[arg(long)]
    pub overwrite: bool,
}

/// Analyses a ringdown and prints or writes the campaign fragment.
pub fn ringdown(args: &RingdownArgs, out: &Output) -> Result<()> {
    let start_refused = |start: f64, span: &str| {
        BadInput(format!(
            "--start {start}: expected a time on the record's time axis{span} \
             (leave it out to start at the largest drop)"
        ))
    };
    if let Some(start) = args.start.filter(|s| !s.is_finite()) {
        return Err(start_refused(start, "").into());
    }
    let names: [&str; 2] = match args.names.as_slice() {
        [k, c] => [k, c],
        _ => {
            return Err(BadInput(format!(
                "--names takes the stiffness and the damping name, found {}",
                args.names.len()
            ))
            .into());
        }
    };
    let files = Files {
        fragment: args.out.as_deref(),
        figure: args.svg.as_deref(),
    };
    files.check(&[], &[&args.data], args.overwrite)?;
    let data = read_record(args)?;
    if let (Some(start), Some(&first), Some(&last)) = (args.start, data.x.first(), data.x.last())
        && !(first..last).contains(&start)
    {
        let span = format!(
            ", from {first} s to before {last} s in `{}`",
            args.data.display()
        );
        return Err(start_refused(start, &span).into());
    }
    let opts = RingdownOptions {
        m1: args.m1,
        k1: args.k1,
        start: args.start,
        ..RingdownOptions::default()
    };
    let r = ringdown::analyse(&data.x, &data.y, &opts).map_err(|e| in_file(&args.data, e))?;
    let figure = Figure {
        title: format!("ringdown of {}", args.data.display()),
        panels: || ringdown::figure(&r, &data.x, &data.y),
        columns: 2,
    };
    Findings {
        report: serde_json::json!({"ringdown": r}),
        fragment: r.to_campaign_fragment_named(names),
        text: || report(args, names, &r),
    }
    .deliver_with(out, files, figure)
}

/// The time and signal columns: the two columns of a two-column record, or
/// those `--time` and `--signal` choose.
fn read_record(args: &RingdownArgs) -> Result<TwoColumns> {
    if args.time.is_none() && args.signal.is_none() {
        return read_two_columns(&args.data);
    }
    let record = Record::read(&args.data)?;
    let column = |which: &Option<String>, default: &str| {
        record
            .column(which.as_deref().unwrap_or(default))
            .map(<[f64]>::to_vec)
    };
    Ok(TwoColumns {
        header: None,
        x: column(&args.time, "1")?,
        y: column(&args.signal, "2")?,
    })
}

/// The human report, naming the stiffness and damping `[k, c]` as the fragment does.
fn report(
    args: &RingdownArgs,
    [k_name, c_name]: [&str; 2],
    r: &ringdown::RingdownReport,
) -> String {
    let mut s = format!(
        "ringdown of {} (sampled at {:.0} Hz, free ringing from {:.6e} s)\n",
        args.data.display(),
        r.sample_rate_hz,
        r.start.time
    );
    s += &format!(
        "  PSD ({} window, {} samples × {} segments, resolution {:.1} Hz): peak {:.1} Hz\n",
        r.psd.window, r.psd.segment_len, r.psd.n_segments, r.psd.resolution_hz, r.psd.peak_hz
    );
    s += &format!(
        "  log decrement over {} peaks: ζ = {:.5} (spread {:.2e}, {:.5}..{:.5})\n",
        r.decrement.n_peaks,
        r.decrement.zeta_mean,
        r.decrement.zeta_std,
        r.decrement.zeta_min,
        r.decrement.zeta_max
    );
    s += &format!(
        "  damped-oscillator fit: f_n = {:.2} Hz, ζ = {:.6}, R² = {:.5}\n",
        r.natural_frequency_hz, r.fit.zeta, r.fit.r2
    );
    if let Some(e) = &r.envelope {
        s += &format!(
            "  analytic-signal envelope in {:.1}…{:.1} Hz: ζ = {:.6} (R² = {:.5})\n",
            e.band_hz.0, e.band_hz.1, e.zeta, e.r2
        );
    }
    let g = &r.agreement;
    s += &format!(
        "  the damping estimates {} (spread {:.1} %, {:.1} samples per cycle)\n",
        if g.agree { "agree" } else { "DISAGREE" },
        100.0 * g.relative_spread,
        g.samples_per_cycle
    );
    for w in &g.warnings {
        s += &format!("  warning: {w}\n");
    }
    let cell = &r.load_cell;
    if let (true, Some(k1)) = (cell.k1_from_frequency, cell.k1) {
        s += &format!("  {k_name} from frequency and mass = {k1:.6e} N/m\n");
    }
    if let Some(c) = cell.c1_post {
        s += &format!("  {c_name} = {c:.6e} N·s/m\n");
    }
    s
}
