//! The local polish after the GA: on synthetic records of a known rig at two
//! speeds, a short GA stops above the noise floor (the joint `1 − R²` of the
//! true parameters on the same noisy records); the polish brings the fit down to
//! the floor, and the reported 95 % intervals hold the true values. An interrupt
//! in the middle of the polish, once resumed, ends with the bits of a job that
//! was never interrupted.
mod oracle;
mod tensile_common;

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use rigfit::campaign::Campaign;
use rigfit::eval::{
    Batch, CpuEvaluator, EvalError, Evaluator, EvaluatorInfo, History, Problem, Scores,
};
use rigfit::job::{self, JobOptions, JobSummary};
use tensile_common::reference_like;
use tensile_common::{REFERENCE, ix};

/// The true values of the free parameters, by gene name.
const TRUTH: [(&str, f64); 7] = [
    ("k1", 8.4e9),
    ("c1", 5.51e5),
    ("c1_post", 9.22e3),
    ("k3", 4.4e8),
    ("c4", 1.57e4),
    ("slow.e_fracture", 0.8e-3),
    ("fast.e_fracture", 1.0e-3),
];

/// A synthetic record of the reference rig at `velocity`, fracturing at
/// `e_fracture`, with 20 N of noise, as CSV text.
fn record(velocity: f64, e_fracture: f64, samples: usize, seed: u64) -> String {
    let mut p = REFERENCE;
    p[ix::VELOCITY] = velocity;
    p[ix::E_FRACTURE] = e_fracture;
    let exp = reference_like(&p, samples, 1e-6, 2, 20.0, seed);
    let mut s = String::from("# synthetic\nt_s,force_N\n");
    for (k, f) in exp.measured.iter().enumerate() {
        s += &format!("{:e},{f:e}\n", k as f64 * 1e-6);
    }
    s
}

fn campaign(dir: &Path) -> Campaign {
    std::fs::write(dir.join("slow.csv"), record(1.0, 0.8e-3, 2200, 1)).unwrap();
    std::fs::write(dir.join("fast.csv"), record(2.0, 1.0e-3, 1500, 2)).unwrap();
    let json = serde_json::json!({
        "name": "two-speeds",
        "rig": "tensile4",
        "params": {
            "m1": 7.9, "m2": 0.14, "m3": 0.48,
            "k1": {"min": 2e9, "max": 3e10, "scale": "log"},
            "c1": {"min": 1e5, "max": 2e6, "scale": "log"},
            "c1_post": {"min": 1e3, "max": 1e5, "scale": "log"},
            "k3": {"min": 1e8, "max": 2e9, "scale": "log"},
            "slack_a": 4.43e3, "slack_b": 4.87e5, "slack_c": 1.94e7,
            "k4_lin": 1.19e8,
            "c4": {"min": 1e3, "max": 1e5, "scale": "log"},
            "gap": 1.87e-5,
            "k_lin": 8.63e7, "e_yield": 5.4e-5,
            "a0": 4.56e3, "a1": 1.97e6, "a2": -9.26e8, "a3": 1.36e11, "ramp": 1.76e-6
        },
        "experiments": [
            {"name": "slow", "data": {"file": "slow.csv"},
             "params": {"velocity": 1.0, "e_fracture": {"min": 5e-4, "max": 2e-3}}},
            {"name": "fast", "data": {"file": "fast.csv"},
             "params": {"velocity": 2.0, "e_fracture": {"min": 5e-4, "max": 2e-3}}}
        ],
        "solver": {"substeps": 2},
        "search": {"population": 64, "generations": 12, "seed": 5,
                   "polish": {"starts": 4, "max_iterations": 25}}
    });
    Campaign::from_str(&json.to_string(), dir, "two_speeds.json").unwrap()
}

fn options(out: &Path, resume: bool, interrupt: Arc<AtomicBool>) -> JobOptions {
    JobOptions {
        out: out.to_path_buf(),
        resume,
        quiet: true,
        interrupt,
        require_gpu: false,
        threads: 0,
    }
}

/// The joint `1 − R²` of the true parameters on the noisy records.
fn noise_floor(c: &Campaign) -> f64 {
    let truth: Vec<f64> = c
        .genes
        .iter()
        .map(|g| TRUTH.iter().find(|(n, _)| *n == g.name).unwrap().1)
        .collect();
    let mut cpu = CpuEvaluator::new(c.problem.clone(), 0);
    c.combine(&cpu.fitness(&c.batch(&[truth])).unwrap())[0]
}

/// The CPU evaluator that raises `flag` on its `at`-th history request: the
/// polish asks for histories once per iteration, the GA never.
struct InterruptOnHistories {
    inner: CpuEvaluator,
    calls: AtomicUsize,
    at: usize,
    flag: Arc<AtomicBool>,
}

