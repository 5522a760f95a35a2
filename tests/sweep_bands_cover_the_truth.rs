//! The calibration's uncertainty carried into a prediction holds the truth:
//! a one-mass rig (spring and damper to ground, a unit force step) is
//! calibrated (its stiffness and damping free) on 200 synthetic records of a
//! known truth, each with its own noise seed; each calibration's
//! `result.json` then predicts a changed design (the mass doubled, which
//! the record never saw) through `rigfit sweep` with `"uncertainty"`, and the
//! 95 % band of the predicted overshoot and peak is checked against the
//! truth's prediction of the same design. About 95 % of the bands must hold
//! it: at least 180 and at most 199 of 200 (outside that range a well
//! calibrated band is rarer than 1 in 1 000).

mod sweep_common;

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rigfit::campaign::Campaign;
use rigfit::design::{Engine, RunOptions, Sweep, run_sweep};
use rigfit::eval::CpuEvaluator;
use rigfit::job::{self, JobOptions};

use sweep_common::SDOF_STEP_RIG as RIG;

/// The truth: 10 Hz undamped, ζ = 0.1 at m = 1 kg.
const K: f64 = 3947.841760435743;
const C: f64 = 12.566370614359172;
/// Samples and step of the record (0.3 s).
const SAMPLES: usize = 601;
const DT: f64 = 5e-4;
/// The noise, against a peak displacement of about 4.6e-4 m.
const NOISE: f64 = 1e-5;

/// The step response of the truth at m = 1 kg.
fn truth_x(t: f64) -> f64 {
    let (m, k, c) = (1.0, K, C);
    let wn = (k / m).sqrt();
    let z = c / (2.0 * (k * m).sqrt());
    let wd = wn * (1.0 - z * z).sqrt();
    (1.0 - (-z * wn * t).exp() * ((wd * t).cos() + z * wn / wd * (wd * t).sin())) / k
}

fn setup(d: &Path) {
    std::fs::write(d.join("rig.json"), RIG).unwrap();
    // The truth's values, and the sweep that predicts the doubled mass.
    std::fs::write(
        d.join("truth.json"),
        format!(r#"{{"m": 1.0, "k": {K}, "c": {C}}}"#),
    )
    .unwrap();
}

fn campaign_json(seed: u64) -> String {
    format!(
        r#"{{"name": "sdof-{seed}", "rig": "rig.json",
            "params": {{"m": 1.0,
              "k": {{"min": 1000, "max": 20000, "scale": "log"}},
              "c": {{"min": 1, "max": 100, "scale": "log"}}}},
            "experiments": [{{"name": "step", "drive": "velocity",
              "data": {{"file": "rec{seed}.csv", "time_column": "t_s", "force_column": "x_m"}}}}],
            "search": {{"population": 24, "generations": 6, "seed": {seed},
              "polish": {{"starts": 1}}}}}}"#
    )
}

fn sweep_json(seed: u64, params: &str, draws: bool) -> String {
    let u = if draws {
        format!(r#", "uncertainty": {{"samples": 200, "seed": {seed}}}"#)
    } else {
        String::new()
    };
    format!(
        r#"{{"campaign": "c{seed}.json", "params": "{params}",
            "variables": {{"m": {{"values": [2.0]}}}},
            "metrics": [{{"name": "os", "metric": "overshoot", "output": "x"}},
                        {{"name": "pk", "metric": "peak", "output": "x"}}],
            "substeps": 4{u}}}"#
    )
}

fn sweep(path: &Path) -> rigfit::design::Table {
    let s = Sweep::load(path).unwrap_or_else(|e| panic!("{e}"));
    run_sweep(&s, &RunOptions::default(), Engine::Cpu, &|_, _| {}).unwrap()
}

