//! Ring-down analysis of a free decay (`rigfit ringdown`): a structure
//! ringing after a hammer impact or a release, such as the load cell of the
//! tensile rig after a brittle fracture.
//!
//! Once released, the ringing mode is a single free mass on its spring (for
//! the tensile rig, the load cell after the specimen has broken): `m1·ÿ + c1_post·ẏ + k1·y = 0`, and the measured force
//! `F1 = k1·y + c1_post·ẏ` decays as `A·e^{−ζω_n t}·cos(ω_d t + φ)`, with
//! `ω_n = sqrt(k1/m1)`, `ζ = c1_post / (2·sqrt(k1·m1))`, `ω_d = ω_n·sqrt(1 − ζ²)`.
//!
//! # Method
//! 1. **Start**: unless a start time is given, the free ringing starts at the
//!    largest drop (the largest fall from a running maximum to a later sample:
//!    a fracture, a release, the first swing after an impact). A drop below
//!    half the signal's range means no start was found; the analysis uses the
//!    samples from the peak before the drop on.
//! 2. **Frequency**: Welch PSD of the free ringing (see [`super::psd`]:
//!    Hann, 50 % overlap, segment length from the data, `Δf = fs/segment_len`,
//!    log-parabolic peak interpolation).
//! 3. **Logarithmic decrement**: positive peaks (local maxima over ±0.4 period,
//!    refined by a least-squares parabola over ±period/8, taken while above
//!    5 % of the first peak), each numbered by its cycle. For `K` separations
//!    `j = s, 2s, …, K·s` peaks (`s = max(1, ⌊(N−1)/(2K)⌋)`, `K` ≤ 5 by
//!    default) `δ_j` is the mean of `ln(x_i/x_{i+j}) / (cycles between them)`,
//!    `ζ_j = δ_j / sqrt(4π² + δ_j²)`; the report gives each `ζ_j`, their mean
//!    and spread (standard deviation, min, max).
//! 4. **Decay fit**: Levenberg–Marquardt on `(A, φ, σ = ζω_n, ω_d, offset)`
//!    (see [`DecayFit`]) from `ω_d` of the peak times and `ζ` of step 3; its ζ
//!    and ω_n are the refined values, with the fit's R².
//! 5. **Envelope**: the analytic signal of the band `f_n ± band` (default
//!    ±30 % of `f_n`; see [`super::envelope`]) gives a third ζ that does not
//!    depend on sampling the crests, and isolates the chosen mode of a record
//!    with several.
//! 6. **Agreement**: the three ζ (decrement, fit, envelope) are compared; when
//!    their spread exceeds [`AGREEMENT_TOLERANCE`] of their median the report
//!    carries a warning saying which disagree, since then at least one of them
//!    is wrong (too few samples per cycle for the peaks, another mode in the
//!    record, a decay that is not exponential).
//! 7. **Load cell**: with `m1` and `k1` given, `c1_post = 2ζ·sqrt(k1·m1)` (held
//!    fixed, so the fit acts as a single-mass oscillator with known `m1, k1`);
//!    with `m1` only, `k1 = m1·ω_n²` and `c1_post = 2ζ·m1·ω_n`; with `k1` only,
//!    `c1_post = 2ζ·k1/ω_n`. `c1_post` is given for both the decrement ζ and the
//!    fitted ζ; the fragment takes the fitted one.

use std::f64::consts::PI;

use serde::Serialize;
use serde_json::{Value, json};

use super::decay_fit::fit_decay;
pub use super::decrement::Decrement;
use super::decrement::{find_peaks, log_decrement, slope};
use super::envelope::{EnvelopeDecay, envelope_decay};
use super::psd::welch;
use super::{DecayFit, IdentifyError, check_inputs};

/// Fewest samples of free ringing accepted.
pub const MIN_RING_SAMPLES: usize = 256;
/// Fewest positive peaks accepted for the logarithmic decrement.
pub const MIN_PEAKS: usize = 6;
/// Largest spread of the three damping estimates, relative to their median,
/// that counts as agreement.
pub const AGREEMENT_TOLERANCE: f64 = 0.1;

/// Options of [`analyse`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RingdownOptions {
    /// Load-cell mass `m1` (kg), if known.
    pub m1: Option<f64>,
    /// Load-cell stiffness `k1` (N/m), if known.
    pub k1: Option<f64>,
    /// Start of the free ringing (s); detected from the largest drop when `None`.
    pub start: Option<f64>,
    /// Welch segment length (samples); chosen from the data when `None`.
    pub segment_len: Option<usize>,
    /// Number of peak separations `K` for the logarithmic decrement (≥ 1).
    pub max_separations: usize,
    /// Lowest frequency considered for the PSD peak (Hz).
    pub min_frequency: f64,
    /// Half-width of the envelope's band around the peak (Hz); 30 % of the
    /// peak frequency when `None`.
    pub envelope_band_hz: Option<f64>,
}

