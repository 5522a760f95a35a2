//! Inverse-model least squares for a driven mass with viscous and Coulomb
//! friction (IDIM-LS): the recipe of the EMPS benchmark (Janot, Gautier, Brunot,
//! 2019, "Data set and reference models of EMPS"), for *Non-linear signal analysis
//! applied to surface wear condition monitoring in reciprocating sliding testing
//! machines*'s friction rigs (§2 Eq. 2 with `k = 0`, Coulomb `g(ẋ) = sgn ẋ`).
//!
//! The inverse model is linear in the parameters:
//!
//! ```text
//! τ = M·q̈ + Fv·q̇ + Fc·sgn(q̇) + OFF
//! ```
//!
//! with `τ` the applied force (N; for EMPS `gtau·vir`) and `q` the measured
//! position (m). The benchmark's recipe, followed step by step:
//!
//! 1. the position is low-passed by a Butterworth filter run forward and
//!    backward (4th order, 100 Hz for EMPS);
//! 2. `q̇` is its central difference and `q̈` the central difference of `q̇`;
//! 3. the first 49 samples are dropped (the filter's and the differences' start),
//!    and the last two (one-sided differences; the benchmark keeps them);
//! 4. "parallel decimation": every column of the observation matrix
//!    `[q̈, q̇, sgn q̇, 1]` and the force are decimated alike by 10 (zero-phase
//!    Chebyshev I anti-alias filter, see [`super::signal::decimate`]), so both
//!    sides of the equation see the same band — the Coulomb column too, which
//!    is therefore smoothed at each reversal;
//! 5. least squares gives the parameters and their standard errors
//!    `σ̂·sqrt(diag (AᵀA)⁻¹)`.

use serde::Serialize;
use serde_json::{Value, json};

use super::lsq::{LinearFit, least_squares};
use super::signal::{self, butter_lowpass, decimate, derivative, downsample, filtfilt};
use super::{IdentifyError, check_inputs, require_points};

/// Options of [`estimate`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IdimOptions {
    /// Sample rate of the record (Hz).
    pub sample_rate_hz: f64,
    /// Cut-off of the zero-phase Butterworth low-pass on `q` and `τ` (Hz).
    pub cutoff_hz: f64,
    /// Its order.
    pub filter_order: usize,
    /// Decimation factor of the rows (≥ 2).
    pub decimation: usize,
    /// Samples dropped at the start, before decimating.
    pub border: usize,
}

impl Default for IdimOptions {
    fn default() -> Self {
        Self {
            sample_rate_hz: 1000.0,
            cutoff_hz: 100.0,
            filter_order: 4,
            decimation: 10,
            border: 49,
        }
    }
}

/// One estimated parameter.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Estimate {
    /// Campaign parameter name.
    pub param: &'static str,
    /// Value.
    pub value: f64,
    /// Standard error.
    pub std_error: f64,
    /// Standard error relative to the value (%).
    pub relative_error_percent: f64,
    /// Unit.
    pub unit: &'static str,
}

/// The inverse-model fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IdimReport {
    /// Rows of the least squares (after decimation).
    pub rows: usize,
    /// `M` (kg), `Fv` (N·s/m), `Fc` (N), `OFF` (N), named `m`, `f_v`, `f_c`, `f_offset`.
    pub estimates: Vec<Estimate>,
    /// R² of the force.
    pub r2: f64,
    /// RMS residual force (N).
    pub rms_residual: f64,
    /// The options used.
    pub options: IdimOptions,
    /// The rows over time, for the figure (not in the JSON).
    #[serde(skip)]
    pub series: IdimSeries,
}

/// The inverse model's rows over time.
#[derive(Debug, Clone, PartialEq)]
pub struct IdimSeries {
    /// Measured force at the rows (N).
    pub force: Vec<f64>,
    /// Model force at the rows (N).
    pub model: Vec<f64>,
    /// Time of the rows (s).
    pub time: Vec<f64>,
}

const PARAMS: [(&str, &str); 4] = [
    ("m", "kg"),
    ("f_v", "N·s/m"),
    ("f_c", "N"),
    ("f_offset", "N"),
];

impl IdimReport {
    /// The estimate named `param`.
    pub fn get(&self, param: &str) -> Option<f64> {
        self.estimates
            .iter()
            .find(|e| e.param == param)
            .map(|e| e.value)
    }