#[test]
fn prediction_bands_hold_the_truth_in_about_95_percent_of_200_noise_seeds() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    setup(d);
    let seeds = 200u64;
    let mut held = [0usize; 2];
    let mut widths = [0.0f64; 2];
    let mut truth_pred: Option<Vec<f64>> = None;
    for seed in 0..seeds {
        let mut rng = ChaCha8Rng::seed_from_u64(1000 + seed);
        let mut rec = String::from("t_s,x_m\n");
        for i in 0..SAMPLES {
            let t = i as f64 * DT;
            // Box–Muller.
            let (u1, u2): (f64, f64) = (1.0 - rng.random::<f64>(), rng.random::<f64>());
            let n = (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos();
            rec.push_str(&format!("{t:e},{:e}\n", truth_x(t) + NOISE * n));
        }
        std::fs::write(d.join(format!("rec{seed}.csv")), rec).unwrap();
        let cfile = format!("c{seed}.json");
        std::fs::write(d.join(&cfile), campaign_json(seed)).unwrap();
        let c = Campaign::load(&d.join(&cfile)).unwrap();
        let out = d.join(format!("out{seed}"));
        let opts = JobOptions {
            out: out.clone(),
            resume: false,
            quiet: true,
            interrupt: Arc::new(AtomicBool::new(false)),
            require_gpu: false,
            threads: 0,
        };
        job::run(&c, Box::new(CpuEvaluator::new(c.problem.clone(), 0)), &opts)
            .unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        if truth_pred.is_none() {
            std::fs::write(
                d.join("truth.sweep.json"),
                sweep_json(seed, "truth.json", false),
            )
            .unwrap();
            let t = sweep(&d.join("truth.sweep.json"));
            truth_pred = Some(t.rows[0].metrics.iter().map(|m| m.unwrap()).collect());
        }
        let truth = truth_pred.as_ref().unwrap();
        let sfile = d.join(format!("s{seed}.json"));
        std::fs::write(
            &sfile,
            sweep_json(seed, &format!("out{seed}/result.json"), true),
        )
        .unwrap();
        let t = sweep(&sfile);
        for m in 0..2 {
            let b = t.rows[0].bands[m].expect("a band");
            assert!(b.lo <= b.median && b.median <= b.hi);
            widths[m] += (b.hi - b.lo) / truth[m] / seeds as f64;
            if b.lo <= truth[m] && truth[m] <= b.hi {
                held[m] += 1;
            }
        }
    }
    eprintln!(
        "95 % bands of the doubled mass's prediction holding the truth's, of {seeds} noise \
         seeds: overshoot {} (mean width {:.2} % of it), peak {} (mean width {:.2} %)",
        held[0],
        100.0 * widths[0],
        held[1],
        100.0 * widths[1]
    );
    for (m, name) in ["overshoot", "peak"].iter().enumerate() {
        assert!(
            (180..=199).contains(&held[m]),
            "{name}: the band held the truth in {} of {seeds} seeds; about 95 % expected",
            held[m]
        );
    }
}

/// `rigfit simulate --params result.json --bands N`: each output gets its
/// median and 95 % band over the draws as columns, the band brackets the
/// calibrated run, and a job's result without a polish is refused.
#[test]
fn simulate_draws_prediction_bands_from_a_result() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    setup(d);
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut rec = String::from("t_s,x_m\n");
    for i in 0..SAMPLES {
        let t = i as f64 * DT;
        let (u1, u2): (f64, f64) = (1.0 - rng.random::<f64>(), rng.random::<f64>());
        let n = (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos();
        rec.push_str(&format!("{t:e},{:e}\n", truth_x(t) + NOISE * n));
    }
    std::fs::write(d.join("rec7.csv"), rec).unwrap();
    std::fs::write(d.join("c7.json"), campaign_json(7)).unwrap();
    let rigfit = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_rigfit"))
            .args(args)
            .current_dir(d)
            .output()
            .unwrap()
    };
    let o = rigfit(&["run", "c7.json", "--out", "fit", "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = rigfit(&[
        "simulate",
        "c7.json",
        "--params",
        "fit/result.json",
        "--bands",
        "100",
        "--out",
        "b.csv",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(d.join("b.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("{name} in {header:?}"))
    };
    let (x, m, lo, hi) = (col("x_m"), col("x_m.median"), col("x_m.lo"), col("x_m.hi"));
    let mut inside = 0;
    let mut rows = 0;
    for l in lines {
        let v: Vec<f64> = l.split(',').map(|c| c.parse().unwrap()).collect();
        assert!(v[lo] <= v[m] && v[m] <= v[hi], "{l}");
        rows += 1;
        if v[lo] <= v[x] && v[x] <= v[hi] {
            inside += 1;
        }
    }
    assert_eq!(rows, SAMPLES);
    assert!(
        inside as f64 >= 0.95 * rows as f64,
        "{inside} of {rows} samples inside"
    );
    // A flat parameter file has no covariance to draw from.
    std::fs::write(d.join("flat.json"), format!(r#"{{"k": {K}, "c": {C}}}"#)).unwrap();
    let o = rigfit(&[
        "simulate",
        "c7.json",
        "--params",
        "flat.json",
        "--bands",
        "10",
        "--out",
        "f.csv",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--bands"));
    assert!(!d.join("f.csv").exists());
    // --bands without --params is refused by the flags.
    let o = rigfit(&["simulate", "c7.json", "--bands", "10", "--out", "g.csv"]);
    assert_eq!(o.status.code(), Some(2));
}
