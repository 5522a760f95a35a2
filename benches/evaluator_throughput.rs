//! Candidate-steps per second (candidates × total RK4 steps / seconds) of every
//! evaluator on the reference problem, shortened to `SAMPLES` samples: CPU on one
//! thread, CPU on all threads, GPU f32, GPU f64, at populations 1024, 4096 and
//! 16384.
//!
//! `cargo bench --bench evaluator_throughput` prints a Markdown table first (two
//! timed evaluations per cell after a warm-up), then runs the criterion groups.
//! `RIGFIT_BENCH_TABLE_ONLY=1` stops after the table.
//!
//! On the 2-core development machine (lavapipe, LLVM 15, 256-bit), idle: CPU
//! 1 thread ≈ 1.0e7, all threads ≈ 1.9e7, GPU f32 ≈ 6.5–7.9e7, GPU f64 ≈
//! 3.7–3.9e7 candidate-steps/s; timings drop by half or more while other builds
//! share the cores.

use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, Throughput};
use rigfit::eval::{Batch, CpuEvaluator, Evaluator, Precision, Problem};
use rigfit::fixtures::reference_problem;
use rigfit::gpu::{GpuContext, GpuEvaluator, GpuOptions};
use rigfit::model::tensile::REFERENCE;

const SAMPLES: usize = 500;
const POPULATIONS: [usize; 3] = [1024, 4096, 16384];

fn problem() -> Problem {
    let mut p = reference_problem();
    let e = &mut p.experiments[0];
    e.force.truncate(SAMPLES);
    e.window = 0..SAMPLES;
    p
}

/// `n` copies of the reference rig with ±20 % jitter on each value, seeded.
fn batch(n: usize) -> Batch {
    let mut params = Vec::with_capacity(n * REFERENCE.len());
    let mut s = 0x2545_f491_4f6c_dd1d_u64;
    for _ in 0..n {
        for v in REFERENCE {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let u = (s >> 11) as f64 / (1u64 << 53) as f64;
            params.push(v * (0.8 + 0.4 * u));
        }
    }
    Batch {
        candidates: n,
        params: vec![params],
        offsets: vec![vec![0.0; n]],
    }
}

fn steps(problem: &Problem) -> usize {
    problem.experiments[0]
        .grid(0.0, problem.substeps)
        .total_steps()
}

type Factory = Box<dyn Fn() -> Box<dyn Evaluator>>;

fn evaluators() -> Vec<(&'static str, Factory)> {
    let mut v: Vec<(&'static str, Factory)> = vec![
        (
            "cpu-1-thread",
            Box::new(|| Box::new(CpuEvaluator::new(problem(), 1))),
        ),
        (
            "cpu-all-threads",
            Box::new(|| Box::new(CpuEvaluator::new(problem(), 0))),
        ),
    ];
    match GpuContext::new() {
        Ok(ctx) => {
            let c = ctx.clone();
            v.push((
                "gpu-f32",
                Box::new(move || {
                    Box::new(
                        GpuEvaluator::new(
                            c.clone(),
                            problem(),
                            Precision::F32,
                            GpuOptions::default(),
                        )
                        .unwrap(),
                    )
                }),
            ));
            if ctx.has_f64() {
                v.push((
                    "gpu-f64",
                    Box::new(move || {
                        Box::new(
                            GpuEvaluator::new(
                                ctx.clone(),
                                problem(),
                                Precision::F64,
                                GpuOptions::default(),
                            )
                            .unwrap(),
                        )
                    }),
                ));
            }
        }
        Err(e) => eprintln!("no GPU ({e}); GPU rows skipped"),
    }
    v
}

fn print_table(evals: &[(&'static str, Factory)]) {
    let steps = steps(&problem());
    println!(
        "\nReference problem, {SAMPLES} samples × {} substeps = {steps} RK4 steps per candidate",
        problem().substeps
    );
    println!("\n| evaluator | 1024 | 4096 | 16384 |\n|---|---|---|---|");
    for (name, make) in evals {
        let mut eval = make();
        let mut row = format!("| {name} |");
        for n in POPULATIONS {
            let b = batch(n);
            eval.fitness(&b).unwrap();
            let t = Instant::now();
            for _ in 0..2 {
                eval.fitness(&b).unwrap();
            }
            let rate = (2 * n * steps) as f64 / t.elapsed().as_secs_f64();
            row.push_str(&format!(" {rate:.2e} |"));
        }
        println!("{row}");
    }
    println!("\n(candidate-steps/s = candidates × RK4 steps / wall seconds per evaluation)\n");
}

fn main() {
    let evals = evaluators();
    print_table(&evals);
    if std::env::var_os("RIGFIT_BENCH_TABLE_ONLY").is_some() {
        return;
    }
    let mut c = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .configure_from_args();
    let steps = steps(&problem());
    let mut group = c.benchmark_group("candidate_steps");
    for (name, make) in &evals {
        let mut eval = make();
        for n in POPULATIONS {
            let b = batch(n);
            group.throughput(Throughput::Elements((n * steps) as u64));
            group.bench_with_input(BenchmarkId::new(*name, n), &b, |bench, b| {
                bench.iter(|| eval.fitness(b).unwrap())
            });
        }
    }
    group.finish();
    c.final_summary();
}
