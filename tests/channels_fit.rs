//! Several measured channels of one experiment fitted at once, end to end
//! through the binary: the quarter car (`rigs/quarter_car.json`) with an
//! accelerometer on the sprung mass whose sensitivity is a free parameter
//! (its output's gain names a parameter, in V per m/s²) and a load cell in
//! the strut, recorded together by `rigfit simulate` with a noise of its own
//! on each channel. Fitting both recovers the truth inside every 95 %
//! interval, the sensitivity too, and narrows the intervals against either
//! channel alone; a campaign that names one channel through `"channels"`
//! gives the same numbers, bit for bit, as the same campaign with `"column"`.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::{Value, json};

fn rigfit() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_rigfit"));
    c.env("RIGFIT_CACHE_DIR", std::env::temp_dir());
    c
}

fn ok(c: &mut Command) -> String {
    let o = c.output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{c:?}: {err}");
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The shipped quarter car with the accelerometer's sensitivity `sens` as
/// a parameter: its output reads volts.
fn rig() -> Value {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("rigs/quarter_car.json");
    let mut rig: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    rig["params"].as_array_mut().unwrap().push(json!(
        {"name": "sens", "unit": "V/(m/s²)", "doc": "accelerometer sensitivity"}
    ));
    let out = &mut rig["outputs"][0];
    assert_eq!(out["name"], "sprung_acceleration");
    out["unit"] = json!("V");
    out["sum"][0]["gain"] = json!("sens");
    rig
}

const TRUTH: [(&str, f64); 11] = [
    ("m1", 40.0),
    ("m2", 350.0),
    ("k1", 1.751e5),
    ("c1", 1751.0),
    ("k2", 3.0e4),
    ("c2", 2500.0),
    ("c2_high", 800.0),
    ("v_knee", 0.01),
    ("k_b", 2.0e4),
    ("play", 3.0e-4),
    ("sens", 0.1),
];

/// A campaign over `record` fitting `channels` (output, column), with `free`
/// searched and every other parameter at the truth.
fn campaign(dir: &Path, name: &str, channels: Value, free: &[&str]) -> PathBuf {
    let mut params = serde_json::Map::new();
    for (p, v) in TRUTH {
        let value = if free.contains(&p) {
            json!({"min": v / 3.0, "max": v * 3.0, "scale": "log"})
        } else {
            json!(v)
        };
        params.insert(p.into(), value);
    }
    let mut x = json!({
        "name": "sweep",
        "data": {"file": "record.csv", "time_column": "t_s"},
        "params": {"amplitude": 0.0005, "f_start": 1.0, "rate": 2.8}
    });
    match channels {
        Value::String(column) => x["data"]["column"] = json!(column),
        list => x["channels"] = list,
    }
    let c = json!({
        "name": name,
        "rig": rig(),
        "params": params,
        "experiments": [x],
        "search": {"population": 128, "generations": 30, "seed": 3, "stall_generations": 15},
        "solver": {"backend": "cpu"},
        "output": format!("out_{name}")
    });
    let path = dir.join(format!("{name}.json"));
    std::fs::write(&path, serde_json::to_string_pretty(&c).unwrap()).unwrap();
    path
}

fn both() -> Value {
    json!([
        {"output": "sprung_acceleration", "column": "accel_V"},
        {"output": "strut_force", "column": "force_N"}
    ])
}

/// The record: both channels from the truth, with noise 3e-4 V (3e-3 m/s²)
/// and 2 N.
fn record(dir: &Path) {
    let c = campaign(dir, "record", both(), &[]);
    let truth: serde_json::Map<String, Value> = TRUTH
        .iter()
        .map(|(p, v)| (p.to_string(), json!(v)))
        .collect();
    std::fs::write(dir.join("truth.json"), Value::Object(truth).to_string()).unwrap();
    ok(rigfit()
        .args(["simulate"])
        .arg(&c)
        .args(["--params"])
        .arg(dir.join("truth.json"))
        .args(["--noise", "3e-4,2", "--seed", "9", "--samples", "3000"])
        .args(["--dt", "1.6666666666666667e-3", "--out"])
        .arg(dir.join("record.csv")));
}

/// `name -> (value, 95 % interval)` of the free parameters of a run.
fn fit(dir: &Path, campaign: &Path) -> (Value, Vec<(String, f64, [f64; 2])>) {
    ok(rigfit().args(["--quiet", "run"]).arg(campaign));
    let name = campaign.file_stem().unwrap().to_str().unwrap();
    let r: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join(format!("out_{name}/result.json"))).unwrap(),
    )
    .unwrap();
    let free = r["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| p["free"] == true)
        .map(|p| {
            let ci = &p["interval_95"];
            (
                p["name"].as_str().unwrap().to_string(),
                p["value"].as_f64().unwrap(),
                [ci[0].as_f64().unwrap(), ci[1].as_f64().unwrap()],
            )
        })
        .collect();
    (r, free)
}

fn width(free: &[(String, f64, [f64; 2])], p: &str) -> f64 {
    let (_, _, ci) = free.iter().find(|(n, ..)| n == p).unwrap();
    ci[1] - ci[0]
}

