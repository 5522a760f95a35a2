//! Candidate-steps per second (candidates × total RK4 steps / seconds) of every
//! evaluator on the shipped example (`campaigns/aa2024_t3_synthetic.json`: 2501
//! samples, one RK4 step per sample, seven free parameters), with the free
//! parameters drawn uniformly over their bounds (log-uniform on log scales,
//! seeded), through the compiled rig `rigs/tensile4.json` with every event
//! located: CPU lanes on one thread, on all threads, in f32 (native lanes), GPU
//! f32 and f64 (specialised to the batch, as a calibration runs them) and the
//! same without specialisation (`-generic`), at populations 1024, 4096 and
//! 16384.
//!
//! `cargo bench --bench evaluator_throughput` prints a Markdown table first (the
//! fastest of five timed evaluations per cell, after a warm-up), then runs the
//! criterion groups.
//! `RIGFIT_BENCH_TABLE_ONLY=1` stops after the table; `RIGFIT_BENCH_ROWS=gpu-f32,…`
//! keeps only the rows whose names contain one of the given words,
//! `RIGFIT_BENCH_POPS=4096,…` only the given populations and
//! `RIGFIT_BENCH_SAMPLES=500` shortens the record (for quick kernel work),
//! `RIGFIT_BENCH_SUBSTEPS=10` takes that many RK4 steps per sample;
//! `RIGFIT_BENCH_PAIRS=N` instead times each specialised GPU row against its
//! generic twin (`gpu-f32` against `gpu-f32-generic`, …) in N alternating
//! rounds and prints the ratio of their rates per CPU-second (median over the
//! rounds);
//! `RIGFIT_BENCH_CAMPAIGN=campaigns/emps_closed_loop.json` measures another
//! campaign's problem instead of the shipped example (a rig driven by a
//! measured column, say);
//! `RIGFIT_BENCH_THREADS=128x32,…` adds GPU rows whose fitness kernel has that
//! workgroup size and that many vote lanes (`GpuOptions::threads`; the rows'
//! names end in `-wg128v32`), and `RIGFIT_BENCH_KNOBS=unchecked,storage,chunk512`
//! rows with one other option each (`GpuOptions::runtime_checks` off, the
//! record read from storage, 512 steps per dispatch; names end in
//! `-unchecked`, …);
//! `RIGFIT_BENCH_STATS=1` prints, instead of timing, the driver's statistics of
//! each GPU row's fitness kernel (registers per thread and the like, where the
//! driver offers `VK_KHR_pipeline_executable_properties`: an NVIDIA driver
//! does, lavapipe does not);
//! `RIGFIT_BENCH_CPU_TIME=1` adds candidate-steps per CPU-second of the process
//! (its CPU-time clock, all threads, lavapipe's included).
//! `RIGFIT_LANES_ISA=avx2 GALLIUM_OVERRIDE_CPU_CAPS=avx` runs both paths as on
//! a processor with AVX2 alone: the lanes in 32-byte vectors, and lavapipe's
//! JIT without AVX-512 (whose 32 vector registers it otherwise uses at
//! 256 bits, where the lanes built for AVX2 have 16).
//!
//! Rates per wall second drop by half or more while other work shares the
//! cores, or when lavapipe gets one core instead of two; the rate per
//! CPU-second moved by about 2 % between such runs, so compare variants by it,
//! alternately, several times. docs/engineering/performance.md has the
//! measured tables.

#[path = "common/cpu_time.rs"]
mod cpu_time;
#[path = "common/machine.rs"]
mod machine;
#[path = "common/population.rs"]
mod population;
#[path = "common/vk_stats.rs"]
mod vk_stats;
use cpu_time::process_cpu_seconds;
use population::{env_list, seeded_batch, steps};
use std::path::Path;
use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, Throughput};
use rigfit::campaign::Campaign;
use rigfit::eval::{Batch, CpuEvaluator, Evaluator, Precision, Problem};
use rigfit::gpu::shaders::Kernel;
use rigfit::gpu::{GpuContext, GpuEvaluator, GpuOptions, Threads};

const POPULATIONS: [usize; 3] = [1024, 4096, 16384];
/// Timed evaluations per table cell; the table shows the fastest.
const REPEATS: usize = 5;

