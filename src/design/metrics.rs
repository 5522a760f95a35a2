//! The metrics of one run: numbers computed from an output's history over
//! the experiment's fit window, each in the output's unit unless said.
//!
//! Every function takes the samples `x` (and their times `t`, s) of that
//! window and returns `None` where the metric is not defined (a response
//! that does not move, a threshold never crossed, a reference of mean zero).
//! Times are measured from the window's first sample.

use rustfft::FftPlanner;
use rustfft::num_complex::Complex;
use serde::Deserialize;

/// What a metric computes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MetricKind {
    /// `max |x|` (output's unit).
    Peak,
    /// `max x`.
    Max,
    /// `min x`.
    Min,
    /// The arithmetic mean of the samples.
    Mean,
    /// `√(mean x²)`.
    Rms,
    /// `(max x − x_f)/|x_f − x_0|` for a rising response (`x_f > x_0`),
    /// `(x_f − min x)/|x_f − x_0|` for a falling one (unit 1), with `x_0` the
    /// first sample and `x_f` the final value, [`final_value`].
    Overshoot,
    /// Time (s) from the first crossing of `x_0 + 0.1·(x_f − x_0)` to the
    /// first crossing of `x_0 + 0.9·(x_f − x_0)`, crossings interpolated
    /// linearly between samples.
    RiseTime,
    /// Time (s) from the window's start to the first sample after the last
    /// one with `|x − x_f| > 0.02·|x_f − x_0|` (0 when none is outside).
    SettlingTime,
    /// Time (s) from the window's start at which `x` first reaches
    /// `threshold` (from either side), interpolated linearly between samples.
    FirstCrossing,
    /// `∫ x² dt` by the trapezoid rule (output's unit² · s).
    Energy,
    /// The ringing's relative amplitude (unit 1): `rms(x − r) / mean |r|`,
    /// with `r` the reference (another output, or a moving average of `x`).
    Ringing,
    /// The ringing's dominant frequency (Hz): the largest peak of the
    /// amplitude spectrum of `x − r` (see [`dominant_frequency`]).
    RingingHz,
    /// A formula of the metrics before it, by name, and of the design
    /// variables whose names are plain identifiers (`"100 * ring / peak"`;
    /// the functions and operators of a rig's expression laws).
    Expression,
}

impl MetricKind {
    /// Whether the metric compares the output with a reference (`against` or
    /// `window_s`).
    pub fn uses_reference(self) -> bool {
        matches!(self, Self::Ringing | Self::RingingHz)
    }
}

/// Fraction of the samples, at the end of the window, whose mean is the
/// final value.
pub const FINAL_SHARE: f64 = 0.05;

/// The band around the final value a settled response stays in, as a
/// fraction of `|x_f − x_0|`.
pub const SETTLING_BAND: f64 = 0.02;

/// The final value `x_f`: the mean of the last [`FINAL_SHARE`] of the
/// samples (at least one).
pub fn final_value(x: &[f64]) -> Option<f64> {
    let n = x.len();
    if n == 0 {
        return None;
    }
    let k = ((n as f64 * FINAL_SHARE).ceil() as usize).clamp(1, n);
    mean(&x[n - k..])
}

/// `max |x|`.
pub fn peak(x: &[f64]) -> Option<f64> {
    x.iter().map(|v| v.abs()).reduce(f64::max)
}

/// `max x`.
pub fn max(x: &[f64]) -> Option<f64> {
    x.iter().copied().reduce(f64::max)
}

/// `min x`.
pub fn min(x: &[f64]) -> Option<f64> {
    x.iter().copied().reduce(f64::min)
}

/// The mean of `x`.
pub fn mean(x: &[f64]) -> Option<f64> {
    (!x.is_empty()).then(|| x.iter().sum::<f64>() / x.len() as f64)
}

