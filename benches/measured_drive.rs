//! A rig driven by a measured column against the same rig driven by the same
//! signal written as a law: candidate-steps per second of each, on every
//! path, and their ratio from one run.
//!
//! The rig is `rigs/duffing_base.json` (one mass on a linear + cubic spring
//! and a damper, excited through its base): the smallest shipped rig, so the
//! drive's share of a step is the largest any rig has. One twin's base
//! accelerates as a chirp law, `9.81·sin(2π(5·t + 100·t²/2))` m/s²; the other
//! reads that chirp, sampled at the record's 10 kHz, from a column of its data
//! file (`"drive": {"force": {"column": "base_acceleration"}}`), the way a
//! shaker's measured acceleration drives a user's rig. Both fit the same
//! record (5 000 samples, two RK4 steps per sample) with the same free
//! parameters drawn from the same seed.
//!
//! `cargo bench --bench measured_drive` times each path's twins alternately
//! (`RIGFIT_BENCH_ROUNDS` rounds, default 7; `RIGFIT_BENCH_POPS`, default 4096;
//! `RIGFIT_BENCH_ROWS=gpu-f32,…` keeps the rows whose names contain one of the
//! words) and prints per path: the fastest rate of each twin and the median of
//! the rounds' analytic ÷ column ratios of candidate-steps per CPU-second of
//! the process (lavapipe's threads included), which moves least while other
//! work shares the cores.

#[path = "common/cpu_time.rs"]
mod cpu_time;
#[path = "common/machine.rs"]
mod machine;
#[path = "common/population.rs"]
mod population;
use std::f64::consts::PI;
use std::time::Instant;

use cpu_time::process_cpu_seconds;
use population::{env_list, seeded_batch, steps};
use rigfit::campaign::Campaign;
use rigfit::eval::{Batch, CpuEvaluator, Evaluator, Precision, Problem};
use rigfit::gpu::{GpuContext, GpuEvaluator, GpuOptions};
use serde_json::json;

const SAMPLES: usize = 5000;
const DT: f64 = 1e-4;
const AMPLITUDE: f64 = 9.81;
const F_START: f64 = 5.0;
const RATE: f64 = 100.0;

/// The chirp both twins are driven by (m/s²).
fn chirp(t: f64) -> f64 {
    AMPLITUDE * (2.0 * PI * (F_START * t + RATE * t * t / 2.0)).sin()
}

/// The record: time, a response to fit (any smooth signal: the rates do not
/// depend on the fit) and the chirp as the measured base acceleration.
fn write_record(dir: &std::path::Path) {
    let mut csv = String::from("t_s,x_m,base_acceleration\n");
    for i in 0..SAMPLES {
        let t = i as f64 * DT;
        let x = 1e-4 * (2.0 * PI * 20.0 * t).sin();
        csv.push_str(&format!("{t:.6},{x:.9e},{:.12e}\n", chirp(t)));
    }
    std::fs::write(dir.join("record.csv"), csv).expect("writes the bench's record");
}

/// The twin whose drive is the chirp law (`measured: false`) or the record's
/// column (`measured: true`).
fn campaign(dir: &std::path::Path, measured: bool) -> Campaign {
    let rig_file = concat!(env!("CARGO_MANIFEST_DIR"), "/rigs/duffing_base.json");
    let mut rig: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(rig_file).unwrap()).unwrap();
    let mut experiment = json!({
        "name": "chirp",
        "data": {"file": "record.csv", "time_column": "t_s", "force_column": "x_m"}
    });
    if measured {
        rig["drives"][0] = json!({"mode": "force", "law": {"type": "base_acceleration_table"}});
        experiment["drive"] = json!({"force": {"column": "base_acceleration"}});
    } else {
        rig["drives"][0]["law"] = json!({
            "type": "chirp", "quantity": "base_acceleration",
            "amplitude": AMPLITUDE, "f_start": F_START, "rate": RATE
        });
    }
    let text = json!({
        "name": if measured { "measured-column" } else { "analytic-chirp" },
        "rig": rig,
        "params": {
            "m": 1.0,
            "k": {"min": 1e4, "max": 1e5, "scale": "log"},
            "k3": {"min": 0.0, "max": 1e9},
            "c": {"min": 0.0, "max": 50.0}
        },
        "experiments": [experiment],
        "solver": {"substeps": 2, "backend": "cpu", "precision": "f64"},
        "search": {"population": 16, "generations": 1, "seed": 1},
        "output": "unused"
    });
    Campaign::from_str(&text.to_string(), dir, "measured_drive.json")
        .unwrap_or_else(|e| panic!("the bench's campaign: {e:#}"))
}

