//! Inverse-model least squares (IDIM-LS) recovers a driven mass with viscous
//! and Coulomb friction: on a synthetic record made with rigfit's integrator, and
//! on the real EMPS record within 1 % of the benchmark's reference values.

mod identify_common;

use std::path::Path;

use identify_common::{Multisine, System, simulate};
use rigfit::identify::columns::Table;
use rigfit::identify::idim::{self, IdimOptions};

/// EMPS's force gain (N/V), from the benchmark's .mat file.
const GTAU: f64 = 35.15065188248547;

/// A mass on a position loop `τ = kp(q_ref − q) − kd·q̇` against friction
/// `Fv·q̇ + Fc·sgn q̇ + OFF`; state `(q, q̇)`.
struct ServoMass {
    m: f64,
    fv: f64,
    fc: f64,
    off: f64,
    kp: f64,
    kd: f64,
    reference: Multisine,
}

impl ServoMass {
    fn force(&self, t: f64, y: &[f64]) -> f64 {
        self.kp * (self.reference.at(t) - y[0]) - self.kd * y[1]
    }
}

impl System for ServoMass {
    fn dim(&self) -> usize {
        2
    }

    fn deriv(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        let friction = self.fv * y[1] + self.fc * y[1].signum() + self.off;
        dy[1] = (self.force(t, y) - friction) / self.m;
    }
}

fn close(name: &str, got: f64, want: f64, rel: f64) {
    assert!(
        (got - want).abs() <= rel * want.abs(),
        "{name}: {got}, want {want} within {:.1} %",
        rel * 100.0
    );
}

#[test]
fn synthetic_servo_mass_parameters_are_recovered() {
    let mut sys = ServoMass {
        m: 95.0,
        fv: 200.0,
        fc: 20.0,
        off: -3.0,
        kp: 1.4e6,
        kd: 8.5e3,
        reference: Multisine::new(0.2, 3.0, 15, 0.05, 3),
    };
    let (t, y) = simulate(&mut sys, 1000.0, 21_000, 4);
    // The first second holds the jump from rest onto the reference.
    let (t, y) = (&t[1000..], &y[1000..]);
    let q: Vec<f64> = y.iter().map(|s| s[0]).collect();
    let tau: Vec<f64> = t.iter().zip(y).map(|(&t, s)| sys.force(t, s)).collect();
    let r = idim::estimate(&q, &tau, &IdimOptions::default()).unwrap();
    println!("{r:#?}");
    close("M", r.get("m").unwrap(), 95.0, 0.01);
    close("Fv", r.get("f_v").unwrap(), 200.0, 0.01);
    close("Fc", r.get("f_c").unwrap(), 20.0, 0.02);
    // OFF is told apart from Fc·sgn q̇ only by the motion's asymmetry, and the
    // filters smear each reversal: it is the least determined (0.3 N of 20 N).
    assert!(
        (r.get("f_offset").unwrap() + 3.0).abs() < 0.3,
        "{:?}",
        r.get("f_offset")
    );
}

#[test]
fn emps_record_matches_the_benchmark_reference_within_one_percent() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/emps/emps_position_voltage.csv");
    let table = Table::read(&path).unwrap();
    let q = table.column("position_m").unwrap();
    let tau: Vec<f64> = table
        .column("controller_voltage_V")
        .unwrap()
        .iter()
        .map(|v| GTAU * v)
        .collect();
    assert_eq!(q.len(), 24_841);
    let r = idim::estimate(q, &tau, &IdimOptions::default()).unwrap();
    println!("{r:#?}");
    close("M", r.get("m").unwrap(), 95.09, 0.01);
    close("Fv", r.get("f_v").unwrap(), 203.1, 0.01);
    close("Fc", r.get("f_c").unwrap(), 20.44, 0.01);
    close("OFF", r.get("f_offset").unwrap(), -3.19, 0.01);
}

#[test]
fn identify_idim_command_writes_a_fragment_and_a_figure() {
    let dir = tempfile::tempdir().unwrap();
    let data =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/emps/emps_position_voltage.csv");
    let (frag, svg) = (dir.path().join("emps.json"), dir.path().join("emps.svg"));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(["--json", "identify", "idim"])
        .arg(&data)
        .args([
            "--position",
            "position_m",
            "--force",
            "controller_voltage_V",
        ])
        .args(["--gain", &GTAU.to_string(), "--sample-rate", "1000"])
        .arg("--out")
        .arg(&frag)
        .arg("--svg")
        .arg(&svg)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["idim"]["rows"], 2479);
    let fragment: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&frag).unwrap()).unwrap();
    let m = &fragment["params"]["m"];
    let init = m["init"].as_f64().unwrap();
    assert!((init - 95.09).abs() < 0.01 * 95.09, "{m}");
    assert!(m["min"].as_f64().unwrap() < init && init < m["max"].as_f64().unwrap());
    assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));
    // Without a sample rate or a time column the command refuses, as bad input.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(["identify", "idim"])
        .arg(&data)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn a_zero_gain_is_refused_and_writes_no_fragment() {
    let dir = tempfile::tempdir().unwrap();
    let data =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/emps/emps_position_voltage.csv");
    let frag = dir.path().join("emps.json");
    for gain in ["0", "-0"] {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_rigfit"))
            .args(["identify", "idim"])
            .arg(&data)
            .args([
                "--position",
                "position_m",
                "--force",
                "controller_voltage_V",
            ])
            .args([&format!("--gain={gain}"), "--sample-rate", "1000"])
            .arg("--out")
            .arg(&frag)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        println!("{gain}: {err}");
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains("nothing to fit"), "{err}");
        assert!(!frag.exists(), "a fragment was written");
    }
}

#[test]
fn a_force_without_spread_is_refused_by_the_library() {
    let q: Vec<f64> = (0..2000).map(|i| (f64::from(i) * 0.01).sin()).collect();
    for tau in [vec![0.0; 2000], vec![3.5; 2000]] {
        let err = idim::estimate(&q, &tau, &IdimOptions::default()).unwrap_err();
        assert!(err.to_string().contains("nothing to fit"), "{err}");
    }
}
