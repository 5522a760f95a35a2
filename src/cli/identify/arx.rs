//! `rigfit identify arx`: the transmissibility between two measured points,
//! its frequency-domain ARX coefficients, and the stiffness and damping of the
//! element between the points.

use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, ValueEnum};
use rustfft::num_complex::Complex64;

use super::common::{Band, Common};
use crate::cli::exit::BadInput;
use crate::cli::fragment::{Figure, Findings};
use crate::cli::output::{Output, write_file};
use crate::cli::record::Record;
use rigfit::identify::transmissibility::{self as tr, ArxForm, ArxLine, BlockSpectra, ElementFit};

/// `rigfit identify arx`.
#[derive(Debug, Args)]
pub struct ArxArgs {
    /// CSV record.
    pub data: PathBuf,
    /// Time column (s).
    #[arg(long, default_value = "1")]
    pub time: String,
    /// Reference channel: the node on the driven side of the element.
    #[arg(long, default_value = "2")]
    pub input: String,
    /// Response channels: the node across the element first, then every node it carries.
    #[arg(long, value_delimiter = ',', default_values_t = ["3".to_string()])]
    pub output: Vec<String>,
    /// Masses (kg) of the response channels' nodes, in the same order.
    #[arg(long, value_delimiter = ',', required = true)]
    pub mass: Vec<f64>,
    /// Campaign names of the element's stiffness and damping.
    #[arg(long, value_delimiter = ',', default_values_t = ["k2".to_string(), "c2".to_string()])]
    pub names: Vec<String>,
    /// ARX form: Eq. 5 (neighbouring lines) or Eq. 6 (the cube at k/3 and 3k).
    #[arg(long, value_enum, default_value_t = ArxFormArg::Linear)]
    pub form: ArxFormArg,
    /// Samples per segment (default: the largest power of two giving ≥ 8 segments).
    #[arg(long)]
    pub segment: Option<usize>,
    #[command(flatten)]
    pub band: Band,
    /// Lines with a lower coherence are left out of the element fit.
    #[arg(long, default_value_t = 0.9)]
    pub min_coherence: f64,
    /// Write the table (frequency, T, coherence, model, ARX coefficients) here.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    #[command(flatten)]
    pub common: Common,
}

/// The ARX form on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ArxFormArg {
    /// Eq. 5: Y(k) = B·U(k) + A₋₁·Y(k−1) + A₁·Y(k+1).
    Linear,
    /// Eq. 6: Y(k) = B·U(k) + A₋₁·Z(k/3) + A₁·Z(3k), Z the spectrum of y³.
    Cubic,
}

impl From<ArxFormArg> for ArxForm {
    fn from(f: ArxFormArg) -> Self {
        match f {
            ArxFormArg::Linear => ArxForm::Linear,
            ArxFormArg::Cubic => ArxForm::Cubic,
        }
    }
}

/// The transmissibilities of every response channel and their coherences.
struct Ratios {
    ts: Vec<Vec<Complex64>>,
    coherences: Vec<Vec<f64>>,
}

