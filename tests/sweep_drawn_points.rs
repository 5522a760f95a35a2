//! Design points drawn from distributions: a Saltelli design over a one-mass
//! rig's mass, stiffness and damping under a unit force step, whose mean
//! displacement over a long window is about `1/k` whatever the mass and
//! damping: its Sobol indices put (almost) all the variance on `k`. The
//! indices table and picture are written; the table has one row per run of
//! the design (n (k + 2)); bad sampling and mixed variables are refused with
//! their JSON path before any run.

mod sweep_common;

use std::path::Path;
use std::process::Command;

use sweep_common::SDOF_STEP_RIG as RIG;

fn setup(d: &Path) {
    std::fs::write(d.join("rig.json"), RIG).unwrap();
    let mut rec = String::from("t_s,x_m\n");
    for i in 0..2001 {
        rec.push_str(&format!("{:e},0\n", i as f64 * 1e-3));
    }
    std::fs::write(d.join("rec.csv"), rec).unwrap();
    std::fs::write(
        d.join("c.json"),
        r#"{"name": "sdof", "rig": "rig.json", "params": {"m": 1.0, "k": 4000, "c": 40},
            "experiments": [{"name": "step", "drive": "velocity",
              "data": {"file": "rec.csv", "time_column": "t_s", "force_column": "x_m"}}]}"#,
    )
    .unwrap();
}

fn rigfit(d: &Path, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(args)
        .current_dir(d)
        .output()
        .expect("rigfit runs")
}