#[test]
fn two_channels_hold_the_truth_and_narrow_the_intervals() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    record(dir);
    let strut = ["k2", "c2", "c2_high"];
    let mut with_sens = strut.to_vec();
    with_sens.push("sens");
    let (r, both_fit) = fit(dir, &campaign(dir, "both", both(), &with_sens));
    let names: Vec<&str> = r["experiments"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["sweep.sprung_acceleration", "sweep.strut_force"]);
    // Each channel's own unit, residual file and fit near its noise floor.
    for (x, unit) in r["experiments"].as_array().unwrap().iter().zip(["V", "N"]) {
        assert_eq!(x["unit"], unit);
        let floor = x["cost_over_noise_floor"].as_f64().unwrap();
        assert!((0.8..1.25).contains(&floor), "{x}");
        let csv =
            std::fs::read_to_string(dir.join("out_both").join(x["csv"].as_str().unwrap())).unwrap();
        assert!(
            csv.lines()
                .next()
                .unwrap()
                .contains(&format!("residual_{unit}"))
        );
    }
    for (p, value, ci) in &both_fit {
        let truth = TRUTH.iter().find(|(n, _)| n == p).unwrap().1;
        assert!(
            ci[0] <= truth && truth <= ci[1],
            "{p} = {value}: 95 % interval {ci:?} misses the truth {truth}"
        );
    }
    let (_, accel) = fit(
        dir,
        &campaign(dir, "accel", json!([both()[0].clone()]), &with_sens),
    );
    let (_, force) = fit(
        dir,
        &campaign(dir, "force", json!([both()[1].clone()]), &strut),
    );
    for p in strut {
        let (b, a, f) = (width(&both_fit, p), width(&accel, p), width(&force, p));
        eprintln!(
            "{p}: 95 % interval width {b:.4e} with both channels, {a:.4e} accelerometer alone, {f:.4e} load cell alone"
        );
        assert!(b < a && b < f, "{p}: {b} not narrower than {a} and {f}");
    }
    let (b, a) = (width(&both_fit, "sens"), width(&accel, "sens"));
    eprintln!("sens: 95 % interval width {b:.4e} with both channels, {a:.4e} accelerometer alone");
    assert!(b < a, "sens: {b} vs {a}");
}

#[test]
fn one_channel_named_in_channels_gives_the_same_bits_as_a_column() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    record(dir);
    let mut rig_out0 = both()[1].clone();
    rig_out0["output"] = json!("sprung_acceleration");
    rig_out0["column"] = json!("accel_V");
    let free = ["k2", "c2"];
    let (a, _) = fit(dir, &campaign(dir, "column", json!("accel_V"), &free));
    let (b, _) = fit(dir, &campaign(dir, "channel", json!([rig_out0]), &free));
    assert_eq!(a["fitness"], b["fitness"]);
    assert_eq!(a["parameters"], b["parameters"]);
    assert_eq!(a["experiments"][0]["r2"], b["experiments"][0]["r2"]);
}

/// An output term with no quantity is its constant `gain`: here a parameter,
/// a sensor's zero offset added to the strut force.
#[test]
fn a_term_without_a_quantity_is_a_constant_offset() {
    use rigfit::base::{Drive, SampleGrid};
    use rigfit::model::compiled::CompiledRig;
    let mut desc = rig();
    desc["params"]
        .as_array_mut()
        .unwrap()
        .push(json!({"name": "zero", "unit": "N", "doc": "load cell zero"}));
    let plain =
        CompiledRig::shared(serde_json::from_value(desc.clone()).unwrap(), "plain").unwrap();
    let strut = 3;
    assert_eq!(desc["outputs"][strut]["name"], "strut_force");
    desc["outputs"][strut]["sum"]
        .as_array_mut()
        .unwrap()
        .push(json!({"gain": "zero"}));
    let shifted = CompiledRig::shared(serde_json::from_value(desc).unwrap(), "shifted").unwrap();
    let names: Vec<String> = shifted.params().iter().map(|p| p.name.clone()).collect();
    let mut p: Vec<f64> = names
        .iter()
        .map(|n| match n.as_str() {
            "amplitude" => 5e-4,
            "f_start" => 1.0,
            "rate" => 2.8,
            "zero" => 12.5,
            other => TRUTH.iter().find(|(t, _)| *t == other).unwrap().1,
        })
        .collect();
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-3,
        samples: 400,
        substeps: 1,
    };
    let run = |rig: &CompiledRig, p: &[f64]| {
        let mut out = Vec::new();
        rig.simulate(p, &Drive::Velocity, &grid, &mut |s| {
            out.push(s.outputs[strut]);
            std::ops::ControlFlow::Continue(())
        });
        out
    };
    let with = run(&shifted, &p);
    p.pop();
    let without = run(&plain, &p);
    assert!(without.iter().any(|f| f.abs() > 1.0));
    for (a, b) in with.iter().zip(&without) {
        assert_eq!(*a, b + 12.5);
    }
}
