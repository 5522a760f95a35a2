//! `rigfit identify <method>`: the classical identification tools of the seed
//! documents, each writing a campaign fragment and an SVG figure.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::{Args, Subcommand, ValueEnum};

use super::Output;
use super::precal::{deliver, in_file};
use rigfit::identify::columns::{Table, sample_interval};
use rigfit::identify::dpe::{self, DpeOptions, GridOptions, Term};
use rigfit::identify::frf;
use rigfit::identify::idim::{self, IdimOptions};
use rigfit::identify::modal::{self, ModalOptions, Response};
use rigfit::identify::nimiso::{self, NimisoOptions, Nonlinearity};
use rigfit::identify::plot::{Panel, panels_svg};
use rigfit::identify::rfs::{self, RfsOptions};

/// `rigfit identify`.
#[derive(Debug, Args)]
pub struct IdentifyArgs {
    /// The method.
    #[command(subcommand)]
    pub method: Method,
}

/// The identification methods.
#[derive(Debug, Subcommand)]
pub enum Method {
    /// Restoring-force surface and direct parameter estimation of a base-excited
    /// SDOF rig (document 000, §3.2–3.3).
    #[command(after_help = "Example:\n  \
        rigfit identify rfs rig.csv --x x_m --accel a_ms2 --mass 9 \\\n    \
        --terms linear,cubic,power-stiffness,viscous,cubic-damping,power-damping \\\n    \
        --out sdof.json --svg rfs.svg\n\n\
        Input: CSV with a time column (s), the relative displacement of the mass (m)\n\
        and the base acceleration (m/s²); columns by header name or 1-based position.")]
    Rfs(RfsArgs),
    /// H1/H2 frequency response with coherence and a modal fit (documents 003, 002).
    #[command(after_help = "Example:\n  \
        rigfit identify frf hammer.csv --input force_N --output x_m --modes 2 \\\n    \
        --f-min 5 --f-max 80 --csv frf.csv --svg frf.svg --out modes.json\n\n\
        Input: CSV with a time column (s), the input force (N) and the response\n\
        (m, m/s or m/s², see --response).")]
    Frf(FrfArgs),
    /// Inverse-model least squares for a driven mass with friction (EMPS IDIM-LS).
    #[command(after_help = "Example:\n  \
        rigfit identify idim tests/data/emps/emps_position_voltage.csv \\\n    \
        --position position_m --force controller_voltage_V --gain 35.15065188248547 \\\n    \
        --sample-rate 1000 --out emps.json --svg emps.svg\n\n\
        Input: CSV with the position (m) and the applied force (N, or a signal times --gain).")]
    Idim(IdimArgs),
    /// Reverse-path nonlinear MISO analysis of a force-driven rig (Bendat; document 004).
    #[command(after_help = "Example:\n  \
        rigfit identify nimiso rig.csv --motion x_m --force force_N --nonlinear cubic \\\n    \
        --f-min 3 --f-max 38 --out rig.json --svg paths.svg\n\n\
        Input: CSV with a time column (s), the measured motion (m) and the applied force (N).")]
    Nimiso(NimisoArgs),
    /// Transmissibility, frequency-domain ARX coefficients and the stiffness and
    /// damping of the element between two measured points (document 002, §2.1.2).
    #[command(
        after_help = "Example (the strut of the quarter car, unsprung to sprung mass):\n  \
        rigfit identify arx car.csv --input unsprung_acceleration \\\n    \
        --output sprung_acceleration --mass 350 --names k2,c2 --f-min 0.5 --f-max 30 \\\n    \
        --out strut.json --svg strut.svg\n\n\
        The tire (wheel pan to unsprung mass, carrying both masses):\n  \
        rigfit identify arx car.csv --input wheel_pan_acceleration \\\n    \
        --output unsprung_acceleration,sprung_acceleration --mass 40,350 --names k1,c1 ...\n\n\
        Input: CSV with a time column (s), the reference channel and the response\n\
        channels, all the same quantity (accelerations, velocities or displacements)."
    )]
    Arx(ArxArgs),
    /// The 2 × 2 impedance and receptance matrices of a point mass in x and y
    /// from two impacts, with K, C and M fitted (document 003, the FRF method's
    /// two-degree-of-freedom form).
    #[command(after_help = "Example:\n  \
        rigfit identify impedance hx.csv hy.csv --force force_N --x x_m --y y_m \\\n    \
        --mass 3 --f-min 20 --f-max 400 --out bearing.json --svg impedance.svg\n\n\
        Input: two CSV records of equal rate, the first struck in x, the second in y,\n\
        each with a time column (s), the hammer force (N) and the x and y displacements (m).")]
    Impedance(ImpedanceArgs),
    /// The change of a quarter car's strut stiffness between two records, by the
    /// experimental sensitivity functions (document 002, §2.2 and §3.4).
    #[command(after_help = "Example:\n  \
        rigfit identify sensitivity base.csv changed.csv --wheel-pan wheel_pan_acceleration \\\n    \
        --unsprung unsprung_acceleration --sprung sprung_acceleration \\\n    \
        --k1 1.751e5 --c1 1751 --f-min 5 --f-max 15 --name k2 --base-value 3e4 --svg dk.svg\n\n\
        Input: two CSV records (before and after the change), each with a time column (s)\n\
        and the wheel pan's, the unsprung mass's and the sprung mass's motion, all the same\n\
        quantity. The tire force of Eq. 10 stands in for a load cell.")]
    Sensitivity(SensitivityArgs),
}

