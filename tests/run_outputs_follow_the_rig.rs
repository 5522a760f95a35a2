//! `rigfit run` and `rigfit modes` on compiled rigs that are not the tensile
//! rig: every output file is written and well formed for a rig with one output
//! and for one with three (columns named from the rig's own outputs), and the
//! modes header names the rig and the point it is linearised about.

use std::path::Path;
use std::process::{Command, Output};

use serde_json::{Value, json};

fn rigfit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

const DT: f64 = 1e-3;
const SAMPLES: usize = 300;

/// A mass on a spring and a damper to ground, pushed by a sine force; the
/// outputs are the first `n` of displacement (m), spring force (N) and
/// velocity (m/s).
fn rig(n: usize) -> Value {
    let outputs = [
        json!({"name": "displacement", "unit": "m", "sum": [{"displacement": "mass"}]}),
        json!({"name": "spring_force", "unit": "N", "sum": [{"force": "joint"}]}),
        json!({"name": "velocity", "unit": "m/s", "sum": [{"velocity": "mass"}]}),
    ];
    json!({
        "id": format!("sdof_{n}_outputs"),
        "params": [
            {"name": "m", "unit": "kg", "default": 1.0},
            {"name": "k", "unit": "N/m", "default": 4e3},
            {"name": "c", "unit": "N·s/m", "default": 8.0},
            {"name": "f0", "unit": "N", "default": 2.0},
            {"name": "freq", "unit": "Hz", "default": 5.0}
        ],
        "nodes": [{"name": "mass", "mass": "m"}],
        "elements": [{
            "name": "joint", "between": ["ground", "mass"],
            "spring": {"law": "linear", "k": "k"}, "damper": {"law": "viscous", "c": "c"}
        }],
        "drives": [{"node": "mass", "law": {"type": "sine", "quantity": "force",
                                            "amplitude": "f0", "frequency": "freq"}}],
        "outputs": outputs[..n]
    })
}

/// Writes a campaign over `rig` with one experiment `sweep` (a record of
/// `SAMPLES` samples) and a tiny search into `dir`; returns its path.
fn campaign(dir: &Path, rig: &Value) -> std::path::PathBuf {
    let mut record = String::from("t_s,force_N\n");
    for k in 0..SAMPLES {
        let t = k as f64 * DT;
        let x = 4e-4 * (std::f64::consts::TAU * 5.0 * t).sin() * (1.0 - (-t / 0.05).exp());
        record += &format!("{t:e},{x:e}\n");
    }
    std::fs::write(dir.join("sweep.csv"), record).unwrap();
    let c = json!({
        "name": "output-count",
        "rig": rig,
        "params": {"k": {"min": 2e3, "max": 8e3}, "c": {"min": 2.0, "max": 20.0}},
        "experiments": [{
            "name": "sweep",
            "data": {"file": "sweep.csv", "time_column": "t_s", "force_column": "force_N"}
        }],
        "solver": {"substeps": 4, "backend": "cpu"},
        "search": {"population": 16, "generations": 3, "seed": 2,
                   "polish": {"enabled": true, "starts": 1, "max_iterations": 4}}
    });
    let path = dir.join("campaign.json");
    std::fs::write(&path, c.to_string()).unwrap();
    path
}

fn numbers(line: &str) -> Vec<f64> {
    line.split(',')
        .map(|x| {
            x.parse()
                .unwrap_or_else(|_| panic!("{x:?} in {line:?} is not a number"))
        })
        .collect()
}

#[test]
fn run_writes_every_output_file_for_one_and_three_outputs() {
    for n in [1, 3] {
        let dir = tempfile::tempdir().unwrap();
        let rig = rig(n);
        let path = campaign(dir.path(), &rig);
        let out = dir.path().join("result");
        let o = rigfit()
            .arg("run")
            .arg(&path)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{n} outputs: rigfit run failed: {}",
            stderr(&o)
        );

        for f in [
            "result.json",
            "sweep.csv",
            "fit_sweep.svg",
            "history.csv",
            "fitness.svg",
        ] {
            assert!(out.join(f).is_file(), "{n} outputs: missing {f}");
        }

        let r: Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap())
                .unwrap();
        assert_eq!(r["rig"], rig["id"]);
        assert_eq!(r["generations"], 3);
        assert_eq!(r["experiments"][0]["csv"], "sweep.csv");
        assert_eq!(r["experiments"][0]["plot"], "fit_sweep.svg");
        assert!(r["fitness"].as_f64().unwrap().is_finite(), "{r}");
        for p in ["k", "c", "m", "sweep.offset"] {
            assert!(
                r["params"][p].is_number(),
                "{n} outputs: params.{p} missing"
            );
        }

        // One model column per rig output, named from the rig's name and unit;
        // the measurement and the residual in output 0's unit.
        let outputs = rig["outputs"].as_array().unwrap();
        let col = |o: &Value| {
            format!(
                "{}_{}",
                o["name"].as_str().unwrap(),
                o["unit"].as_str().unwrap()
            )
        };
        let mut header = vec![
            "t_record_s".to_string(),
            "t_model_s".into(),
            format!("measured_{}", col(&outputs[0])),
        ];
        header.extend(outputs.iter().map(|o| format!("model_{}", col(o))));
        header.push(format!("residual_{}", outputs[0]["unit"].as_str().unwrap()));
        header.push("in_fit_window".into());
        let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
        let mut lines = csv.lines();
        assert_eq!(lines.next().unwrap(), header.join(","), "{n} outputs");
        let rows: Vec<Vec<f64>> = lines.map(numbers).collect();
        assert_eq!(rows.len(), SAMPLES, "{n} outputs");
        let (measured, model, residual) = (2, 3, 3 + n);
        for row in &rows {
            assert_eq!(row.len(), header.len(), "{n} outputs");
            assert!(row[model].is_finite());
            let scale = row[measured].abs().max(row[model].abs()).max(1e-12);
            assert!(
                (row[residual] - (row[model] - row[measured])).abs() <= 1e-5 * scale,
                "{n} outputs: {row:?}"
            );
            assert!([0.0, 1.0].contains(&row[header.len() - 1]));
        }

        let history = std::fs::read_to_string(out.join("history.csv")).unwrap();
        let mut lines = history.lines();
        let width = lines.next().unwrap().split(',').count();
        let rows: Vec<&str> = lines.collect();
        assert_eq!(rows.len(), 3, "{n} outputs: one history row per generation");
        for row in rows {
            assert_eq!(row.split(',').count(), width, "{n} outputs: {row}");
        }

        for svg in ["fit_sweep.svg", "fitness.svg"] {
            let text = std::fs::read_to_string(out.join(svg)).unwrap();
            assert!(
                text.starts_with("<svg") && text.trim_end().ends_with("</svg>"),
                "{n} outputs: {svg} is not an SVG"
            );
        }
        let fit = std::fs::read_to_string(out.join("fit_sweep.svg")).unwrap();
        assert!(
            fit.contains("displacement"),
            "{n} outputs: fit plot names no output"
        );
        assert!(
            !fit.contains("load-cell"),
            "{n} outputs: fit plot speaks of a load cell"
        );
    }
}