    /// The campaign fragment in the names of the shipped `emps` rigs (`m`,
    /// `f_v`, `f_c`, `f_offset`): each free with `init` at the estimate and
    /// bounds of ±max(10 standard errors, 20 %), or plain numbers with `fixed`.
    pub fn to_campaign_fragment(&self, fixed: bool) -> Value {
        let mut params = serde_json::Map::new();
        for e in &self.estimates {
            let name = e.param;
            let entry = if fixed {
                json!(e.value)
            } else {
                let w = (10.0 * e.std_error).max(0.2 * e.value.abs());
                json!({"min": e.value - w, "max": e.value + w, "init": e.value})
            };
            params.insert(name.into(), entry);
        }
        json!({ "params": params })
    }
}

/// Fits the inverse model to position `q` (m) and force `tau` (N).
///
/// # Errors
/// Input errors, [`IdentifyError::InvalidOption`] for a bad filter or decimation,
/// and the least-squares errors.
pub fn estimate(q: &[f64], tau: &[f64], opts: &IdimOptions) -> Result<IdimReport, IdentifyError> {
    check_inputs("position and force", q, tau)?;
    // A force without spread (a gain of 0, a constant column) fits any model
    // exactly, with R² = 1 and parameters of 0 ± NaN %: nothing to identify.
    let (lo, hi) = tau
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
        return Err(IdentifyError::InvalidOption {
            name: "force",
            reason: format!(
                "the force (the column times --gain) is {lo:e} N at every sample: \
                 nothing to fit; give the column that holds the applied force or the drive \
                 signal (--force), and a gain other than 0 (--gain)"
            ),
        });
    }
    require_points("samples after the border", opts.border + 65, q.len())?;
    let fs = opts.sample_rate_hz;
    let sections = butter_lowpass(opts.filter_order, opts.cutoff_hz, fs)?;
    let dt = 1.0 / fs;
    let qf = filtfilt(&sections, q)?;
    let v = derivative(&qf, dt);
    let acc = derivative(&v, dt);
    let b = opts.border;
    // The last two samples have one-sided differences.
    let e = q.len() - 2;
    let sign: Vec<f64> = v[b..e].iter().map(|&v| signal::sign(v)).collect();
    let columns = vec![
        decimate(&acc[b..e], opts.decimation)?,
        decimate(&v[b..e], opts.decimation)?,
        decimate(&sign, opts.decimation)?,
        decimate(&vec![1.0; sign.len()], opts.decimation)?,
    ];
    let y = decimate(&tau[b..e], opts.decimation)?;
    let kept = sign.len();
    let time: Vec<f64> = downsample(
        &(b..b + kept).map(|i| i as f64 * dt).collect::<Vec<_>>(),
        (kept - 1) % opts.decimation,
        opts.decimation,
    );
    let fit: LinearFit = least_squares(&columns, &y)?;
    let model = (0..y.len())
        .map(|i| {
            (0..4)
                .map(|j| fit.coefficients[j].value * columns[j][i])
                .sum()
        })
        .collect();
    Ok(IdimReport {
        rows: fit.rows,
        estimates: PARAMS
            .iter()
            .enumerate()
            .map(|(j, &(param, unit))| Estimate {
                param,
                value: fit.coefficients[j].value,
                std_error: fit.coefficients[j].std_error,
                relative_error_percent: 100.0 * fit.coefficients[j].relative_error(),
                unit,
            })
            .collect(),
        r2: fit.r2,
        rms_residual: fit.rms,
        options: opts.clone(),
        series: IdimSeries {
            force: y,
            model,
            time,
        },
    })
}

/// Panel of the inverse-model figure: the measured force and the model's, over
/// time, at the rows of the least squares.
pub fn figure(report: &IdimReport) -> Vec<super::plot::Panel> {
    use super::plot::{FIT, MEASURED, Panel, Series, Style, thin};
    let pair = |ys: &[f64]| -> Vec<(f64, f64)> {
        thin(
            report
                .series
                .time
                .iter()
                .copied()
                .zip(ys.iter().copied())
                .collect(),
            4000,
        )
    };
    vec![Panel {
        caption: "applied force and inverse model".into(),
        x_desc: "time (s)".into(),
        y_desc: "force (N)".into(),
        series: vec![
            Series {
                label: "measured τ".into(),
                points: pair(&report.series.force),
                style: Style::Dots,
                color: MEASURED,
            },
            Series {
                label: "M·q̈ + Fv·q̇ + Fc·sgn q̇ + OFF".into(),
                points: pair(&report.series.model),
                style: Style::Line,
                color: FIT,
            },
        ],
    }]
}