/// A restoring-force term on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TermArg {
    /// kf1·x
    Linear,
    /// kf2·x³
    Cubic,
    /// kf3·|x|^β·sgn x
    PowerStiffness,
    /// cf1·ẋ
    Viscous,
    /// cf2·ẋ³
    CubicDamping,
    /// cf3·|ẋ|^α·sgn ẋ
    PowerDamping,
    /// fc·sgn ẋ
    Coulomb,
}

impl From<TermArg> for Term {
    fn from(t: TermArg) -> Self {
        match t {
            TermArg::Linear => Term::Linear,
            TermArg::Cubic => Term::Cubic,
            TermArg::PowerStiffness => Term::PowerStiffness,
            TermArg::Viscous => Term::Viscous,
            TermArg::CubicDamping => Term::CubicDamping,
            TermArg::PowerDamping => Term::PowerDamping,
            TermArg::Coulomb => Term::Coulomb,
        }
    }
}

/// What the FRF's output column measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ResponseArg {
    /// Displacement (m).
    Displacement,
    /// Velocity (m/s).
    Velocity,
    /// Acceleration (m/s²).
    Acceleration,
}

/// The nonlinear input of the reverse path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum NonlinearArg {
    /// x³ (cubic stiffness, fragment name k3).
    Cubic,
    /// sgn ẋ (Coulomb friction, fragment name f_c).
    SignVelocity,
    /// |ẋ|·ẋ (quadratic damping, fragment name c2).
    QuadraticDamping,
}

/// Options every method shares.
#[derive(Debug, Args)]
pub struct Common {
    /// Write the campaign fragment (JSON) here.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write the figure (SVG) here.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Write fixed values instead of free parameters with bounds and an init seed.
    #[arg(long)]
    pub fixed: bool,
}

/// `rigfit identify rfs`.
#[derive(Debug, Args)]
pub struct RfsArgs {
    /// CSV record.
    pub data: PathBuf,
    /// Time column (s).
    #[arg(long, default_value = "1")]
    pub time: String,
    /// Relative displacement column (m).
    #[arg(long, default_value = "2")]
    pub x: String,
    /// Base acceleration column (m/s²).
    #[arg(long, default_value = "3")]
    pub accel: String,
    /// Mass of the moving body (kg), measured.
    #[arg(long)]
    pub mass: f64,
    /// Terms of the restoring force.
    #[arg(long, value_enum, value_delimiter = ',', default_values_t = [TermArg::Linear, TermArg::Viscous])]
    pub terms: Vec<TermArg>,
    /// Fixed damping exponent α (default: searched).
    #[arg(long)]
    pub alpha: Option<f64>,
    /// Fixed stiffness exponent β (default: searched).
    #[arg(long)]
    pub beta: Option<f64>,
    /// Zero-phase low-pass on x and a before differencing (Hz).
    #[arg(long)]
    pub cutoff: Option<f64>,
    /// Order of that Butterworth filter.
    #[arg(long, default_value_t = 4)]
    pub filter_order: usize,
    #[command(flatten)]
    pub common: Common,
}

