//! Seeded Gaussian noise, for synthetic records (`rigfit simulate --noise`).

use rand::Rng;

/// Standard normal deviate by Box–Muller from a seeded RNG.
pub fn gaussian(rng: &mut impl Rng) -> f64 {
    let u1: f64 = rng.random::<f64>().max(f64::MIN_POSITIVE);
    let u2: f64 = rng.random();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}
