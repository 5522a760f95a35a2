//! Proves that a sweep's rows are the runs `rigfit simulate --params` makes
//! of the same values, bit for bit: every row's metrics equal those of the
//! history the library gives for that point along simulate's own path (the
//! campaign loaded for a simulation, the parameter file applied, the step of
//! a simulation without noise), and its peak equals the `abs_max` the
//! `rigfit simulate` binary reports. Also that the table is written
//! atomically, that an existing file is kept without `--overwrite`, and that
//! bad sweep files are refused with their JSON path.

use std::path::{Path, PathBuf};
use std::process::Command;

use rigfit::campaign::{Campaign, DEFAULT_MAX_STEPS, SimulationGrid};
use rigfit::design::Sweep;
use rigfit::eval::simulate_history;

fn campaign() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns/aa2024_t3_synthetic.json")
}

fn rigfit(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(args)
        .output()
        .expect("rigfit runs")
}

const METRICS: &str = r#"[
    {"name": "ring", "metric": "ringing", "output": "load_cell_force", "against": "specimen_force"},
    {"name": "ring_hz", "metric": "ringing_hz", "output": "load_cell_force", "against": "specimen_force"},
    {"name": "peak", "metric": "peak", "output": "load_cell_force"},
    {"name": "over", "metric": "overshoot", "output": "specimen_force"},
    {"name": "cross", "metric": "first_crossing", "output": "load_cell_force", "threshold": 1e9},
    {"name": "e", "metric": "energy", "output": "specimen_force"}
]"#;

fn write_sweep(dir: &Path, variables: &str) -> PathBuf {
    let path = dir.join("design.sweep.json");
    let text = format!(
        r#"{{"campaign": {:?}, "variables": {variables}, "metrics": {METRICS}}}"#,
        campaign().display().to_string()
    );
    std::fs::write(&path, text).expect("sweep file written");
    path
}