/// `rigfit identify frf`.
#[derive(Debug, Args)]
pub struct FrfArgs {
    /// CSV record.
    pub data: PathBuf,
    /// Time column (s).
    #[arg(long, default_value = "1")]
    pub time: String,
    /// Input (force) column.
    #[arg(long, default_value = "2")]
    pub input: String,
    /// Output (response) column.
    #[arg(long, default_value = "3")]
    pub output: String,
    /// What the output measures.
    #[arg(long, value_enum, default_value_t = ResponseArg::Displacement)]
    pub response: ResponseArg,
    /// Samples per Welch segment (default: the largest power of two giving ≥ 8 segments).
    #[arg(long)]
    pub segment: Option<usize>,
    /// Modes to fit in the band (0: no modal fit).
    #[arg(long, default_value_t = 1)]
    pub modes: usize,
    /// Lower edge of the fitted band (Hz).
    #[arg(long)]
    pub f_min: Option<f64>,
    /// Upper edge of the fitted band (Hz).
    #[arg(long)]
    pub f_max: Option<f64>,
    /// Lines with a lower coherence are left out of the fit.
    #[arg(long, default_value_t = 0.8)]
    pub min_coherence: f64,
    /// Campaign names of the SDOF mass, stiffness and damping (one mode).
    #[arg(long, value_delimiter = ',', default_values_t = ["m".to_string(), "k".to_string(), "c".to_string()])]
    pub names: Vec<String>,
    /// Write the FRF table (frequency, H1, H2, coherence, fit) here.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    #[command(flatten)]
    pub common: Common,
}

/// `rigfit identify idim`.
#[derive(Debug, Args)]
pub struct IdimArgs {
    /// CSV record.
    pub data: PathBuf,
    /// Position column (m).
    #[arg(long, default_value = "1")]
    pub position: String,
    /// Force column (N, or a signal scaled by --gain).
    #[arg(long, default_value = "2")]
    pub force: String,
    /// Force per unit of the force column (e.g. EMPS gtau, N/V).
    #[arg(long, default_value_t = 1.0)]
    pub gain: f64,
    /// Time column (s); or give --sample-rate.
    #[arg(long, conflicts_with = "sample_rate")]
    pub time: Option<String>,
    /// Sample rate (Hz) when the record has no time column.
    #[arg(long)]
    pub sample_rate: Option<f64>,
    /// Cut-off of the zero-phase Butterworth low-pass (Hz).
    #[arg(long, default_value_t = 100.0)]
    pub cutoff: f64,
    /// Order of that filter.
    #[arg(long, default_value_t = 4)]
    pub filter_order: usize,
    /// Keep every N-th row in the least squares.
    #[arg(long, default_value_t = 10)]
    pub decimation: usize,
    #[command(flatten)]
    pub common: Common,
}

/// `rigfit identify nimiso`.
#[derive(Debug, Args)]
pub struct NimisoArgs {
    /// CSV record.
    pub data: PathBuf,
    /// Time column (s).
    #[arg(long, default_value = "1")]
    pub time: String,
    /// Motion column (m), the reverse path's input.
    #[arg(long, default_value = "2")]
    pub motion: String,
    /// Force column (N), the reverse path's output.
    #[arg(long, default_value = "3")]
    pub force: String,
    /// The nonlinear input v = g(x, ẋ).
    #[arg(long, value_enum, default_value_t = NonlinearArg::Cubic)]
    pub nonlinear: NonlinearArg,
    /// Samples per Welch segment (default: the largest power of two giving ≥ 8 segments).
    #[arg(long)]
    pub segment: Option<usize>,
    /// Lower edge of the fitted band (Hz).
    #[arg(long)]
    pub f_min: f64,
    /// Upper edge of the fitted band (Hz).
    #[arg(long)]
    pub f_max: f64,
    #[command(flatten)]
    pub common: Common,
}

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
    /// Lower edge of the fitted band (Hz).
    #[arg(long)]
    pub f_min: f64,
    /// Upper edge of the fitted band (Hz).
    #[arg(long)]
    pub f_max: f64,
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

/// `rigfit identify impedance`.
#[derive(Debug, Args)]
pub struct ImpedanceArgs {
    /// CSV record of the impact in x.
    pub x_test: PathBuf,
    /// CSV record of the impact in y.
    pub y_test: PathBuf,
    /// Time column (s).
    #[arg(long, default_value = "1")]
    pub time: String,
    /// Hammer force column (N).
    #[arg(long, default_value = "2")]
    pub force: String,
    /// x displacement column (m).
    #[arg(long, default_value = "3")]
    pub x: String,
    /// y displacement column (m).
    #[arg(long, default_value = "4")]
    pub y: String,
    /// The mass (kg), if known (default: fitted).
    #[arg(long)]
    pub mass: Option<f64>,
    /// Lower edge of the fitted band (Hz).
    #[arg(long)]
    pub f_min: f64,
    /// Upper edge of the fitted band (Hz).
    #[arg(long)]
    pub f_max: f64,
    #[command(flatten)]
    pub common: Common,
}

