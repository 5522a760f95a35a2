//! Seeded Gaussian noise, for synthetic records (`rigfit simulate --noise`).

use rand::Rng;

use super::stats::median;

/// Standard normal deviate by Box–Muller from a seeded RNG.
pub fn gaussian(rng: &mut impl Rng) -> f64 {
    let u1: f64 = rng.random::<f64>().max(f64::MIN_POSITIVE);
    let u2: f64 = rng.random();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// The standard deviation of white noise on a smooth record, estimated from
/// the record itself: the third difference `y[i+3] − 3y[i+2] + 3y[i+1] − y[i]`
/// of white noise of deviation σ has deviation `σ·√20`, while that of a signal
/// sampled many times per period is small; the median absolute deviation
/// (× 1.4826, the normal's) keeps the few samples around a kink (a fracture,
/// a contact) from counting. Where the signal's own third difference is not
/// small against the noise's (few samples per period, or very little noise)
/// the estimate is too large: an upper bound. `None` under 16 samples.
pub fn noise_sigma(values: &[f64]) -> Option<f64> {
    if values.len() < 16 {
        return None;
    }
    let mut d3: Vec<f64> = values
        .windows(4)
        .map(|w| w[3] - 3.0 * w[2] + 3.0 * w[1] - w[0])
        .filter(|d| d.is_finite())
        .collect();
    if d3.len() < 13 {
        return None;
    }
    let m = median(&mut d3);
    let mut dev: Vec<f64> = d3.iter().map(|d| (d - m).abs()).collect();
    Some(1.482_602_218_505_602 * median(&mut dev) / 20f64.sqrt())
}

#[cfg(test)]
mod tests {
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    use super::*;

    #[test]
    fn the_noise_on_a_ringing_record_is_found_within_ten_percent() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for sigma in [0.001, 1.0, 20.0] {
            // A decaying 5 kHz ring at 1 MHz with a jump half way, plus noise.
            let y: Vec<f64> = (0..4000)
                .map(|k| {
                    let t = k as f64 * 1e-6;
                    let ring = 5e3 * (-t / 1e-3).exp() * (std::f64::consts::TAU * 5.2e3 * t).sin();
                    let jump = if k > 2000 { 3e3 } else { 0.0 };
                    ring + jump + sigma * gaussian(&mut rng)
                })
                .collect();
            let s = noise_sigma(&y).unwrap();
            if sigma < 0.01 {
                // The ring's own third difference (about 0.2 at its start)
                // outweighs this noise: an upper bound.
                assert!(s > sigma, "{s} for {sigma}");
            } else {
                assert!((s / sigma - 1.0).abs() < 0.1, "{s} for {sigma}");
            }
        }
        assert_eq!(noise_sigma(&[1.0; 10]), None);
    }
}
