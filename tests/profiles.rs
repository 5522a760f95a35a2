//! Profile likelihoods: on a model linear in its parameters every profile
//! interval is the covariance interval; a parameter nothing depends on is
//! flagged not identifiable; a resumed profile gives the same bits; on the
//! three-rate tensile example every profile interval holds the generating
//! value.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rigfit::base::Scale;
use rigfit::base::noise::gaussian;
use rigfit::search::profile::ProfileFlag;
use rigfit::search::{
    FnResiduals, GeneSpec, Polish, PolishSettings, ProfileOutcome, ProfileSettings, Profiles,
    Uncertainty,
};

/// `y = a + b·t + c·sin(3t)` (+ `0·d`) with seeded Gaussian noise of σ 0.05.
struct Linear {
    t: Vec<f64>,
    y: Vec<f64>,
}

impl Linear {
    fn new(seed: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let t: Vec<f64> = (0..300).map(|k| k as f64 * 0.02).collect();
        let y = t
            .iter()
            .map(|&t| Self::model(&[1.0, -0.5, 0.3], t) + 0.05 * gaussian(&mut rng))
            .collect();
        Self { t, y }
    }

    fn model(g: &[f64], t: f64) -> f64 {
        g[0] + g[1] * t + g[2] * (3.0 * t).sin()
    }

    fn residuals(&self) -> impl FnMut(&[f64]) -> Option<Vec<f64>> + '_ {
        |g: &[f64]| {
            Some(
                self.t
                    .iter()
                    .zip(&self.y)
                    .map(|(&t, y)| Self::model(g, t) - y)
                    .collect(),
            )
        }
    }
}

fn genes(dead: bool) -> Vec<GeneSpec> {
    let mut g = vec![
        GeneSpec::new("a", -10.0, 10.0, Scale::Linear),
        GeneSpec::new("b", -10.0, 10.0, Scale::Linear),
        GeneSpec::new("c", -10.0, 10.0, Scale::Linear),
    ];
    if dead {
        g.push(GeneSpec::new("d", 0.0, 5.0, Scale::Linear));
    }
    g
}

fn fit(model: &Linear, genes: &[GeneSpec], start: &[f64]) -> (Vec<f64>, Uncertainty) {
    let out = Polish::new(PolishSettings::default(), genes.to_vec())
        .run(FnResiduals(model.residuals()), &[start.to_vec()])
        .unwrap();
    (out.best_genome, out.uncertainty.unwrap())
}

#[test]
fn on_a_linear_model_every_profile_interval_is_the_covariance_interval() {
    let model = Linear::new(57);
    let genes = genes(false);
    let (best, u) = fit(&model, &genes, &[0.0, 0.0, 0.0]);
    let out = Profiles::new(ProfileSettings::default(), genes)
        .run(FnResiduals(model.residuals()), &best, &u)
        .unwrap();
    assert_eq!(out.parameters.len(), 3);
    for (p, g) in out.parameters.iter().zip(&u.genes) {
        let [lo, hi] = p.interval.expect("closed on both sides");
        let (lo, hi) = (lo.unwrap(), hi.unwrap());
        let [a, b] = g.interval_95.unwrap();
        let width = b - a;
        assert!(
            (lo - a).abs() < 0.01 * width && (hi - b).abs() < 0.01 * width,
            "{}: profile [{lo}, {hi}], covariance [{a}, {b}]",
            p.name
        );
        assert_eq!(p.flag, None, "{}", p.name);
        assert!((p.threshold - 1.959_963_984_540_054f64.powi(2)).abs() < 1e-12);
        // Twelve points and the optimum, one round: the grid closes both sides.
        assert_eq!(p.grid.len(), 13, "{}", p.name);
        assert!(p.converged.iter().all(|&c| c));
        assert!(p.grid.windows(2).all(|w| w[0] < w[1]));
    }
}

#[test]
fn a_parameter_nothing_depends_on_is_not_identifiable() {
    let model = Linear::new(58);
    let genes = genes(true);
    let mut f = model.residuals();
    let (best, u) = fit(&model, &genes, &[0.0, 0.0, 0.0, 2.0]);
    let out = Profiles::new(ProfileSettings::default(), genes)
        .run(FnResiduals(|g: &[f64]| f(&g[..3])), &best, &u)
        .unwrap();
    let d = &out.parameters[3];
    assert_eq!(d.flag, Some(ProfileFlag::NotIdentifiable));
    assert_eq!(d.interval, None);
    // The grid reaches both bounds.
    assert_eq!(d.grid.first(), Some(&0.0));
    assert_eq!(d.grid.last(), Some(&5.0));
    assert!(d.delta_chi2.iter().all(|v| v.unwrap().abs() < 1e-6));
    for p in &out.parameters[..3] {
        assert_eq!(p.flag, None, "{}", p.name);
    }
    assert!(
        out.warnings()
            .iter()
            .any(|w| w.starts_with("d: profile is flat to both bounds"))
    );
}

