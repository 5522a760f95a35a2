//! Several experiments per problem, each with its own sample count, interval,
//! fit window, start time and drive (one velocity-driven, one force-driven from
//! a piecewise-linear table), give the same fitness and histories on the GPU as
//! on the CPU reference.
mod oracle;
mod tensile_common;

mod gpu_common;
use gpu_common as common;

use rigfit::base::{Drive, PiecewiseLinear};
use rigfit::eval::{
    Batch, CpuEvaluator, Evaluator, ExperimentData, Precision, Problem, simulate_history,
};
use rigfit::gpu::{F32_HISTORY_TOLERANCE, F64_HISTORY_TOLERANCE, GpuByDrive, GpuOptions};
use tensile_common::{REFERENCE, tensile4};

fn experiment(name: &str, drive: Drive, samples: usize, dt: f64, t_first: f64) -> ExperimentData {
    common::self_measured(tensile4(), &REFERENCE, name, drive, (samples, dt, t_first))
}

fn problem() -> Problem {
    let table = PiecewiseLinear {
        t: vec![0.0, 5.0e-5, 2.0e-4, 6.0e-4],
        value: vec![0.0, 5.0e4, 2.0e5, 2.0e5],
    };
    let mut velocity = experiment("velocity", Drive::Velocity, 300, 1.0e-6, 2.5e-6);
    velocity.window = 20..300;
    let mut force = experiment("force", Drive::Force(table), 200, 2.0e-6, 0.0);
    force.window = 10..150;
    Problem {
        model: tensile4().clone(),
        experiments: vec![velocity, force],
        substeps: 2,
    }
}

fn batch(candidates: usize) -> Batch {
    let params = common::spread_params(candidates, 5);
    let offsets: Vec<f64> = (0..candidates).map(|i| (i % 3) as f64 * 0.7e-6).collect();
    Batch {
        candidates,
        params: vec![params.clone(), params],
        offsets: vec![offsets.clone(), offsets],
    }
}

#[test]
fn multi_experiment_force_drive_fitness_and_histories_match_cpu() {
    let Some(ctx) = common::gpu() else { return };
    let problem = problem();
    let batch = batch(64);
    let cpu = CpuEvaluator::new(problem.clone(), 0)
        .fitness(&batch)
        .unwrap();
    for e in 0..2 {
        let ok = (0..batch.candidates)
            .filter(|&i| cpu.get(i, e) < rigfit::eval::DIVERGED)
            .count();
        eprintln!("experiment {e}: {ok} of {} runs finite", batch.candidates);
        assert!(
            ok > batch.candidates / 2,
            "experiment {e}: {ok} finite runs"
        );
    }
    let mut precisions = vec![(Precision::F32, 1e-3, F32_HISTORY_TOLERANCE)];
    if ctx.has_f64() {
        precisions.push((Precision::F64, 1e-9, F64_HISTORY_TOLERANCE));
    }
    for (precision, fit_tol, hist_tol) in precisions {
        // The rig has a kernel per drive mode: one evaluator per mode, on one
        // device, each scoring its experiments.
        let mut gpu = GpuByDrive::new(
            ctx.clone(),
            problem.clone(),
            precision,
            GpuOptions::default(),
        )
        .unwrap();
        let g = gpu.fitness(&batch).unwrap();
        assert_eq!(g.diverged, cpu.diverged, "{precision:?}");
        for (j, (a, b)) in g.values.iter().zip(&cpu.values).enumerate() {
            let err = (a - b).abs() / b.abs().max(1e-3);
            assert!(err <= fit_tol, "{precision:?} run {j}: {a} vs {b}");
        }
        histories_match(
            &mut gpu,
            &problem,
            &batch,
            &[0, 1, 2, 5],
            precision,
            hist_tol,
        );
    }
}

/// GPU histories of candidates `which` within `hist_tol` of the largest force
/// of the CPU reference's, with the actuator state as the drive prescribes it.
fn histories_match(
    gpu: &mut impl Evaluator,
    problem: &Problem,
    batch: &Batch,
    which: &[usize],
    precision: Precision,
    hist_tol: f64,
) {
    let hist = gpu.histories(batch, which).unwrap();
    for (h, &i) in hist.iter().zip(which) {
        for (e, he) in h.iter().enumerate() {
            let c = simulate_history(problem, e, batch.params_of(e, i), batch.offsets[e][i]);
            assert_eq!(he.t.len(), c.t.len());
            let scale = c.outputs[0]
                .iter()
                .fold(f64::MIN_POSITIVE, |m, f| m.max(f.abs()));
            for (k, (x, y)) in he.outputs[0].iter().zip(&c.outputs[0]).enumerate() {
                assert!(
                    (x - y).abs() <= hist_tol * scale,
                    "{precision:?} candidate {i} experiment {e} sample {k}: {x} vs {y}"
                );
            }
            let (x, y) = (he.states[3].last().unwrap(), c.states[3].last().unwrap());
            assert!((x - y).abs() <= 1e-5 * y.abs().max(1e-9), "y4: {x} vs {y}");
        }
    }
}

/// A force table of 1500 unevenly spaced breakpoints, read at every RK4 stage:
/// the GPU's table search (shared/table.wgsl) must find the segment the CPU's
/// `PiecewiseLinear::at` finds at every time, or the histories part.
#[test]
fn long_force_table_histories_match_cpu() {
    let Some(ctx) = common::gpu() else { return };
    let n = 1500;
    let t: Vec<f64> = (0..n)
        .map(|i| {
            let i = i as f64;
            4.0e-4 * (i + 0.3 * (i * 0.7).sin()) / n as f64
        })
        .collect();
    let value: Vec<f64> = t
        .iter()
        .enumerate()
        .map(|(i, &ti)| 2.0e5 * (ti / 3.0e-4).min(1.0) + 4.0e3 * (i as f64 * 1.3).sin())
        .collect();
    let exp = experiment(
        "table",
        Drive::Force(PiecewiseLinear { t, value }),
        400,
        1.0e-6,
        0.0,
    );
    let problem = Problem {
        model: tensile4().clone(),
        experiments: vec![exp],
        substeps: 2,
    };
    let params = common::spread_params(8, 3);
    let batch = Batch {
        candidates: 8,
        params: vec![params],
        offsets: vec![vec![0.0; 8]],
    };
    let mut precisions = vec![(Precision::F32, F32_HISTORY_TOLERANCE)];
    if ctx.has_f64() {
        precisions.push((Precision::F64, F64_HISTORY_TOLERANCE));
    }
    for (precision, tol) in precisions {
        let mut gpu = common::evaluator(&ctx, &problem, precision);
        histories_match(&mut gpu, &problem, &batch, &[0, 3, 7], precision, tol);
    }
}