/// `rigfit identify sensitivity`.
#[derive(Debug, Args)]
pub struct SensitivityArgs {
    /// CSV record before the change.
    pub base: PathBuf,
    /// CSV record after the change.
    pub changed: PathBuf,
    /// Time column (s).
    #[arg(long, default_value = "1")]
    pub time: String,
    /// Wheel-pan (tire patch) column.
    #[arg(long, default_value = "2")]
    pub wheel_pan: String,
    /// Unsprung-mass column.
    #[arg(long, default_value = "3")]
    pub unsprung: String,
    /// Sprung-mass column.
    #[arg(long, default_value = "4")]
    pub sprung: String,
    /// Tire stiffness K1 (N/m), for the input force of Eq. 10.
    #[arg(long)]
    pub k1: f64,
    /// Tire damping C1 (N·s/m).
    #[arg(long, default_value_t = 0.0)]
    pub c1: f64,
    /// Samples per segment (default: the largest power of two giving ≥ 8 segments).
    #[arg(long)]
    pub segment: Option<usize>,
    /// Lower edge of the band ΔK is averaged over (Hz).
    #[arg(long)]
    pub f_min: f64,
    /// Upper edge of that band (Hz).
    #[arg(long)]
    pub f_max: f64,
    /// Campaign name of the strut stiffness, for the fragment.
    #[arg(long, default_value = "k2")]
    pub name: String,
    /// The strut stiffness before the change (N/m): with it, the fragment holds
    /// the value after the change.
    #[arg(long)]
    pub base_value: Option<f64>,
    #[command(flatten)]
    pub common: Common,
}

/// Runs one identification method.
pub fn identify(args: &IdentifyArgs, out: &Output) -> Result<()> {
    match &args.method {
        Method::Rfs(a) => rfs_cmd(a, out),
        Method::Frf(a) => frf_cmd(a, out),
        Method::Idim(a) => idim_cmd(a, out),
        Method::Nimiso(a) => nimiso_cmd(a, out),
        Method::Arx(a) => arx_cmd(a, out),
        Method::Impedance(a) => impedance_cmd(a, out),
        Method::Sensitivity(a) => sensitivity_cmd(a, out),
    }
}

fn write_svg(path: Option<&Path>, title: &str, panels: &[Panel], columns: usize) -> Result<()> {
    if let Some(path) = path {
        let svg = panels_svg(title, panels, columns)?;
        rigfit::base::fsutil::atomic_write(path, svg.as_bytes())
            .with_context(|| format!("writing `{}`", path.display()))?;
    }
    Ok(())
}

fn rfs_cmd(a: &RfsArgs, out: &Output) -> Result<()> {
    let bad = |e| in_file(&a.data, e);
    let table = Table::read(&a.data).map_err(bad)?;
    let t = table.column(&a.time).map_err(bad)?;
    let x = table.column(&a.x).map_err(bad)?;
    let acc = table.column(&a.accel).map_err(bad)?;
    let surface = rfs::surface(
        t,
        x,
        acc,
        &RfsOptions {
            mass: a.mass,
            cutoff_hz: a.cutoff,
            filter_order: a.filter_order,
        },
    )
    .map_err(bad)?;
    let opts = DpeOptions {
        terms: a.terms.iter().map(|&t| t.into()).collect(),
        alpha: a.alpha,
        beta: a.beta,
        grid: GridOptions::default(),
    };
    let r = dpe::estimate(&surface, &opts).map_err(bad)?;
    write_svg(
        a.common.svg.as_deref(),
        &format!("restoring force of {}", a.data.display()),
        &dpe::figure(&surface, &r),
        3,
    )?;
    let fragment = r.to_campaign_fragment(a.common.fixed, &opts.grid);
    deliver(
        out,
        a.common.out.as_deref(),
        serde_json::json!({"dpe": r}),
        &fragment,
        || {
            let mut s = format!(
                "restoring-force surface of {} ({} samples at {:.0} Hz, m = {} kg)\n",
                a.data.display(),
                r.samples,
                surface.sample_rate_hz,
                r.mass
            );
            for c in &r.coefficients {
                s += &format!(
                    "  {:<4} = {:>12.5e} ± {:.2e} {}\n",
                    c.param, c.value, c.std_error, c.unit
                );
            }
            if let Some(al) = r.alpha {
                s += &format!("  alpha = {al:.4}\n");
            }
            if let Some(b) = r.beta {
                s += &format!("  beta  = {b:.4}\n");
            }
            if !r.search.is_empty() {
                s += &format!(
                    "  exponent grid: {} levels, step {} → {}\n",
                    r.search.len(),
                    r.search[0].step,
                    r.search[r.search.len() - 1].step
                );
            }
            s += &format!(
                "  R² = {:.6}, RMS residual {:.4e} N, largest {:.4e} N, condition {:.2e}\n",
                r.r2, r.rms_residual, r.max_residual, r.condition
            );
            s
        },
    )
}

