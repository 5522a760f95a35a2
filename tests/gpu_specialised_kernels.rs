//! Fitness kernels specialised to a batch (per-run values that are the same in
//! every run baked in as constants) score as the generic kernel does, to
//! rounding (the driver's compiler may regroup arithmetic on folded constants):
//! on the shipped example's free parameters, and when batches share different
//! values; each batch gets the kernel of its own shared values, so the same
//! batch always gets the same bits.
mod oracle;
mod tensile_common;

mod gpu_common;
use gpu_common as common;

use std::path::Path;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rigfit::campaign::Campaign;
use rigfit::eval::{Batch, Evaluator, Precision, Problem, Timed};
use rigfit::gpu::{GpuContext, GpuEvaluator, GpuOptions};
use rigfit::job::gene_specs;
use tensile_common::ix;

const CANDIDATES: usize = 96;
const SAMPLES: usize = 700;

/// The shipped example, shortened to `SAMPLES` samples.
fn shipped() -> Campaign {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns/aa2024_t3_synthetic.json");
    let mut c = Campaign::load(&path).unwrap();
    for e in &mut c.problem.experiments {
        e.measured.truncate(SAMPLES);
        e.window = e.window.start..SAMPLES;
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

fn evaluator(ctx: &GpuContext, problem: &Problem, p: Precision, specialise: bool) -> GpuEvaluator {
    let options = GpuOptions {
        specialise,
        ..GpuOptions::default()
    };
    GpuEvaluator::new(ctx.clone(), problem.clone(), p, options).unwrap()
}

fn precisions(ctx: &GpuContext) -> Vec<Precision> {
    let mut v = vec![Precision::F32];
    if ctx.has_f64() {
        v.push(Precision::F64);
    }
    v
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// Largest relative difference allowed between specialised and generic fitness.
fn tolerance(p: Precision) -> f64 {
    match p {
        Precision::F64 => 1e-11,
        Precision::F32 => 1e-4,
    }
}

/// Asserts that two fitness vectors agree within `tolerance(p)`, relative.
fn assert_close(generic: &[f64], special: &[f64], p: Precision) {
    assert_eq!(generic.len(), special.len());
    for (i, (g, s)) in generic.iter().zip(special).enumerate() {
        let rel = ((g - s) / g.abs().max(1e-12)).abs();
        assert!(
            rel <= tolerance(p),
            "{p:?} candidate {i}: generic {g}, specialised {s}"
        );
    }
}

/// Sets parameter `j` of every candidate with `value(i)`.
fn set_param(b: &mut Batch, j: usize, value: impl Fn(usize) -> f64) {
    let n = b.params[0].len() / b.candidates;
    for i in 0..b.candidates {
        b.params[0][i * n + j] = value(i);
    }
}

#[test]
fn specialised_fitness_equals_generic_to_rounding() {
    let Some(ctx) = common::gpu() else { return };
    let c = shipped();
    let b = batch(&c, 11);
    for p in precisions(&ctx) {
        let generic = evaluator(&ctx, &c.problem, p, false).fitness(&b).unwrap();
        let special = evaluator(&ctx, &c.problem, p, true).fitness(&b).unwrap();
        assert_eq!(generic.diverged, special.diverged, "{p:?}");
        assert_close(&generic.values, &special.values, p);
        // Not vacuous: every candidate scores differently, some of them well.
        let mut distinct = bits(&generic.values);
        distinct.sort_unstable();
        distinct.dedup();
        assert_eq!(distinct.len(), CANDIDATES, "{p:?}");
        assert!(generic.values.iter().any(|v| *v < 0.1), "{p:?}");
    }
}

#[test]
fn each_batch_gets_the_kernel_of_its_own_shared_values() {
    let Some(ctx) = common::gpu() else { return };
    let c = shipped();
    for p in precisions(&ctx) {
        let mut generic = evaluator(&ctx, &c.problem, p, false);
        let mut special = evaluator(&ctx, &c.problem, p, true);
        let first = batch(&c, 5);
        // The specimen mass moves to another shared value, then varies per
        // candidate: each batch must still score as the generic kernel does.
        let mut moved = batch(&c, 6);
        let m2 = moved.params[0][ix::M2];
        set_param(&mut moved, ix::M2, |_| m2 * 1.5);
        let mut spread = batch(&c, 7);
        set_param(&mut spread, ix::M2, |i| m2 * (1.0 + i as f64 / 64.0));
        let mut baked = Vec::new();
        let mut first_bits = Vec::new();
        for b in [&first, &moved, &spread, &first] {
            let g = generic.fitness(b).unwrap();
            let s = special.fitness(b).unwrap();
            assert_eq!(g.diverged, s.diverged, "{p:?}");
            assert_close(&g.values, &s.values, p);
            baked.push(special.specialised_constants().unwrap());
            if std::ptr::eq(b, &first) {
                first_bits.push(bits(&s.values));
            }
        }
        // 1/m2 is baked while it is shared (with either value) and not once
        // it varies.
        let n = baked[0];
        assert_eq!(baked, vec![n, n, n - 1, n], "{p:?}");
        // The same batch gets the same bits whatever was scored in between.
        assert_eq!(first_bits[0], first_bits[1], "{p:?}");
        assert_eq!(generic.specialised_constants(), None);
        // The mass did matter.
        let a = generic.fitness(&spread).unwrap();
        let b = generic.fitness(&moved).unwrap();
        assert_ne!(bits(&a.values), bits(&b.values));
    }
}

#[test]
fn small_batches_use_the_generic_kernel() {
    let Some(ctx) = common::gpu() else { return };
    let c = shipped();
    let mut b = batch(&c, 9);
    let keep = rigfit::gpu::specialise::MIN_RUNS - 1;
    let per_candidate = b.params[0].len() / b.candidates;
    b.params[0].truncate(keep * per_candidate);
    b.offsets[0].truncate(keep);
    b.candidates = keep;
    let mut special = evaluator(&ctx, &c.problem, Precision::F32, true);
    special.fitness(&b).unwrap();
    assert_eq!(special.specialised_constants(), None);
}

/// A trial's warm-up builds the kernel that scores the batch and runs its
/// first chunk only (and a trial's part of a pass its first chunks): the batch scored after it has the bits of a batch
/// scored by an evaluator that never warmed up (the runs start again from
/// their initial state), and the specialised kernel it built is the one
/// that scores the batch.
#[test]
fn a_warm_up_readies_the_batch_and_leaves_its_scores_alone() {
    let Some(ctx) = common::gpu() else { return };
    let c = shipped();
    let b = batch(&c, 13);
    // Chunks of 64 steps: the warm-up's one chunk is a tenth of a run.
    let options = GpuOptions {
        chunk_steps: 64,
        ..GpuOptions::default()
    };
    for p in precisions(&ctx) {
        let mut fresh = GpuEvaluator::new(ctx.clone(), c.problem.clone(), p, options).unwrap();
        let expected = fresh.fitness(&b).unwrap();
        let mut warmed = GpuEvaluator::new(ctx.clone(), c.problem.clone(), p, options).unwrap();
        warmed.warm_up(&b).unwrap();
        let baked = warmed.specialised_constants();
        assert!(baked.is_some_and(|n| n > 0), "{p:?}: {baked:?}");
        let got = warmed.fitness(&b).unwrap();
        assert_eq!(warmed.specialised_constants(), baked, "{p:?}");
        assert_eq!(bits(&got.values), bits(&expected.values), "{p:?}");
        assert_eq!(got.diverged, expected.diverged, "{p:?}");
        // A trial's part of a pass (130 steps: three whole chunks) says how
        // far the runs went and leaves the next pass's bits alone too.
        assert_eq!(warmed.fitness_part(&b, 130).unwrap(), Some(192), "{p:?}");
        let again = warmed.fitness(&b).unwrap();
        assert_eq!(bits(&again.values), bits(&expected.values), "{p:?}");
    }
}
