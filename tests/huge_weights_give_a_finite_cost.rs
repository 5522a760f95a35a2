//! Experiment weights are relative: three experiments weighted 1e308 each
//! (whose sum overflows an f64) are scored as three of weight 1, through the
//! GA and through the polish, and the job's joint cost is the positive,
//! finite weighted mean of the experiments' `1 − R²`.

use std::path::Path;

use rigfit::campaign::Campaign;
use rigfit::eval::CpuEvaluator;
use rigfit::job::{self, JobOptions};
use serde_json::{Value, json};

#[test]
fn weights_near_the_largest_f64_give_the_weighted_mean() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns");
    let mut v: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("tensile4_three_rates_synthetic.json")).unwrap(),
    )
    .unwrap();
    for e in v["experiments"].as_array_mut().unwrap() {
        e["weight"] = json!(1e308);
        let f = e["data"]["file"].as_str().unwrap().to_string();
        e["data"]["file"] = Value::String(dir.join(f).display().to_string());
    }
    v["search"]["polish"] = json!({"starts": 1, "max_iterations": 3});
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("c.json");
    std::fs::write(&path, v.to_string()).unwrap();
    let mut c = Campaign::load(&path).unwrap();
    c.search.population = 16;
    c.search.generations = 2;
    let opts = JobOptions::quiet(tmp.path().join("out"));
    let s = job::run(&c, Box::new(CpuEvaluator::new(c.problem.clone(), 0)), &opts).unwrap();
    let mean = s.experiments.iter().map(|e| e.one_minus_r2).sum::<f64>() / 3.0;
    println!("joint {:e}, mean of the experiments {mean:e}", s.fitness);
    assert!(s.fitness.is_finite() && s.fitness > 0.0, "{}", s.fitness);
    assert!(
        (s.fitness / mean - 1.0).abs() < 1e-6,
        "joint {} against the mean {mean}",
        s.fitness
    );
    let polish = s.polish.as_ref().expect("the polish ran");
    assert!(polish.ga_fitness.is_finite() && polish.ga_fitness > 0.0);
}

/// The GA alone (no polish): its joint fitness is the mean of the
/// experiments' `1 − R²`, never 0 from an overflowed sum of weights, and a
/// fitness target of 0 is not reached by it.
#[test]
fn the_ga_alone_scores_huge_weights_as_the_mean() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns");
    let mut v: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("tensile4_three_rates_synthetic.json")).unwrap(),
    )
    .unwrap();
    for (i, e) in v["experiments"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .enumerate()
    {
        // Unequal, all near the largest f64: their sum overflows.
        e["weight"] = json!([1e308, 5e307, 1.7e308][i % 3]);
        let f = e["data"]["file"].as_str().unwrap().to_string();
        e["data"]["file"] = Value::String(dir.join(f).display().to_string());
    }
    v["search"]["polish"] = json!({"enabled": false});
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("c.json");
    std::fs::write(&path, v.to_string()).unwrap();
    let mut c = Campaign::load(&path).unwrap();
    c.search.population = 16;
    c.search.generations = 2;
    let opts = JobOptions::quiet(tmp.path().join("out"));
    let s = job::run(&c, Box::new(CpuEvaluator::new(c.problem.clone(), 0)), &opts).unwrap();
    assert!(s.polish.is_none());
    let w = [1e308 / 1.7e308, 5e307 / 1.7e308, 1.0];
    let n = s.experiments.len();
    let total: f64 = (0..n).map(|i| w[i % 3]).sum();
    let mean = s
        .experiments
        .iter()
        .enumerate()
        .map(|(i, e)| w[i % 3] * e.one_minus_r2)
        .sum::<f64>()
        / total;
    println!("joint {:e}, weighted mean {mean:e}", s.fitness);
    assert!(s.fitness.is_finite() && s.fitness > 0.0, "{}", s.fitness);
    assert!(
        (s.fitness / mean - 1.0).abs() < 1e-9,
        "joint {} against the weighted mean {mean}",
        s.fitness
    );
    assert!(!s.stop_reason.contains("target"), "{}", s.stop_reason);
}
