//! A batch with more runs than one dispatch may cover is split into several
//! dispatches, each over its own slice of the run buffers, and scores every run
//! with the same bits as one unsplit dispatch: the hand-written kernels on the
//! shipped example (one experiment per candidate) and a compiled rig with two
//! experiments per candidate (a part starts at a candidate's first run), f32
//! and f64, specialised and generic. The device limit (65 535 workgroups) is
//! far above what a test can run on lavapipe, so the tests lower it with
//! `GpuOptions::max_runs_per_pass`.
mod oracle;
mod tensile_common;

mod gpu_common;
use gpu_common as common;

use std::path::Path;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rigfit::campaign::Campaign;
use rigfit::eval::{Batch, Evaluator, Precision};
use rigfit::gpu::{GpuContext, GpuEvaluator, GpuOptions};
use rigfit::job::gene_specs;

const CANDIDATES: usize = 1200;
const SAMPLES: usize = 160;
const MAX_RUNS_PER_PASS: usize = 512;

/// A shipped campaign, every record shortened to `SAMPLES` samples.
fn shipped(file: &str) -> Campaign {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("campaigns")
        .join(file);
    let mut c = Campaign::load(&path).unwrap();
    for e in &mut c.problem.experiments {
        e.measured.truncate(SAMPLES);
        e.window = e.window.start.min(SAMPLES / 2)..SAMPLES;
    }
    c
}

/// Free parameters uniform over their bounds (log-uniform on log scales).
fn batch(c: &Campaign, seed: u64) -> Batch {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let genes = gene_specs(c);
    let genomes: Vec<Vec<f64>> = (0..CANDIDATES)
        .map(|_| genes.iter().map(|g| g.at_fraction(rng.random())).collect())
        .collect();
    c.batch(&genomes)
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn precisions(ctx: &GpuContext) -> Vec<Precision> {
    let mut v = vec![Precision::F32];
    if ctx.has_f64() {
        v.push(Precision::F64);
    }
    v
}

fn split_scores_as_unsplit(file: &str) {
    let Some(ctx) = common::gpu() else { return };
    let c = shipped(file);
    let runs = CANDIDATES * c.problem.experiments.len();
    let batch = batch(&c, 5);
    for precision in precisions(&ctx) {
        for specialise in [true, false] {
            let open = |max_runs_per_pass| {
                let options = GpuOptions {
                    specialise,
                    max_runs_per_pass,
                    ..GpuOptions::default()
                };
                GpuEvaluator::new(ctx.clone(), c.problem.clone(), precision, options).unwrap()
            };
            let mut whole = open(None);
            let mut split = open(Some(MAX_RUNS_PER_PASS));
            let a = whole.fitness(&batch).unwrap();
            let b = split.fitness(&batch).unwrap();
            let what = format!("{file}, {precision:?}, specialise {specialise}");
            let per_pass = split.runs_per_pass_in_use().unwrap();
            assert!(
                per_pass > 0 && per_pass <= MAX_RUNS_PER_PASS && per_pass < runs,
                "{what}: {per_pass} runs per pass for {runs} runs"
            );
            assert_eq!(per_pass % c.problem.experiments.len(), 0, "{what}");
            assert!(whole.runs_per_pass_in_use().unwrap() >= runs, "{what}");
            assert_eq!(a.values.len(), runs, "{what}");
            // Not all diverged: the comparison compares numbers.
            assert!(a.diverged < runs / 2, "{what}: {} diverged", a.diverged);
            assert_eq!(bits(&a.values), bits(&b.values), "{what}");
            assert_eq!(a.diverged, b.diverged, "{what}");
        }
    }
}

#[test]
fn shipped_example_split_into_dispatches_scores_as_one_dispatch() {
    split_scores_as_unsplit("aa2024_t3_synthetic.json");
}

#[test]
fn two_experiment_rig_split_into_dispatches_scores_as_one_dispatch() {
    split_scores_as_unsplit("bearing_2dof_synthetic.json");
}