impl Default for RingdownOptions {
    fn default() -> Self {
        Self {
            m1: None,
            k1: None,
            start: None,
            segment_len: None,
            max_separations: 5,
            min_frequency: 0.0,
            envelope_band_hz: None,
        }
    }
}

/// Where the free ringing starts.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RingStart {
    /// Sample index of the start.
    pub index: usize,
    /// Its time (s).
    pub time: f64,
    /// Force there (N).
    pub force: f64,
    /// The largest drop found (N); `None` when the start was given.
    pub drop: Option<f64>,
}

/// PSD settings and peak.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PsdSummary {
    /// Window name.
    pub window: &'static str,
    /// Samples per segment.
    pub segment_len: usize,
    /// Averaged segments.
    pub n_segments: usize,
    /// Overlap (fraction).
    pub overlap: f64,
    /// Resolution `Δf = fs/segment_len` (Hz).
    pub resolution_hz: f64,
    /// Frequency of the highest bin (Hz).
    pub peak_bin_hz: f64,
    /// Interpolated peak frequency (Hz).
    pub peak_hz: f64,
}

/// Result of [`analyse`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RingdownReport {
    /// Sample rate (Hz).
    pub sample_rate_hz: f64,
    /// Where the free ringing starts.
    pub start: RingStart,
    /// Samples of free ringing analysed.
    pub n_samples: usize,
    /// PSD settings and peak.
    pub psd: PsdSummary,
    /// Logarithmic decrement.
    pub decrement: Decrement,
    /// Damped-oscillator fit.
    pub fit: DecayFit,
    /// Analytic-signal envelope in a band around the peak; `None` when the band
    /// does not fit below the Nyquist rate or leaves too few samples.
    pub envelope: Option<EnvelopeDecay>,
    /// How the three damping estimates agree.
    pub agreement: Agreement,
    /// Undamped natural frequency from the fit, `ω_n/2π` (Hz).
    pub natural_frequency_hz: f64,
    /// What follows for the load cell (its fields in the JSON).
    #[serde(flatten)]
    pub load_cell: LoadCell,
    /// The peaks the decrement used: (time from the start (s), height above
    /// the mean of the free ringing).
    #[serde(skip)]
    pub peaks: Vec<(f64, f64)>,
}

/// The load cell's `k1` and `c1_post` from its mass, its stiffness or both
/// (step 7 of the module docs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LoadCell {
    /// Load-cell mass used (kg).
    pub m1: Option<f64>,
    /// Load-cell stiffness (N/m), given or derived.
    pub k1: Option<f64>,
    /// Whether `k1` was derived from the frequency (`m1·ω_n²`).
    pub k1_from_frequency: bool,
    /// `sqrt(k1/m1)/2π` when both were given (Hz), to compare with the measured one.
    pub model_frequency_hz: Option<f64>,
    /// `c1_post` from the decrement ζ (N·s/m).
    pub c1_post_decrement: Option<f64>,
    /// `c1_post` from the fitted ζ (N·s/m); this one goes into the fragment.
    pub c1_post: Option<f64>,
}

impl LoadCell {
    /// From the given `m1` and `k1`, the fitted natural frequency `wn`
    /// (rad/s) and the decrement's and the fit's ζ.
    fn of(m1: Option<f64>, k1: Option<f64>, wn: f64, zeta_decrement: f64, zeta_fit: f64) -> Self {
        let c1_of = |zeta: f64| match (m1, k1) {
            (Some(m), Some(k)) => Some(2.0 * zeta * (k * m).sqrt()),
            (Some(m), None) => Some(2.0 * zeta * m * wn),
            (None, Some(k)) => Some(2.0 * zeta * k / wn),
            (None, None) => None,
        };
        Self {
            m1,
            k1: k1.or(m1.map(|m| m * wn * wn)),
            k1_from_frequency: k1.is_none() && m1.is_some(),
            model_frequency_hz: m1.zip(k1).map(|(m, k)| (k / m).sqrt() / (2.0 * PI)),
            c1_post_decrement: c1_of(zeta_decrement),
            c1_post: c1_of(zeta_fit),
        }
    }
}