impl Evaluator for InterruptOnHistories {
    fn info(&self) -> EvaluatorInfo {
        self.inner.info()
    }
    fn fitness(&mut self, batch: &Batch) -> Result<Scores, EvalError> {
        self.inner.fitness(batch)
    }
    fn problem(&self) -> &Problem {
        self.inner.problem()
    }

    fn checked_histories(
        &mut self,
        batch: &Batch,
        which: &[usize],
    ) -> Result<Vec<Vec<History>>, EvalError> {
        if self.calls.fetch_add(1, Ordering::SeqCst) + 1 == self.at {
            self.flag.store(true, Ordering::SeqCst);
        }
        self.inner.histories(batch, which)
    }
}

fn bits(s: &JobSummary) -> Vec<u64> {
    let mut v: Vec<u64> = s.params.values().map(|x| x.to_bits()).collect();
    v.push(s.fitness.to_bits());
    for p in s.parameters.iter().filter(|p| p.free) {
        v.extend(p.interval_95.unwrap().map(f64::to_bits));
    }
    v
}

#[test]
fn polish_reaches_the_noise_floor_with_intervals_that_hold_the_truth_and_resumes_bit_identically() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path());
    let floor = noise_floor(&c);

    let out = dir.path().join("straight");
    let no_interrupt = Arc::new(AtomicBool::new(false));
    let cpu = || Box::new(CpuEvaluator::new(c.problem.clone(), 0));
    let s = job::run(&c, cpu(), &options(&out, false, no_interrupt.clone())).unwrap();
    let polish = s.polish.as_ref().expect("the polish is on by default");
    eprintln!(
        "floor {floor:.6e}, GA {:.6e} ({:.3}×), polished {:.6e} ({:.4}×), {} iterations, {} evaluations",
        polish.ga_fitness,
        polish.ga_fitness / floor,
        s.fitness,
        s.fitness / floor,
        polish.iterations,
        polish.evaluations
    );
    assert!(
        polish.ga_fitness > 1.1 * floor,
        "the GA alone should stop above the floor"
    );
    assert!(s.fitness <= 1.02 * floor, "{} vs floor {floor}", s.fitness);
    for (name, truth) in TRUTH {
        let p = s.parameters.iter().find(|p| p.name == name).unwrap();
        let [lo, hi] = p.interval_95.unwrap();
        eprintln!(
            "{name}: {:.5e} [{lo:.5e}, {hi:.5e}] truth {truth:.5e}",
            p.value
        );
        assert!(
            lo < truth && truth < hi,
            "{name}: [{lo:e}, {hi:e}] ∌ {truth:e}"
        );
        assert_eq!(p.determined, Some(true), "{name}");
    }
    let result: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    let corr = &result["polish"]["correlation"];
    assert_eq!(corr.as_array().unwrap().len(), TRUTH.len());
    assert_eq!(corr[2][2].as_f64(), Some(1.0));

    // The same job, interrupted during the polish's second iteration and resumed.
    let out2 = dir.path().join("interrupted");
    let flag = Arc::new(AtomicBool::new(false));
    let interrupted = job::run(
        &c,
        Box::new(InterruptOnHistories {
            inner: CpuEvaluator::new(c.problem.clone(), 0),
            calls: AtomicUsize::new(0),
            at: 2,
            flag: flag.clone(),
        }),
        &options(&out2, false, flag),
    )
    .unwrap();
    assert_eq!(interrupted.stop_reason, "interrupted");
    assert!(out2.join(job::CHECKPOINT_FILE).is_file());
    let resumed = job::run(&c, cpu(), &options(&out2, true, no_interrupt)).unwrap();
    assert_eq!(bits(&resumed), bits(&s), "resumed job differs");
    assert!(!out2.join(job::CHECKPOINT_FILE).exists());
}