#[test]
fn sobol_indices_of_a_mean_displacement_fall_on_the_stiffness() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    setup(d);
    std::fs::write(
        d.join("s.json"),
        r#"{"campaign": "c.json",
            "variables": {"m": {"uniform": [0.5, 2.0]}, "k": {"loguniform": [2000, 8000]},
                          "c": {"lognormal": [40, 0.5]}},
            "sampling": {"method": "sobol", "points": 256, "seed": 3, "indices": true},
            "metrics": [{"name": "mean_x", "metric": "mean", "output": "x"},
                        {"name": "peak_x", "metric": "peak", "output": "x"},
                        {"name": "k_est", "metric": "expression", "expression": "1 / mean_x / k"}]}"#,
    )
    .unwrap();
    let o = rigfit(
        d,
        &[
            "sweep",
            "s.json",
            "--out",
            "t.csv",
            "--indices",
            "ix.csv",
            "--picture",
            "ix.svg",
            "--metric",
            "mean_x",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let table = std::fs::read_to_string(d.join("t.csv")).unwrap();
    assert_eq!(
        table.lines().count(),
        1 + 256 * 5,
        "n (k + 2) rows and a header"
    );
    assert!(table.starts_with("point,m,k,c,mean_x,peak_x,k_est\n"));
    // The formula reads the run's mean and the point's k: the mean
    // displacement under a unit force is 1/k but for the transient.
    for line in table.lines().skip(1) {
        let ratio: f64 = line.split(',').nth(6).unwrap().parse().unwrap();
        assert!((ratio - 1.0).abs() < 0.1, "1/(mean·k) = {ratio} in {line}");
    }
    let ix = std::fs::read_to_string(d.join("ix.csv")).unwrap();
    let row = |metric: &str, var: &str| -> Vec<f64> {
        let line = ix
            .lines()
            .find(|l| l.starts_with(&format!("{metric},{var},")))
            .unwrap_or_else(|| panic!("{metric},{var} in\n{ix}"));
        line.split(',')
            .skip(2)
            .map(|v| v.parse().unwrap())
            .collect()
    };
    let k = row("mean_x", "k");
    assert!(k[0] > 0.95 && k[3] > 0.95, "k's S1 and ST: {k:?}");
    for v in ["m", "c"] {
        let x = row("mean_x", v);
        assert!(x[0].abs() < 0.03 && x[3] < 0.03, "{v}'s S1 and ST: {x:?}");
        assert!(
            x[1] <= x[0] && x[0] <= x[2],
            "S1 inside its interval: {x:?}"
        );
    }
    // The peak's overshoot depends on the damping and the mass too.
    let (m, c) = (row("peak_x", "m"), row("peak_x", "c"));
    assert!(
        m[3] + c[3] > 0.05,
        "the mass and damping shape the peak: {m:?} {c:?}"
    );
    let svg = std::fs::read_to_string(d.join("ix.svg")).unwrap();
    assert_eq!(svg.matches("class=\"bar first\"").count(), 3);
    assert!(String::from_utf8_lossy(&o.stdout).contains("Sobol indices"));
}

#[test]
fn drawn_points_without_indices_and_a_latin_hypercube() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    setup(d);
    std::fs::write(
        d.join("s.json"),
        r#"{"campaign": "c.json",
            "variables": {"k": {"triangular": [3000, 4000, 6000]}},
            "sampling": {"method": "latin", "points": 50},
            "metrics": [{"name": "mean_x", "metric": "mean", "output": "x"}]}"#,
    )
    .unwrap();
    let o = rigfit(d, &["sweep", "s.json", "--out", "t.csv"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let ks: Vec<f64> = std::fs::read_to_string(d.join("t.csv"))
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    assert_eq!(ks.len(), 50);
    // One point in each of 50 strata of the triangular distribution's
    // probability.
    let cdf = |k: f64| {
        let (a, m, b) = (3000.0, 4000.0, 6000.0);
        if k <= m {
            (k - a).powi(2) / ((b - a) * (m - a))
        } else {
            1.0 - (b - k).powi(2) / ((b - a) * (b - m))
        }
    };
    let mut strata: Vec<usize> = ks.iter().map(|&k| (cdf(k) * 50.0) as usize).collect();
    strata.sort_unstable();
    assert_eq!(strata, (0..50).collect::<Vec<_>>());
    // Indices of points drawn without Saltelli's design are refused.
    let o = rigfit(
        d,
        &["sweep", "s.json", "--out", "u.csv", "--indices", "i.csv"],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("\"indices\": true"));
    assert!(!d.join("u.csv").exists());
}

#[test]
fn bad_drawn_designs_are_refused_with_their_path() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    setup(d);
    let cases = [
        (
            r#""variables": {"k": {"uniform": [3000, 5000]}, "m": {"values": [1, 2]}}"#,
            "variables.m",
        ),
        (
            r#""variables": {"k": {"uniform": [3000, 5000]}}"#,
            "sampling",
        ),
        (
            r#""variables": {"k": {"uniform": [5000, 3000]}}, "sampling": {"method": "random", "points": 8}"#,
            "variables.k",
        ),
        (
            r#""variables": {"k": {"values": [3000]}}, "sampling": {"method": "random", "points": 8}"#,
            "sampling",
        ),
        (
            r#""variables": {"k": {"uniform": [3000, 5000]}}, "sampling": {"method": "halton", "points": 8}"#,
            "sampling.method",
        ),
        (
            r#""variables": {"k": {"uniform": [3000, 5000]}}, "sampling": {"method": "random", "points": 1}"#,
            "sampling.points",
        ),
        (
            r#""variables": {"k": {"values": [3000]}}, "uncertainty": {"samples": 8}"#,
            "params",
        ),
        (
            r#""variables": {"k": {"values": [3000]}}, "substeps": "many""#,
            "substeps",
        ),
    ];
    let formulas = [
        (
            r#"{"name": "f", "metric": "expression", "expression": "2 * nope"}"#,
            "metrics[1].expression",
        ),
        (
            r#"{"name": "f", "metric": "expression", "expression": "2 * (m_x"}"#,
            "metrics[1].expression",
        ),
        (
            r#"{"name": "f", "metric": "expression"}"#,
            "metrics[1].expression",
        ),
        (
            r#"{"name": "f", "metric": "expression", "expression": "m_x", "output": "x"}"#,
            "metrics[1].output",
        ),
        (r#"{"name": "f", "metric": "peak"}"#, "metrics[1].output"),
    ];
    for (metric, path) in formulas {
        std::fs::write(
            d.join("bad.json"),
            format!(
                r#"{{"campaign": "c.json", "variables": {{"k": {{"values": [3000]}}}},
                    "metrics": [{{"name": "m_x", "metric": "mean", "output": "x"}}, {metric}]}}"#
            ),
        )
        .unwrap();
        let o = rigfit(d, &["sweep", "bad.json", "--out", "t.csv"]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{metric}: {err}");
        assert!(err.contains(path), "{metric}: expected `{path}` in: {err}");
    }
    for (vars, path) in cases {
        std::fs::write(
            d.join("bad.json"),
            format!(
                r#"{{"campaign": "c.json", {vars},
                    "metrics": [{{"name": "m_x", "metric": "mean", "output": "x"}}]}}"#
            ),
        )
        .unwrap();
        let o = rigfit(d, &["sweep", "bad.json", "--out", "t.csv"]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{vars}: {err}");
        assert!(err.contains(path), "{vars}: expected `{path}` in: {err}");
        assert!(!d.join("t.csv").exists());
    }
}