/// The three damping estimates side by side.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Agreement {
    /// ζ from the logarithmic decrement.
    pub zeta_decrement: f64,
    /// ζ from the damped-oscillator fit.
    pub zeta_fit: f64,
    /// ζ from the envelope, when there is one.
    pub zeta_envelope: Option<f64>,
    /// (largest − smallest) / median.
    pub relative_spread: f64,
    /// Whether the spread is within [`AGREEMENT_TOLERANCE`].
    pub agree: bool,
    /// Samples per cycle at the peak frequency.
    pub samples_per_cycle: f64,
    /// What to look at when they disagree (empty when they agree).
    pub warnings: Vec<String>,
}

impl Agreement {
    fn of(decrement: f64, fit: f64, envelope: Option<f64>, samples_per_cycle: f64) -> Self {
        let mut z: Vec<f64> = [Some(decrement), Some(fit), envelope]
            .into_iter()
            .flatten()
            .collect();
        z.sort_by(f64::total_cmp);
        let median = if z.len() == 3 {
            z[1]
        } else {
            0.5 * (z[0] + z[1])
        };
        let relative_spread = (z[z.len() - 1] - z[0]) / median.abs();
        let agree = relative_spread <= AGREEMENT_TOLERANCE;
        let mut warnings = Vec::new();
        if !agree {
            warnings.push(format!(
                "the damping estimates disagree by {:.0} % (decrement {decrement:.5}, fit {fit:.5}, envelope {})",
                100.0 * relative_spread,
                envelope.map_or("none".to_string(), |e| format!("{e:.5}"))
            ));
            if samples_per_cycle < 10.0 {
                warnings.push(format!(
                    "only {samples_per_cycle:.1} samples per cycle: picked peaks miss the crests, so the decrement is the least reliable"
                ));
            }
        }
        Self {
            zeta_decrement: decrement,
            zeta_fit: fit,
            zeta_envelope: envelope,
            relative_spread,
            agree,
            samples_per_cycle,
            warnings,
        }
    }
}

/// The campaign names the fragment gives the stiffness and the damping of the
/// ringing mode when no others are asked for: the tensile rig's load cell.
pub const DEFAULT_NAMES: [&str; 2] = ["k1", "c1_post"];

impl RingdownReport {
    /// `{"params": {"c1_post": …, "k1": …}}`: the fragment of
    /// [`Self::to_campaign_fragment_named`] under [`DEFAULT_NAMES`].
    pub fn to_campaign_fragment(&self) -> Value {
        self.to_campaign_fragment_named(DEFAULT_NAMES)
    }

    /// `{"params": {damping: …, stiffness: …}}` for `[stiffness, damping]` the
    /// names of the ringing mode's stiffness and damping in the rig: the damping
    /// when it could be computed, the stiffness only when derived from the
    /// frequency. Values are fixed parameters; replace them by bounds to let the
    /// search refine them.
    pub fn to_campaign_fragment_named(&self, [stiffness, damping]: [&str; 2]) -> Value {
        let mut params = serde_json::Map::new();
        let cell = &self.load_cell;
        if let Some(c) = cell.c1_post {
            params.insert(damping.into(), json!(c));
        }
        if let (true, Some(k)) = (cell.k1_from_frequency, cell.k1) {
            params.insert(stiffness.into(), json!(k));
        }
        json!({ "params": params })
    }
}