/// The shipped example, or the campaign `RIGFIT_BENCH_CAMPAIGN` names
/// (relative to the crate's folder).
fn campaign() -> Campaign {
    let file = std::env::var("RIGFIT_BENCH_CAMPAIGN")
        .unwrap_or_else(|_| "campaigns/aa2024_t3_synthetic.json".into());
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(&file);
    Campaign::load(&path).unwrap_or_else(|e| panic!("{file}: {e:#}"))
}

fn problem() -> Problem {
    let mut p = campaign().problem;
    if let Some(n) = std::env::var("RIGFIT_BENCH_SAMPLES")
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
    {
        for e in &mut p.experiments {
            let n = n.min(e.measured.len());
            e.measured.truncate(n);
            e.window = e.window.start.min(n)..n;
        }
    }
    if let Some(n) = std::env::var("RIGFIT_BENCH_SUBSTEPS")
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
    {
        p.substeps = n.max(1);
    }
    p
}

/// `n` candidates of the measured campaign, from the benches' fixed seed.
fn batch(n: usize) -> Batch {
    seeded_batch(&campaign(), n)
}

type Factory = Box<dyn Fn() -> Box<dyn Evaluator>>;

/// What a GPU row runs: its device, precision and options.
struct GpuRow {
    ctx: GpuContext,
    precision: Precision,
    options: GpuOptions,
}

