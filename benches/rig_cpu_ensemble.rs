//! CPU throughput of the compiled rig (candidate-steps per second, f64, all
//! cores): the hand-written tensile model, the compiled `rigs/tensile4.json`
//! one run at a time, and the compiled rig's lane-batched ensemble, on the
//! shipped example's grid. `cargo bench --bench rig_cpu_ensemble`
//! (`RIGFIT_BENCH_POPULATION`, default 4096).

use std::ops::ControlFlow;
use std::time::Instant;

use rayon::prelude::*;
use rigfit::integrate::SampleGrid;
use rigfit::model::compiled::CompiledRig;
use rigfit::model::{Drive, RigModel, tensile};

fn population() -> Vec<Vec<f64>> {
    let n: usize = std::env::var("RIGFIT_BENCH_POPULATION")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(4096);
    (0..n)
        .map(|i| {
            let mut p = tensile::REFERENCE.to_vec();
            let f = 1.0 + 0.2 * (i as f64 / n as f64);
            p[tensile::ix::K1] *= f;
            p[tensile::ix::C4] *= f;
            p
        })
        .collect()
}

fn measure(name: &str, runs: usize, steps: usize, f: impl Fn()) -> f64 {
    let mut best = f64::INFINITY;
    for _ in 0..3 {
        let t = Instant::now();
        f();
        best = best.min(t.elapsed().as_secs_f64());
    }
    let rate = (runs * steps) as f64 / best;
    println!("{name:<40} {rate:.3e} candidate-steps/s ({best:.3} s)");
    rate
}

fn main() {
    let ps = population();
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-6,
        samples: 2501,
        substeps: 1,
    };
    let steps = grid.total_steps();
    let rig = CompiledRig::new(rigfit::rig::shipped("tensile4").unwrap(), "tensile4").unwrap();
    let drive = Drive::Velocity;
    let one = |m: &dyn RigModel, p: &[f64]| {
        let mut s = 0.0;
        m.simulate(p, &drive, &grid, &mut |x| {
            s += x.outputs[0];
            ControlFlow::Continue(())
        });
        s
    };
    println!(
        "population {}, {steps} RK4 steps per run, {} threads",
        ps.len(),
        rayon::current_num_threads()
    );
    let hand = measure("hand-written tensile4, scalar", ps.len(), steps, || {
        let _: f64 = ps.par_iter().map(|p| one(&tensile::TENSILE4, p)).sum();
    });
    let scalar = measure("compiled tensile4, scalar tape", ps.len(), steps, || {
        let _: f64 = ps.par_iter().map(|p| one(&rig, p)).sum();
    });
    let lanes = measure("compiled tensile4, lane ensemble", ps.len(), steps, || {
        let _: f64 = ps
            .par_chunks(rigfit::compile::LANES)
            .map(|c| {
                let refs: Vec<&[f64]> = c.iter().map(|p| p.as_slice()).collect();
                let mut s = 0.0;
                rig.simulate_many(&refs, &drive, &grid, &mut |_, x| {
                    s += x.outputs[0];
                    ControlFlow::Continue(())
                });
                s
            })
            .sum();
    });
    println!(
        "lane ensemble / scalar tape: {:.2}×; lane ensemble / hand-written: {:.2}×",
        lanes / scalar,
        lanes / hand
    );
}
