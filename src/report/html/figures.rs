//! The figures' data as the page embeds it: long series decimated for
//! drawing (the smallest and largest value of each pixel-column bucket, in
//! the order they occur), numbers rounded to what a drawing can show, the
//! fit window as time spans, and each residual's amplitude spectrum.

use serde_json::{Value, json};

use super::input::{FitCsv, History, Profile};
use super::spectrum::amplitude_spectrum;

/// Buckets a drawn series is reduced to: at most two points each.
pub const BUCKETS: usize = 2000;

/// `v` to 6 significant digits (`null` when not finite): what a figure
/// can show, and a third of the text of a full `f64`.
pub fn round6(v: f64) -> Value {
    if !v.is_finite() {
        return Value::Null;
    }
    let r: f64 = format!("{v:.5e}").parse().unwrap_or(v);
    json!(r)
}

fn rounded(v: &[f64]) -> Value {
    Value::Array(v.iter().map(|&x| round6(x)).collect())
}

/// `(x, y)` reduced to at most `2·buckets` points: each bucket of
/// consecutive samples keeps its smallest and largest `y` (NaN kept as a
/// gap where a bucket holds nothing else), in the order they occur.
pub fn decimate(x: &[f64], y: &[f64], buckets: usize) -> (Vec<f64>, Vec<f64>) {
    let n = x.len().min(y.len());
    if n <= 2 * buckets {
        return (x[..n].to_vec(), y[..n].to_vec());
    }
    let (mut xs, mut ys) = (
        Vec::with_capacity(2 * buckets),
        Vec::with_capacity(2 * buckets),
    );
    for b in 0..buckets {
        let (lo, hi) = (b * n / buckets, (b + 1) * n / buckets);
        let mut min: Option<usize> = None;
        let mut max: Option<usize> = None;
        for k in lo..hi {
            if y[k].is_nan() {
                continue;
            }
            if min.is_none_or(|m| y[k] < y[m]) {
                min = Some(k);
            }
            if max.is_none_or(|m| y[k] > y[m]) {
                max = Some(k);
            }
        }
        match (min, max) {
            (Some(a), Some(b)) => {
                let (first, second) = if a <= b { (a, b) } else { (b, a) };
                xs.push(x[first]);
                ys.push(y[first]);
                if second != first {
                    xs.push(x[second]);
                    ys.push(y[second]);
                }
            }
            _ => {
                xs.push(x[lo]);
                ys.push(f64::NAN);
            }
        }
    }
    (xs, ys)
}

fn series(label: &str, role: &str, x: &[f64], y: &[f64]) -> Value {
    let (xs, ys) = decimate(x, y, BUCKETS);
    json!({"label": label, "role": role, "x": rounded(&xs), "y": rounded(&ys)})
}

/// The fit window as time spans `[t_first, t_last]` of consecutive scored
/// samples.
pub fn window_spans(csv: &FitCsv) -> Vec<[f64; 2]> {
    let mut spans = Vec::new();
    let mut open: Option<usize> = None;
    for (k, &w) in csv.in_fit_window.iter().enumerate() {
        match (w, open) {
            (true, None) => open = Some(k),
            (false, Some(a)) => {
                spans.push([csv.t[a], csv.t[k - 1]]);
                open = None;
            }
            _ => {}
        }
    }
    if let Some(a) = open {
        spans.push([csv.t[a], csv.t[csv.t.len() - 1]]);
    }
    spans
}

/// The record's sample interval (s): its span over its samples.
pub fn sample_interval(t: &[f64]) -> f64 {
    match t {
        [first, .., last] => (last - first) / (t.len() - 1) as f64,
        _ => f64::NAN,
    }
}

