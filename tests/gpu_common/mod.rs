//! Helpers shared by the GPU tests: getting a device (fail or skip loudly), and
//! seeded candidate batches spread around the reference rig.
#![allow(dead_code, reason = "each test file uses a different subset")]

use std::io::Write;
use std::sync::Arc;

use crate::tensile_common::{REFERENCE, ix};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rigfit::base::Drive;
use rigfit::eval::Precision;
use rigfit::eval::{Batch, ExperimentData, Problem, simulate_history};
use rigfit::gpu::{GpuContext, GpuEvaluator, GpuOptions, gpu_required};
use rigfit::model::CompiledRig;

/// The default GPU context; `None` (with a loud message) when there is no
/// adapter, or a panic when `RIGFIT_REQUIRE_GPU=1`.
pub fn gpu() -> Option<GpuContext> {
    match GpuContext::new() {
        Ok(ctx) => Some(ctx),
        Err(e) if gpu_required() => panic!("RIGFIT_REQUIRE_GPU is set but no GPU is usable: {e}"),
        Err(e) => {
            // Straight to stderr: the test harness captures eprintln!.
            let _ = writeln!(
                std::io::stderr(),
                "\n==================== GPU TEST SKIPPED ====================\n\
                 {e}\nSet RIGFIT_REQUIRE_GPU=1 to make this a failure.\n\
                 ==========================================================\n"
            );
            None
        }
    }
}

/// The shipped campaign files (`campaigns/*.json`), sorted.
pub fn campaign_files() -> Vec<std::path::PathBuf> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    files
}

/// A GPU evaluator of `problem` on `ctx` with the default options.
pub fn evaluator(ctx: &GpuContext, problem: &Problem, precision: Precision) -> GpuEvaluator {
    GpuEvaluator::new(
        ctx.clone(),
        problem.clone(),
        precision,
        GpuOptions::default(),
    )
    .unwrap()
}

/// Log-uniform factor in `[1/spread, spread]`.
fn factor(rng: &mut impl Rng, spread: f64) -> f64 {
    spread.powf(rng.random_range(-1.0..=1.0))
}

/// `n` candidates around the reference values: stiffnesses, dampings and masses
/// ×/÷ 3; fracture elongations from far below to far above what the run
/// reaches (some break, some don't); every 16th with a gap so large that the
/// slack adapter never engages; every 16th (offset 8) unstable (huge stiffness,
/// tiny mass for the step).
pub fn spread_params(n: usize, seed: u64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = Vec::with_capacity(n * REFERENCE.len());
    for i in 0..n {
        let mut p = REFERENCE;
        for j in [
            ix::M1,
            ix::M2,
            ix::M3,
            ix::K1,
            ix::K3,
            ix::K_LIN,
            ix::K4_LIN,
        ] {
            p[j] *= factor(&mut rng, 3.0);
        }
        for j in [ix::C1, ix::C1_POST, ix::C4, ix::SLACK_A] {
            p[j] *= factor(&mut rng, 3.0);
        }
        p[ix::SLACK_B] *= factor(&mut rng, 1.5);
        p[ix::E_FRACTURE] = 5e-4 * factor(&mut rng, 10.0);
        p[ix::GAP] *= factor(&mut rng, 2.0);
        if i % 16 == 3 {
            p[ix::GAP] = 1.0;
        }
        if i % 16 == 8 {
            p[ix::K1] *= 1e3;
            p[ix::M1] *= 1e-3;
        }
        out.extend_from_slice(&p);
    }
    out
}

/// A batch of `params` (candidate-major) for a one-experiment problem, with zero
/// clock offsets.
pub fn batch_of(problem: &Problem, params: Vec<f64>) -> Batch {
    let n = params.len() / REFERENCE.len();
    assert_eq!(problem.experiments.len(), 1);
    Batch {
        candidates: n,
        params: vec![params],
        offsets: vec![vec![0.0; n]],
    }
}

/// An experiment of `model` whose measured force is the model's own history
/// at `params` (exactly fitted there), over `samples` samples `dt` apart from
/// `t_first`, fitted over all of them.
pub fn self_measured(
    model: &Arc<CompiledRig>,
    params: &[f64],
    name: &str,
    drive: Drive,
    (samples, dt, t_first): (usize, f64, f64),
) -> ExperimentData {
    let mut exp = ExperimentData {
        output: 0,
        name: name.into(),
        drive,
        t_first,
        dt,
        measured: vec![0.0; samples],
        window: 0..samples,
        weight: 1.0,
    };
    let one = Problem {
        model: model.clone(),
        experiments: vec![exp.clone()],
        substeps: 2,
    };
    exp.measured = simulate_history(&one, 0, params, 0.0).outputs[0].clone();
    exp
}