/// `√(mean x²)`.
pub fn rms(x: &[f64]) -> Option<f64> {
    (!x.is_empty()).then(|| (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt())
}

/// The step `(x_0, x_f)` of a response, `None` where it does not move.
fn step(x: &[f64]) -> Option<(f64, f64)> {
    let (x0, xf) = (*x.first()?, final_value(x)?);
    (xf != x0 && (xf - x0).is_finite()).then_some((x0, xf))
}

/// See [`MetricKind::Overshoot`].
pub fn overshoot(x: &[f64]) -> Option<f64> {
    let (x0, xf) = step(x)?;
    let beyond = if xf > x0 { max(x)? - xf } else { xf - min(x)? };
    Some(beyond / (xf - x0).abs())
}

/// See [`MetricKind::RiseTime`].
pub fn rise_time(t: &[f64], x: &[f64]) -> Option<f64> {
    let (x0, xf) = step(x)?;
    let lo = crossing(t, x, x0 + 0.1 * (xf - x0))?;
    let hi = crossing(t, x, x0 + 0.9 * (xf - x0))?;
    Some(hi - lo)
}

/// See [`MetricKind::SettlingTime`].
pub fn settling_time(t: &[f64], x: &[f64]) -> Option<f64> {
    let (x0, xf) = step(x)?;
    let band = SETTLING_BAND * (xf - x0).abs();
    let t0 = *t.first()?;
    match x.iter().rposition(|v| (v - xf).abs() > band) {
        None => Some(0.0),
        Some(k) => t.get(k + 1).map(|tk| tk - t0),
    }
}

/// See [`MetricKind::FirstCrossing`].
pub fn first_crossing(t: &[f64], x: &[f64], threshold: f64) -> Option<f64> {
    crossing(t, x, threshold)
}

/// Time from `t[0]` at which `x` first reaches `level`, linear between
/// samples; `t[0]`'s own sample counts when it sits on the level.
fn crossing(t: &[f64], x: &[f64], level: f64) -> Option<f64> {
    let t0 = *t.first()?;
    if *x.first()? == level {
        return Some(0.0);
    }
    x.windows(2).zip(t.windows(2)).find_map(|(xs, ts)| {
        let (a, b) = (xs[0] - level, xs[1] - level);
        (a * b <= 0.0 && a != b).then(|| {
            let f = a / (a - b);
            ts[0] + f * (ts[1] - ts[0]) - t0
        })
    })
}

/// See [`MetricKind::Energy`].
pub fn energy(t: &[f64], x: &[f64]) -> Option<f64> {
    if x.len() < 2 {
        return None;
    }
    Some(
        x.windows(2)
            .zip(t.windows(2))
            .map(|(xs, ts)| 0.5 * (xs[0] * xs[0] + xs[1] * xs[1]) * (ts[1] - ts[0]))
            .sum(),
    )
}

/// A centred moving average of `x` over `width` samples (odd; the window
/// shrinks to the samples there are at either end).
pub fn moving_average(x: &[f64], width: usize) -> Vec<f64> {
    let half = width / 2;
    let mut prefix = Vec::with_capacity(x.len() + 1);
    prefix.push(0.0);
    for v in x {
        prefix.push(prefix.last().copied().unwrap_or(0.0) + v);
    }
    (0..x.len())
        .map(|i| {
            let (a, b) = (i.saturating_sub(half), (i + half + 1).min(x.len()));
            (prefix[b] - prefix[a]) / (b - a) as f64
        })
        .collect()
}

/// See [`MetricKind::Ringing`]: `rms(x − r) / mean |r|`.
pub fn ringing(x: &[f64], reference: &[f64]) -> Option<f64> {
    let d: Vec<f64> = x.iter().zip(reference).map(|(a, b)| a - b).collect();
    let scale = mean(&reference.iter().map(|v| v.abs()).collect::<Vec<_>>())?;
    (scale > 0.0).then(|| rms(&d).map(|r| r / scale)).flatten()
}

/// How many times finer than the record's own frequency resolution
/// [`dominant_frequency`] samples the spectrum (by zero-padding), for
/// records up to [`PAD_UP_TO`] samples; longer ones are padded to twice the
/// next power of two.
pub const PAD_FACTOR: usize = 8;

/// See [`PAD_FACTOR`].
pub const PAD_UP_TO: usize = 1 << 18;

/// The dominant frequency (Hz) of `d` sampled at `dt` (s): `d`, less its
/// mean under the window, times a Hann window, zero-padded to [`PAD_FACTOR`] times the next
/// power of two, its amplitude spectrum's largest peak above the zero bin,
/// refined by a parabola through the log amplitudes of the peak bin and its
/// neighbours (`δ = ½(a₋ − a₊)/(a₋ − 2a₀ + a₊)`, `f = (k + δ)/(M·dt)`);
/// frequencies below two cycles per record are not looked at. The
/// spectrum of a sinusoid under any envelope ≥ 0 (the window times a decay)
/// is largest at the sinusoid's frequency, but for the tail of its
/// negative-frequency image: a heavily damped ringing's peak sits a little
/// off `ω_d` (ζ = 0.2: ≈ 10⁻³), a lightly damped one's on it. The window
/// goes smoothly to 0 at the ends, so what happens there (a run's start, a
/// moving average cut short) weighs little. `None` for fewer than 4 samples
/// or a difference that does not vary.
pub fn dominant_frequency(d: &[f64], dt: f64) -> Option<f64> {
    let n = d.len();
    if n < 4 || dt.is_nan() || dt <= 0.0 {
        return None;
    }
    let pad = if n <= PAD_UP_TO { PAD_FACTOR } else { 2 };
    let size = pad * n.next_power_of_two();
    let last = (n - 1) as f64;
    let w: Vec<f64> = (0..n)
        .map(|i| (std::f64::consts::PI * i as f64 / last).sin().powi(2))
        .collect();
    // The window's own mean removed, so that no step left over by a
    // plain mean shows as a peak at the window's lowest frequencies.
    let m = d.iter().zip(&w).map(|(v, w)| v * w).sum::<f64>() / w.iter().sum::<f64>();
    let mut buf: Vec<Complex<f64>> = vec![Complex::new(0.0, 0.0); size];
    for ((b, v), w) in buf.iter_mut().zip(d).zip(&w) {
        *b = Complex::new((v - m) * w, 0.0);
    }
    // The planner keeps its plans: one per thread, so that a sweep's runs
    // of one length plan once.
    thread_local! {
        static PLANNER: std::cell::RefCell<FftPlanner<f64>> =
            std::cell::RefCell::new(FftPlanner::new());
    }
    PLANNER
        .with(|p| p.borrow_mut().plan_fft_forward(size))
        .process(&mut buf);
    let amp: Vec<f64> = buf[..size / 2 + 1].iter().map(|c| c.norm()).collect();
    // Above the window's main lobe about zero (2 bins of the record).
    let k = (2 * pad + 1..amp.len())
        .max_by(|&a, &b| amp[a].total_cmp(&amp[b]))
        .filter(|&k| amp[k] > 0.0 && amp[k].is_finite())?;
    let delta = if k + 1 < amp.len() && amp[k - 1] > 0.0 && amp[k + 1] > 0.0 {
        let (a, b, c) = (amp[k - 1].ln(), amp[k].ln(), amp[k + 1].ln());
        let den = a - 2.0 * b + c;
        // Within half a bin of the largest: amplitudes equal to rounding
        // leave `den` a hair below 0 and the quotient unbounded.
        if den < 0.0 {
            (0.5 * (a - c) / den).clamp(-0.5, 0.5)
        } else {
            0.0
        }
    } else {
        0.0
    };
    Some((k as f64 + delta) / (size as f64 * dt))
}

/// A named metric of a sweep, validated against the rig: what it computes
/// and on which outputs (indices into the rig's outputs).
#[derive(Debug, Clone, PartialEq)]
pub struct Metric {
    /// The column name in the table.
    pub name: String,
    /// What it computes.
    pub kind: MetricKind,
    /// The output it reads.
    pub output: usize,
    /// The reference of a ringing metric: another output.
    pub against: Option<usize>,
    /// The reference of a ringing metric without `against`: a centred moving
    /// average over this many samples (odd).
    pub window_samples: Option<usize>,
    /// The level of `first_crossing` (output's unit).
    pub threshold: Option<f64>,
    /// The formula of an [`MetricKind::Expression`] metric, and the names it
    /// reads resolved: `Ok(i)` the `i`-th metric, `Err(j)` the `j`-th design
    /// variable.
    pub formula: Option<Formula>,
    /// The gate: the metric reads only the span from the first to the last
    /// sample where output `.0`'s magnitude is at least `.1` times its
    /// largest (the plateau of a test, `"gate": {"output", "above"}`).
    pub gate: Option<(usize, f64)>,
}

/// A formula metric: its parsed expression and where each name it reads
/// comes from.
#[derive(Debug, Clone, PartialEq)]
pub struct Formula {
    /// The expression.
    pub expr: crate::compile::front::expr::Expr,
    /// Each name it reads: `Ok(i)` the `i`-th metric (before it), `Err(j)`
    /// the `j`-th design variable.
    pub names: Vec<(String, Result<usize, usize>)>,
}

impl Formula {
    /// Its value from the run's earlier metrics and the point's variables;
    /// `None` where a metric it reads is not defined or the value is not
    /// finite.
    pub fn value(&self, metrics: &[Option<f64>], variables: &[f64]) -> Option<f64> {
        let undefined = std::cell::Cell::new(false);
        let v = self.expr.eval(&|n: &str| match self
            .names
            .iter()
            .find(|(k, _)| k == n)
            .map(|(_, at)| *at)
        {
            Some(Ok(i)) => metrics.get(i).copied().flatten().unwrap_or_else(|| {
                undefined.set(true);
                f64::NAN
            }),
            Some(Err(j)) => variables.get(j).copied().unwrap_or(f64::NAN),
            None => {
                undefined.set(true);
                f64::NAN
            }
        });
        (!undefined.get() && v.is_finite()).then_some(v)
    }
}

/// The span `[first, last + 1)` of the samples where `|g|` is at least
/// `fraction` of its largest magnitude; `None` where `g` is zero throughout.
pub fn gated_span(g: &[f64], fraction: f64) -> Option<std::ops::Range<usize>> {
    let top = peak(g)?;
    if top <= 0.0 {
        return None;
    }
    let level = fraction * top;
    let first = g.iter().position(|v| v.abs() >= level)?;
    let last = g.iter().rposition(|v| v.abs() >= level)?;
    Some(first..last + 1)
}

impl Metric {
    /// [`Metric::evaluate`] over the gate's span where the metric has a gate
    /// (times still measured from the window's first sample); `None` where
    /// the gate output never rises.
    pub fn evaluate_gated(&self, t: &[f64], outputs: &[&[f64]], dt: f64) -> Option<f64> {
        match self.gate {
            None => self.evaluate(t, outputs, dt),
            Some((o, fraction)) => {
                let span = gated_span(outputs[o], fraction)?;
                let cut: Vec<&[f64]> = outputs.iter().map(|x| &x[span.clone()]).collect();
                self.evaluate(&t[span], &cut, dt)
            }
        }
    }

    /// The metric of one run: `t` the window's times (s), `outputs` every
    /// output over the same samples, `dt` the sample interval (s).
    pub fn evaluate(&self, t: &[f64], outputs: &[&[f64]], dt: f64) -> Option<f64> {
        let x = outputs[self.output];
        match self.kind {
            MetricKind::Peak => peak(x),
            MetricKind::Max => max(x),
            MetricKind::Min => min(x),
            MetricKind::Mean => mean(x),
            MetricKind::Rms => rms(x),
            MetricKind::Overshoot => overshoot(x),
            MetricKind::RiseTime => rise_time(t, x),
            MetricKind::SettlingTime => settling_time(t, x),
            MetricKind::FirstCrossing => first_crossing(t, x, self.threshold?),
            MetricKind::Energy => energy(t, x),
            // Computed from the other metrics ([`Formula::value`]).
            MetricKind::Expression => None,
            MetricKind::Ringing | MetricKind::RingingHz => {
                let owned;
                let reference: &[f64] = match (self.against, self.window_samples) {
                    (Some(o), _) => outputs[o],
                    (None, Some(w)) => {
                        owned = moving_average(x, w);
                        &owned
                    }
                    (None, None) => return None,
                };
                if self.kind == MetricKind::Ringing {
                    ringing(x, reference)
                } else {
                    let d: Vec<f64> = x.iter().zip(reference).map(|(a, b)| a - b).collect();
                    dominant_frequency(&d, dt)
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sampled(n: usize, dt: f64, f: impl Fn(f64) -> f64) -> (Vec<f64>, Vec<f64>) {
        let t: Vec<f64> = (0..n).map(|k| k as f64 * dt).collect();
        let x = t.iter().map(|&s| f(s)).collect();
        (t, x)
    }

    #[test]
    fn moving_average_of_a_line_is_the_line_inside() {
        let x: Vec<f64> = (0..20).map(f64::from).collect();
        let a = moving_average(&x, 5);
        assert_eq!(a[10], 10.0);
        assert_eq!(a[0], 1.0);
    }

    #[test]
    fn crossing_interpolates_and_none_when_never_reached() {
        let (t, x) = sampled(11, 0.1, |s| 2.0 * s);
        let c = first_crossing(&t, &x, 0.55).expect("crosses");
        assert!((c - 0.275).abs() < 1e-12, "{c}");
        assert_eq!(first_crossing(&t, &x, 5.0), None);
    }

    #[test]
    fn a_still_response_has_no_step_metrics() {
        let x = [1.0; 10];
        let t: Vec<f64> = (0..10).map(f64::from).collect();
        assert_eq!(overshoot(&x), None);
        assert_eq!(rise_time(&t, &x), None);
        assert_eq!(settling_time(&t, &x), None);
        assert_eq!(dominant_frequency(&x, 1.0), None);
    }

    #[test]
    fn dominant_frequency_of_a_sine() {
        let (_, x) = sampled(4000, 1e-4, |s| {
            (2.0 * std::f64::consts::PI * 123.4 * s).sin()
        });
        let f = dominant_frequency(&x, 1e-4).expect("a peak");
        assert!((f / 123.4 - 1.0).abs() < 1e-6, "{f}");
    }

    #[test]
    fn dominant_frequency_stays_within_half_a_bin_of_a_flat_peak() {
        // Two bins of equal height beside the largest: the parabola's
        // denominator is 0 to rounding, the refinement held to ±½ bin.
        let (_, x) = sampled(64, 1e-3, |s| {
            (2.0 * std::f64::consts::PI * 200.0 * s).sin() + 1e-3 * (s * 1e4).cos()
        });
        let f = dominant_frequency(&x, 1e-3).expect("a peak");
        assert!(f > 0.0 && (f - 200.0).abs() < 20.0, "{f}");
        let gated = gated_span(&[0.0, 1.0, 3.0, 2.0, 0.5, 0.0], 0.5).expect("a span");
        assert_eq!(gated, 2..4);
        assert_eq!(gated_span(&[0.0; 4], 0.5), None);
    }
}