type Factory = Box<dyn Fn(Problem) -> Box<dyn Evaluator>>;

fn paths() -> Vec<(String, Factory)> {
    let mut v: Vec<(String, Factory)> = vec![
        (
            "cpu-all-threads".into(),
            Box::new(|p| Box::new(CpuEvaluator::new(p, 0))),
        ),
        (
            "cpu-all-threads-f32".into(),
            Box::new(|p| {
                let mut ev = CpuEvaluator::new(p, 0);
                ev.use_f32().expect("the C compiler builds the f32 lanes");
                Box::new(ev)
            }),
        ),
    ];
    match GpuContext::new() {
        Ok(ctx) => {
            let mut precisions = vec![("f32", Precision::F32)];
            if ctx.has_f64() {
                precisions.push(("f64", Precision::F64));
            }
            for (name, precision) in precisions {
                let c = ctx.clone();
                v.push((
                    format!("gpu-{name}"),
                    Box::new(move |p| {
                        Box::new(
                            GpuEvaluator::new(c.clone(), p, precision, GpuOptions::default())
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

/// (wall seconds, CPU seconds of the process) of one evaluation.
fn timed(eval: &mut dyn Evaluator, b: &Batch) -> (f64, f64) {
    let (t, c) = (Instant::now(), process_cpu_seconds());
    eval.fitness(b).unwrap();
    let wall = t.elapsed().as_secs_f64();
    let cpu = match (c, process_cpu_seconds()) {
        (Some(a), Some(z)) => z - a,
        _ => wall,
    };
    (wall, cpu)
}

fn main() {
    let dir = tempfile::tempdir().expect("a temporary folder for the bench's record");
    write_record(dir.path());
    let analytic = campaign(dir.path(), false);
    let measured = campaign(dir.path(), true);
    let steps = steps(&analytic.problem);
    assert_eq!(steps, population::steps(&measured.problem));
    let rounds: usize = std::env::var("RIGFIT_BENCH_ROUNDS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(7)
        .max(1);
    let pops: Vec<usize> = env_list("RIGFIT_BENCH_POPS")
        .map(|l| l.iter().filter_map(|s| s.parse().ok()).collect())
        .unwrap_or_else(|| vec![4096]);
    let mut paths = paths();
    if let Some(rows) = env_list("RIGFIT_BENCH_ROWS") {
        paths.retain(|(name, _)| rows.iter().any(|r| name.contains(r.as_str())));
    }
    println!("\n{}", machine::machine_line());
    println!(
        "rigs/duffing_base.json, {SAMPLES} samples × {} substeps = {steps} RK4 steps per candidate; \
         a chirp base acceleration as a law against the same chirp as a measured column",
        analytic.problem.substeps
    );
    println!(
        "\n| path | population | analytic drive (candidate-steps/s) | measured column (candidate-steps/s) | analytic ÷ column, per CPU-second (median of {rounds} rounds) |\n|---|---|---|---|---|"
    );
    for (name, make) in &paths {
        let mut law = make(analytic.problem.clone());
        let mut column = make(measured.problem.clone());
        for &n in &pops {
            let (ba, bm) = (seeded_batch(&analytic, n), seeded_batch(&measured, n));
            law.fitness(&ba).unwrap();
            column.fitness(&bm).unwrap();
            let (mut fast_a, mut fast_m) = (f64::INFINITY, f64::INFINITY);
            let mut ratios = Vec::with_capacity(rounds);
            for _ in 0..rounds {
                let (wa, ca) = timed(law.as_mut(), &ba);
                let (wm, cm) = timed(column.as_mut(), &bm);
                fast_a = fast_a.min(wa);
                fast_m = fast_m.min(wm);
                // Rates' ratio: the column's seconds over the law's.
                ratios.push(cm / ca);
            }
            ratios.sort_by(f64::total_cmp);
            let work = (n * steps) as f64;
            println!(
                "| {name} | {n} | {:.3e} | {:.3e} | {:.2} |",
                work / fast_a,
                work / fast_m,
                ratios[ratios.len() / 2]
            );
        }
    }
    println!(
        "\n(rates: candidates × RK4 steps over the fastest round's wall seconds; the ratio is the column's CPU seconds over the law's, per round)\n"
    );
}