fn frf_cmd(a: &FrfArgs, out: &Output) -> Result<()> {
    let bad = |e| in_file(&a.data, e);
    let table = Table::read(&a.data).map_err(bad)?;
    let t = table.column(&a.time).map_err(bad)?;
    let u = table.column(&a.input).map_err(bad)?;
    let y = table.column(&a.output).map_err(bad)?;
    let fs = 1.0 / sample_interval(t).map_err(bad)?;
    let est = frf::estimate(u, y, fs, a.segment).map_err(bad)?;
    let response = match a.response {
        ResponseArg::Displacement => Response::Displacement,
        ResponseArg::Velocity => Response::Velocity,
        ResponseArg::Acceleration => Response::Acceleration,
    };
    let fit = if a.modes > 0 {
        let opts = ModalOptions {
            modes: a.modes,
            f_min: a.f_min.unwrap_or(est.settings.resolution_hz),
            f_max: a.f_max.unwrap_or(fs / 2.0),
            response,
            min_coherence: a.min_coherence,
            iterations: 10,
        };
        Some(modal::fit(&est.freqs, &est.h1, &est.coherence, &opts).map_err(bad)?)
    } else {
        None
    };
    if let Some(path) = &a.csv {
        let mut text = String::from(
            "frequency_Hz,h1_re,h1_im,h1_abs,h1_phase_rad,h2_abs,h2_phase_rad,coherence,fit_abs,fit_phase_rad\n",
        );
        for k in 0..est.freqs.len() {
            let f = est.freqs[k];
            let fitted = fit
                .as_ref()
                .map(|m| m.response(f, response))
                .unwrap_or(f64::NAN.into());
            text += &format!(
                "{f},{},{},{},{},{},{},{},{},{}\n",
                est.h1[k].re,
                est.h1[k].im,
                est.h1[k].norm(),
                est.h1[k].arg(),
                est.h2[k].norm(),
                est.h2[k].arg(),
                est.coherence[k],
                fitted.norm(),
                fitted.arg()
            );
        }
        rigfit::base::fsutil::atomic_write(path, text.as_bytes())
            .with_context(|| format!("writing `{}`", path.display()))?;
    }
    write_svg(
        a.common.svg.as_deref(),
        &format!("frequency response of {}", a.data.display()),
        &modal::figure(&est, fit.as_ref(), response),
        1,
    )?;
    let fragment = match &fit {
        Some(m) => m.to_campaign_fragment(&a.names, a.common.fixed),
        None => serde_json::json!({"params": {}}),
    };
    deliver(
        out,
        a.common.out.as_deref(),
        serde_json::json!({"welch": est.settings, "modal": fit}),
        &fragment,
        || {
            let w = &est.settings;
            let mut s = format!(
                "frequency response of {} ({} samples at {:.1} Hz)\n  Welch: {} window, {} samples × {} segments, resolution {:.4} Hz\n",
                a.data.display(),
                u.len(),
                fs,
                w.window,
                w.segment_len,
                w.n_segments,
                w.resolution_hz
            );
            if let Some(m) = &fit {
                for (i, md) in m.modes.iter().enumerate() {
                    s += &format!(
                        "  mode {}: f_n = {:.4} Hz, ζ = {:.5}, modal m = {:.5e} kg, k = {:.5e} N/m, c = {:.5e} N·s/m\n",
                        i + 1,
                        md.natural_frequency_hz,
                        md.damping_ratio,
                        md.mass,
                        md.stiffness,
                        md.damping
                    );
                }
                s += &format!(
                    "  fit over {} lines: relative RMS error {:.4}\n",
                    m.lines, m.relative_error
                );
            }
            s
        },
    )
}