#[test]
fn a_one_sided_profile_is_flagged() {
    // y = a − exp(−k t), sampled from t = 0.05 on: a k above ~100 has
    // decayed before the first sample, so all large k look alike.
    let t: Vec<f64> = (1..200).map(|k| k as f64 * 0.05).collect();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let y: Vec<f64> = t
        .iter()
        .map(|&t| 1.0 - (-300.0 * t).exp() + 0.01 * gaussian(&mut rng))
        .collect();
    let res = |g: &[f64]| {
        Some(
            t.iter()
                .zip(&y)
                .map(|(&t, y)| g[0] - (-g[1] * t).exp() - y)
                .collect::<Vec<f64>>(),
        )
    };
    let genes = vec![
        GeneSpec::new("a", 0.0, 2.0, Scale::Linear),
        GeneSpec::new("k", 1.0, 1e5, Scale::Log),
    ];
    let polish = Polish::new(PolishSettings::default(), genes.clone());
    let fit = polish.run(FnResiduals(res), &[vec![1.0, 300.0]]).unwrap();
    let u = fit.uncertainty.unwrap();
    let out = Profiles::new(ProfileSettings::default(), genes)
        .run(FnResiduals(res), &fit.best_genome, &u)
        .unwrap();
    let k = &out.parameters[1];
    assert_eq!(k.flag, Some(ProfileFlag::OneSided), "{k:?}");
    let [lo, hi] = k.interval.unwrap();
    assert!(lo.is_some() && hi.is_none(), "{k:?}");
    assert_eq!(k.grid.last(), Some(&1e5));
}

/// Everything but the wall time, evaluation and iteration counts, bit for bit.
fn assert_same_profiles(a: &ProfileOutcome, b: &ProfileOutcome) {
    let bits = |v: &[Option<f64>]| v.iter().map(|x| x.map(f64::to_bits)).collect::<Vec<_>>();
    assert_eq!(a.parameters.len(), b.parameters.len());
    for (p, q) in a.parameters.iter().zip(&b.parameters) {
        let grid = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(grid(&p.grid), grid(&q.grid), "{}", p.name);
        assert_eq!(bits(&p.cost), bits(&q.cost), "{}", p.name);
        assert_eq!(bits(&p.delta_chi2), bits(&q.delta_chi2), "{}", p.name);
        let ends = |i: Option<[Option<f64>; 2]>| i.map(|[a, b]| bits(&[a, b]));
        assert_eq!(ends(p.interval), ends(q.interval), "{}", p.name);
        assert_eq!(p.flag, q.flag);
        assert_eq!(p.converged, q.converged);
    }
    assert_eq!(a.stop, b.stop);
}

#[test]
fn a_resumed_profile_gives_the_same_bits() {
    // A curved problem, so that the runs take several iterations.
    let t: Vec<f64> = (0..200).map(|k| k as f64 * 0.02).collect();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let model = |g: &[f64], t: f64| g[0] * (-t / g[1]).exp() + g[2];
    let y: Vec<f64> = t
        .iter()
        .map(|&t| model(&[2.0, 0.7, 0.1], t) + 0.02 * gaussian(&mut rng))
        .collect();
    let res = |g: &[f64]| {
        Some(
            t.iter()
                .zip(&y)
                .map(|(&t, y)| model(g, t) - y)
                .collect::<Vec<f64>>(),
        )
    };
    let genes = vec![
        GeneSpec::new("a", 0.0, 10.0, Scale::Linear),
        GeneSpec::new("tau", 1e-2, 1e2, Scale::Log),
        GeneSpec::new("c", -1.0, 1.0, Scale::Linear),
    ];
    let fit = Polish::new(PolishSettings::default(), genes.clone())
        .run(FnResiduals(res), &[vec![1.0, 1.0, 0.0]])
        .unwrap();
    let u = fit.uncertainty.unwrap();
    let settings = ProfileSettings {
        span: 6.0,
        ..ProfileSettings::default()
    };
    let whole = Profiles::new(settings, genes.clone())
        .run(FnResiduals(res), &fit.best_genome, &u)
        .unwrap();
    assert!(whole.iterations >= 3, "{}", whole.iterations);

    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("profiles.checkpoint.json");
    for stop_at in [1, 2, whole.iterations - 1] {
        let _ = std::fs::remove_file(&path);
        let flag = Arc::new(AtomicBool::new(false));
        let first = Profiles::new(settings, genes.clone())
            .interrupt(flag.clone())
            .checkpoint_to(&path, false)
            .run_observed(FnResiduals(res), &fit.best_genome, &u, &mut |i| {
                if i.iteration == stop_at {
                    flag.store(true, Ordering::SeqCst);
                }
                Ok(())
            })
            .unwrap();
        assert_eq!(first.stop, rigfit::search::PolishStop::Interrupted);
        assert_eq!(first.iterations, stop_at);
        let resumed = Profiles::new(settings, genes.clone())
            .checkpoint_to(&path, true)
            .run(FnResiduals(res), &fit.best_genome, &u)
            .unwrap();
        assert_same_profiles(&whole, &resumed);
        assert_eq!(resumed.iterations, whole.iterations);
    }
    // A checkpoint of another fit is refused, naming the file.
    let mut other = fit.best_genome.clone();
    other[0] += 0.01;
    let e = Profiles::new(settings, genes)
        .checkpoint_to(&path, true)
        .run(FnResiduals(res), &other, &u)
        .unwrap_err()
        .to_string();
    assert!(e.contains("profiles.checkpoint.json"), "{e}");
}

