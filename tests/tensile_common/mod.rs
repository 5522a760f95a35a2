//! The compiled tensile rig (`rigs/tensile4.json`) and canonical problems on
//! it shared by the tests: a synthetic "measured" history made by the f64
//! reference plus seeded Gaussian noise. The parameter vector's order and
//! reference values are the oracle's (`tests/oracle/tensile.rs`).
#![allow(
    dead_code,
    unused_imports,
    reason = "each test file uses a different subset"
)]

use std::sync::{Arc, OnceLock};

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use rigfit::base::Drive;
use rigfit::base::noise::gaussian;
use rigfit::eval::{ExperimentData, Problem, simulate_history};
use rigfit::model::compiled::CompiledRig;

pub use crate::oracle::tensile::{REFERENCE, ix};

/// The shipped `rigs/tensile4.json`, compiled once per test process.
pub fn tensile4() -> &'static Arc<CompiledRig> {
    static RIG: OnceLock<Arc<CompiledRig>> = OnceLock::new();
    RIG.get_or_init(|| {
        let desc = rigfit::rig::shipped("tensile4").expect("the shipped tensile4 rig");
        CompiledRig::shared(desc, "rigs/tensile4.json").expect("tensile4 compiles")
    })
}

/// Sample interval of the reference experiment (s): 1 MHz acquisition.
pub const REFERENCE_DT: f64 = 1.0e-6;
/// Samples in the reference experiment (3 ms).
pub const REFERENCE_SAMPLES: usize = 3000;
/// RK4 steps per sample in the reference experiment.
pub const REFERENCE_SUBSTEPS: usize = 2;

/// The reference tensile rig ([`REFERENCE`]) simulated over `samples`
/// samples of `dt` with `substeps`, plus Gaussian noise of standard deviation
/// `noise` (N), drawn from `seed`. The fit window is the whole record.
pub fn reference_experiment(
    samples: usize,
    dt: f64,
    substeps: usize,
    noise: f64,
    seed: u64,
) -> ExperimentData {
    reference_like(&REFERENCE, samples, dt, substeps, noise, seed)
}

/// Like [`reference_experiment`] for any tensile parameter vector.
pub fn reference_like(
    params: &[f64],
    samples: usize,
    dt: f64,
    substeps: usize,
    noise: f64,
    seed: u64,
) -> ExperimentData {
    let mut exp = ExperimentData {
        output: 0,
        name: "synthetic".into(),
        drive: Drive::Velocity,
        t_first: 0.0,
        dt,
        measured: vec![0.0; samples],
        window: 0..samples,
        weight: 1.0,
    };
    let problem = Problem {
        model: tensile4().clone(),
        experiments: vec![exp.clone()],
        substeps,
    };
    let h = simulate_history(&problem, 0, params, 0.0);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    exp.measured = h.outputs[0]
        .iter()
        .map(|f| f + noise * gaussian(&mut rng))
        .collect();
    exp
}

/// The reference problem: one reference experiment of [`REFERENCE_SAMPLES`]
/// samples with 20 N of noise.
pub fn reference_problem() -> Problem {
    Problem {
        model: tensile4().clone(),
        experiments: vec![reference_experiment(
            REFERENCE_SAMPLES,
            REFERENCE_DT,
            REFERENCE_SUBSTEPS,
            20.0,
            7,
        )],
        substeps: REFERENCE_SUBSTEPS,
    }
}
