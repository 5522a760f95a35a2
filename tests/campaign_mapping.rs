//! Good campaigns become the expected genes, base vectors, batches and joint
//! fitness: shared versus per-experiment genes, offsets and weights.
mod oracle;
mod tensile_common;

mod campaign_common;
use campaign_common as common;

use common::{csv, example, set, write};
use rigfit::base::Scale;
use rigfit::campaign::{Campaign, GeneTarget};
use rigfit::eval::{DIVERGED, Scores};
use serde_json::json;
use tensile_common::ix;

fn load(v: &serde_json::Value, data: &[(&str, &str)]) -> (tempfile::TempDir, Campaign) {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), &v.to_string(), data);
    let c = Campaign::load(&path).unwrap_or_else(|e| panic!("{e}"));
    (dir, c)
}

/// Two experiments: `v2` overrides `k_lin` with its own gene, `v5` takes the
/// shared `k_lin` gene and has a free offset; weights 1 and 3.
fn two_experiments() -> serde_json::Value {
    let mut v = example();
    set(&mut v, "/params/k_lin", json!({"min": 1e7, "max": 1e9}));
    let mut v5 = v["experiments"][0].clone();
    set(&mut v5, "/name", json!("v5"));
    set(&mut v5, "/data", json!({"file": "v5.csv"}));
    set(&mut v5, "/params", json!({"velocity": 5.0}));
    set(
        &mut v5,
        "/offset",
        json!({"min": -1e-5, "max": 1e-5, "init": 2e-6}),
    );
    set(&mut v5, "/weight", json!(3.0));
    set(&mut v5, "/fit_window", json!({"start": 1e-5}));
    v["experiments"].as_array_mut().unwrap().push(v5);
    v
}

#[test]
fn example_campaign_gives_shared_and_own_genes() {
    let (dir, c) = load(&example(), &[("v2.csv", &csv(300, 1e-6, 0.0))]);
    let names: Vec<&str> = c.genes.iter().map(|g| g.name.as_str()).collect();
    assert_eq!(names, ["k1", "c1", "v2.k_lin"]);
    assert_eq!(c.genes[0].target, GeneTarget::Param(ix::K1));
    assert_eq!(c.genes[0].experiment, None);
    assert_eq!(c.genes[0].init, Some(8e9));
    assert_eq!(c.genes[0].unit, "N/m");
    assert_eq!(
        c.genes[1].scale,
        Scale::Log,
        "c1 takes the model's default scale"
    );
    assert_eq!(c.genes[2].experiment, Some(0));
    assert_eq!((c.genes[2].lower, c.genes[2].upper), (3e7, 3e8));
    let base = &c.base[0];
    assert_eq!(base[ix::K1], 8e9, "init seeds the base vector");
    assert!(
        (base[ix::C1] - (1e4f64 * 3e6).sqrt()).abs() < 1e-6,
        "log mid-range"
    );
    assert_eq!(base[ix::M4], 37.4, "model default");
    assert_eq!(base[ix::VELOCITY], 2.0);
    let x = &c.problem.experiments[0];
    assert_eq!(x.window, 0..251, "0 to 2.5e-4 s at 1 µs");
    assert_eq!(x.measured.len(), 251, "data past the window is dropped");
    assert!((x.dt - 1e-6).abs() < 1e-15);
    assert_eq!(c.output, dir.path().join("results/aa2024"));
    assert!(c.solver.auto && c.solver.substeps >= 1);
    assert_eq!(c.problem.substeps, c.solver.substeps);
    assert!(c.warnings.is_empty(), "{:?}", c.warnings);
}

