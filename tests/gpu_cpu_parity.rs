//! The GPU kernels reproduce the f64 CPU reference on a seeded batch of 256
//! candidates spread over the parameter space (some fracture, some don't, some
//! never engage the slack adapter, some blow up; clock offsets with and without
//! a prologue): force histories, fitness values, divergence and the ranking of
//! the best ten. f64 within 1e-9 of each history's largest |F|; f32 within
//! `F32_HISTORY_TOLERANCE`. A fracture placed just before, at and just after a
//! step boundary does not flip the result either.
mod oracle;
mod tensile_common;

mod gpu_common;
use gpu_common as common;

use rigfit::eval::{
    Batch, CpuEvaluator, Evaluator, Precision, Problem, score_one, simulate_history,
};
use rigfit::gpu::{
    F32_HISTORY_TOLERANCE, F64_HISTORY_TOLERANCE, GpuContext, GpuEvaluator, GpuOptions,
};
use tensile_common::{REFERENCE, ix, tensile4};
use tensile_common::{REFERENCE_DT, REFERENCE_SUBSTEPS, reference_experiment};

const SAMPLES: usize = 800;
const CANDIDATES: usize = 256;

fn problem() -> Problem {
    Problem {
        model: tensile4().clone(),
        experiments: vec![reference_experiment(
            SAMPLES,
            REFERENCE_DT,
            REFERENCE_SUBSTEPS,
            20.0,
            7,
        )],
        substeps: REFERENCE_SUBSTEPS,
    }
}

/// The spread batch with clock offsets: none, a few steps and a fraction of a
/// step (prologue), and negative (starts before the drive).
fn spread_batch(problem: &Problem) -> Batch {
    let mut b = common::batch_of(problem, common::spread_params(CANDIDATES, 42));
    for (i, o) in b.offsets[0].iter_mut().enumerate() {
        *o = [0.0, 1.7e-6, 3.0e-6, -2.3e-6][i % 4];
    }
    b
}

/// Largest |GPU − CPU| load-cell force over each non-diverged candidate's
/// history, relative to that history's largest |F|; and how many broke.
fn history_error(
    ctx: &GpuContext,
    precision: Precision,
    problem: &Problem,
    batch: &Batch,
) -> (f64, usize) {
    let mut gpu = common::evaluator(ctx, problem, precision);
    let which: Vec<usize> = (0..batch.candidates).collect();
    let hist = gpu.histories(batch, &which).unwrap();
    let (mut worst, mut broke) = (0.0_f64, 0);
    for i in which {
        let (params, offset) = (batch.params_of(0, i), batch.offsets[0][i]);
        if score_one(problem, 0, params, offset).1 {
            continue;
        }
        let cpu = simulate_history(problem, 0, params, offset);
        let g = &hist[i][0];
        let scale = cpu.outputs[0]
            .iter()
            .fold(f64::MIN_POSITIVE, |m, f| m.max(f.abs()));
        let t_tol = match precision {
            Precision::F64 => 1e-12,
            Precision::F32 => 1e-6,
        };
        for k in 0..cpu.t.len() {
            let t_err = (g.t[k] - cpu.t[k]).abs() / (cpu.t[k].abs() + REFERENCE_DT);
            assert!(t_err <= t_tol, "t[{k}] of {i}: {} vs {}", g.t[k], cpu.t[k]);
            let err = (g.outputs[0][k] - cpu.outputs[0][k]).abs() / scale;
            assert!(
                err.is_finite(),
                "candidate {i} sample {k}: {} vs {}",
                g.outputs[0][k],
                cpu.outputs[0][k]
            );
            worst = worst.max(err);
        }
        broke += usize::from(*cpu.outputs[1].last().unwrap() == 0.0);
    }
    (worst, broke)
}

#[test]
fn f64_force_histories_match_cpu_within_1e_9() {
    let Some(ctx) = common::gpu() else { return };
    if !ctx.has_f64() {
        eprintln!("no SHADER_F64 on {}; skipped", ctx.describe());
        return;
    }
    let problem = problem();
    let (worst, broke) = history_error(&ctx, Precision::F64, &problem, &spread_batch(&problem));
    eprintln!("f64 worst relative history error {worst:e}; {broke} of {CANDIDATES} fractured");
    assert!(
        broke > 10 && broke < CANDIDATES - 10,
        "fracture mix: {broke}"
    );
    assert!(worst <= F64_HISTORY_TOLERANCE, "{worst:e}");
}

/// The same 1600 RK4 steps of length REFERENCE_DT / 2 taken as one and as three
/// steps per sample: a fracture step then ends its interval or sits anywhere in
/// it, and a block of 32 samples spans 32 or 96 steps.
#[test]
fn f64_force_histories_match_cpu_at_one_and_three_steps_per_sample() {
    let Some(ctx) = common::gpu() else { return };
    if !ctx.has_f64() {
        eprintln!("no SHADER_F64 on {}; skipped", ctx.describe());
        return;
    }
    let h = REFERENCE_DT / REFERENCE_SUBSTEPS as f64;
    for substeps in [1, 3] {
        let samples = SAMPLES * REFERENCE_SUBSTEPS / substeps;
        let dt = h * substeps as f64;
        let problem = Problem {
            model: tensile4().clone(),
            experiments: vec![reference_experiment(samples, dt, substeps, 20.0, 7)],
            substeps,
        };
        let (worst, broke) = history_error(&ctx, Precision::F64, &problem, &spread_batch(&problem));
        eprintln!(
            "{substeps} steps per sample: f64 worst relative history error {worst:e}; {broke} fractured"
        );
        assert!(
            broke > 10 && broke < CANDIDATES - 10,
            "fracture mix: {broke}"
        );
        assert!(
            worst <= F64_HISTORY_TOLERANCE,
            "{substeps} steps per sample: {worst:e}"
        );
    }
}