#[test]
fn each_iteration_is_one_batch_and_the_held_gene_gets_no_stencil() {
    let model = Linear::new(5);
    let genes = genes(false);
    let (best, u) = fit(&model, &genes, &[0.0, 0.0, 0.0]);
    let mut sizes = Vec::new();
    struct Counting<'a, F>(F, &'a mut Vec<usize>);
    impl<F: FnMut(&[f64]) -> Option<Vec<f64>>> rigfit::search::ResidualCost for Counting<'_, F> {
        fn residuals(
            &mut self,
            genomes: &[Vec<f64>],
        ) -> Result<Vec<Option<Vec<f64>>>, rigfit::search::SearchError> {
            self.1.push(genomes.len());
            Ok(genomes.iter().map(|g| (self.0)(g)).collect())
        }
    }
    let out = Profiles::new(ProfileSettings::default(), genes)
        .run(Counting(model.residuals(), &mut sizes), &best, &u)
        .unwrap();
    // The optimum (7 runs: 1 + 2·3), then 3 × 13 points of 1 + 2·2 each.
    assert_eq!(sizes[0], 7);
    assert_eq!(sizes[1], 39 * 5);
    assert!(
        sizes[2..].iter().all(|&s| s % 5 == 0 && s <= 39 * 5),
        "{sizes:?}"
    );
    assert_eq!(out.evaluations, sizes.iter().sum::<usize>() as u64);
    assert_eq!(out.iterations, sizes.len() - 2);
}

/// The generating values of the three-rate tensile example's records.
fn tensile_truth() -> serde_json::Map<String, serde_json::Value> {
    let text =
        std::fs::read_to_string("campaigns/tensile4_three_rates_reference_params.json").unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["params"].as_object().unwrap().clone()
}