/// Analyses a signal `f` (a force in N for the tensile rig's load cell; any
/// unit) at times `t` (s) that rings down freely from a start.
///
/// # Errors
/// Input errors, [`IdentifyError::NonUniformTime`], [`IdentifyError::NoRingStart`],
/// [`IdentifyError::TooShortRingdown`] (fewer than [`MIN_RING_SAMPLES`] samples or
/// [`MIN_PEAKS`] peaks after the start), [`IdentifyError::InvalidOption`] and
/// [`IdentifyError::Numerical`].
pub fn analyse(
    t: &[f64],
    f: &[f64],
    options: &RingdownOptions,
) -> Result<RingdownReport, IdentifyError> {
    check_inputs("ring-down data", t, f)?;
    validate(options)?;
    if t.len() < MIN_RING_SAMPLES {
        return Err(IdentifyError::TooShortRingdown {
            what: "samples",
            needed: MIN_RING_SAMPLES,
            found: t.len(),
        });
    }
    let dt = uniform_step(t)?;
    let fs = 1.0 / dt;
    let start = match options.start {
        Some(start) => {
            let index = t.partition_point(|&ti| ti < start).min(t.len() - 1);
            RingStart {
                index,
                time: t[index],
                force: f[index],
                drop: None,
            }
        }
        None => detect_start(t, f)?,
    };
    let x = &f[start.index..];
    if x.len() < MIN_RING_SAMPLES {
        return Err(IdentifyError::TooShortRingdown {
            what: "samples of free ringing",
            needed: MIN_RING_SAMPLES,
            found: x.len(),
        });
    }
    let tp: Vec<f64> = (0..x.len()).map(|i| i as f64 * dt).collect();

    let psd = welch(x, fs, options.segment_len)?;
    let (peak_bin_hz, peak_hz) =
        psd.peak(options.min_frequency)
            .ok_or_else(|| IdentifyError::Numerical {
                stage: "PSD peak",
                reason: "no bin above the minimum frequency".into(),
            })?;
    let period = fs / peak_hz;
    let mean = x.iter().sum::<f64>() / x.len() as f64;
    let peaks = find_peaks(x, mean, period);
    if peaks.len() < MIN_PEAKS {
        return Err(IdentifyError::TooShortRingdown {
            what: "positive peaks",
            needed: MIN_PEAKS,
            found: peaks.len(),
        });
    }
    // Cycle numbers counted peak to peak, so a PSD period off by a few percent
    // cannot misnumber late peaks; a missed peak shows as a step of two.
    let mut cycles = vec![0.0];
    for w in peaks.windows(2) {
        let last = cycles[cycles.len() - 1];
        cycles.push(last + ((w[1].0 - w[0].0) / period).round().max(1.0));
    }
    let decrement = log_decrement(&peaks, &cycles, options.max_separations);
    let omega_d0 = 2.0 * PI * fs / slope(&cycles, &peaks.iter().map(|p| p.0).collect::<Vec<_>>());
    let z0 = decrement.zeta_mean.clamp(1e-6, 0.5);
    let fit = fit_decay(&tp, x, omega_d0, z0 * omega_d0 / (1.0 - z0 * z0).sqrt())?;

    let (m1, k1_given) = (options.m1, options.k1);
    let wn = fit.omega_n;
    let fn_hz = wn / (2.0 * PI);
    let band = options.envelope_band_hz.unwrap_or(0.3 * fn_hz);
    let envelope = envelope_decay(x, fs, fn_hz, band.min(0.49 * fs - fn_hz)).ok();
    let agreement = Agreement::of(
        decrement.zeta_mean,
        fit.zeta,
        envelope.as_ref().map(|e| e.zeta),
        fs / fn_hz,
    );
    let load_cell = LoadCell::of(m1, k1_given, wn, decrement.zeta_mean, fit.zeta);
    Ok(RingdownReport {
        sample_rate_hz: fs,
        n_samples: x.len(),
        psd: PsdSummary {
            window: psd.window,
            segment_len: psd.segment_len,
            n_segments: psd.n_segments,
            overlap: psd.overlap,
            resolution_hz: psd.resolution_hz,
            peak_bin_hz,
            peak_hz,
        },
        decrement,
        natural_frequency_hz: wn / (2.0 * PI),
        load_cell,
        peaks: peaks.iter().map(|&(i, a)| (i * dt, a)).collect(),
        start,
        fit,
        envelope,
        agreement,
    })
}

