//! GA operators on scale-space coordinates with bounds `[lo, hi]`.
//!
//! Bounded simulated-binary crossover and polynomial mutation follow Deb & Agrawal
//! (1995) and Deb & Goyal (1996) in the bounded form used by NSGA-II: the spread
//! distribution is truncated at the bounds, so children land inside them without
//! piling up on the edges. Every result is still clamped, so rounding cannot leave
//! the range. All randomness comes from the caller's RNG, in a fixed draw order.

use rand::Rng;

use super::genes::clamp_into;

/// Differences below this are treated as "parents equal" in SBX.
const SBX_EPS: f64 = 1.0e-14;

/// Bounded SBX on one coordinate: two children from parents `y1`, `y2`.
///
/// Draws exactly two uniforms (spread and side swap) unless the parents are
/// equal or the range is empty, in which case it draws none.
pub fn sbx_pair<R: Rng + ?Sized>(
    rng: &mut R,
    y1: f64,
    y2: f64,
    lo: f64,
    hi: f64,
    eta: f64,
) -> (f64, f64) {
    if (y1 - y2).abs() < SBX_EPS || hi <= lo {
        return (clamp_into(y1, lo, hi), clamp_into(y2, lo, hi));
    }
    let (a, b) = if y1 < y2 { (y1, y2) } else { (y2, y1) };
    let u: f64 = rng.random();
    let exp = 1.0 / (eta + 1.0);
    let spread = |beta: f64| {
        let alpha = 2.0 - beta.powf(-(eta + 1.0));
        if u <= 1.0 / alpha {
            (u * alpha).powf(exp)
        } else {
            (1.0 / (2.0 - u * alpha)).powf(exp)
        }
    };
    let q1 = spread(1.0 + 2.0 * (a - lo) / (b - a));
    let q2 = spread(1.0 + 2.0 * (hi - b) / (b - a));
    let c1 = clamp_into(0.5 * ((a + b) - q1 * (b - a)), lo, hi);
    let c2 = clamp_into(0.5 * ((a + b) + q2 * (b - a)), lo, hi);
    if rng.random::<f64>() < 0.5 {
        (c2, c1)
    } else {
        (c1, c2)
    }
}

/// SBX over whole genomes: each coordinate is crossed with probability ½
/// (NSGA-II convention), otherwise copied.
pub fn sbx<R: Rng + ?Sized>(
    rng: &mut R,
    p1: &[f64],
    p2: &[f64],
    bounds: &[(f64, f64)],
    eta: f64,
) -> (Vec<f64>, Vec<f64>) {
    let mut c1 = p1.to_vec();
    let mut c2 = p2.to_vec();
    for (j, &(lo, hi)) in bounds.iter().enumerate() {
        if rng.random::<f64>() < 0.5 {
            let (a, b) = sbx_pair(rng, p1[j], p2[j], lo, hi, eta);
            c1[j] = a;
            c2[j] = b;
        }
    }
    (c1, c2)
}

/// Bounded polynomial mutation of one coordinate (always draws one uniform).
pub fn polynomial_mutation<R: Rng + ?Sized>(
    rng: &mut R,
    y: f64,
    lo: f64,
    hi: f64,
    eta: f64,
) -> f64 {
    let u: f64 = rng.random();
    let width = hi - lo;
    if width <= 0.0 {
        return lo;
    }
    let y = clamp_into(y, lo, hi);
    let d1 = (y - lo) / width;
    let d2 = (hi - y) / width;
    let pow = 1.0 / (eta + 1.0);
    let dq = if u < 0.5 {
        let v = 2.0 * u + (1.0 - 2.0 * u) * (1.0 - d1).powf(eta + 1.0);
        v.powf(pow) - 1.0
    } else {
        let v = 2.0 * (1.0 - u) + 2.0 * (u - 0.5) * (1.0 - d2).powf(eta + 1.0);
        1.0 - v.powf(pow)
    };
    clamp_into(y + dq * width, lo, hi)
}

/// Mutates each coordinate of `genome` with probability `probability`.
pub fn mutate<R: Rng + ?Sized>(
    rng: &mut R,
    genome: &mut [f64],
    bounds: &[(f64, f64)],
    eta: f64,
    probability: f64,
) {
    for (x, &(lo, hi)) in genome.iter_mut().zip(bounds) {
        if rng.random::<f64>() < probability {
            *x = polynomial_mutation(rng, *x, lo, hi, eta);
        }
    }
}

/// Tournament selection: the best of `size` uniformly drawn indices (with
/// replacement). `rank[i]` is candidate `i`'s position in the sorted population,
/// so ties in cost are broken the same way everywhere.
pub fn tournament<R: Rng + ?Sized>(rng: &mut R, rank: &[usize], size: usize) -> usize {
    let n = rank.len();
    let mut best = rng.random_range(0..n);
    for _ in 1..size {
        let c = rng.random_range(0..n);
        if rank[c] < rank[best] {
            best = c;
        }
    }
    best
}

/// `n` points by Latin hypercube: each coordinate's range is cut into `n` equal
/// strata and every stratum is used exactly once, at a uniform point inside it.
pub fn latin_hypercube<R: Rng + ?Sized>(
    rng: &mut R,
    n: usize,
    bounds: &[(f64, f64)],
) -> Vec<Vec<f64>> {
    let mut pop = vec![Vec::with_capacity(bounds.len()); n];
    for &(lo, hi) in bounds {
        let mut strata: Vec<usize> = (0..n).collect();
        // Fisher–Yates with the caller's RNG (draw order fixed).
        for i in (1..n).rev() {
            strata.swap(i, rng.random_range(0..=i));
        }
        for (genome, s) in pop.iter_mut().zip(strata) {
            let t = (s as f64 + rng.random::<f64>()) / n as f64;
            genome.push(clamp_into(lo + t * (hi - lo), lo, hi));
        }
    }
    pop
}

/// `n` points uniform over the box.
pub fn uniform<R: Rng + ?Sized>(rng: &mut R, n: usize, bounds: &[(f64, f64)]) -> Vec<Vec<f64>> {
    (0..n)
        .map(|_| {
            bounds
                .iter()
                .map(|&(lo, hi)| clamp_into(lo + rng.random::<f64>() * (hi - lo), lo, hi))
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn lhs_uses_every_stratum_once() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let pop = latin_hypercube(&mut rng, 10, &[(0.0, 1.0), (-5.0, 5.0)]);
        for (j, &(lo, hi)) in [(0.0, 1.0), (-5.0, 5.0)].iter().enumerate() {
            let mut seen = [false; 10];
            for g in &pop {
                let s = (((g[j] - lo) / (hi - lo)) * 10.0).floor() as usize;
                seen[s.min(9)] = true;
            }
            assert!(seen.iter().all(|&b| b));
        }
    }

    #[test]
    fn tournament_prefers_better_rank() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let rank = [3, 0, 2, 1];
        let wins = (0..2000)
            .filter(|_| tournament(&mut rng, &rank, 4) == 1)
            .count();
        // P(index 1 among 4 draws) = 1 − (3/4)^4 ≈ 0.68.
        assert!((1200..1550).contains(&wins), "{wins}");
    }

    #[test]
    fn sbx_children_average_to_parents_mean_inside_bounds() {
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        for _ in 0..1000 {
            let (a, b) = sbx_pair(&mut rng, 0.2, 0.7, 0.0, 1.0, 2.0);
            assert!((0.0..=1.0).contains(&a) && (0.0..=1.0).contains(&b));
        }
    }
}
