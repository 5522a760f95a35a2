//! Validation records are simulated at the fitted values, never fitted: a
//! record made with the fit's own true values (another drive, another noise
//! seed) sits at its noise floor, one made with a stiffer spring is flagged;
//! `rigfit validate` on the finished job writes the same numbers and bytes;
//! a validation record with a free value of its own is refused by its JSON
//! path, and a campaign of another rig is refused naming both.
//!
//! The records are made here, as the README's "Your own rig in three
//! commands" makes its own: `rigfit simulate --noise` from true values.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use rigfit::campaign::Campaign;
use rigfit::job;
use serde_json::{Value, json};

/// The README's rig, its chirp's amplitude and start frequency parameters
/// of each experiment's own.
const RIG: &str = r#"{
  "id": "my_rig",
  "params": [{"name": "m", "unit": "kg"}, {"name": "k", "unit": "N/m", "scale": "log"},
             {"name": "c", "unit": "N·s/m", "default": 0.0},
             {"name": "F", "unit": "N", "scope": "experiment"},
             {"name": "f0", "unit": "Hz", "scope": "experiment"}],
  "nodes": [{"name": "mass", "mass": "m"}],
  "elements": [{"name": "suspension", "between": ["mass", "ground"],
                "spring": {"law": "linear", "k": "k"}, "damper": {"law": "viscous", "c": "c"}}],
  "drives": [{"node": "mass", "law": {"type": "chirp", "quantity": "force",
                                      "amplitude": "F", "f_start": "f0", "rate": 20.0}}],
  "outputs": [{"name": "displacement", "unit": "m", "sum": [{"displacement": "mass"}]}]
}"#;

/// The record's noise (m).
const SIGMA: f64 = 5e-6;

