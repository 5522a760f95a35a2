//! Canonical problems shared by the tests, the benchmarks and the shipped example:
//! the reference tensile rig and a synthetic "measured" history made by the f64
//! reference plus seeded Gaussian noise.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::eval::{ExperimentData, Problem, simulate_history};
use crate::model::{Drive, tensile};

/// Sample interval of the reference experiment (s): 1 MHz acquisition.
pub const REFERENCE_DT: f64 = 1.0e-6;
/// Samples in the reference experiment (3 ms).
pub const REFERENCE_SAMPLES: usize = 3000;
/// RK4 steps per sample in the reference experiment.
pub const REFERENCE_SUBSTEPS: usize = 2;

/// Standard normal deviate by Box–Muller from a seeded RNG.
pub fn gaussian(rng: &mut impl Rng) -> f64 {
    let u1: f64 = rng.random::<f64>().max(f64::MIN_POSITIVE);
    let u2: f64 = rng.random();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// The reference tensile rig ([`tensile::REFERENCE`]) simulated over `samples`
/// samples of `dt` with `substeps`, plus Gaussian noise of standard deviation
/// `noise` (N), drawn from `seed`. The fit window is the whole record.
pub fn reference_experiment(
    samples: usize,
    dt: f64,
    substeps: usize,
    noise: f64,
    seed: u64,
) -> ExperimentData {
    reference_like(&tensile::REFERENCE, samples, dt, substeps, noise, seed)
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
        name: "synthetic".into(),
        drive: Drive::Velocity,
        t_first: 0.0,
        dt,
        force: vec![0.0; samples],
        window: 0..samples,
        weight: 1.0,
    };
    let problem = Problem {
        model: &tensile::TENSILE4,
        experiments: vec![exp.clone()],
        substeps,
    };
    let h = simulate_history(&problem, 0, params, 0.0);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    exp.force = h.outputs[0]
        .iter()
        .map(|f| f + noise * gaussian(&mut rng))
        .collect();
    exp
}

/// The reference problem: one reference experiment of [`REFERENCE_SAMPLES`]
/// samples with 20 N of noise.
pub fn reference_problem() -> Problem {
    Problem {
        model: &tensile::TENSILE4,
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
