//! What the evaluator benches share: a campaign's candidates drawn from a
//! fixed seed, the RK4 steps one candidate takes, and the comma-separated
//! lists of the `RIGFIT_BENCH_*` variables.

use rigfit::campaign::Campaign;
use rigfit::eval::{Batch, Problem};
use rigfit::job::gene_specs;

/// `n` candidates of `c` with every free parameter uniform over its bounds (in
/// the logarithm for log-scale genes), from a fixed xorshift seed.
pub fn seeded_batch(c: &Campaign, n: usize) -> Batch {
    let mut s = 0x2545_f491_4f6c_dd1d_u64;
    let mut uniform = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let genes = gene_specs(c);
    let genomes: Vec<Vec<f64>> = (0..n)
        .map(|_| genes.iter().map(|g| g.at_fraction(uniform())).collect())
        .collect();
    c.batch(&genomes)
}

/// RK4 steps one candidate takes, over every experiment.
pub fn steps(problem: &Problem) -> usize {
    problem
        .experiments
        .iter()
        .map(|e| e.grid(0.0, problem.substeps).total_steps())
        .sum()
}

/// The comma-separated items of environment variable `name`, if set (empty
/// items left out: set to "", an empty list).
pub fn env_list(name: &str) -> Option<Vec<String>> {
    std::env::var(name).ok().map(|v| {
        v.split(',')
            .map(|s| s.trim().to_string())
            .filter(|s| !s.is_empty())
            .collect()
    })
}