#[test]
fn f32_force_histories_match_cpu_within_documented_tolerance() {
    let Some(ctx) = common::gpu() else { return };
    let problem = problem();
    let (worst, _) = history_error(&ctx, Precision::F32, &problem, &spread_batch(&problem));
    eprintln!("f32 worst relative history error {worst:e}");
    assert!(worst <= F32_HISTORY_TOLERANCE, "{worst:e}");
}

/// Indices of the ten best candidates, best first.
fn best_ten(values: &[f64]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..values.len()).collect();
    idx.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    idx.truncate(10);
    idx
}

fn fitness_agrees(precision: Precision, rel_tol: f64) {
    let Some(ctx) = common::gpu() else { return };
    if precision == Precision::F64 && !ctx.has_f64() {
        return;
    }
    let problem = problem();
    let batch = spread_batch(&problem);
    let cpu = CpuEvaluator::new(problem.clone(), 0)
        .fitness(&batch)
        .unwrap();
    let mut gpu = GpuEvaluator::new(ctx, problem, precision, GpuOptions::default()).unwrap();
    let g = gpu.fitness(&batch).unwrap();
    assert!(
        cpu.diverged > 0,
        "the batch should hold unstable candidates"
    );
    assert_eq!(g.diverged, cpu.diverged, "{precision:?} diverged count");
    let mut worst = 0.0_f64;
    for (i, (a, b)) in g.values.iter().zip(&cpu.values).enumerate() {
        assert_eq!(
            *a >= rigfit::eval::DIVERGED,
            *b >= rigfit::eval::DIVERGED,
            "candidate {i}"
        );
        let err = (a - b).abs() / b.abs().max(1e-3);
        worst = worst.max(err);
    }
    eprintln!("{precision:?} worst relative fitness error {worst:e}");
    assert!(worst <= rel_tol, "{precision:?}: {worst:e}");
    assert_eq!(
        best_ten(&g.values),
        best_ten(&cpu.values),
        "{precision:?} best ten"
    );
}

#[test]
fn f64_fitness_divergence_and_best_ten_match_cpu() {
    fitness_agrees(Precision::F64, 1e-8);
}

#[test]
fn f32_fitness_divergence_and_best_ten_match_cpu() {
    fitness_agrees(Precision::F32, 1e-4);
}

/// Elongation y2 − y1 of the unbreakable reference rig after RK4 step `i`:
/// the same steps as `problem`'s, sampled at every step.
fn elongation_after_step(problem: &Problem, i: usize) -> f64 {
    let mut fine = problem.clone();
    fine.experiments[0].dt /= problem.substeps as f64;
    fine.experiments[0].window = 0..i + 1;
    fine.experiments[0].measured = vec![0.0; i + 1];
    fine.substeps = 1;
    let mut p = REFERENCE;
    p[ix::E_FRACTURE] = 1.0;
    let h = simulate_history(&fine, 0, &p, 0.0);
    h.states[1][i] - h.states[0][i]
}

#[test]
fn fracture_at_a_step_boundary_does_not_flip_results() {
    let Some(ctx) = common::gpu() else { return };
    let problem = problem();
    // Step 601 ends between samples 300 and 301 (two steps per sample), so no
    // sample sits on the load-cell damping jump at fracture; place the fracture
    // just before, at and just after the elongation reached there.
    let e_b = elongation_after_step(&problem, 601);
    assert!(e_b > 1e-5, "elongation at the boundary: {e_b}");
    let mut params = Vec::new();
    for rel in [-1e-12, -1e-15, 0.0, 1e-15, 1e-12] {
        let mut p = REFERENCE;
        p[ix::E_FRACTURE] = e_b * (1.0 + rel);
        params.extend_from_slice(&p);
    }
    let batch = common::batch_of(&problem, params);
    let precisions: &[(Precision, f64)] = if ctx.has_f64() {
        &[
            (Precision::F64, F64_HISTORY_TOLERANCE),
            (Precision::F32, F32_HISTORY_TOLERANCE),
        ]
    } else {
        &[(Precision::F32, F32_HISTORY_TOLERANCE)]
    };
    for &(precision, tol) in precisions {
        let mut gpu = common::evaluator(&ctx, &problem, precision);
        let hist = gpu.histories(&batch, &[0, 1, 2, 3, 4]).unwrap();
        for (i, h) in hist.iter().enumerate() {
            let cpu = simulate_history(&problem, 0, batch.params_of(0, i), 0.0);
            let scale = cpu.outputs[0].iter().fold(0.0_f64, |m, f| m.max(f.abs()));
            assert_eq!(
                *cpu.outputs[1].last().unwrap(),
                0.0,
                "reference run {i} must break"
            );
            assert_eq!(
                h[0].outputs[1].last().copied(),
                Some(0.0),
                "{precision:?} run {i} must break"
            );
            for (k, (g, c)) in h[0].outputs[0].iter().zip(&cpu.outputs[0]).enumerate() {
                assert!(
                    (g - c).abs() <= tol * scale,
                    "{precision:?} run {i} sample {k}: {g} vs {c}"
                );
            }
        }
    }
}