/// Panels of the ringdown figure: the free ringing with the fitted decay and
/// its envelope `±A·e^{−σt}` and the decrement's peaks; and the peaks' heights
/// on a log scale with the decay each estimator's ζ implies (`σ = ζ·ω_n` from
/// the fit's amplitude), so a disagreement shows as diverging lines. `t` and
/// `f` are the record [`analyse`] was given.
pub fn figure(report: &RingdownReport, t: &[f64], f: &[f64]) -> Vec<super::plot::Panel> {
    use super::plot::{FIT, MEASURED, OTHER, Panel, Series, Style, THIRD, thin};
    let i0 = report.start.index;
    let t0 = t[i0];
    let x = &f[i0..];
    let mean = x.iter().sum::<f64>() / x.len() as f64;
    let fit = &report.fit;
    // Up to a little past the last peak the decrement used (the rest is
    // noise), with 40 points per cycle for the fitted curve.
    let last_peak = report.peaks.last().map_or(0.0, |p| p.0);
    let span = (t[t.len() - 1] - t0).min(1.3 * last_peak.max(10.0 * PI / fit.omega_d));
    let n = ((span * fit.omega_d / (2.0 * PI) * 40.0) as usize).clamp(200, 4000);
    let grid: Vec<f64> = (0..=n).map(|i| span * i as f64 / n as f64).collect();
    let curve = |g: &dyn Fn(f64) -> f64| -> Vec<(f64, f64)> {
        grid.iter().map(|&tt| (tt, g(tt))).collect()
    };
    let env = |tt: f64| fit.amplitude.abs() * (-fit.decay_rate * tt).exp();
    let ringing = vec![
        Series {
            label: "record".into(),
            points: thin(
                x.iter()
                    .enumerate()
                    .take_while(|(i, _)| t[i0 + i] - t0 <= span)
                    .map(|(i, v)| (t[i0 + i] - t0, *v))
                    .collect(),
                4000,
            ),
            style: Style::Dots,
            color: MEASURED,
        },
        Series {
            label: "fitted decay".into(),
            points: curve(&|tt| {
                fit.amplitude * (-fit.decay_rate * tt).exp() * (fit.omega_d * tt + fit.phase).cos()
                    + fit.offset
            }),
            style: Style::Line,
            color: FIT,
        },
        Series {
            label: "envelope ±A·e^(−σt)".into(),
            points: curve(&|tt| fit.offset + env(tt)),
            style: Style::Line,
            color: OTHER,
        },
        Series {
            label: "".into(),
            points: curve(&|tt| fit.offset - env(tt)),
            style: Style::Line,
            color: OTHER,
        },
        Series {
            label: "decrement peaks".into(),
            points: report.peaks.iter().map(|&(tt, a)| (tt, a + mean)).collect(),
            style: Style::Dots,
            color: THIRD,
        },
    ];
    let wn = fit.omega_n;
    let ln_a = fit.amplitude.abs().ln();
    let line = |label: String, zeta: f64, color| Series {
        label,
        points: curve(&|tt| ln_a - zeta * wn * tt),
        style: Style::Line,
        color,
    };
    let g = &report.agreement;
    let mut decay = vec![
        Series {
            label: "peaks".into(),
            points: report.peaks.iter().map(|&(tt, a)| (tt, a.ln())).collect(),
            style: Style::Dots,
            color: MEASURED,
        },
        line(
            format!("decrement ζ = {:.5}", g.zeta_decrement),
            g.zeta_decrement,
            THIRD,
        ),
        line(format!("fit ζ = {:.5}", g.zeta_fit), g.zeta_fit, FIT),
    ];
    if let Some(z) = g.zeta_envelope {
        decay.push(line(format!("envelope ζ = {z:.5}"), z, OTHER));
    }
    vec![
        Panel {
            caption: "free ringing".into(),
            x_desc: "time from the start (s)".into(),
            y_desc: "signal".into(),
            series: ringing,
        },
        Panel {
            caption: format!(
                "decay of the peaks: estimators {} (spread {:.1} %)",
                if g.agree { "agree" } else { "DISAGREE" },
                100.0 * g.relative_spread
            ),
            x_desc: "time from the start (s)".into(),
            y_desc: "ln(peak height)".into(),
            series: decay,
        },
    ]
}

fn validate(o: &RingdownOptions) -> Result<(), IdentifyError> {
    for (name, v) in [
        ("m1", o.m1),
        ("k1", o.k1),
        ("envelope_band_hz", o.envelope_band_hz),
    ] {
        if let Some(v) = v.filter(|v| !(v.is_finite() && *v > 0.0)) {
            return Err(IdentifyError::InvalidOption {
                name,
                reason: format!("{v} is not positive"),
            });
        }
    }
    if o.max_separations == 0 {
        return Err(IdentifyError::InvalidOption {
            name: "max_separations",
            reason: "must be ≥ 1".into(),
        });
    }
    Ok(())
}

/// The median time step, after checking every step is within 1 % of it.
fn uniform_step(t: &[f64]) -> Result<f64, IdentifyError> {
    let mut steps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    let mut sorted = steps.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    if let Some(i) = steps
        .iter_mut()
        .position(|s| !(median > 0.0 && (*s - median).abs() <= 0.01 * median))
    {
        return Err(IdentifyError::NonUniformTime {
            index: i + 1,
            step: steps[i],
            expected: median,
        });
    }
    Ok(median)
}

/// Start of the largest drop from a running maximum.
fn detect_start(t: &[f64], f: &[f64]) -> Result<RingStart, IdentifyError> {
    let (mut peak, mut best, mut best_drop) = (0, 0, 0.0);
    for (i, &v) in f.iter().enumerate() {
        if v > f[peak] {
            peak = i;
        }
        if f[peak] - v > best_drop {
            best_drop = f[peak] - v;
            best = peak;
        }
    }
    let (lo, hi) = f
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let range = hi - lo;
    if best_drop <= 0.5 * range {
        return Err(IdentifyError::NoRingStart {
            drop: best_drop,
            range,
        });
    }
    Ok(RingStart {
        index: best,
        time: t[best],
        force: f[best],
        drop: Some(best_drop),
    })
}