#[test]
fn shared_gene_reaches_only_experiments_that_do_not_override_it() {
    let data = [
        ("v2.csv", csv(300, 1e-6, 0.0)),
        ("v5.csv", csv(200, 2e-6, 0.0)),
    ];
    let data: Vec<(&str, &str)> = data.iter().map(|(a, b)| (*a, b.as_str())).collect();
    let (_dir, c) = load(&two_experiments(), &data);
    let names: Vec<&str> = c.genes.iter().map(|g| g.name.as_str()).collect();
    assert_eq!(names, ["k1", "c1", "k_lin", "v2.k_lin", "v5.offset"]);
    assert_eq!(c.base_offsets, [0.0, 2e-6]);
    let genomes = vec![
        vec![9e9, 2e5, 5e7, 6e7, -3e-6],
        vec![1e10, 3e5, 7e7, 8e7, 4e-6],
    ];
    let b = c.batch(&genomes);
    assert_eq!(b.candidates, 2);
    for (i, g) in genomes.iter().enumerate() {
        let (p0, p1) = (b.params_of(0, i), b.params_of(1, i));
        assert_eq!((p0[ix::K1], p0[ix::C1], p0[ix::K_LIN]), (g[0], g[1], g[3]));
        assert_eq!((p1[ix::K1], p1[ix::C1], p1[ix::K_LIN]), (g[0], g[1], g[2]));
        assert_eq!((p0[ix::VELOCITY], p1[ix::VELOCITY]), (2.0, 5.0));
        assert_eq!((b.offsets[0][i], b.offsets[1][i]), (0.0, g[4]));
        let full = c.full_params(g);
        assert_eq!((full[1].0.as_slice(), full[1].1), (p1, g[4]));
    }
    assert_eq!(
        c.problem.experiments[1].window,
        5..200,
        "window starts at 1e-5 s"
    );
}

#[test]
fn combine_is_the_weighted_mean_and_keeps_divergence() {
    let data = [
        ("v2.csv", csv(300, 1e-6, 0.0)),
        ("v5.csv", csv(200, 2e-6, 0.0)),
    ];
    let data: Vec<(&str, &str)> = data.iter().map(|(a, b)| (*a, b.as_str())).collect();
    let (_dir, c) = load(&two_experiments(), &data);
    let scores = Scores {
        experiments: 2,
        values: vec![0.2, 0.1, 0.05, DIVERGED, DIVERGED, 0.0],
        diverged: 2,
    };
    let joint = c.combine(&scores);
    assert!((joint[0] - (0.2 + 3.0 * 0.1) / 4.0).abs() < 1e-15);
    assert_eq!(joint[1], DIVERGED);
    assert_eq!(joint[2], DIVERGED);
}