/// The multi-rate case of the README's measurements: three records of one rig
/// at 2, 1 and 0.1 m/s (20 N of noise), a shared rig with free k1, c1, c1_post,
/// k3, c4 and gap, and a free fracture elongation per rate (nine genes).
/// Too long for the suite; run it with
/// `cargo test --release --test polish_reaches_noise_floor -- --ignored --nocapture`
/// (`RIGFIT_MULTI_RATE_SEARCH` overrides the `"search"` object as JSON).
#[test]
#[ignore = "minutes of CPU time; for the README's measurements"]
fn multi_rate_case() {
    let dir = tempfile::tempdir().unwrap();
    let rates = [
        ("v2", 2.0, 1.0e-3, 2000),
        ("v1", 1.0, 0.9e-3, 2500),
        ("v01", 0.1, 0.8e-3, 9500),
    ];
    let gen_record = |v: f64, ef: f64, n: usize, seed: u64| {
        let mut p = REFERENCE;
        p[ix::VELOCITY] = v;
        p[ix::E_FRACTURE] = ef;
        let exp = reference_like(&p, n, 1e-6, 2, 20.0, seed);
        let mut s = String::from("t_s,force_N\n");
        for (k, f) in exp.measured.iter().enumerate() {
            s += &format!("{:e},{f:e}\n", k as f64 * 1e-6);
        }
        s
    };
    let mut experiments = Vec::new();
    let mut truth = vec![
        ("k1", 8.4e9),
        ("c1", 5.51e5),
        ("c1_post", 9.22e3),
        ("k3", 4.4e8),
        ("c4", 1.57e4),
        ("gap", 1.87e-5),
    ];
    for (i, (name, v, ef, n)) in rates.iter().enumerate() {
        let file = format!("{name}.csv");
        std::fs::write(
            dir.path().join(&file),
            gen_record(*v, *ef, *n, 10 + i as u64),
        )
        .unwrap();
        experiments.push(serde_json::json!({
            "name": name, "data": {"file": file},
            "params": {"velocity": v, "e_fracture": {"min": 5e-4, "max": 2e-3}}
        }));
    }
    let search = std::env::var("RIGFIT_MULTI_RATE_SEARCH").map_or_else(
        |_| serde_json::json!({"population": 2048, "generations": 400, "seed": 1}),
        |s| serde_json::from_str(&s).unwrap(),
    );
    let json = serde_json::json!({
        "name": "three-rates",
        "rig": "tensile4",
        "params": {
            "m1": 7.9, "m2": 0.14, "m3": 0.48,
            "k1": {"min": 2e9, "max": 3e10, "scale": "log"},
            "c1": {"min": 1e5, "max": 2e6, "scale": "log"},
            "c1_post": {"min": 1e3, "max": 1e5, "scale": "log"},
            "k3": {"min": 1e8, "max": 1e10, "scale": "log"},
            "slack_a": 4.43e3, "slack_b": 4.87e5, "slack_c": 1.94e7,
            "k4_lin": 1.19e8,
            "c4": {"min": 1e3, "max": 1e5, "scale": "log"},
            "gap": {"min": 0.0, "max": 5e-5},
            "k_lin": 8.63e7, "e_yield": 5.4e-5,
            "a0": 4.56e3, "a1": 1.97e6, "a2": -9.26e8, "a3": 1.36e11, "ramp": 1.76e-6
        },
        "experiments": experiments,
        "solver": {"substeps": 2, "backend": "cpu"},
        "search": search
    });
    let c = Campaign::from_str(&json.to_string(), dir.path(), "three_rates.json").unwrap();
    for (name, _, ef, _) in rates {
        truth.push((Box::leak(format!("{name}.e_fracture").into_boxed_str()), ef));
    }
    let values: Vec<f64> = c
        .genes
        .iter()
        .map(|g| truth.iter().find(|(n, _)| *n == g.name).unwrap().1)
        .collect();
    let mut cpu = CpuEvaluator::new(c.problem.clone(), 0);
    let floor = c.combine(&cpu.fitness(&c.batch(&[values])).unwrap())[0];
    let out = dir.path().join("out");
    let s = job::run(
        &c,
        Box::new(cpu),
        &options(&out, false, Arc::new(AtomicBool::new(false))),
    )
    .unwrap();
    let p = s.polish.as_ref().unwrap();
    println!(
        "noise floor {floor:.5e}; GA {:.5e} ({:.3}×) in {} generations, {} evaluations, {:.1} s; \
         polished {:.5e} ({:.4}×) in {} iterations, {} evaluations, {:.1} s ({:?}, best start {})",
        p.ga_fitness,
        p.ga_fitness / floor,
        s.generations,
        s.evaluations,
        s.wall_time_s,
        s.fitness,
        s.fitness / floor,
        p.iterations,
        p.evaluations,
        p.wall_time_s,
        p.stop,
        p.best_start
    );
    for (name, t) in &truth {
        let q = s.parameters.iter().find(|q| q.name == *name).unwrap();
        let iv = q
            .interval_95
            .map_or("—".into(), |[lo, hi]| format!("[{lo:.4e}, {hi:.4e}]"));
        let inside = q.interval_95.is_some_and(|[lo, hi]| lo <= *t && *t <= hi);
        println!(
            "| {name} | {:.4e} | {iv} | {t:.4e} | {} | {} | {:.1} % |",
            q.value,
            if inside { "yes" } else { "no" },
            if q.determined == Some(true) {
                "yes"
            } else {
                "no"
            },
            100.0 * q.elite_relative_width.unwrap_or(f64::NAN)
        );
    }
}