fn idim_cmd(a: &IdimArgs, out: &Output) -> Result<()> {
    let bad = |e| in_file(&a.data, e);
    let table = Table::read(&a.data).map_err(bad)?;
    let q = table.column(&a.position).map_err(bad)?;
    let tau: Vec<f64> = table
        .column(&a.force)
        .map_err(bad)?
        .iter()
        .map(|v| a.gain * v)
        .collect();
    let fs = match (&a.time, a.sample_rate) {
        (Some(col), _) => 1.0 / sample_interval(table.column(col).map_err(bad)?).map_err(bad)?,
        (None, Some(fs)) => fs,
        (None, None) => anyhow::bail!(super::BadInput(
            "give the sample rate (--sample-rate) or a time column (--time)".into()
        )),
    };
    let opts = IdimOptions {
        sample_rate_hz: fs,
        cutoff_hz: a.cutoff,
        filter_order: a.filter_order,
        decimation: a.decimation,
        border: 49,
    };
    let r = idim::estimate(q, &tau, &opts).map_err(bad)?;
    write_svg(
        a.common.svg.as_deref(),
        &format!("inverse model of {}", a.data.display()),
        &idim::figure(&r),
        1,
    )?;
    let fragment = r.to_campaign_fragment(a.common.fixed);
    deliver(
        out,
        a.common.out.as_deref(),
        serde_json::json!({"idim": r}),
        &fragment,
        || {
            let mut s = format!(
                "inverse model of {} ({} rows after decimation by {})\n",
                a.data.display(),
                r.rows,
                opts.decimation
            );
            for e in &r.estimates {
                s += &format!(
                    "  {:<3} = {:>10.4} ± {:.2} % {}\n",
                    e.param, e.value, e.relative_error_percent, e.unit
                );
            }
            s += &format!("  R² = {:.5}, RMS residual {:.4} N\n", r.r2, r.rms_residual);
            s
        },
    )
}

fn nimiso_cmd(a: &NimisoArgs, out: &Output) -> Result<()> {
    let bad = |e| in_file(&a.data, e);
    let table = Table::read(&a.data).map_err(bad)?;
    let t = table.column(&a.time).map_err(bad)?;
    let x = table.column(&a.motion).map_err(bad)?;
    let f = table.column(&a.force).map_err(bad)?;
    let fs = 1.0 / sample_interval(t).map_err(bad)?;
    let (nonlinearity, name) = match a.nonlinear {
        NonlinearArg::Cubic => (Nonlinearity::Cubic, "k3"),
        NonlinearArg::SignVelocity => (Nonlinearity::SignVelocity, "f_c"),
        NonlinearArg::QuadraticDamping => (Nonlinearity::QuadraticDamping, "c2"),
    };
    let opts = NimisoOptions {
        sample_rate_hz: fs,
        segment_len: a.segment,
        nonlinearity,
        f_min: a.f_min,
        f_max: a.f_max,
    };
    let (path, r) = nimiso::analyse(x, f, &opts).map_err(bad)?;
    write_svg(
        a.common.svg.as_deref(),
        &format!("reverse-path analysis of {}", a.data.display()),
        &nimiso::figure(&path, &r, (a.f_min, a.f_max)),
        3,
    )?;
    let fragment = r.to_campaign_fragment(name, a.common.fixed);
    deliver(
        out,
        a.common.out.as_deref(),
        serde_json::json!({"nimiso": r}),
        &fragment,
        || {
            format!(
                "reverse-path analysis of {} ({} lines in {}…{} Hz, {} segments of {})\n  \
                 m = {:.5e} kg, k = {:.5e} N/m, c = {:.5e} N·s/m\n  \
                 {name} = {:.5e} (spread over the band {:.2e})\n  \
                 coherence: linear path {:.4}, nonlinear path adds {:.4}\n",
                a.data.display(),
                r.lines,
                a.f_min,
                a.f_max,
                r.settings.n_segments,
                r.settings.segment_len,
                r.mass,
                r.stiffness,
                r.damping,
                r.nonlinear_coefficient,
                r.nonlinear_spread,
                r.mean_coherence_linear,
                r.mean_coherence_nonlinear
            )
        },
    )
}

