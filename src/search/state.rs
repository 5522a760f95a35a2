//! The complete, resumable state of a search between two generations.

use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::report::GenerationReport;

/// Everything needed to continue a search exactly where it stopped: after a
/// generation was evaluated and reported, before the next one is asked for.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SearchState {
    /// The method's own state ([`super::Solver::state`]: the GA's population
    /// and costs, CMA-ES's mean, step and covariance).
    pub solver: Value,
    /// The search's only RNG, positioned after the last draw.
    #[serde(with = "rng_serde")]
    pub rng: ChaCha8Rng,
    /// Index of the last evaluated generation.
    pub generation: usize,
    /// Best genome so far (scale space).
    pub best_genome: Vec<f64>,
    /// Its cost.
    pub best_cost: f64,
    /// Generations since the best last improved.
    pub stall: usize,
    /// Cost evaluations so far.
    pub evaluations: u64,
    /// Wall time spent so far, across resumes (s).
    pub elapsed_s: f64,
    /// Reports of all generations so far.
    pub history: Vec<GenerationReport>,
    /// Generations where more than a quarter of the candidates diverged.
    pub divergence_alerts: Vec<usize>,
}

impl SearchState {
    /// A search before its first batch: the RNG seeded, nothing scored.
    pub fn start(seed: u64) -> Self {
        use rand::SeedableRng;
        Self {
            solver: Value::Null,
            rng: ChaCha8Rng::seed_from_u64(seed),
            generation: 0,
            best_genome: Vec::new(),
            best_cost: f64::INFINITY,
            stall: 0,
            evaluations: 0,
            elapsed_s: 0.0,
            history: Vec::new(),
            divergence_alerts: Vec::new(),
        }
    }
}

/// ChaCha8Rng as (seed, stream, word position). The word position is a `u128`,
/// stored as a decimal string because JSON numbers cannot hold it.
mod rng_serde {
    use rand_chacha::ChaCha8Rng;
    use rand_chacha::rand_core::SeedableRng;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    #[derive(Serialize, Deserialize)]
    struct RngState {
        seed: String,
        stream: u64,
        word_pos: String,
    }

    pub fn serialize<S: Serializer>(rng: &ChaCha8Rng, s: S) -> Result<S::Ok, S::Error> {
        let seed = rng.get_seed().iter().map(|b| format!("{b:02x}")).collect();
        RngState {
            seed,
            stream: rng.get_stream(),
            word_pos: rng.get_word_pos().to_string(),
        }
        .serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<ChaCha8Rng, D::Error> {
        use serde::de::Error;
        let st = RngState::deserialize(d)?;
        if st.seed.len() != 64 || !st.seed.is_ascii() {
            return Err(D::Error::custom("rng seed must be 64 hex digits"));
        }
        let mut seed = [0u8; 32];
        for (i, b) in seed.iter_mut().enumerate() {
            *b = u8::from_str_radix(&st.seed[2 * i..2 * i + 2], 16).map_err(D::Error::custom)?;
        }
        let word_pos: u128 = st.word_pos.parse().map_err(D::Error::custom)?;
        let mut rng = ChaCha8Rng::from_seed(seed);
        rng.set_stream(st.stream);
        rng.set_word_pos(word_pos);
        Ok(rng)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn rng_round_trips_mid_block() {
        let mut rng = ChaCha8Rng::seed_from_u64(42);
        for _ in 0..7 {
            let _: u32 = rng.random();
        }
        let state = SearchState {
            solver: Value::Null,
            rng: rng.clone(),
            generation: 0,
            best_genome: vec![],
            best_cost: 0.0,
            stall: 0,
            evaluations: 0,
            elapsed_s: 0.0,
            history: vec![],
            divergence_alerts: vec![],
        };
        let json = serde_json::to_string(&state).unwrap();
        let mut back: SearchState = serde_json::from_str(&json).unwrap();
        for _ in 0..100 {
            assert_eq!(rng.random::<u64>(), back.rng.random::<u64>());
        }
    }
}