/// One experiment's (or validation record's) figures: the fit (the
/// measurement and the model outputs of its unit), the residual, its
/// spectrum over the fit window with the natural frequencies `modes_hz`.
pub fn experiment(id: &str, csv: &FitCsv, modes_hz: &[f64]) -> Value {
    let measured = csv.of_kind("measured").next();
    let unit = measured.map_or("", |m| m.unit.as_str());
    let mut fit = Vec::new();
    if let Some(m) = measured {
        fit.push(series(
            &format!("measured {}", m.name),
            "measured",
            &csv.t,
            &m.values,
        ));
        // The measured output's model first, then the others of its unit.
        let mut models: Vec<_> = csv.of_kind("model").filter(|c| c.unit == unit).collect();
        models.sort_by_key(|c| c.name != m.name);
        for c in models {
            let role = if c.name == m.name { "model" } else { "other" };
            fit.push(series(
                &format!("model {}", c.name),
                role,
                &csv.t,
                &c.values,
            ));
        }
    }
    let residual = csv.of_kind("residual").next();
    let scored: Vec<f64> = residual.map_or_else(Vec::new, |r| {
        r.values
            .iter()
            .zip(&csv.in_fit_window)
            .filter(|(v, w)| **w && v.is_finite())
            .map(|(v, _)| *v)
            .collect()
    });
    let spectrum = amplitude_spectrum(&scored, sample_interval(&csv.t));
    json!({
        "id": id,
        "unit": unit,
        "quantity": measured.map_or("", |m| m.name.as_str()).replace('_', " "),
        "t": [round6(csv.t.first().copied().unwrap_or(0.0)), round6(csv.t.last().copied().unwrap_or(1.0))],
        "window": window_spans(csv).iter().map(|s| [round6(s[0]), round6(s[1])]).collect::<Vec<_>>(),
        "fit": fit,
        "residual": residual.map(|r| series("residual", "residual", &csv.t, &r.values)),
        "spectrum": {"x": rounded(&spectrum.hz), "y": rounded(&spectrum.amplitude)},
        "modes": rounded(modes_hz),
    })
}

/// The convergence figure's data: best and median cost by generation and
/// the noise floor.
pub fn convergence(history: Option<&History>, noise_floor: Option<f64>) -> Value {
    let h = history.cloned().unwrap_or_default();
    json!({
        "generation": rounded(&h.generation),
        "best": rounded(&h.best),
        "median": rounded(&h.median),
        "floor": noise_floor.map(round6),
    })
}

/// One profile's figure data: `Δχ²` (or, without it, the cost) against
/// the value, the threshold and the fitted value.
pub fn profile(p: &Profile) -> Value {
    let delta = !p.delta_chi2.is_empty();
    let ys = if delta { &p.delta_chi2 } else { &p.cost };
    let pairs: Vec<(f64, f64)> = p
        .grid
        .iter()
        .zip(ys)
        .filter_map(|(x, y)| Some(((*x)?, (*y)?)))
        .collect();
    let label = if p.unit.is_empty() {
        p.name.clone()
    } else {
        format!("{} ({})", p.name, p.unit)
    };
    json!({
        "name": label,
        "ylabel": if delta { "Δχ²" } else { "cost (1 − R²)" },
        "x": pairs.iter().map(|q| round6(q.0)).collect::<Vec<_>>(),
        "y": pairs.iter().map(|q| round6(q.1)).collect::<Vec<_>>(),
        "threshold": p.threshold.map(round6),
        "value": p.value.map(round6),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimation_keeps_each_buckets_extremes_in_order() {
        let x: Vec<f64> = (0..100_000).map(f64::from).collect();
        let y: Vec<f64> = x
            .iter()
            .map(|t| (t * 0.01).sin() * (1.0 + t * 1e-5))
            .collect();
        let (xs, ys) = decimate(&x, &y, 500);
        assert!(xs.len() <= 1000 && xs.len() >= 500);
        assert!(xs.windows(2).all(|w| w[0] < w[1]));
        let max = y.iter().copied().fold(f64::MIN, f64::max);
        let min = y.iter().copied().fold(f64::MAX, f64::min);
        assert_eq!(ys.iter().copied().fold(f64::MIN, f64::max), max);
        assert_eq!(ys.iter().copied().fold(f64::MAX, f64::min), min);
        // Short series pass whole.
        assert_eq!(decimate(&x[..10], &y[..10], 500).0.len(), 10);
    }

    #[test]
    fn rounding_keeps_six_digits_and_drops_what_is_not_finite() {
        assert_eq!(round6(1.234_567_89e-7), json!(1.23457e-7));
        assert_eq!(round6(f64::NAN), Value::Null);
    }
}