/// The cells of a CSV table, header first.
fn table(path: &Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(path)
        .expect("table read")
        .lines()
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

#[test]
fn rows_equal_the_runs_simulate_makes() {
    let dir = tempfile::tempdir().expect("temp dir");
    let sweep_file = write_sweep(
        dir.path(),
        r#"{"c4": {"log": [2e3, 5e4, 2]}, "m1": {"values": [6.5, 7.9]}}"#,
    );
    let out = dir.path().join("table.csv");
    let o = rigfit(&[
        "sweep",
        sweep_file.to_str().expect("utf-8"),
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rows = table(&out);
    assert_eq!(
        rows[0],
        [
            "point", "c4", "m1", "ring", "ring_hz", "peak", "over", "cross", "e"
        ]
    );
    assert_eq!(rows.len(), 5, "one row per design point");
    let sweep = Sweep::load(&sweep_file).expect("sweep loads");
    for row in &rows[1..] {
        let (c4, m1) = (&row[1], &row[2]);
        let params = dir.path().join(format!("point{}.json", row[0]));
        std::fs::write(&params, format!(r#"{{"c4": {c4}, "m1": {m1}}}"#)).expect("params");
        // Simulate's path, through the library.
        let mut c = Campaign::load_for_simulation(&campaign(), &SimulationGrid::Record)
            .expect("campaign loads");
        c.apply_param_file(&params).expect("values apply");
        let step = c.simulation_step(&[(0, 0.0)], None, DEFAULT_MAX_STEPS);
        c.problem.substeps = step.substeps;
        let h = simulate_history(&c.problem, 0, &c.base[0], c.base_offsets[0]);
        let w = c.problem.experiments[0].window.clone();
        let outputs: Vec<&[f64]> = h.outputs.iter().map(|o| &o[w.clone()]).collect();
        for (m, cell) in sweep.metrics.iter().zip(&row[3..]) {
            let expected = m.evaluate(&h.t[w.clone()], &outputs, c.problem.experiments[0].dt);
            let found: Option<f64> = (!cell.is_empty()).then(|| cell.parse().expect("a number"));
            assert_eq!(
                found.map(f64::to_bits),
                expected.map(f64::to_bits),
                "point {} metric {}: the sweep's {found:?} against simulate's path {expected:?}",
                row[0],
                m.name
            );
        }
        assert_eq!(
            row[7], "",
            "a threshold never crossed leaves the cell empty"
        );
        // The binary's own run: its largest |load_cell_force|.
        let sim_out = dir.path().join("sim.csv");
        let s = rigfit(&[
            "--json",
            "simulate",
            campaign().to_str().expect("utf-8"),
            "--params",
            params.to_str().expect("utf-8"),
            "--out",
            sim_out.to_str().expect("utf-8"),
            "--overwrite",
        ]);
        assert!(s.status.success(), "{}", String::from_utf8_lossy(&s.stderr));
        let v: serde_json::Value = serde_json::from_slice(&s.stdout).expect("json");
        let peak = v["peak"]["abs_max"].as_f64().expect("abs_max");
        let swept: f64 = row[5].parse().expect("peak");
        assert_eq!(swept.to_bits(), peak.to_bits(), "point {}", row[0]);
    }
    // An existing table is kept without --overwrite.
    let again = rigfit(&[
        "sweep",
        sweep_file.to_str().expect("utf-8"),
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert_eq!(again.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&again.stderr).contains("exists"));
    // Never one of its inputs, even with --overwrite.
    let input = rigfit(&[
        "sweep",
        sweep_file.to_str().expect("utf-8"),
        "--out",
        sweep_file.to_str().expect("utf-8"),
        "--overwrite",
    ]);
    assert_eq!(input.status.code(), Some(2));
}

#[test]
fn bad_sweep_files_are_refused_with_their_json_path() {
    let dir = tempfile::tempdir().expect("temp dir");
    let cases: &[(&str, &str, &[&str])] = &[
        (
            r#"{"k9": {"values": [1.0]}}"#,
            METRICS,
            &["variables.k9", "unknown parameter"],
        ),
        (
            r#"{"c4": {"log": [0.0, 1e4, 3]}}"#,
            METRICS,
            &["variables.c4", "log range"],
        ),
        (
            r#"{"c4": {"linear": [1e3, 1e4, 2.5]}}"#,
            METRICS,
            &["variables.c4", "whole number"],
        ),
        (
            r#"{"c4": {"steps": [1e3]}}"#,
            METRICS,
            &["variables.c4", "steps"],
        ),
        (
            r#"{"c4": {"values": [1e3]}}"#,
            r#"[{"name": "a", "metric": "peak", "output": "loadcell"}]"#,
            &["metrics[0].output", "load_cell_force, specimen_force"],
        ),
        (
            r#"{"c4": {"values": [1e3]}}"#,
            r#"[{"name": "a", "metric": "wobble", "output": "load_cell_force"}]"#,
            &["metrics[0].metric", "ringing_hz"],
        ),
        (
            r#"{"c4": {"values": [1e3]}}"#,
            r#"[{"name": "a", "metric": "ringing", "output": "load_cell_force"}]"#,
            &["metrics[0].against", "window_s"],
        ),
        (
            r#"{"c4": {"values": [1e3]}}"#,
            r#"[{"name": "a", "metric": "peak", "output": "load_cell_force", "colour": 1}]"#,
            &["metrics[0]", "colour"],
        ),
        (
            r#"{"c4": {"values": [1e3]}}"#,
            r#"[{"name": "c4", "metric": "peak", "output": "load_cell_force"}]"#,
            &["metrics[0].name", "not yet taken"],
        ),
    ];
    for (variables, metrics, expected) in cases {
        let path = dir.path().join("bad.sweep.json");
        let text = format!(
            r#"{{"campaign": {:?}, "variables": {variables}, "metrics": {metrics}}}"#,
            campaign().display().to_string()
        );
        std::fs::write(&path, &text).expect("written");
        let out = dir.path().join("never.csv");
        let o = rigfit(&[
            "sweep",
            path.to_str().expect("utf-8"),
            "--out",
            out.to_str().expect("utf-8"),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{text}: {err}");
        assert!(err.contains("bad.sweep.json"), "names the file: {err}");
        for e in *expected {
            assert!(err.contains(e), "{text}: expected `{e}` in: {err}");
        }
        assert!(!out.exists(), "nothing written for a refused sweep");
    }
}

#[test]
fn a_fixed_step_equals_simulate_with_substeps() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("fixed.sweep.json");
    let text = format!(
        r#"{{"campaign": {:?}, "variables": {{"k1": {{"values": [5e9, 1.2e10]}}}},
            "metrics": {METRICS}, "substeps": 3}}"#,
        campaign().display().to_string()
    );
    std::fs::write(&path, text).expect("sweep file written");
    let out = dir.path().join("fixed.csv");
    let o = rigfit(&[
        "sweep",
        path.to_str().expect("utf-8"),
        "--out",
        out.to_str().expect("utf-8"),
        "--threads",
        "1",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rows = table(&out);
    assert_eq!(rows.len(), 3);
    for row in &rows[1..] {
        let params = dir.path().join(format!("k{}.json", row[0]));
        std::fs::write(&params, format!(r#"{{"k1": {}}}"#, row[1])).expect("params");
        let sim_out = dir.path().join("sim.csv");
        let s = rigfit(&[
            "--json",
            "simulate",
            campaign().to_str().expect("utf-8"),
            "--params",
            params.to_str().expect("utf-8"),
            "--substeps",
            "3",
            "--out",
            sim_out.to_str().expect("utf-8"),
            "--overwrite",
        ]);
        assert!(s.status.success(), "{}", String::from_utf8_lossy(&s.stderr));
        let v: serde_json::Value = serde_json::from_slice(&s.stdout).expect("json");
        assert_eq!(v["substeps"], 3);
        let peak = v["peak"]["abs_max"].as_f64().expect("abs_max");
        let swept: f64 = row[4].parse().expect("peak");
        assert_eq!(swept.to_bits(), peak.to_bits(), "point {}", row[0]);
    }
    // The two stiffnesses ring at different frequencies: the rows are the
    // points' own runs.
    assert_ne!(rows[1][3], rows[2][3]);
}
