//! Runs the `rigfit` binary as a user would: the README's first command on the
//! shipped campaign (with small search settings), the files it leaves, feeding
//! the result back into `simulate`, exit codes and bad input.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn rigfit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
}

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn shipped() -> PathBuf {
    repo().join("campaigns/aa2024_t3_synthetic.json")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn read_json(p: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

#[test]
fn readme_run_command_leaves_a_complete_result_folder() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("result");
    let o = rigfit()
        .arg("run")
        .arg(shipped())
        .arg("--out")
        .arg(&out)
        .args(["--population", "48", "--generations", "3", "--seed", "5"])
        .output()
        .unwrap();
    assert!(o.status.success(), "rigfit run failed: {}", stderr(&o));
    let summary = String::from_utf8_lossy(&o.stdout);
    assert!(summary.contains("R² ="), "no summary on stdout: {summary}");

    for f in [
        "result.json",
        "v2.csv",
        "fit_v2.svg",
        "history.csv",
        "fitness.svg",
    ] {
        assert!(out.join(f).is_file(), "missing {f}");
    }
    assert!(
        !out.join("checkpoint.json").exists(),
        "checkpoint left behind"
    );

    let r = read_json(&out.join("result.json"));
    assert_eq!(r["seed"], 5);
    assert_eq!(r["rig"], "tensile4");
    assert_eq!(r["generations"], 3);
    assert!(["cpu", "gpu"].contains(&r["backend"].as_str().unwrap()));
    let exp = &r["experiments"][0];
    let r2 = exp["r2"].as_f64().unwrap();
    let fitness = r["fitness"].as_f64().unwrap();
    assert!(
        (1.0 - r2 - fitness).abs() < 1e-9 + 1e-6 * fitness,
        "R² {r2} vs fitness {fitness}"
    );
    let reference = exp["r2_cpu_reference"].as_f64().unwrap();
    assert!(
        (reference - r2).abs() < 1e-3,
        "evaluator R² {r2} vs CPU reference {reference}"
    );
    for name in ["k1", "c1_post", "v2.k_lin", "v2.offset", "m1"] {
        assert!(r["params"][name].is_number(), "params.{name} missing");
    }
    let k1 = r["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "k1")
        .unwrap();
    assert_eq!(k1["free"], true);
    assert_eq!(k1["unit"], "N/m");
    let [lo, hi] = [
        k1["bounds"][0].as_f64().unwrap(),
        k1["bounds"][1].as_f64().unwrap(),
    ];
    let v = k1["value"].as_f64().unwrap();
    assert!(lo <= v && v <= hi);
    assert!(k1["elite_range"].is_array());

    let csv = std::fs::read_to_string(out.join("v2.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t_record_s,t_model_s,measured_load_cell_force_N,model_load_cell_force_N,model_specimen_force_N,residual_N,in_fit_window"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 2501);
    for row in &rows {
        assert!((row[5] - (row[3] - row[2])).abs() <= 1e-6 * row[2].abs().max(1.0) + 1e-3);
    }
    let history = std::fs::read_to_string(out.join("history.csv")).unwrap();
    assert_eq!(
        history.lines().count(),
        1 + 3,
        "header + one row per generation"
    );
    for svg in ["fit_v2.svg", "fitness.svg"] {
        let text = std::fs::read_to_string(out.join(svg)).unwrap();
        assert!(
            text.starts_with("<svg") && text.contains("</svg>"),
            "{svg} is not an SVG"
        );
    }

    // The result file feeds back into simulate and reproduces the model force.
    let sim = dir.path().join("sim.csv");
    let o = rigfit()
        .arg("simulate")
        .arg(shipped())
        .arg("--params")
        .arg(out.join("result.json"))
        .arg("--out")
        .arg(&sim)
        .arg("--quiet")
        .output()
        .unwrap();
    assert!(o.status.success(), "simulate failed: {}", stderr(&o));
    let sim_text = std::fs::read_to_string(&sim).unwrap();
    let sim_rows: Vec<Vec<f64>> = sim_text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    let peak = rows.iter().fold(0.0_f64, |m, r| m.max(r[3].abs()));
    for (a, b) in sim_rows.iter().zip(&rows) {
        assert!(
            (a[1] - b[3]).abs() <= 1e-3 * peak,
            "simulate --params result.json differs from the run's model force at t = {}",
            b[0]
        );
    }
}

#[test]
fn existing_results_are_not_overwritten_without_asking() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("result.json"), "{}").unwrap();
    let o = rigfit()
        .arg("run")
        .arg(shipped())
        .arg("--out")
        .arg(dir.path())
        .args(["--backend", "cpu", "--generations", "1"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--overwrite"), "{}", stderr(&o));
    assert_eq!(
        std::fs::read_to_string(dir.path().join("result.json")).unwrap(),
        "{}"
    );
}

#[test]
fn bad_campaign_exits_2_with_one_line_and_no_output_folder() {
    let dir = tempfile::tempdir().unwrap();
    let mut c = read_json(&shipped());
    c["params"]["m1"] = Value::from(-1.0);
    c["experiments"][0]["data"]["file"] = Value::from(
        repo()
            .join("campaigns/aa2024_t3_v2_synthetic.csv")
            .to_str()
            .unwrap(),
    );
    c["output"] = Value::from("out");
    let path = dir.path().join("bad.json");
    std::fs::write(&path, serde_json::to_string_pretty(&c).unwrap()).unwrap();
    let o = rigfit().arg("run").arg(&path).output().unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    let first = err.lines().next().unwrap();
    assert!(first.contains("bad.json") && first.contains("m1"), "{err}");
    assert!(
        !dir.path().join("out").exists(),
        "output folder created for bad input"
    );
}

#[test]
fn json_flag_prints_machine_readable_output() {
    let o = rigfit()
        .args(["--json", "check"])
        .arg(shipped())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["rig"], "tensile4");
    assert_eq!(v["genes"].as_array().unwrap().len(), 7);
}

#[test]
fn usage_errors_exit_2_and_help_exits_0() {
    let o = rigfit().args(["run"]).output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    let o = rigfit().args(["run", "--help"]).output().unwrap();
    assert!(o.status.success());
    let help = String::from_utf8_lossy(&o.stdout);
    assert!(help.contains("Examples:") && help.contains("--resume"));
    let o = rigfit().arg("--version").output().unwrap();
    assert!(String::from_utf8_lossy(&o.stdout).contains(env!("CARGO_PKG_VERSION")));
}

#[test]
fn modes_shows_the_load_cell_mode() {
    let o = rigfit()
        .args(["--json", "modes"])
        .arg(shipped())
        .arg("--params")
        .arg(repo().join("campaigns/aa2024_t3_reference_params.json"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    let modes = v[0]["modes"]["modes"].as_array().unwrap();
    assert!(
        modes
            .iter()
            .any(|m| (m["frequency_hz"].as_f64().unwrap() - 5217.0).abs() < 20.0),
        "{v}"
    );
}

#[test]
fn precalibration_commands_write_campaign_fragments() {
    let dir = tempfile::tempdir().unwrap();
    let frag = dir.path().join("specimen.json");
    let o = rigfit()
        .args(["--quiet", "fit-specimen"])
        .arg(repo().join("campaigns/specimen_quasistatic_synthetic.csv"))
        .args(["--degree", "3", "--out"])
        .arg(&frag)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let f = read_json(&frag);
    let k_lin = f["params"]["k_lin"].as_f64().unwrap();
    assert!((k_lin / 8.63e7 - 1.0).abs() < 0.01, "k_lin {k_lin}");
    assert!(f["params"]["e_yield"].is_number() && f["params"]["a3"].is_number());

    let o = rigfit()
        .args(["--json", "ringdown"])
        .arg(repo().join("campaigns/ringdown_synthetic.csv"))
        .args(["--m1", "7.9"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    let c1 = v["fragment"]["params"]["c1_post"].as_f64().unwrap();
    assert!((c1 / 9220.0 - 1.0).abs() < 0.02, "c1_post {c1}");

    let o = rigfit().arg("ringdown").arg(shipped()).output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("aa2024_t3_synthetic.json"),
        "{}",
        stderr(&o)
    );
}