#[test]
fn param_file_fixes_genes_and_values() {
    let data = [
        ("v2.csv", csv(300, 1e-6, 0.0)),
        ("v5.csv", csv(200, 2e-6, 0.0)),
    ];
    let data: Vec<(&str, &str)> = data.iter().map(|(a, b)| (*a, b.as_str())).collect();
    let (dir, mut c) = load(&two_experiments(), &data);
    let file = dir.path().join("result.json");
    let text = json!({
        "fitness": 0.01,
        "params": {"k1": 9e9, "k_lin": 5e7, "v2.k_lin": 1e8, "v5.offset": 1e-6, "m3": 0.5}
    });
    std::fs::write(&file, text.to_string()).unwrap();
    c.apply_param_file(&file).unwrap();
    let names: Vec<&str> = c.genes.iter().map(|g| g.name.as_str()).collect();
    assert_eq!(names, ["c1"]);
    assert_eq!((c.base[0][ix::K1], c.base[1][ix::K1]), (9e9, 9e9));
    assert_eq!((c.base[0][ix::K_LIN], c.base[1][ix::K_LIN]), (1e8, 5e7));
    assert_eq!((c.base[0][ix::M3], c.base[1][ix::M3]), (0.5, 0.5));
    assert_eq!(c.base_offsets, [0.0, 1e-6]);

    std::fs::write(&file, r#"{"params": {"v2.k1": 1e9}}"#).unwrap();
    let err = c.apply_param_file(&file).unwrap_err().to_string();
    assert!(
        err.contains("result.json: params.v2.k1: rig parameter 'k1'"),
        "{err}"
    );
    std::fs::write(&file, r#"{"params": {"v9.k_lin": 1e9}}"#).unwrap();
    let err = c.apply_param_file(&file).unwrap_err().to_string();
    assert!(
        err.contains("params.v9.k_lin: expected an experiment of the campaign (v2, v5)"),
        "{err}"
    );
    std::fs::write(&file, r#"{"params": {"m1": -1}}"#).unwrap();
    let err = c.apply_param_file(&file).unwrap_err().to_string();
    assert!(
        err.contains("result.json: params: expected m1: a mass > 0"),
        "{err}"
    );
}

#[test]
fn defaults_output_columns_and_digest() {
    let mut v = example();
    v.as_object_mut().unwrap().remove("output");
    set(&mut v, "/experiments/0/data", json!({"file": "v2.csv"}));
    let (dir, c) = load(&v, &[("v2.csv", &csv(300, 1e-6, 0.0))]);
    assert_eq!(c.output, dir.path().join("results/aa2024-t3-synthetic"));
    assert_eq!(c.problem.experiments[0].measured.len(), 251);
    // Same text, different data: a different digest.
    let (_d2, c2) = load(&v, &[("v2.csv", &csv(300, 1e-6, 1e-6))]);
    assert_ne!(c.digest, c2.digest);
    let (_d3, c3) = load(&v, &[("v2.csv", &csv(300, 1e-6, 0.0))]);
    assert_eq!(c.digest, c3.digest);
}

#[test]
fn from_str_resolves_data_against_the_given_folder() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("v2.csv"), csv(300, 1e-6, 0.0)).unwrap();
    let c = Campaign::from_str(&example().to_string(), dir.path(), "inline.json").unwrap();
    assert_eq!(c.path, std::path::Path::new("inline.json"));
    let err = Campaign::from_str("{}", dir.path(), "inline.json")
        .unwrap_err()
        .to_string();
    assert!(
        err.starts_with("inline.json:1:2: .: missing field `name`"),
        "{err}"
    );
}

#[test]
fn warnings_report_resampling_and_unused_shared_genes() {
    let mut v = example();
    set(&mut v, "/params/k_lin", json!({"min": 1e7, "max": 1e9}));
    let mut text = csv(300, 1e-6, 0.0);
    text = text.replace("\n1e-6,", "\n1.2e-6,");
    let (_dir, c) = load(&v, &[("v2.csv", &text)]);
    assert_eq!(c.warnings.len(), 2, "{:?}", c.warnings);
    assert!(
        c.warnings
            .iter()
            .any(|w| w.contains("v2.csv: sampling is not uniform"))
    );
    assert!(
        c.warnings
            .iter()
            .any(|w| w.contains("params.k_lin: free parameter is overridden in every experiment"))
    );
    assert!(!c.genes.iter().any(|g| g.name == "k_lin"));
}

#[test]
fn a_fixed_experiment_value_beats_the_shared_gene() {
    let mut v = two_experiments();
    set(&mut v, "/experiments/0/params/k_lin", json!(4e7));
    let data = [
        ("v2.csv", csv(300, 1e-6, 0.0)),
        ("v5.csv", csv(200, 2e-6, 0.0)),
    ];
    let data: Vec<(&str, &str)> = data.iter().map(|(a, b)| (*a, b.as_str())).collect();
    let (_dir, c) = load(&v, &data);
    let names: Vec<&str> = c.genes.iter().map(|g| g.name.as_str()).collect();
    assert_eq!(names, ["k1", "c1", "k_lin", "v5.offset"]);
    assert!(!c.gene_acts_in(2, 0) && c.gene_acts_in(2, 1));
    let full = c.full_params(&[9e9, 2e5, 5e8, 0.0]);
    assert_eq!((full[0].0[ix::K_LIN], full[1].0[ix::K_LIN]), (4e7, 5e8));
    let (lo, hi) = c.bounds(0);
    assert_eq!((lo[ix::K_LIN], hi[ix::K_LIN]), (4e7, 4e7));
}
