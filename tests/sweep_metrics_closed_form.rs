//! Proves each sweep metric against its closed form on finely sampled
//! analytic signals: a damped oscillator's step response (overshoot
//! `exp(−ζπ/√(1−ζ²))`), a first-order response (rise time `τ·ln 9`, 2 %
//! settling time `τ·ln 50` within one sample, the crossing of ½ at `τ·ln 2`),
//! a sine about a mean (peak, max, min, mean, RMS, its ringing against the
//! mean), a decaying exponential's energy, and a lightly damped sine's
//! frequency; then a one-mass rig's step response through `rigfit sweep`.

mod sweep_common;

use std::f64::consts::PI;

use rigfit::design::metrics::{
    self, Metric, MetricKind, dominant_frequency, energy, first_crossing, overshoot, rise_time,
    settling_time,
};

fn sampled(n: usize, dt: f64, f: impl Fn(f64) -> f64) -> (Vec<f64>, Vec<f64>) {
    let t: Vec<f64> = (0..n).map(|k| k as f64 * dt).collect();
    let x = t.iter().map(|&s| f(s)).collect();
    (t, x)
}

fn close(found: Option<f64>, exact: f64, rel: f64, what: &str) {
    let v = found.unwrap_or_else(|| panic!("{what}: not defined"));
    assert!(
        (v - exact).abs() <= rel * exact.abs(),
        "{what}: {v} against the closed form {exact} (relative {:e})",
        (v - exact).abs() / exact.abs()
    );
}

#[test]
fn damped_oscillator_step_overshoot() {
    let (zeta, wn) = (0.2_f64, 2.0 * PI * 10.0);
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    // The peak, at t = π/ω_d, falls on a sample; the response has settled
    // to 1e-11 by the end.
    let tp = PI / wd;
    let dt = tp / 1000.0;
    let n = (2.0 / dt) as usize;
    let (_, x) = sampled(n, dt, |t| {
        1.0 - (-zeta * wn * t).exp()
            * ((wd * t).cos() + zeta / (1.0 - zeta * zeta).sqrt() * (wd * t).sin())
    });
    let exact = (-zeta * PI / (1.0 - zeta * zeta).sqrt()).exp();
    close(overshoot(&x), exact, 1e-6, "overshoot");
    // A falling response overshoots downwards by the same share.
    let down: Vec<f64> = x.iter().map(|v| -v).collect();
    close(
        overshoot(&down),
        exact,
        1e-6,
        "overshoot of the falling response",
    );
}

#[test]
fn first_order_rise_settling_and_crossing() {
    let tau = 0.01;
    let dt = 1e-6;
    let (t, x) = sampled(300_000, dt, |t| 1.0 - (-t / tau).exp());
    close(rise_time(&t, &x), tau * 9.0_f64.ln(), 1e-6, "rise time");
    close(
        first_crossing(&t, &x, 0.5),
        tau * 2.0_f64.ln(),
        1e-6,
        "first crossing of 0.5",
    );
    let ts = settling_time(&t, &x).expect("settles");
    let exact = tau * 50.0_f64.ln();
    assert!(
        ts >= exact - 1e-12 && ts <= exact + dt + 1e-12,
        "settling time {ts} s against τ·ln 50 = {exact} s (one sample: {dt} s)"
    );
    assert_eq!(first_crossing(&t, &x, 2.0), None, "never reaches 2");
}

#[test]
fn sine_about_a_mean_statistics_and_ringing() {
    // Whole periods, a sample on every quarter period.
    let n = 4000;
    let dt = 1.0 / n as f64;
    let (t, x) = sampled(n, dt, |t| 2.0 + 3.0 * (2.0 * PI * t).sin());
    let mean_line = vec![2.0; n];
    let outputs: Vec<&[f64]> = vec![&x, &mean_line];
    let metric = |kind: MetricKind| Metric {
        name: "m".into(),
        kind,
        output: 0,
        against: Some(1),
        window_samples: None,
        threshold: None,
        gate: None,
        formula: None,
    };
    let eval = |kind| metric(kind).evaluate(&t, &outputs, dt);
    close(eval(MetricKind::Peak), 5.0, 1e-12, "peak");
    close(eval(MetricKind::Max), 5.0, 1e-12, "max");
    close(eval(MetricKind::Min), -1.0, 1e-12, "min");
    close(eval(MetricKind::Mean), 2.0, 1e-12, "mean");
    close(eval(MetricKind::Rms), (4.0_f64 + 4.5).sqrt(), 1e-12, "rms");
    close(
        eval(MetricKind::Ringing),
        3.0 / 2.0_f64.sqrt() / 2.0,
        1e-12,
        "ringing against the mean",
    );
    // Sampled over a second: one cycle, one Hz.
    let long_n = 64_000;
    let (lt, lx) = sampled(long_n, 1e-3, |t| 2.0 + 3.0 * (2.0 * PI * 1.7 * t).sin());
    let line = vec![2.0; long_n];
    let m = metric(MetricKind::RingingHz);
    close(
        m.evaluate(&lt, &[&lx, &line], 1e-3),
        1.7,
        1e-6,
        "ringing_hz",
    );
    // A moving average over one whole period is the mean, but near the ends.
    let ma = Metric {
        window_samples: Some(1001),
        against: None,
        ..metric(MetricKind::Ringing)
    };
    let (mt, mx) = sampled(100_000, 1e-3, |t| 2.0 + 3.0 * (2.0 * PI * t).sin());
    close(
        ma.evaluate(&mt, &[&mx], 1e-3),
        3.0 / 2.0_f64.sqrt() / 2.0,
        2e-2,
        "ringing against a moving average",
    );
}

