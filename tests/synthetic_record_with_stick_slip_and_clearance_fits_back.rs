//! A synthetic record made by `rigfit simulate` on a rig with a stick-slip
//! joint and an end stop across a clearance, fitted back with `rigfit run`
//! for 20 noise seeds: every truth lies within 3 standard errors of its
//! fitted value, and the coverage of the 95 % intervals is printed. A record
//! made at the step the fit itself takes (or coarser) carries integration
//! error the intervals do not know of and puts truths outside them.

use std::path::Path;
use std::process::Command;

use serde_json::Value;

fn rigfit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
}

/// A test mass on a flexure, a bolted joint that sticks and slips (Coulomb
/// with a tangential spring) and an end stop across a clearance, shaken by a
/// 20 Hz force of 60 N that slides the joint and closes the stop each cycle.
const RIG: &str = r#"{
  "id": "shaker_joint",
  "doc": "A test mass on a flexure with a stick-slip joint and an end stop across a clearance, driven by a shaker force.",
  "params": [
    {"name": "m", "unit": "kg", "doc": "test mass", "scale": "log"},
    {"name": "k", "unit": "N/m", "doc": "flexure stiffness", "scale": "log"},
    {"name": "c", "unit": "N·s/m", "doc": "flexure damping"},
    {"name": "f_c", "unit": "N", "doc": "joint slip force"},
    {"name": "k_t", "unit": "N/m", "doc": "joint tangential stiffness", "scale": "log"},
    {"name": "clearance", "unit": "m", "doc": "gap to the end stop"},
    {"name": "k_stop", "unit": "N/m", "doc": "end stop stiffness", "scale": "log"},
    {"name": "amplitude", "unit": "N", "doc": "shaker force amplitude", "scope": "experiment"},
    {"name": "frequency", "unit": "Hz", "doc": "shaker frequency", "scope": "experiment"}
  ],
  "nodes": [{"name": "mass", "mass": "m"}],
  "elements": [
    {"name": "flexure", "between": ["ground", "mass"],
     "spring": {"law": "linear", "k": "k"}, "damper": {"law": "viscous", "c": "c"}},
    {"name": "joint", "between": ["ground", "mass"],
     "friction": {"law": "stick_slip", "f_c": "f_c", "k_t": "k_t"}},
    {"name": "stop", "between": ["ground", "mass"],
     "gap": {"kind": "tension", "size": "clearance"},
     "spring": {"law": "linear", "k": "k_stop"}}
  ],
  "drives": [
    {"node": "mass", "law": {"type": "sine", "quantity": "force", "amplitude": "amplitude", "frequency": "frequency"}}
  ],
  "outputs": [
    {"name": "load_cell", "unit": "N", "sum": [{"force": "flexure"}, {"force": "joint"}, {"force": "stop"}]},
    {"name": "displacement", "unit": "m", "sum": [{"displacement": "mass"}]}
  ],
  "reach": {"elongation": 0.005, "rate": 1.0}
}"#;

/// Five free parameters, the truth their `init`; a small search (the polish
/// does the rest) on the CPU.
const CAMPAIGN: &str = r#"{
  "name": "shaker-joint",
  "rig": "rig.json",
  "params": {
    "m": 1.0,
    "k": {"min": 2e4, "max": 8e4, "scale": "log", "init": 4e4},
    "c": {"min": 2.0, "max": 20.0, "init": 8.0},
    "f_c": {"min": 2.0, "max": 10.0, "init": 5.0},
    "k_t": 1e6,
    "clearance": {"min": 5e-4, "max": 2e-3, "init": 1e-3},
    "k_stop": {"min": 2e5, "max": 2e6, "scale": "log", "init": 6e5}
  },
  "experiments": [
    {"name": "drive", "data": {"file": "rec.csv", "time_column": "t_s", "force_column": "load_cell_N"},
     "params": {"amplitude": 60.0, "frequency": 20.0}}
  ],
  "solver": {"substeps": "auto", "backend": "cpu"},
  "search": {"population": 32, "generations": 10, "seed": 1},
  "output": "out"
}"#;

const TRUTH: [(&str, f64); 5] = [
    ("k", 4e4),
    ("c", 8.0),
    ("f_c", 5.0),
    ("clearance", 1e-3),
    ("k_stop", 6e5),
];

/// Noise on the load cell (N): about 0.1 % of its 450 N peak.
const SIGMA: &str = "0.5";

fn ok(cmd: &mut Command) -> Vec<u8> {
    let o = cmd.output().unwrap();
    assert!(
        o.status.success(),
        "{cmd:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    o.stdout
}

/// Makes the record for `seed` with `simulate`'s own step, fits it back, and
/// returns (truths outside the 95 % interval, truths beyond 3 standard
/// errors, the record's and the fit's steps per sample).
fn one_seed(dir: &Path, seed: u64) -> (usize, Vec<String>, u64, u64) {
    let made: Value = serde_json::from_slice(&ok(rigfit()
        .current_dir(dir)
        .args(["--json", "simulate", "campaign.json"])
        .args(["--dt", "5e-4", "--samples", "1000", "--out", "rec.csv"])
        .args(["--overwrite", "--noise", SIGMA, "--seed"])
        .arg(seed.to_string())))
    .unwrap();
    let out = dir.join("out");
    if out.exists() {
        std::fs::remove_dir_all(&out).unwrap();
    }
    ok(rigfit()
        .current_dir(dir)
        .args(["--quiet", "run", "campaign.json"]));
    let result: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    let mut outside = 0;
    let mut far = Vec::new();
    for (name, truth) in TRUTH {
        let p = result["parameters"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| p["name"] == name)
            .unwrap();
        let (value, se) = (
            p["value"].as_f64().unwrap(),
            p["std_error"].as_f64().unwrap(),
        );
        let iv = &p["interval_95"];
        let (lo, hi) = (iv[0].as_f64().unwrap(), iv[1].as_f64().unwrap());
        if !(lo..=hi).contains(&truth) {
            outside += 1;
        }
        let z = (value - truth) / se;
        if z.abs() > 3.0 {
            far.push(format!(
                "{name}: {value:e} is {z:.1} standard errors from {truth:e}"
            ));
        }
    }
    (
        outside,
        far,
        made["substeps"].as_u64().unwrap(),
        result["substeps"].as_u64().unwrap(),
    )
}

#[test]
fn twenty_noise_seeds_fit_back_with_every_truth_within_three_standard_errors() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("rig.json"), RIG).unwrap();
    std::fs::write(dir.path().join("campaign.json"), CAMPAIGN).unwrap();
    let (mut outside, mut far) = (0, Vec::new());
    for seed in 0..20 {
        let (o, f, made, fit) = one_seed(dir.path(), seed);
        assert!(
            made > fit,
            "seed {seed}: the record at {made} steps per sample, the fit at {fit}"
        );
        outside += o;
        far.extend(f.into_iter().map(|w| format!("seed {seed}: {w}")));
    }
    let total = 20 * TRUTH.len();
    println!(
        "coverage of the 95 % intervals: {} of {total} truths inside ({:.0} %)",
        total - outside,
        100.0 * (total - outside) as f64 / total as f64
    );
    assert!(far.is_empty(), "{far:#?}");
}
