//! Two experiments on the same rig at different speeds, fitted jointly: rig
//! parameters shared, the specimen's fracture elongation and one clock offset
//! per experiment, and the joint fitness the weighted mean of the two 1 − R².
mod oracle;
mod tensile_common;

use rigfit::campaign::Campaign;
use rigfit::eval::CpuEvaluator;
use rigfit::job::{self, JobOptions};
use tensile_common::reference_like;
use tensile_common::{REFERENCE, ix};

/// A synthetic record of the reference rig at `velocity`, fracturing at
/// `e_fracture`, as CSV text.
fn record(velocity: f64, e_fracture: f64, samples: usize, seed: u64) -> String {
    let mut p = REFERENCE;
    p[ix::VELOCITY] = velocity;
    p[ix::E_FRACTURE] = e_fracture;
    let exp = reference_like(&p, samples, 1e-6, 1, 10.0, seed);
    let mut s = String::from("# synthetic\nt_s,force_N\n");
    for (k, f) in exp.measured.iter().enumerate() {
        s += &format!("{:e},{f:e}\n", k as f64 * 1e-6);
    }
    s
}

#[test]
fn two_speeds_fit_jointly_with_shared_rig_and_own_specimen_parameters() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("slow.csv"), record(1.0, 0.8e-3, 2200, 1)).unwrap();
    std::fs::write(dir.path().join("fast.csv"), record(2.0, 1.0e-3, 1500, 2)).unwrap();
    let campaign = serde_json::json!({
        "name": "two-speeds",
        "rig": "tensile4",
        "params": {
            "m1": 7.9, "m2": 0.14, "m3": 0.48,
            "k1": {"min": 2e9, "max": 3e10, "scale": "log"},
            "c1": 5.51e5,
            "c1_post": {"min": 1e3, "max": 1e5, "scale": "log"},
            "k3": 4.4e8, "slack_a": 4.43e3, "slack_b": 4.87e5, "slack_c": 1.94e7,
            "k4_lin": 1.19e8, "c4": 1.57e4, "gap": 1.87e-5,
            "k_lin": 8.63e7, "e_yield": 5.4e-5,
            "a0": 4.56e3, "a1": 1.97e6, "a2": -9.26e8, "a3": 1.36e11, "ramp": 1.76e-6
        },
        "experiments": [
            {"name": "slow", "data": {"file": "slow.csv"}, "weight": 1.0,
             "params": {"velocity": 1.0, "e_fracture": {"min": 5e-4, "max": 2e-3}}},
            {"name": "fast", "data": {"file": "fast.csv"}, "weight": 2.0,
             "offset": {"min": -3e-6, "max": 3e-6},
             "params": {"velocity": 2.0, "e_fracture": {"min": 5e-4, "max": 2e-3}}}
        ],
        "search": {"population": 192, "generations": 60, "seed": 4, "tournament": 3}
    });
    let c = Campaign::from_str(&campaign.to_string(), dir.path(), "two_speeds.json").unwrap();
    let names: Vec<&str> = c.genes.iter().map(|g| g.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "k1",
            "c1_post",
            "slow.e_fracture",
            "fast.e_fracture",
            "fast.offset"
        ]
    );

    let out = dir.path().join("out");
    let opts = JobOptions::quiet(out.clone());
    let s = job::run(&c, Box::new(CpuEvaluator::new(c.problem.clone(), 0)), &opts).unwrap();

    assert_eq!(s.experiments.len(), 2);
    for e in &s.experiments {
        assert!(e.r2 > 0.99, "{}: R² = {}", e.name, e.r2);
        assert!(out.join(&e.csv).is_file() && out.join(&e.plot).is_file());
    }
    let joint = (s.experiments[0].one_minus_r2 + 2.0 * s.experiments[1].one_minus_r2) / 3.0;
    assert!(
        (joint - s.fitness).abs() <= 1e-9 * s.fitness.max(1e-12),
        "{joint} vs {}",
        s.fitness
    );
    let k1 = s.params["k1"];
    assert!((k1 / 8.4e9 - 1.0).abs() < 0.02, "k1 = {k1}");
    for (name, truth) in [("slow.e_fracture", 0.8e-3), ("fast.e_fracture", 1.0e-3)] {
        let v = s.params[name];
        assert!((v / truth - 1.0).abs() < 0.05, "{name} = {v}");
    }
    assert!(s.params["fast.offset"].abs() <= 3e-6);
    assert_eq!(s.params["slow.velocity"], 1.0);
    assert_eq!(s.params["fast.velocity"], 2.0);
}