#[test]
fn energy_of_a_decaying_exponential() {
    let dt = 1e-5;
    let (t, x) = sampled(300_001, dt, |t| (-t).exp());
    let exact = (1.0 - (-2.0 * 3.0_f64).exp()) / 2.0;
    close(energy(&t, &x), exact, 1e-6, "∫ x² dt");
}

#[test]
fn lightly_damped_sine_frequency() {
    // ω_d of an oscillator with ζ = 0.002 at 250 Hz, over 0.4 s: under an
    // envelope ≥ 0 the spectrum of a sine is largest at its frequency.
    let (zeta, fnat) = (0.002_f64, 250.0);
    let wn = 2.0 * PI * fnat;
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let dt = 1e-5;
    let (_, x) = sampled(40_000, dt, |t| (-zeta * wn * t).exp() * (wd * t).sin());
    close(
        dominant_frequency(&x, dt),
        wd / (2.0 * PI),
        1e-6,
        "dominant frequency",
    );
    assert_eq!(metrics::dominant_frequency(&[1.0; 100], dt), None);
}

/// A one-mass rig (spring and damper to ground) under a unit force step from
/// t = 0, through `rigfit sweep`: its overshoot `exp(−ζπ/√(1−ζ²))`, its peak
/// `(1 + overshoot)/k` and the time it first reaches its final value `1/k`,
/// `(π − atan(√(1−ζ²)/ζ))/ω_d`, and its ringing frequency near `ω_d/2π`,
/// for two masses (the second's ζ and ω_d follow from the same k and c).
#[test]
fn a_one_mass_rig_through_the_sweep() {
    let dir = tempfile::tempdir().expect("temp dir");
    let d = dir.path();
    let rig = sweep_common::SDOF_STEP_RIG;
    std::fs::write(d.join("rig.json"), rig).expect("rig");
    // A placeholder record: 2 s at 0.1 ms (never scored).
    let mut rec = String::from("t_s,x_m\n");
    for i in 0..20_001 {
        rec.push_str(&format!("{:e},0\n", i as f64 * 1e-4));
    }
    std::fs::write(d.join("rec.csv"), rec).expect("record");
    // ζ = 0.2 at ω_d = 20π rad/s (the peak at 0.05 s, on a sample) for m = 1
    // kg; the sweep's second mass keeps k and c, so its ζ and ω_d follow.
    let zeta = 0.2_f64;
    let wd = 20.0 * PI;
    let wn = wd / (1.0 - zeta * zeta).sqrt();
    let (k, c) = (wn * wn, 2.0 * zeta * wn);
    let campaign = format!(
        r#"{{"name": "sdof-step", "rig": "rig.json", "params": {{"m": 1.0, "k": {k}, "c": {c}}},
            "experiments": [{{"name": "step", "drive": "velocity",
              "data": {{"file": "rec.csv", "time_column": "t_s", "force_column": "x_m"}}}}]}}"#
    );
    std::fs::write(d.join("c.json"), campaign).expect("campaign");
    let sweep = format!(
        r#"{{"campaign": "c.json", "variables": {{"m": {{"values": [1.0, 1.5]}}}},
            "metrics": [
              {{"name": "os", "metric": "overshoot", "output": "x"}},
              {{"name": "pk", "metric": "peak", "output": "x"}},
              {{"name": "x1", "metric": "first_crossing", "output": "x", "threshold": {}}},
              {{"name": "hz", "metric": "ringing_hz", "output": "x", "window_s": 0.1}}
            ]}}"#,
        1.0 / k
    );
    std::fs::write(d.join("s.json"), sweep).expect("sweep");
    let out = d.join("t.csv");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(["sweep", "s.json", "--out", "t.csv"])
        .current_dir(d)
        .output()
        .expect("rigfit runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&out).expect("table");
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().expect("a number")).collect())
        .collect();
    assert_eq!(rows.len(), 2);
    for row in &rows {
        let m = row[1];
        let wn = (k / m).sqrt();
        let zeta = c / (2.0 * (k * m).sqrt());
        let root = (1.0 - zeta * zeta).sqrt();
        let wd = wn * root;
        let os = (-zeta * PI / root).exp();
        // The second mass's peak falls between samples: the sampled
        // maximum is within (ω_d·dt/2)²/2 of the peak, relative.
        let sampled = if m == 1.0 { 1e-6 } else { (wd * 1e-4).powi(2) };
        close(Some(row[2]), os, sampled, "overshoot through the rig");
        close(
            Some(row[3]),
            (1.0 + os) / k,
            sampled,
            "peak through the rig",
        );
        close(
            Some(row[4]),
            (PI - (root / zeta).atan()) / wd,
            1e-6,
            "first crossing of the final value",
        );
        // A heavily damped ringing (ζ = 0.2): its spectral peak sits off
        // ω_d by the tail of the negative-frequency image, about 1e-3.
        close(Some(row[5]), wd / (2.0 * PI), 2e-3, "ringing frequency");
    }
}