fn arx_cmd(a: &ArxArgs, out: &Output) -> Result<()> {
    use rigfit::identify::transmissibility::{self as tr, ArxForm};
    let bad = |e| in_file(&a.data, e);
    if a.names.len() != 2 {
        anyhow::bail!(super::BadInput(format!(
            "--names takes the stiffness and the damping name, found {}",
            a.names.len()
        )));
    }
    let table = Table::read(&a.data).map_err(bad)?;
    let t = table.column(&a.time).map_err(bad)?;
    let u = table.column(&a.input).map_err(bad)?;
    let ys = a
        .output
        .iter()
        .map(|c| table.column(c))
        .collect::<Result<Vec<_>, _>>()
        .map_err(bad)?;
    let fs = 1.0 / sample_interval(t).map_err(bad)?;
    let spec = tr::block_spectra(u, &ys, fs, a.segment).map_err(bad)?;
    let (ts, coherences): (Vec<_>, Vec<_>) =
        (0..ys.len()).map(|c| spec.transmissibility(c)).unzip();
    let form = match a.form {
        ArxFormArg::Linear => ArxForm::Linear,
        ArxFormArg::Cubic => ArxForm::Cubic,
    };
    let lines = tr::arx(&spec, form, a.f_min, a.f_max).map_err(bad)?;
    let fit = tr::element_fit(
        &spec.freqs,
        &ts,
        &coherences[0],
        &a.mass,
        (a.f_min, a.f_max),
        a.min_coherence,
    )
    .map_err(bad)?;
    if let Some(path) = &a.csv {
        let mut text = String::from(
            "frequency_Hz,T_abs,T_phase_rad,coherence,model_abs,model_phase_rad,B_abs,A_minus_abs,A_plus_abs,explained\n",
        );
        for l in &lines {
            let k = (l.frequency_hz / spec.settings.resolution_hz).round() as usize;
            let beyond: Vec<_> = ts[1..].iter().map(|t| t[k]).collect();
            let m = fit.model(l.frequency_hz, &beyond);
            text += &format!(
                "{},{},{},{},{},{},{},{},{},{}\n",
                l.frequency_hz,
                ts[0][k].norm(),
                ts[0][k].arg(),
                coherences[0][k],
                m.norm(),
                m.arg(),
                l.b.0.hypot(l.b.1),
                l.a_minus.0.hypot(l.a_minus.1),
                l.a_plus.0.hypot(l.a_plus.1),
                l.explained
            );
        }
        rigfit::base::fsutil::atomic_write(path, text.as_bytes())
            .with_context(|| format!("writing `{}`", path.display()))?;
    }
    write_svg(
        a.common.svg.as_deref(),
        &format!("transmissibility of {}", a.data.display()),
        &tr::figure(
            &spec.freqs,
            &ts,
            &coherences[0],
            Some(&fit),
            &lines,
            (a.f_min, a.f_max),
        ),
        3,
    )?;
    let fragment = fit.to_campaign_fragment([&a.names[0], &a.names[1]], a.common.fixed);
    let mean_feature = |pick: &dyn Fn(&tr::ArxLine) -> (f64, f64)| {
        let v: Vec<f64> = lines
            .iter()
            .map(|l| {
                let (re, im) = pick(l);
                re.hypot(im)
            })
            .filter(|v| v.is_finite())
            .collect();
        v.iter().sum::<f64>() / v.len().max(1) as f64
    };
    deliver(
        out,
        a.common.out.as_deref(),
        serde_json::json!({"welch": spec.settings, "element": fit, "arx": lines}),
        &fragment,
        || {
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
                u.len(),
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
                mean_feature(&|l| l.a_minus),
                mean_feature(&|l| l.a_plus)
            )
        },
    )
}

