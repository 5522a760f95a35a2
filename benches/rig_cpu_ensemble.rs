//! CPU throughput of the compiled rig (candidate-steps per second, all
//! cores): the compiled `rigs/tensile4.json` one run at a time, and the compiled rig's lane-batched ensemble on the
//! fitness path (output 0 of a group at each sample, `simulate_measured`) in
//! f64 and f32, a call per run and sample (`simulate_many`, output 0 alone or
//! every output and the full state), and interpreted instead of native, on
//! the shipped example's grid. `cargo bench --bench rig_cpu_ensemble`
//! (`RIGFIT_BENCH_POPULATION`, default 4096; `RIGFIT_BENCH_ROWS=scalar,lanes`
//! picks rows from `scalar`, `lanes`, `lanes-f32`, `lanes-each`,
//! `lanes-full`, `interp`). Each rate is printed per second of wall time and per
//! CPU-second of the process (on a shared machine the second is the steadier).

use std::ops::ControlFlow;
use std::time::Instant;

#[path = "common/cpu_time.rs"]
mod cpu_time;
#[path = "common/machine.rs"]
mod machine;
use cpu_time::process_cpu_seconds;
use rayon::prelude::*;
use rigfit::base::SampleGrid;
use rigfit::base::{Drive, Report};
use rigfit::model::compiled::CompiledRig;

#[path = "../tests/oracle/mod.rs"]
mod oracle;
use oracle::tensile::{REFERENCE, ix};

fn population() -> Vec<Vec<f64>> {
    let n: usize = std::env::var("RIGFIT_BENCH_POPULATION")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(4096);
    (0..n)
        .map(|i| {
            let mut p = REFERENCE.to_vec();
            let f = 1.0 + 0.2 * (i as f64 / n as f64);
            p[ix::K1] *= f;
            p[ix::C4] *= f;
            p
        })
        .collect()
}

fn rows() -> Vec<String> {
    std::env::var("RIGFIT_BENCH_ROWS")
        .map(|v| v.split(',').map(|s| s.trim().to_string()).collect())
        .unwrap_or_else(|_| vec!["scalar".into(), "lanes".into()])
}

/// Best of three: (candidate-steps per wall second, per CPU-second).
fn measure(name: &str, runs: usize, steps: usize, f: impl Fn()) -> (f64, f64) {
    let (mut best, mut best_cpu) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..3 {
        let (t, c) = (Instant::now(), process_cpu_seconds());
        f();
        best = best.min(t.elapsed().as_secs_f64());
        if let (Some(a), Some(z)) = (c, process_cpu_seconds()) {
            best_cpu = best_cpu.min(z - a);
        }
    }
    let work = (runs * steps) as f64;
    println!(
        "{name:<40} {:.3e} candidate-steps/s ({best:.3} s), {:.3e} per CPU-second",
        work / best,
        work / best_cpu
    );
    (work / best, work / best_cpu)
}

fn main() {
    let ps = population();
    // `RIGFIT_BENCH_SUBSTEPS` > 1 keeps the steps and reports every k-th.
    let substeps: usize = std::env::var("RIGFIT_BENCH_SUBSTEPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-6 * substeps as f64,
        samples: 2500 / substeps + 1,
        substeps,
    };
    let steps = grid.total_steps();
    let rig = CompiledRig::new(rigfit::rig::shipped("tensile4").unwrap(), "tensile4").unwrap();
    let drive = Drive::Velocity;
    let one = |m: &CompiledRig, p: &[f64]| {
        let mut s = 0.0;
        m.simulate(p, &drive, &grid, &mut |x| {
            s += x.outputs[0];
            ControlFlow::Continue(())
        });
        s
    };
    println!("{}", machine::machine_line());
    println!(
        "population {}, {steps} RK4 steps per run, {} threads",
        ps.len(),
        rayon::current_num_threads()
    );
    let rows = rows();
    let want = |r: &str| rows.iter().any(|x| x == r);
    let mut rates = vec![];
    if want("scalar") {
        let r = measure("compiled tensile4, scalar tape", ps.len(), steps, || {
            let _: f64 = ps.par_iter().map(|p| one(&rig, p)).sum();
        });
        rates.push(("scalar tape", r));
    }
    // The fitness path: output 0 of each group at once, f64 or f32.
    for (row, f32, name, short) in [
        (
            "lanes",
            false,
            "compiled tensile4, lane ensemble",
            "lanes f64",
        ),
        (
            "lanes-f32",
            true,
            "compiled tensile4, lanes, f32",
            "lanes f32",
        ),
    ] {
        if !want(row) {
            continue;
        }
        let r = measure(name, ps.len(), steps, || {
            let _: f64 = ps
                .par_chunks(rigfit::compile::LANES)
                .map(|c| {
                    let refs: Vec<&[f64]> = c.iter().map(|p| p.as_slice()).collect();
                    let mut s = 0.0;
                    let ran_f32 = rig.simulate_measured(&refs, &drive, &grid, f32, &mut |x, _| {
                        s += x.values.iter().sum::<f64>();
                    });
                    assert_eq!(ran_f32, f32, "the C compiler builds the f32 lanes");
                    s
                })
                .sum();
        });
        rates.push((short, r));
    }
    // Each run at each sample (`simulate_many`): output 0 alone, or everything.
    for (row, report, name, short) in [
        (
            "lanes-each",
            Report::Measured,
            "compiled tensile4, lanes, a call per run",
            "lanes, a call per run",
        ),
        (
            "lanes-full",
            Report::Full,
            "compiled tensile4, lanes, full report",
            "lanes, full report",
        ),
    ] {
        if !want(row) {
            continue;
        }
        let r = measure(name, ps.len(), steps, || {
            let _: f64 = ps
                .par_chunks(rigfit::compile::LANES)
                .map(|c| {
                    let refs: Vec<&[f64]> = c.iter().map(|p| p.as_slice()).collect();
                    let mut s = 0.0;
                    rig.simulate_many(&refs, &drive, &grid, report, &mut |_, x| {
                        s += x.outputs[0];
                        ControlFlow::Continue(())
                    });
                    s
                })
                .sum();
        });
        rates.push((short, r));
    }
    if want("interp") {
        // The lane ensemble interpreting its code (as where no C compiler
        // works), on the fitness path.
        let lowered = rigfit::compile::lower(&rig.desc, "tensile4").unwrap();
        let prog = &lowered.programs[0];
        let tape = rigfit::compile::Tape::new(prog);
        let code = rigfit::compile::LaneCode::new(prog, &tape);
        let r = measure(
            "compiled tensile4, lanes interpreted",
            ps.len(),
            steps,
            || {
                let _: f64 = ps
                    .par_chunks(rigfit::compile::LANES)
                    .map(|c| {
                        let refs: Vec<&[f64]> = c.iter().map(|p| p.as_slice()).collect();
                        let mut s = 0.0;
                        rigfit::compile::LaneRunner::new(prog, &tape, &code, &refs, None)
                            .run_measured(&grid, &mut |x, _| s += x.values.iter().sum::<f64>());
                        s
                    })
                    .sum();
            },
        );
        rates.push(("lanes interpreted", r));
    }
    for (i, (a, ra)) in rates.iter().enumerate() {
        for (b, rb) in &rates[i + 1..] {
            println!(
                "{b} / {a}: {:.2}× per wall second, {:.2}× per CPU-second",
                rb.0 / ra.0,
                rb.1 / ra.1
            );
        }
    }
}