fn modes_text(dir: &Path, rig: &Value) -> String {
    let path = campaign(dir, rig);
    let o = rigfit().arg("modes").arg(&path).output().unwrap();
    assert!(o.status.success(), "rigfit modes failed: {}", stderr(&o));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn modes_header_names_the_rig_and_its_linearisation_point() {
    let dir = tempfile::tempdir().unwrap();
    let plain = rig(1);
    let text = modes_text(dir.path(), &plain);
    println!("{text}");
    let header = text.lines().next().unwrap();
    assert!(header.starts_with("experiment sweep:"), "{header}");
    assert!(
        !text.contains("slack adapter") && !text.contains("specimen"),
        "{text}"
    );
    assert!(header.contains(plain["id"].as_str().unwrap()), "{header}");
    // No switching element: nothing to say about contacts or sliders.
    assert!(
        !header.contains("contact") && !header.contains("slider"),
        "{header}"
    );

    // A stop behind a gap and a friction element: the header says they are
    // taken closed and stuck.
    let mut switched = rig(1);
    switched["id"] = json!("sdof_with_stop_and_slider");
    switched["params"]
        .as_array_mut()
        .unwrap()
        .extend([json!({"name": "k_c", "unit": "N/m", "default": 1e4})]);
    switched["elements"].as_array_mut().unwrap().extend([
        json!({"name": "stop", "between": ["ground", "mass"],
               "spring": {"law": "linear", "k": "k_c"}, "gap": {"kind": "tension", "size": 0.001}}),
        json!({"name": "rub", "between": ["ground", "mass"],
               "friction": {"law": "stick_slip", "f_c": 1.0, "k_t": 1e5}}),
    ]);
    let text = modes_text(dir.path(), &switched);
    println!("{text}");
    let header = text.lines().next().unwrap();
    assert!(!text.contains("slack adapter"), "{text}");
    assert!(header.contains("sdof_with_stop_and_slider"), "{header}");
    assert!(header.contains("contact closed"), "{header}");
    assert!(header.contains("slider stuck"), "{header}");
    assert!(!header.contains("backlash"), "{header}");
}

#[test]
fn simulate_reports_the_peak_of_the_rigs_own_output() {
    let dir = tempfile::tempdir().unwrap();
    let path = campaign(dir.path(), &rig(1));
    let sim = dir.path().join("sim.csv");
    let o = rigfit()
        .args(["--json", "simulate"])
        .arg(&path)
        .arg("--out")
        .arg(&sim)
        .output()
        .unwrap();
    assert!(o.status.success(), "rigfit simulate failed: {}", stderr(&o));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["peak"]["output"], "displacement");
    assert_eq!(v["peak"]["unit"], "m");
    // The largest |x| in the written history.
    let csv = std::fs::read_to_string(&sim).unwrap();
    let peak = csv
        .lines()
        .skip(1)
        .map(|l| numbers(l)[1].abs())
        .fold(0.0_f64, f64::max);
    let got = v["peak"]["abs_max"].as_f64().unwrap();
    assert!(
        peak > 0.0 && (got - peak).abs() <= 1e-9 * peak,
        "{got} vs {peak}"
    );
    // The summary line names the output too, never a load cell.
    let o = rigfit()
        .arg("simulate")
        .arg(&path)
        .arg("--out")
        .arg(&sim)
        .arg("--overwrite")
        .output()
        .unwrap();
    assert!(o.status.success(), "rigfit simulate failed: {}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("largest |displacement|") && text.contains(" m → "),
        "{text}"
    );
    assert!(!text.contains("load"), "{text}");
}