fn impedance_cmd(a: &ImpedanceArgs, out: &Output) -> Result<()> {
    use rigfit::identify::impedance::{self, ImpactRecord};
    let read = |path: &Path| -> Result<(Table, f64)> {
        let bad = |e| in_file(path, e);
        let table = Table::read(path).map_err(bad)?;
        let fs = 1.0 / sample_interval(table.column(&a.time).map_err(bad)?).map_err(bad)?;
        Ok((table, fs))
    };
    let (tx, fsx) = read(&a.x_test)?;
    let (ty, fsy) = read(&a.y_test)?;
    if ((fsx - fsy) / fsx).abs() > 1e-6 {
        anyhow::bail!(super::BadInput(format!(
            "the two records have different sample rates ({fsx} Hz and {fsy} Hz)"
        )));
    }
    let record = |t: &Table, path: &Path| -> Result<(Vec<f64>, Vec<f64>, Vec<f64>)> {
        let bad = |e| in_file(path, e);
        Ok((
            t.column(&a.force).map_err(bad)?.to_vec(),
            t.column(&a.x).map_err(bad)?.to_vec(),
            t.column(&a.y).map_err(bad)?.to_vec(),
        ))
    };
    let (f1, x1, y1) = record(&tx, &a.x_test)?;
    let (f2, x2, y2) = record(&ty, &a.y_test)?;
    let mats = impedance::matrices(
        ImpactRecord {
            force: &f1,
            x: &x1,
            y: &y1,
        },
        ImpactRecord {
            force: &f2,
            x: &x2,
            y: &y2,
        },
        fsx,
    )
    .map_err(|e| in_file(&a.x_test, e))?;
    let fit =
        impedance::fit(&mats, (a.f_min, a.f_max), a.mass).map_err(|e| in_file(&a.x_test, e))?;
    write_svg(
        a.common.svg.as_deref(),
        &format!(
            "impedance from {} and {}",
            a.x_test.display(),
            a.y_test.display()
        ),
        &impedance::figure(&mats, &fit),
        4,
    )?;
    let fragment = fit.to_campaign_fragment(a.common.fixed);
    deliver(
        out,
        a.common.out.as_deref(),
        serde_json::json!({"impedance": fit}),
        &fragment,
        || {
            let (k, c) = (&fit.stiffness, &fit.damping);
            let mut s = format!(
                "impedance from {} (x impact) and {} (y impact), {} lines in {}…{} Hz\n  \
                 M = {:.5e} kg{}\n  \
                 K = [[{:.5e}, {:.5e}], [{:.5e}, {:.5e}]] N/m\n  \
                 C = [[{:.5e}, {:.5e}], [{:.5e}, {:.5e}]] N·s/m\n  \
                 R² of Re Z: xx {:.5}, yy {:.5}; of Im Z: xx {:.5}, xy {:.5}, yx {:.5}, yy {:.5}\n  \
                 as bearing_2dof:",
                a.x_test.display(),
                a.y_test.display(),
                fit.lines,
                a.f_min,
                a.f_max,
                fit.mass,
                if fit.mass_given { " (given)" } else { "" },
                k[0][0],
                k[0][1],
                k[1][0],
                k[1][1],
                c[0][0],
                c[0][1],
                c[1][0],
                c[1][1],
                fit.r2_real[0][0],
                fit.r2_real[1][1],
                fit.r2_imag[0][0],
                fit.r2_imag[0][1],
                fit.r2_imag[1][0],
                fit.r2_imag[1][1]
            );
            for (name, v) in fit.bearing_params() {
                s += &format!(" {name} = {v:.5e}");
            }
            s + "\n"
        },
    )
}

fn sensitivity_cmd(a: &SensitivityArgs, out: &Output) -> Result<()> {
    use rigfit::identify::transmissibility as tr;
    let spectra = |path: &Path| -> Result<tr::BlockSpectra> {
        let bad = |e| in_file(path, e);
        let table = Table::read(path).map_err(bad)?;
        let fs = 1.0 / sample_interval(table.column(&a.time).map_err(bad)?).map_err(bad)?;
        let u = table.column(&a.wheel_pan).map_err(bad)?;
        let y1 = table.column(&a.unsprung).map_err(bad)?;
        let y2 = table.column(&a.sprung).map_err(bad)?;
        tr::block_spectra(u, &[y1, y2], fs, a.segment).map_err(bad)
    };
    let (base, changed) = (spectra(&a.base)?, spectra(&a.changed)?);
    let r = tr::strut_sensitivity(&base, &changed, a.k1, a.c1, (a.f_min, a.f_max))
        .map_err(|e| in_file(&a.changed, e))?;
    write_svg(
        a.common.svg.as_deref(),
        &format!(
            "sensitivity: {} against {}",
            a.changed.display(),
            a.base.display()
        ),
        &tr::sensitivity_figure(&r, (a.f_min, a.f_max)),
        2,
    )?;
    let mut params = serde_json::Map::new();
    if let Some(k) = a.base_value {
        let v = k + r.change.mean;
        params.insert(
            a.name.clone(),
            if a.common.fixed {
                serde_json::json!(v)
            } else {
                let w = (0.5 * v.abs()).max(10.0 * r.change.spread);
                serde_json::json!({"min": (v - w).max(0.0), "max": v + w, "init": v})
            },
        );
    }
    let fragment = serde_json::json!({ "params": params });
    deliver(
        out,
        a.common.out.as_deref(),
        serde_json::json!({"welch": base.settings, "sensitivity": r}),
        &fragment,
        || {
            let mut s = format!(
                "strut stiffness change from {} to {} (Eq. 11 and 8a, tire force of Eq. 10)\n  \
                 ΔK12 = {:.5e} N/m (spread {:.2e} over {} lines in {}…{} Hz)\n",
                a.base.display(),
                a.changed.display(),
                r.change.mean,
                r.change.spread,
                r.change.per_line.len(),
                a.f_min,
                a.f_max
            );
            if let Some(k) = a.base_value {
                s += &format!(
                    "  {} = {:.5e} N/m after the change\n",
                    a.name,
                    k + r.change.mean
                );
            }
            s
        },
    )
}
