//! The same batch evaluated twice gives bit-identical fitness on every path:
//! GPU f32, GPU f64 (reusing the evaluator's buffers between the two calls) and
//! the CPU reference.
mod oracle;
mod tensile_common;

mod gpu_common;
use gpu_common as common;

use rigfit::eval::{Batch, CpuEvaluator, Evaluator, Precision, Problem, Timed};
use rigfit::gpu::{GpuEvaluator, GpuOptions};
use tensile_common::tensile4;
use tensile_common::{REFERENCE_DT, REFERENCE_SUBSTEPS, reference_experiment};

fn setup() -> (Problem, Batch) {
    let problem = Problem {
        model: tensile4().clone(),
        experiments: vec![reference_experiment(
            500,
            REFERENCE_DT,
            REFERENCE_SUBSTEPS,
            20.0,
            7,
        )],
        substeps: REFERENCE_SUBSTEPS,
    };
    let batch = common::batch_of(&problem, common::spread_params(256, 9));
    (problem, batch)
}

fn bits(values: &[f64]) -> Vec<u64> {
    values.iter().map(|v| v.to_bits()).collect()
}

fn twice(eval: &mut dyn Evaluator, batch: &Batch) {
    let a = eval.fitness(batch).unwrap();
    let b = eval.fitness(batch).unwrap();
    assert_eq!(bits(&a.values), bits(&b.values), "{:?}", eval.info());
    assert_eq!(a.diverged, b.diverged);
}

#[test]
fn cpu_fitness_is_bit_identical_across_runs() {
    let (problem, batch) = setup();
    twice(&mut CpuEvaluator::new(problem, 0), &batch);
}

/// A batch scored while the native build started early runs (on one
/// thread fewer, beside the compiler) scores as the same batch does once it
/// is done, and as an evaluator that started no build.
#[test]
fn cpu_fitness_while_the_native_build_runs_is_bit_identical() {
    let (problem, batch) = setup();
    let mut plain = CpuEvaluator::new(problem.clone(), 2);
    let want = plain.fitness(&batch).unwrap();
    let mut early = CpuEvaluator::new(problem, 2);
    early.prepare_soon();
    let during = early.fitness(&batch).unwrap();
    early.prepare();
    let after = early.fitness(&batch).unwrap();
    assert_eq!(bits(&during.values), bits(&want.values));
    assert_eq!(bits(&after.values), bits(&want.values));
}

#[test]
fn gpu_f32_fitness_is_bit_identical_across_runs() {
    let Some(ctx) = common::gpu() else { return };
    let (problem, batch) = setup();
    let mut gpu = GpuEvaluator::new(ctx, problem, Precision::F32, GpuOptions::default()).unwrap();
    twice(&mut gpu, &batch);
}

#[test]
fn gpu_f64_fitness_is_bit_identical_across_runs() {
    let Some(ctx) = common::gpu() else { return };
    if !ctx.has_f64() {
        return;
    }
    let (problem, batch) = setup();
    let mut gpu = GpuEvaluator::new(ctx, problem, Precision::F64, GpuOptions::default()).unwrap();
    twice(&mut gpu, &batch);
}

#[test]
fn chunk_size_changes_gpu_fitness_by_rounding_only() {
    let Some(ctx) = common::gpu() else { return };
    let (problem, mut batch) = setup();
    // Clock offsets with a prologue, so a chunk's budget also runs out inside a
    // block of the run loop.
    for (i, o) in batch.offsets[0].iter_mut().enumerate() {
        *o = [0.0, 1.7e-6, 3.0e-6][i % 3];
    }
    let precision = if ctx.has_f64() {
        Precision::F64
    } else {
        Precision::F32
    };
    let mut whole = GpuEvaluator::new(
        ctx.clone(),
        problem.clone(),
        precision,
        GpuOptions {
            chunk_steps: 1 << 20,
            ..GpuOptions::default()
        },
    )
    .unwrap();
    // Rounded up to one block of 32 samples (64 steps): 25 dispatches.
    let chunked_options = GpuOptions {
        chunk_steps: 37,
        ..GpuOptions::default()
    };
    let mut chunked = GpuEvaluator::new(ctx, problem, precision, chunked_options).unwrap();
    let a = whole.fitness(&batch).unwrap();
    let b = chunked.fitness(&batch).unwrap();
    // A chunk that ends inside a block of the run loop restarts the drive's
    // carried clock (`rig_clock`, computed once per block) where the next
    // chunk begins, so the last bits may move; nothing more may.
    let tol = if precision == Precision::F64 {
        1e-12
    } else {
        1e-5
    };
    assert_eq!(a.diverged, b.diverged);
    for (i, (x, y)) in a.values.iter().zip(&b.values).enumerate() {
        assert!(
            x.to_bits() == y.to_bits() || (x - y).abs() <= tol * x.abs(),
            "run {i}: {x:e} whole, {y:e} chunked"
        );
    }
}