#[test]
fn on_the_three_rate_tensile_example_every_profile_interval_holds_the_generating_value() {
    use rigfit::campaign::Campaign;
    use rigfit::eval::CpuEvaluator;
    use rigfit::job::{self, JobOptions};
    let mut c = Campaign::load(std::path::Path::new(
        "campaigns/tensile4_three_rates_synthetic.json",
    ))
    .unwrap();
    c.search.profiles = Some(ProfileSettings::default());
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let summary = job::run(
        &c,
        Box::new(CpuEvaluator::new(c.problem.clone(), 0)),
        &JobOptions::quiet(&out),
    )
    .unwrap();
    let profiles = summary
        .profiles
        .as_ref()
        .expect("the campaign asked for profiles");
    let truth = tensile_truth();
    assert_eq!(profiles.parameters.len(), truth.len());
    for p in &profiles.parameters {
        let t = truth[&p.name].as_f64().unwrap();
        let [lo, hi] = p.interval.expect("closed");
        let (lo, hi) = (lo.unwrap(), hi.unwrap());
        let [a, b] = p.covariance_interval.unwrap();
        println!(
            "{:<16} truth {t:.5e}: profile [{lo:.5e}, {hi:.5e}], covariance [{a:.5e}, {b:.5e}], \
             width ratio {:.3}, flag {:?}",
            p.name,
            (hi.ln() - lo.ln()) / (b.ln() - a.ln()),
            p.flag
        );
        assert!(lo < t && t < hi, "{}: [{lo}, {hi}] ∌ {t}", p.name);
        assert_eq!(p.flag, None, "{}", p.name);
    }
    println!(
        "profiles: {} evaluations, {} iterations, {:.1} s; the job's search {:.1} s",
        profiles.evaluations, profiles.iterations, profiles.wall_time_s, summary.job_wall_time_s
    );
    // result.json holds them in the shape the report reads, and the
    // profiles' checkpoint is gone with the search's.
    let text = std::fs::read_to_string(out.join("result.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let first = &v["profiles"]["parameters"][0];
    for key in [
        "name",
        "unit",
        "value",
        "grid",
        "cost",
        "delta_chi2",
        "threshold",
        "interval",
        "covariance_interval",
        "flag",
        "converged",
    ] {
        assert!(first.get(key).is_some(), "profiles.parameters[0].{key}");
    }
    for key in ["settings", "evaluations", "wall_time_s", "iterations"] {
        assert!(v["profiles"].get(key).is_some(), "profiles.{key}");
    }
    assert_eq!(first["unit"], "N/m");
    assert!(!out.join(job::PROFILE_CHECKPOINT_FILE).exists());
    assert!(!out.join(job::CHECKPOINT_FILE).exists());
}

#[test]
fn a_campaign_names_a_bad_profiles_setting_by_its_json_path() {
    use rigfit::campaign::Campaign;
    let text = std::fs::read_to_string("campaigns/aa2024_t3_synthetic.json").unwrap();
    let with = |profiles: &str| {
        let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
        v["search"]["profiles"] = serde_json::from_str(profiles).unwrap();
        Campaign::from_str(&v.to_string(), std::path::Path::new("campaigns"), "x.json")
    };
    let e = with(r#"{"pionts": 8}"#).unwrap_err().to_string();
    assert!(e.contains("search.profiles") && e.contains("pionts"), "{e}");
    let e = with(r#"{"points": 1}"#).unwrap_err().to_string();
    assert!(e.contains("search.profiles.points"), "{e}");
    let c = with("true").unwrap();
    assert_eq!(c.search.profiles, Some(ProfileSettings::default()));
    let c = with(r#"{"span": 4}"#).unwrap();
    assert_eq!(c.search.profiles.unwrap().span, 4.0);
    assert_eq!(with("false").unwrap().search.profiles, None);
}

#[test]
fn rigfit_profile_adds_the_profiles_to_a_finished_job() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let bin = env!("CARGO_BIN_EXE_rigfit");
    let run = std::process::Command::new(bin)
        .args([
            "run",
            "campaigns/tensile4_three_rates_synthetic.json",
            "--backend",
            "cpu",
        ])
        .args(["--generations", "20", "--quiet", "--out"])
        .arg(&out)
        .status()
        .unwrap();
    assert!(run.success());
    let before: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    assert!(before.get("profiles").is_none());
    for _ in 0..2 {
        let profile = std::process::Command::new(bin)
            .args(["profile", "--backend", "cpu", "--points", "6", "--quiet"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(
            profile.status.success(),
            "{}",
            String::from_utf8_lossy(&profile.stderr)
        );
    }
    let after: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    let params = after["profiles"]["parameters"].as_array().unwrap();
    assert_eq!(params.len(), 9);
    for p in params {
        assert!(p["grid"].as_array().unwrap().len() >= 7, "{p}");
    }
    assert_eq!(after["profiles"]["settings"]["points"], 6);
    // Every other key is kept; run twice, the warnings and flags are not doubled.
    assert_eq!(after["params"], before["params"]);
    assert_eq!(after["parameters"], before["parameters"]);
    let flags = after["verdict"]["flags"].as_array().unwrap();
    let ours = flags
        .iter()
        .filter(|f| f.as_str().unwrap().starts_with("profile of "))
        .count();
    assert_eq!(ours, params.iter().filter(|p| !p["flag"].is_null()).count());
    // A folder that is not a job's is refused, naming it.
    let bad = std::process::Command::new(bin)
        .args(["profile", "--quiet"])
        .arg(tmp.path())
        .output()
        .unwrap();
    assert!(!bad.status.success());
    let said = String::from_utf8_lossy(&bad.stderr);
    assert!(said.contains("result.json"), "{said}");
}

/// A rig whose measured output is linear in its parameters: the head
/// follows a prescribed sine, and the force of the specimen between it and
/// the ground, `k·x(t) + c·v(t)`, is measured. A tip hangs from the head on
/// a spring `kd` whose force never reaches that output.
fn linear_rig_campaign(dir: &std::path::Path) -> rigfit::campaign::Campaign {
    use serde_json::json;
    let rig = json!({
        "id": "prescribed_pair",
        "doc": "A head driven in displacement against a spring and damper to ground, and a tip on a spring from the head.",
        "params": [
            {"name": "m", "unit": "kg", "doc": "head mass"},
            {"name": "m2", "unit": "kg", "doc": "tip mass"},
            {"name": "k", "unit": "N/m", "doc": "specimen stiffness"},
            {"name": "c", "unit": "N·s/m", "doc": "specimen damping"},
            {"name": "kd", "unit": "N/m", "doc": "the tip's spring"}
        ],
        "nodes": [{"name": "head", "mass": "m"}, {"name": "tip", "mass": "m2"}],
        "elements": [
            {"name": "specimen", "between": ["ground", "head"],
             "spring": {"law": "linear", "k": "k"}, "damper": {"law": "viscous", "c": "c"}},
            {"name": "hanger", "between": ["head", "tip"],
             "spring": {"law": "linear", "k": "kd"}}
        ],
        "drives": [{"node": "head", "law": {"type": "sine", "quantity": "displacement",
                    "amplitude": 1e-3, "frequency": 5.0}}],
        "outputs": [{"name": "force", "unit": "N", "sum": [{"force": "specimen"}]}],
        "reach": {"elongation": 0.01, "rate": 1.0}
    });
    let (k, c, a, w) = (1.0e4, 50.0, 1e-3, 2.0 * std::f64::consts::PI * 5.0);
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let mut csv = String::from("t_s,force_N\n");
    for n in 0..1000 {
        let t = n as f64 * 1e-3;
        let f = k * a * (w * t).sin() + c * a * w * (w * t).cos() + 0.1 * gaussian(&mut rng);
        csv += &format!("{t:e},{f:e}\n");
    }
    std::fs::write(dir.join("record.csv"), csv).unwrap();
    let campaign = json!({
        "name": "prescribed-pair",
        "rig": rig,
        "params": {
            "m": 1.0, "m2": 1.0,
            "k": {"min": 5e3, "max": 2e4},
            "c": {"min": 0.0, "max": 200.0},
            "kd": {"min": 1e2, "max": 1e4, "scale": "log"}
        },
        "experiments": [{"name": "sine", "data": {"file": "record.csv"}}],
        "solver": {"substeps": 2, "backend": "cpu"},
        "search": {"population": 32, "generations": 10, "seed": 4, "profiles": true}
    });
    rigfit::campaign::Campaign::from_str(&campaign.to_string(), dir, "pair.json").unwrap()
}

#[test]
fn on_a_rig_linear_in_its_parameters_the_intervals_agree_and_a_spring_out_of_reach_is_not_identifiable()
 {
    use rigfit::eval::CpuEvaluator;
    use rigfit::job::{self, JobOptions};
    let tmp = tempfile::tempdir().unwrap();
    let c = linear_rig_campaign(tmp.path());
    let out = tmp.path().join("out");
    let summary = job::run(
        &c,
        Box::new(CpuEvaluator::new(c.problem.clone(), 0)),
        &JobOptions::quiet(&out),
    )
    .unwrap();
    let profiles = summary.profiles.as_ref().unwrap();
    for p in &profiles.parameters {
        println!(
            "{}: profile {:?}, covariance {:?}, {:?}",
            p.name, p.interval, p.covariance_interval, p.flag
        );
    }
    for p in &profiles.parameters[..2] {
        let [lo, hi] = p.interval.unwrap();
        let [a, b] = p.covariance_interval.unwrap();
        let width = b - a;
        assert!(
            (lo.unwrap() - a).abs() < 0.01 * width && (hi.unwrap() - b).abs() < 0.01 * width,
            "{}: profile {:?}, covariance [{a}, {b}]",
            p.name,
            p.interval
        );
        assert_eq!(p.flag, None, "{}", p.name);
    }
    let kd = &profiles.parameters[2];
    assert_eq!(kd.name, "kd");
    assert_eq!(kd.flag, Some(ProfileFlag::NotIdentifiable));
    assert!(
        summary
            .warnings
            .iter()
            .any(|w| w.starts_with("kd: profile is flat to both bounds")),
        "{:?}",
        summary.warnings
    );
    assert!(
        summary
            .verdict
            .flags
            .contains(&"profile of kd: not identifiable".to_string())
    );
    assert!(
        summary
            .verdict
            .line
            .contains("profile of kd: not identifiable")
    );
}
