//! A rig that cannot follow its record says so: the shipped example fitted
//! with the load cell's stiffness held at half the value that made the record
//! (its ringing 30 % too slow) leaves a residual several times the record's
//! own noise, and the job warns that the misfit is more than noise; a rig
//! without the adapter's free play (the record was made with 18.7 µm) fits
//! within twice the noise floor, but its residual is not white, and the job
//! says so.

use std::path::Path;

use rigfit::campaign::Campaign;
use rigfit::eval::CpuEvaluator;
use rigfit::job::{self, JobOptions};
use serde_json::{Value, json};

#[test]
fn a_rig_with_a_wrong_fixed_stiffness_leaves_a_misfit_above_the_noise() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns");
    let mut v: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("aa2024_t3_synthetic.json")).unwrap(),
    )
    .unwrap();
    v["params"]["k1"] = json!(4.2e9);
    let csv = dir.join("aa2024_t3_v2_synthetic.csv");
    v["experiments"][0]["data"]["file"] = Value::String(csv.display().to_string());
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("c.json");
    std::fs::write(&path, v.to_string()).unwrap();
    let mut c = Campaign::load(&path).unwrap();
    c.search.population = 128;
    c.search.generations = 30;
    let s = job::run(
        &c,
        Box::new(CpuEvaluator::new(c.problem.clone(), 0)),
        &JobOptions::quiet(tmp.path().join("out")),
    )
    .unwrap();
    let e = &s.experiments[0];
    println!(
        "residual {:?}, noise {:?}, {:?}× the floor; {:?}",
        e.residual_rms, e.noise_estimate, e.cost_over_noise_floor, s.warnings
    );
    assert!(e.cost_over_noise_floor.unwrap() > 4.0);
    assert!(
        s.warnings
            .iter()
            .any(|w| w.starts_with("v2: the residual's RMS") && w.contains("more than noise")),
        "{:?}",
        s.warnings
    );
}

#[test]
fn a_rig_without_its_gap_leaves_a_residual_that_is_not_white() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns");
    let mut v: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("aa2024_t3_synthetic.json")).unwrap(),
    )
    .unwrap();
    v["params"]["gap"] = json!(0.0);
    let csv = dir.join("aa2024_t3_v2_synthetic.csv");
    v["experiments"][0]["data"]["file"] = Value::String(csv.display().to_string());
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("c.json");
    std::fs::write(&path, v.to_string()).unwrap();
    let mut c = Campaign::load(&path).unwrap();
    c.search.population = 128;
    c.search.generations = 30;
    let s = job::run(
        &c,
        Box::new(CpuEvaluator::new(c.problem.clone(), 0)),
        &JobOptions::quiet(tmp.path().join("out")),
    )
    .unwrap();
    let e = &s.experiments[0];
    println!(
        "{:?}× the floor, autocorrelation {:?}; {:?}",
        e.cost_over_noise_floor, e.residual_autocorrelation, s.warnings
    );
    assert!(e.residual_autocorrelation.unwrap() > 0.2);
    assert!(
        s.warnings
            .iter()
            .any(|w| w.starts_with("v2: the residual is not white")),
        "{:?}",
        s.warnings
    );
}