/// Estimates the transmissibility, the ARX lines and the element, and
/// delivers the fragment.
pub fn arx(a: &ArxArgs, out: &Output) -> Result<()> {
    if a.names.len() != 2 {
        anyhow::bail!(BadInput(format!(
            "--names takes the stiffness and the damping name, found {}",
            a.names.len()
        )));
    }
    let record = Record::read(&a.data)?;
    let fs = record.time_column_rate(&a.time)?;
    let u = record.column(&a.input)?;
    let ys = record.columns(&a.output)?;
    let spec = tr::block_spectra(u, &ys, fs, a.segment).map_err(|e| record.error(e))?;
    let (ts, coherences) = (0..ys.len()).map(|c| spec.transmissibility(c)).unzip();
    let ratios = Ratios { ts, coherences };
    let form = ArxForm::from(a.form);
    let band = a.band.edges();
    let lines = tr::arx(&spec, form, band.0, band.1).map_err(|e| record.error(e))?;
    let fit = tr::element_fit(
        &spec.freqs,
        &ratios.ts,
        &ratios.coherences[0],
        &a.mass,
        band,
        a.min_coherence,
    )
    .map_err(|e| record.error(e))?;
    if let Some(path) = &a.csv {
        write_file(path, table(&spec, &ratios, &fit, &lines).as_bytes())?;
    }
    let figure = Figure {
        title: format!("transmissibility of {}", a.data.display()),
        panels: || {
            let (ts, coherence) = (&ratios.ts, &ratios.coherences[0]);
            tr::figure(&spec.freqs, ts, coherence, Some(&fit), &lines, band)
        },
        columns: 3,
    };
    Findings {
        report: serde_json::json!({"welch": spec.settings, "element": fit, "arx": lines}),
        fragment: fit.to_campaign_fragment([&a.names[0], &a.names[1]], a.common.fixed),
        text: || report(a, &spec, &fit, form, &lines, u.len(), fs),
    }
    .deliver_with(out, a.common.files(), figure)
}

/// The `--csv` table: one line per ARX line.
fn table(spec: &BlockSpectra, ratios: &Ratios, fit: &ElementFit, lines: &[ArxLine]) -> String {
    let mut text = String::from(
        "frequency_Hz,T_abs,T_phase_rad,coherence,model_abs,model_phase_rad,B_abs,A_minus_abs,A_plus_abs,explained\n",
    );
    let (ts, coherence) = (&ratios.ts, &ratios.coherences[0]);
    for l in lines {
        let k = (l.frequency_hz / spec.settings.resolution_hz).round() as usize;
        let beyond: Vec<_> = ts[1..].iter().map(|t| t[k]).collect();
        let m = fit.model(l.frequency_hz, &beyond);
        text += &format!(
            "{},{},{},{},{},{},{},{},{},{}\n",
            l.frequency_hz,
            ts[0][k].norm(),
            ts[0][k].arg(),
            coherence[k],
            m.norm(),
            m.arg(),
            l.b.0.hypot(l.b.1),
            l.a_minus.0.hypot(l.a_minus.1),
            l.a_plus.0.hypot(l.a_plus.1),
            l.explained
        );
    }
    text
}

/// The mean magnitude of one ARX coefficient over the lines where it is finite.
fn mean_magnitude(lines: &[ArxLine], pick: fn(&ArxLine) -> (f64, f64)) -> f64 {
    let v: Vec<f64> = lines
        .iter()
        .map(|l| {
            let (re, im) = pick(l);
            re.hypot(im)
        })
        .filter(|v| v.is_finite())
        .collect();
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

/// The human report.
fn report(
    a: &ArxArgs,
    spec: &BlockSpectra,
    fit: &ElementFit,
    form: ArxForm,
    lines: &[ArxLine],
    n: usize,
    fs: f64,
) -> String {
    let w = &spec.settings;
    format!(
        "transmissibility of {} ({} → {}; {} samples at {:.1} Hz)\n  \
         segments: {} × {} samples, Hann, 50 % overlap, resolution {:.4} Hz\n  \
         element: {} = {:.5e} ± {:.2e} N/m, {} = {:.5e} ± {:.2e} N·s/m over {} lines \
         (relative error of T {:.4}, R² {:.5})\n  \
         ARX ({:?}) over {} lines: mean |A₋₁| = {:.4}, mean |A₁| = {:.4}\n",
        a.data.display(),
        a.input,
        a.output.join(", "),
        n,
        fs,
        w.n_segments,
        w.segment_len,
        w.resolution_hz,
        a.names[0],
        fit.stiffness,
        fit.stiffness_std_error,
        a.names[1],
        fit.damping,
        fit.damping_std_error,
        fit.lines,
        fit.relative_error,
        fit.r2,
        form,
        lines.len(),
        mean_magnitude(lines, |l| l.a_minus),
        mean_magnitude(lines, |l| l.a_plus)
    )
}
