//! f32 on the CPU: a compiled rig's native f32 lane ensemble scores a
//! campaign within the f32 tolerance of the f64 reference and says so in its
//! info; where the lane code is not built (no C compiler, or
//! `RIGFIT_NATIVE=off`) a campaign asking for f32 on the CPU is scored in f64,
//! with a warning.

use std::path::PathBuf;
use std::process::Command;

use rigfit::campaign::Campaign;
use rigfit::eval::{CpuEvaluator, Evaluator, Precision};
use serde_json::Value;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The campaign's true parameters as genes.
fn true_genes(c: &Campaign, truth: &str) -> Vec<f64> {
    let t: Value = serde_json::from_str(
        &std::fs::read_to_string(repo().join("campaigns").join(truth)).unwrap(),
    )
    .unwrap();
    c.genes
        .iter()
        .map(|g| {
            t["params"]
                .get(&g.name)
                .and_then(Value::as_f64)
                .unwrap_or_else(|| panic!("{}", g.name))
        })
        .collect()
}

#[test]
fn f32_lanes_score_within_the_f32_tolerance_of_the_reference() {
    let c = Campaign::load(&repo().join("campaigns/tensile4_three_rates_synthetic.json")).unwrap();
    let truth = true_genes(&c, "tensile4_three_rates_reference_params.json");
    // The truth and candidates off it by a few per cent, gene by gene.
    let mut genomes = vec![truth.clone()];
    for (i, g) in c.genes.iter().enumerate() {
        let mut x = truth.clone();
        x[i] = (x[i] * 1.03).clamp(g.lower, g.upper);
        genomes.push(x);
    }
    let batch = c.batch(&genomes);
    let mut f64_ev = CpuEvaluator::new(c.problem.clone(), 0);
    // No C compiler here is a failure, not a skip.
    let mut f32_ev = CpuEvaluator::new(c.problem.clone(), 0);
    f32_ev
        .use_f32()
        .expect("the compiled rig's f32 lanes build");
    assert_eq!(f32_ev.info().precision, Precision::F32);
    assert_eq!(f64_ev.info().precision, Precision::F64);
    let a = f64_ev.fitness(&batch).unwrap();
    let b = f32_ev.fitness(&batch).unwrap();
    assert_eq!(a.values.len(), b.values.len());
    let (mut differ, mut worst) = (false, 0.0_f64);
    for (i, (x, y)) in a.values.iter().zip(&b.values).enumerate() {
        // 1 − R² moves by at most 2·√(1 − R²)·δ + δ² for a history off by δ
        // of its spread; δ = 4e-4 holds the f32 tolerance (2e-4 of the
        // largest magnitude) with room.
        let tol = 8e-4 * x.sqrt() + 2e-7;
        assert!((x - y).abs() <= tol, "value {i}: f64 {x:e}, f32 {y:e}");
        differ |= x != y;
        worst = worst.max((x - y).abs() / tol);
    }
    eprintln!("largest difference {worst:.2} of its tolerance");
    assert!(differ, "f32 scores identical to f64: not f32 arithmetic");
}

#[test]
fn without_native_lanes_the_binary_scores_in_f64_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .env("RIGFIT_NATIVE", "off")
        .arg("run")
        .arg(repo().join("campaigns/aa2024_t3_synthetic.json"))
        .arg("--out")
        .arg(&out)
        .args([
            "--backend",
            "cpu",
            "--precision",
            "f32",
            "--generations",
            "1",
        ])
        .args(["--population", "16"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(err.contains("warning: --precision f32 on the CPU"), "{err}");
    assert!(err.contains("RIGFIT_NATIVE=off"), "{err}");
    let result: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    assert_eq!(result["precision"], "f64", "{result}");
}