/// A table row: its name, its evaluator and, for a GPU row, what it runs.
type Row = (&'static str, Factory, Option<GpuRow>);

fn evaluators() -> Vec<Row> {
    let mut v: Vec<Row> = vec![
        (
            "cpu-1-thread",
            Box::new(|| Box::new(CpuEvaluator::new(problem(), 1))),
            None,
        ),
        (
            "cpu-all-threads",
            Box::new(|| Box::new(CpuEvaluator::new(problem(), 0))),
            None,
        ),
        (
            "cpu-all-threads-f32",
            Box::new(|| {
                let mut ev = CpuEvaluator::new(problem(), 0);
                ev.use_f32().expect("the C compiler builds the f32 lanes");
                Box::new(ev)
            }),
            None,
        ),
    ];
    match GpuContext::new() {
        Ok(ctx) => {
            let mut precisions = vec![("f32", Precision::F32)];
            if ctx.has_f64() {
                precisions.push(("f64", Precision::F64));
            }
            let variants = [(true, ""), (false, "-generic")];
            for ((specialise, suffix), (vname, tuned)) in variants
                .iter()
                .flat_map(|v| kernel_variants().into_iter().map(move |k| (*v, k)))
            {
                for &(pname, precision) in &precisions {
                    let name: &'static str = format!("gpu-{pname}{suffix}{vname}").leak();
                    let c = ctx.clone();
                    let options = GpuOptions {
                        specialise,
                        ..tuned
                    };
                    v.push((
                        name,
                        Box::new(move || {
                            Box::new(
                                GpuEvaluator::new(c.clone(), problem(), precision, options)
                                    .unwrap(),
                            )
                        }),
                        Some(GpuRow {
                            ctx: ctx.clone(),
                            precision,
                            options,
                        }),
                    ));
                }
            }
        }
        Err(e) => eprintln!("no GPU ({e}); GPU rows skipped"),
    }
    v
}

/// The GPU kernel variants to compare, each a row name's suffix and its
/// options: the default first, then one per layout of `RIGFIT_BENCH_THREADS`
/// (e.g. "64x8,128x32": workgroup size x vote lanes; `-wg128v32`) and one per
/// knob of `RIGFIT_BENCH_KNOBS` (`unchecked`: without wgpu's runtime checks;
/// `storage`: the record read from the storage buffer, not its uniform copy;
/// `chunkN`: N steps per dispatch), each on the default layout.
fn kernel_variants() -> Vec<(String, GpuOptions)> {
    let mut out = vec![(String::new(), GpuOptions::default())];
    for l in env_list("RIGFIT_BENCH_THREADS").unwrap_or_default() {
        let parsed = l.split_once('x').and_then(|(w, v)| {
            Some(Threads {
                workgroup: w.trim().parse().ok()?,
                vote_lanes: v.trim().parse().ok()?,
            })
        });
        match parsed {
            Some(t) if t != Threads::default() => out.push((
                format!("-wg{}v{}", t.workgroup, t.vote_lanes),
                GpuOptions {
                    threads: t,
                    ..GpuOptions::default()
                },
            )),
            Some(_) => {}
            None => panic!("RIGFIT_BENCH_THREADS: expected WORKGROUPxVOTE, found {l:?}"),
        }
    }
    for knob in env_list("RIGFIT_BENCH_KNOBS").unwrap_or_default() {
        let d = GpuOptions::default();
        let options = match knob.as_str() {
            "unchecked" => GpuOptions {
                runtime_checks: false,
                ..d
            },
            "storage" => GpuOptions {
                uniform_record: false,
                ..d
            },
            k => match k.strip_prefix("chunk").and_then(|n| n.parse().ok()) {
                Some(chunk_steps) => GpuOptions { chunk_steps, ..d },
                None => {
                    panic!("RIGFIT_BENCH_KNOBS: expected unchecked, storage or chunkN, found {k:?}")
                }
            },
        };
        out.push((format!("-{knob}"), options));
    }
    out
}

fn populations() -> Vec<usize> {
    match env_list("RIGFIT_BENCH_POPS") {
        Some(l) => l.iter().filter_map(|s| s.parse().ok()).collect(),
        None => POPULATIONS.to_vec(),
    }
}

fn print_table(evals: &[Row]) {
    let steps = steps(&problem());
    println!("\n{}", machine::machine_line());
    println!(
        "Shipped example, {} samples × {} substeps = {steps} RK4 steps per candidate",
        problem().experiments[0].measured.len(),
        problem().substeps
    );
    let pops = populations();
    let per_cpu = std::env::var_os("RIGFIT_BENCH_CPU_TIME").is_some();
    let head: String = pops.iter().map(|n| format!(" {n} |")).collect();
    let rule: String = pops.iter().map(|_| "---|").collect();
    println!("\n| evaluator |{head}\n|---|{rule}");
    for (name, make, _) in evals {
        let mut eval = make();
        let mut row = format!("| {name} |");
        for &n in &pops {
            let b = batch(n);
            eval.fitness(&b).unwrap();
            // The best of REPEATS timed evaluations: other work on the machine
            // only ever slows one down.
            let mut best = f64::INFINITY;
            let mut best_cpu = f64::INFINITY;
            for _ in 0..REPEATS {
                let t = Instant::now();
                let cpu = process_cpu_seconds();
                eval.fitness(&b).unwrap();
                best = best.min(t.elapsed().as_secs_f64());
                if let (Some(a), Some(z)) = (cpu, process_cpu_seconds()) {
                    best_cpu = best_cpu.min(z - a);
                }
            }
            let rate = (n * steps) as f64 / best;
            row.push_str(&format!(" {rate:.2e} |"));
            // Per CPU-second (lavapipe's threads are this process's).
            if per_cpu && best_cpu.is_finite() {
                row.push_str(&format!(" ({:.2e}/cpu-s) |", (n * steps) as f64 / best_cpu));
            }
        }
        println!("{row}");
    }
    println!(
        "\n(candidate-steps/s = candidates × RK4 steps / wall seconds of the fastest of {REPEATS} evaluations)\n"
    );
}

/// CPU seconds of one evaluation of `b` (wall seconds where the process CPU
/// clock is unavailable).
fn cpu_seconds(eval: &mut dyn Evaluator, b: &Batch) -> f64 {
    let t = Instant::now();
    let cpu = process_cpu_seconds();
    eval.fitness(b).unwrap();
    match (cpu, process_cpu_seconds()) {
        (Some(a), Some(z)) => z - a,
        _ => t.elapsed().as_secs_f64(),
    }
}

/// `RIGFIT_BENCH_PAIRS=N`: each selected row `X` that has a generic twin
/// `X-generic`, timed in N alternating rounds (X, then X-generic) at every
/// population. Prints the specialised ÷ generic ratio of candidate-steps per
/// CPU-second: the median over rounds, and the ratio of the two fastest
/// rounds. Alternating within one process keeps a slow spell of the machine
/// from falling on one row only, which a table of rows run one after the
/// other cannot.
fn print_pairs(evals: &[Row], rounds: usize) {
    println!(
        "\n| pair | population | specialised ÷ generic, median of {rounds} rounds | fastest ÷ fastest | generic, fastest (/cpu-s) | specialised, fastest (/cpu-s) |\n|---|---|---|---|---|---|"
    );
    let steps = steps(&problem());
    for (name, make, _) in evals.iter() {
        let twin = format!("{name}-generic");
        let Some((_, make_generic, _)) = evals.iter().find(|r| r.0 == twin) else {
            continue;
        };
        let (mut generic, mut special) = (make_generic(), make());
        for &n in &populations() {
            let b = batch(n);
            generic.fitness(&b).unwrap();
            special.fitness(&b).unwrap();
            let mut ratios = Vec::new();
            let (mut best_h, mut best_c) = (f64::INFINITY, f64::INFINITY);
            for _ in 0..rounds {
                let h = cpu_seconds(generic.as_mut(), &b);
                let c = cpu_seconds(special.as_mut(), &b);
                best_h = best_h.min(h);
                best_c = best_c.min(c);
                ratios.push(h / c);
            }
            ratios.sort_by(f64::total_cmp);
            let work = (n * steps) as f64;
            println!(
                "| {name} | {n} | {:.3} | {:.3} | {:.2e} | {:.2e} |",
                ratios[ratios.len() / 2],
                best_h / best_c,
                work / best_h,
                work / best_c
            );
        }
    }
}

/// `RIGFIT_BENCH_STATS=1`: instead of timing, the driver's statistics of the
/// fitness kernel each GPU row compiles (registers per thread and the like,
/// through `VK_KHR_pipeline_executable_properties`: benches/common/vk_stats.rs),
/// after one batch of the first population (where a row specialises, the
/// kernel specialised to it). A driver without the extension has none: every
/// kernel is still built, and the table says so.
fn print_stats(evals: &[Row]) {
    let stats = match vk_stats::VkStats::open(std::env::var("RIGFIT_ADAPTER").ok().as_deref()) {
        Ok(s) => s,
        Err(e) => panic!("kernel statistics: {e}"),
    };
    let n = populations().first().copied().unwrap_or(4096);
    println!(
        "\nDriver statistics of the fitness kernels (population {n}): {}",
        stats.about
    );
    let mut columns: Vec<String> = vec![];
    let mut rows: Vec<(&str, Vec<(String, String)>)> = vec![];
    for (name, _, gpu) in evals {
        let Some(g) = gpu else { continue };
        let mut e = GpuEvaluator::new(g.ctx.clone(), problem(), g.precision, g.options).unwrap();
        e.fitness(&batch(n)).unwrap();
        let (src, trusted) = e.fitness_source();
        let got = stats
            .statistics(&src, Kernel::Fitness, g.precision, trusted)
            .unwrap_or_else(|why| panic!("{name}: {why}"));
        let mut cells = vec![];
        for s in got {
            let key = format!("{}: {}", s.executable, s.name);
            if !columns.contains(&key) {
                columns.push(key.clone());
            }
            cells.push((key, s.value));
        }
        rows.push((name, cells));
    }
    if columns.is_empty() {
        println!("\n(every kernel built; the driver gives no statistics)\n");
        return;
    }
    let head: String = columns.iter().map(|c| format!(" {c} |")).collect();
    let rule: String = columns.iter().map(|_| "---|").collect();
    println!("\n| kernel |{head}\n|---|{rule}");
    for (name, cells) in rows {
        let row: String = columns
            .iter()
            .map(|c| {
                let v = cells.iter().find(|(k, _)| k == c).map(|(_, v)| v.as_str());
                format!(" {} |", v.unwrap_or("—"))
            })
            .collect();
        println!("| {name} |{row}");
    }
    println!();
}

fn main() {
    let mut evals = evaluators();
    if let Some(rows) = env_list("RIGFIT_BENCH_ROWS") {
        evals.retain(|(name, ..)| rows.iter().any(|r| name.contains(r.as_str())));
    }
    if let Some(rounds) = std::env::var("RIGFIT_BENCH_PAIRS")
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
    {
        print_pairs(&evals, rounds.max(1));
        return;
    }
    if std::env::var_os("RIGFIT_BENCH_STATS").is_some() {
        print_stats(&evals);
        return;
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
    for (name, make, _) in &evals {
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