fn rigfit(dir: &Path, args: &[&str]) -> Output {
    let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    println!(
        "$ rigfit {}\n{}{}",
        args.join(" "),
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

fn experiment(name: &str, force: f64, f0: f64) -> Value {
    json!({
        "name": name,
        "data": {"file": format!("{name}.csv"), "time_column": "t_s", "column": "x_m"},
        "params": {"F": force, "f0": f0}
    })
}

/// A folder with the rig, the records (`e1` fitted; `w1` the same truth
/// driven harder from 2 Hz; `w2` that drive on a spring 25 % stiffer) and
/// the campaign `c.json` fitting `e1`, validated on `w1` and `w2`.
fn folder() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path();
    std::fs::write(p.join("my_rig.json"), RIG).unwrap();
    let records = [("e1", 10.0, 1.0), ("w1", 14.0, 2.0), ("w2", 14.0, 2.0)];
    let maker = json!({
        "name": "maker",
        "rig": "my_rig.json",
        "params": {"m": 2.0, "k": 4.0e4, "c": 12.0},
        "experiments": records.iter().map(|&(n, f, f0)| experiment(n, f, f0)).collect::<Vec<_>>(),
    });
    std::fs::write(p.join("maker.json"), maker.to_string()).unwrap();
    std::fs::write(p.join("truth.json"), r#"{"k": 4.0e4, "c": 12.0}"#).unwrap();
    std::fs::write(p.join("stiffer.json"), r#"{"k": 5.0e4, "c": 12.0}"#).unwrap();
    for (name, seed, truth) in [
        ("e1", "2", "truth.json"),
        ("w1", "3", "truth.json"),
        ("w2", "4", "stiffer.json"),
    ] {
        let out = format!("{name}.csv");
        let o = rigfit(
            p,
            &[
                "simulate",
                "maker.json",
                "--experiment",
                name,
                "--params",
                truth,
                "--duration",
                "2",
                "--dt",
                "1e-3",
                "--noise",
                "5e-6",
                "--seed",
                seed,
                "--out",
                &out,
            ],
        );
        assert!(o.status.success());
    }
    let campaign = json!({
        "name": "validated",
        "rig": "my_rig.json",
        "params": {"m": 2.0, "k": {"min": 1e3, "max": 1e6, "scale": "log"}, "c": {"min": 0.0, "max": 200.0}},
        "experiments": [experiment("e1", 10.0, 1.0)],
        "validation": [experiment("w1", 14.0, 2.0), experiment("w2", 14.0, 2.0)],
        "search": {"population": 128, "generations": 30, "seed": 1}
    });
    std::fs::write(p.join("c.json"), campaign.to_string()).unwrap();
    dir
}

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn validation_records_are_scored_at_the_fitted_values_and_a_changed_rig_is_flagged() {
    let dir = folder();
    let p = dir.path();
    let c = Campaign::load(&p.join("c.json")).unwrap();
    // The fit never sees the validation records.
    assert_eq!(c.problem.experiments.len(), 1);
    assert_eq!(c.genes.len(), 2);
    let v = c.validation.as_deref().expect("validation records");
    assert_eq!(v.problem.experiments.len(), 2);
    assert!(
        c.inputs.contains(&p.join("w2.csv")),
        "a validation record is an input"
    );
    // The job as a user runs it, so that its folder is one rigfit owns.
    let out = p.join("out");
    let o = rigfit(p, &["run", "c.json", "--backend", "cpu", "--out", "out"]);
    assert!(o.status.success());
    let result = read_json(&out.join("result.json"));
    let cost = |x: &Value| x["cost_over_noise_floor"].as_f64().unwrap();
    let fitted = cost(&result["experiments"][0]);
    let val = &result["validation"];
    let (w1, w2) = (&val["experiments"][0], &val["experiments"][1]);
    let (k1, k2) = (cost(w1), cost(w2));
    println!("fit {fitted:.3}×, w1 {k1:.3}×, w2 {k2:.3}×");
    assert!(
        (0.7..1.3).contains(&fitted),
        "the fit is at its floor: {fitted}"
    );
    // The same truth: at the floor, though never fitted.
    assert!((0.7..1.3).contains(&k1), "w1: {k1}× its noise floor");
    let noise = w1["noise_estimate"].as_f64().unwrap();
    assert!(
        (noise / SIGMA - 1.0).abs() < 0.2,
        "w1's noise estimate {noise}"
    );
    // A 25 % stiffer spring: far above it, and flagged.
    assert!(k2 > 10.0, "w2: {k2}× its noise floor");
    assert_eq!(val["estimation_cost_over_noise_floor"], json!(fitted));
    assert_eq!(val["factor"], json!(job::VALIDATION_FACTOR));
    let flagged: Vec<&str> = result["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(Value::as_str)
        .filter(|w| w.starts_with(job::WARNING_PREFIX))
        .collect();
    assert_eq!(flagged.len(), 1, "{flagged:?}");
    assert!(flagged[0].contains("'w2'"), "{flagged:?}");
    let verdict = &result["verdict"];
    let flags = verdict["flags"].as_array().unwrap();
    assert!(
        flags
            .iter()
            .any(|f| f.as_str().unwrap().starts_with("validation w2")),
        "{verdict}"
    );
    assert!(
        verdict["line"].as_str().unwrap().contains("validation w2"),
        "{verdict}"
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("validation w1: R² = "), "{stdout}");

    // result.json holds what the report reads; the CSVs have the fit's columns.
    let written = &result["validation"];
    for key in [
        "name",
        "r2",
        "one_minus_r2",
        "residual_rms",
        "unit",
        "noise_estimate",
        "cost_over_noise_floor",
        "csv",
    ] {
        assert!(!written["experiments"][0][key].is_null(), "{key}");
    }
    assert_eq!(written["experiments"][1]["csv"], "validation_w2.csv");
    assert_eq!(written["estimation_cost_over_noise_floor"], json!(fitted));
    let header = |name: &str| {
        std::fs::read_to_string(out.join(name))
            .unwrap()
            .lines()
            .next()
            .unwrap()
            .to_string()
    };
    assert_eq!(header("validation_w1.csv"), header("e1.csv"));
    let manifest = std::fs::read_to_string(out.join(job::MANIFEST_FILE)).unwrap();
    assert!(manifest.contains("validation_w2.csv"), "{manifest}");

    // After the fact, the same records give the same numbers and bytes.
    let csv_before = std::fs::read(out.join("validation_w2.csv")).unwrap();
    std::fs::remove_file(out.join("validation_w2.csv")).unwrap();
    let o = rigfit(p, &["validate", "out", "c.json"]);
    assert!(o.status.success());
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("validation w1: R² = "), "{stdout}");
    let again = read_json(&out.join("result.json"));
    assert_eq!(again["validation"], result["validation"]);
    assert_eq!(again["warnings"], result["warnings"]);
    assert_eq!(again["verdict"], result["verdict"]);
    assert_eq!(again["params"], result["params"]);
    assert_eq!(
        std::fs::read(out.join("validation_w2.csv")).unwrap(),
        csv_before
    );

    // A campaign without "validation": its experiments are the records.
    let only_w1 = json!({
        "name": "w1-only",
        "rig": "my_rig.json",
        "params": {"m": 2.0, "k": {"min": 1e3, "max": 1e6, "scale": "log"}, "c": {"min": 0.0, "max": 200.0}},
        "experiments": [experiment("w1", 14.0, 2.0)]
    });
    std::fs::write(p.join("w1_only.json"), only_w1.to_string()).unwrap();
    let o = rigfit(p, &["--json", "validate", "out", "w1_only.json"]);
    assert!(o.status.success());
    let printed: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(
        printed["experiments"][0],
        result["validation"]["experiments"][0]
    );
    let last = read_json(&out.join("result.json"));
    assert_eq!(
        last["validation"]["experiments"].as_array().unwrap().len(),
        1
    );
    // The earlier flag went with the earlier records.
    assert!(
        !last["verdict"]["line"]
            .as_str()
            .unwrap()
            .contains("validation w2"),
        "{}",
        last["verdict"]["line"]
    );
    let kept = last["warnings"].as_array().unwrap();
    assert!(kept.iter().all(|w| !w.as_str().unwrap().contains("'w2'")));

    // Another rig is refused, naming both.
    let shipped =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("campaigns/inertial_sdof_synthetic.json");
    let o = rigfit(p, &["validate", "out", shipped.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("'inertial_sdof'") && err.contains("'my_rig'"),
        "{err}"
    );
    // What is not a job's folder is refused as such.
    let o = rigfit(p, &["validate", ".", "c.json"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("not a rigfit job"));
}

#[test]
fn a_free_value_of_a_validation_records_own_is_refused_by_its_path() {
    let dir = folder();
    let p = dir.path();
    let mut c = read_json(&p.join("c.json"));
    c["validation"][1]["params"]["F"] = json!({"min": 1.0, "max": 20.0});
    std::fs::write(p.join("free.json"), c.to_string()).unwrap();
    let err = Campaign::load(&p.join("free.json"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("validation[1].params.F"), "{err}");
    assert!(
        err.contains("never fitted") && err.contains("fixed value"),
        "{err}"
    );

    let mut c = read_json(&p.join("c.json"));
    c["validation"][0]["offset"] = json!({"min": -1e-3, "max": 1e-3});
    std::fs::write(p.join("offset.json"), c.to_string()).unwrap();
    let err = Campaign::load(&p.join("offset.json"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("validation[0].offset"), "{err}");

    // A validation record's own errors are named under "validation".
    let mut c = read_json(&p.join("c.json"));
    c["validation"][1]["data"]["file"] = json!("missing.csv");
    std::fs::write(p.join("missing.json"), c.to_string()).unwrap();
    let err = Campaign::load(&p.join("missing.json"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("validation[1].data.file"), "{err}");

    let mut c = read_json(&p.join("c.json"));
    c["validation"] = json!([]);
    std::fs::write(p.join("empty.json"), c.to_string()).unwrap();
    let err = Campaign::load(&p.join("empty.json"))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("validation: expected at least one record"),
        "{err}"
    );
}
