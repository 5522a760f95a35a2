//! Campaigns that fit several measured channels of one experiment at once
//! (`campaigns/quarter_car_channels_synthetic.json`: the sprung mass's
//! accelerometer and the strut's load cell; `bearing_2dof_channels_synthetic.json`:
//! the x and y sensors at each of two impacts): every channel is scored on
//! the GPU by kernels that score its own output, and the GPU's fitness and
//! histories equal the f64 CPU reference's as for one channel (1e-9 in f64,
//! the documented f32 tolerances), every output of a history in the rig's
//! own order whichever output the kernels scored; the scored outputs alone
//! (what the polish asks for) are those histories' scored output, bit for
//! bit.
mod oracle;
mod tensile_common;

mod gpu_common;
use gpu_common as common;

use std::path::Path;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rigfit::campaign::Campaign;
use rigfit::eval::{CpuEvaluator, DIVERGED, Evaluator, Precision, simulate_history};
use rigfit::gpu::{
    F32_HISTORY_TOLERANCE, F64_HISTORY_TOLERANCE, GpuByDrive, GpuOptions, kernel_groups,
};

fn campaign(name: &str) -> Campaign {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("campaigns")
        .join(name);
    Campaign::load(&path).unwrap()
}

/// `n` genomes drawn uniformly inside the genes' bounds (seeded).
fn genomes(c: &Campaign, n: usize) -> Vec<Vec<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    (0..n)
        .map(|_| {
            c.genes
                .iter()
                .map(|g| g.lower + (g.upper - g.lower) * rng.random::<f64>())
                .collect()
        })
        .collect()
}

fn check(name: &str) {
    let Some(ctx) = common::gpu() else { return };
    let c = campaign(name);
    let problem = c.problem.clone();
    // Each measured output has kernels of its own.
    let outputs: std::collections::BTreeSet<usize> =
        problem.experiments.iter().map(|x| x.output).collect();
    assert!(outputs.len() > 1, "{name}: channels on {outputs:?}");
    assert_eq!(kernel_groups(&problem).unwrap().len(), outputs.len());
    let batch = c.batch(&genomes(&c, 40));
    let cpu = CpuEvaluator::new(problem.clone(), 0)
        .fitness(&batch)
        .unwrap();
    let mut precisions = vec![(Precision::F32, 1e-3, F32_HISTORY_TOLERANCE)];
    if ctx.has_f64() {
        precisions.push((Precision::F64, 1e-9, F64_HISTORY_TOLERANCE));
    }
    for (precision, fit_tol, hist_tol) in precisions {
        let mut gpu = GpuByDrive::new(
            ctx.clone(),
            problem.clone(),
            precision,
            GpuOptions::default(),
        )
        .unwrap();
        let g = gpu.fitness(&batch).unwrap();
        assert_eq!(g.diverged, cpu.diverged, "{name} {precision:?}");
        let mut worst = 0.0_f64;
        for i in 0..batch.candidates {
            for e in 0..problem.experiments.len() {
                let (a, b) = (g.get(i, e), cpu.get(i, e));
                if b >= DIVERGED {
                    continue;
                }
                let err = (a - b).abs() / b.abs().max(1e-3);
                assert!(
                    err <= fit_tol,
                    "{name} {precision:?} candidate {i} run {e}: {a} vs {b}"
                );
                worst = worst.max(err);
            }
        }
        // Histories: every output, in the rig's order.
        let which = [0, 3, 11];
        let hist = gpu.histories(&batch, &which).unwrap();
        let mut worst_h = 0.0_f64;
        for (h, &i) in hist.iter().zip(&which) {
            for (e, he) in h.iter().enumerate() {
                let want =
                    simulate_history(&problem, e, batch.params_of(e, i), batch.offsets[e][i]);
                assert_eq!(he.outputs.len(), want.outputs.len());
                for (o, (got, want)) in he.outputs.iter().zip(&want.outputs).enumerate() {
                    let scale = want.iter().fold(f64::MIN_POSITIVE, |m, f| m.max(f.abs()));
                    for (k, (x, y)) in got.iter().zip(want).enumerate() {
                        let d = (x - y).abs() / scale;
                        assert!(
                            d <= hist_tol,
                            "{name} {precision:?} candidate {i} run {e} output {o} sample {k}: {x} vs {y}"
                        );
                        worst_h = worst_h.max(d);
                    }
                }
            }
        }
        // The scored output alone: the same kernel's bits.
        let scored = gpu.scored_outputs(&batch, &which).unwrap();
        assert_eq!(scored.len(), which.len());
        for (j, (s, h)) in scored.iter().zip(&hist).enumerate() {
            for (e, (se, he)) in s.iter().zip(h).enumerate() {
                let want = &he.outputs[problem.experiments[e].output];
                assert_eq!(
                    se.len(),
                    want.len(),
                    "{name} {precision:?} slot {j} run {e}"
                );
                for (k, (x, y)) in se.iter().zip(want).enumerate() {
                    assert_eq!(
                        x.to_bits(),
                        y.to_bits(),
                        "{name} {precision:?} slot {j} run {e} sample {k}: {x} vs {y}"
                    );
                }
            }
        }
        eprintln!(
            "{name} {precision:?}: fitness within {worst:.2e} (relative), histories within {worst_h:.2e} of each output's largest value"
        );
    }
}

#[test]
fn quarter_car_channels_match_the_cpu() {
    check("quarter_car_channels_synthetic.json");
}

#[test]
fn bearing_channels_match_the_cpu() {
    check("bearing_2dof_channels_synthetic.json");
}
