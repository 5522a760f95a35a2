//! Candidate-steps per second (candidates × total RK4 steps / seconds) of every
//! evaluator on the reference problem, shortened to `SAMPLES` samples: CPU on one
//! thread, CPU on all threads, GPU f32, GPU f64, at populations 1024, 4096 and
//! 16384.
//!
//! `cargo bench --bench evaluator_throughput` prints a Markdown table first (two
//! timed evaluations per cell after a warm-up), then runs the criterion groups.
//! `RIGFIT_BENCH_TABLE_ONLY=1` stops after the table; `RIGFIT_BENCH_ROWS=gpu-f32,…`
//! keeps only the rows whose names contain one of the given words and
//! `RIGFIT_BENCH_POPS=4096,…` only the given populations (for quick kernel work);
//! `RIGFIT_BENCH_CPU_TIME=1` adds candidate-steps per CPU-second of the process.
//!
//! On the 2-core development machine (lavapipe, LLVM 15, 256-bit), idle: CPU
//! 1 thread ≈ 1.0e7, all threads ≈ 2.0e7, GPU f32 ≈ 1.1–1.2e8, GPU f64 ≈
//! 6.0e7 candidate-steps/s; timings drop by half or more while other builds
//! share the cores (compare variants alternately, several times).

use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, Throughput};
use rigfit::eval::{Batch, CpuEvaluator, Evaluator, Precision, Problem};
use rigfit::fixtures::reference_problem;
use rigfit::gpu::{GpuContext, GpuEvaluator, GpuOptions};
use rigfit::model::tensile::REFERENCE;

const SAMPLES: usize = 500;

fn samples() -> usize {
    std::env::var("RIGFIT_BENCH_SAMPLES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(SAMPLES)
}
const POPULATIONS: [usize; 3] = [1024, 4096, 16384];

fn problem() -> Problem {
    let mut p = reference_problem();
    let e = &mut p.experiments[0];
    let n = samples().min(e.force.len());
    e.force.truncate(n);
    e.window = 0..n;
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

/// The comma-separated items of environment variable `name`, if set.
fn env_list(name: &str) -> Option<Vec<String>> {
    std::env::var(name)
        .ok()
        .map(|v| v.split(',').map(|s| s.trim().to_string()).collect())
}

/// CPU seconds used so far by this process, all threads (lavapipe's included),
/// from `/proc/self/stat`; `None` where that is not available.
fn process_cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name, which ends at the last ')'.
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

fn populations() -> Vec<usize> {
    match env_list("RIGFIT_BENCH_POPS") {
        Some(l) => l.iter().filter_map(|s| s.parse().ok()).collect(),
        None => POPULATIONS.to_vec(),
    }
}

fn print_table(evals: &[(&'static str, Factory)]) {
    let steps = steps(&problem());
    println!(
        "\nReference problem, {} samples × {} substeps = {steps} RK4 steps per candidate",
        problem().experiments[0].force.len(),
        problem().substeps
    );
    let pops = populations();
    let per_cpu = std::env::var_os("RIGFIT_BENCH_CPU_TIME").is_some();
    let head: String = pops.iter().map(|n| format!(" {n} |")).collect();
    let rule: String = pops.iter().map(|_| "---|").collect();
    println!("\n| evaluator |{head}\n|---|{rule}");
    for (name, make) in evals {
        let mut eval = make();
        let mut row = format!("| {name} |");
        for &n in &pops {
            let b = batch(n);
            eval.fitness(&b).unwrap();
            let t = Instant::now();
            let cpu = process_cpu_seconds();
            for _ in 0..2 {
                eval.fitness(&b).unwrap();
            }
            let rate = (2 * n * steps) as f64 / t.elapsed().as_secs_f64();
            row.push_str(&format!(" {rate:.2e} |"));
            // Per CPU-second: steadier than wall time while other jobs share the
            // cores (lavapipe's threads are this process's).
            if let (true, Some(a), Some(b)) = (per_cpu, cpu, process_cpu_seconds()) {
                row.push_str(&format!(
                    " ({:.2e}/cpu-s) |",
                    (2 * n * steps) as f64 / (b - a)
                ));
            }
        }
        println!("{row}");
    }
    println!("\n(candidate-steps/s = candidates × RK4 steps / wall seconds per evaluation)\n");
}

fn main() {
    let mut evals = evaluators();
    if let Some(rows) = env_list("RIGFIT_BENCH_ROWS") {
        evals.retain(|(name, _)| rows.iter().any(|r| name.contains(r.as_str())));
    }
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
