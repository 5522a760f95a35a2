//! Sobol sensitivity indices from Saltelli's design.
//!
//! The first-order index `S_i` of variable `i` is the share of the output's
//! variance explained by `x_i` alone, `V[E(f | x_i)] / V(f)`; the total index
//! `ST_i` is the share left unexplained when everything but `x_i` is known,
//! `E[V(f | x_~i)] / V(f)`, and so includes every interaction of `x_i`
//! (Sobol, "Global sensitivity indices for nonlinear mathematical models and
//! their Monte Carlo estimates", 2001; Homma & Saltelli, "Importance measures
//! in global sensitivity analysis of nonlinear models", 1996).
//!
//! Both are estimated from Saltelli's design ([`saltelli_design`]): two
//! independent `n × k` matrices `A` and `B` of unit-cube points (the two
//! halves of one `2k`-dimensional point set), and for each variable `i` the
//! matrix `AB_i`, `A` with its column `i` taken from `B`; `n (k + 2)` runs in
//! all. With `f_A`, `f_B`, `f_ABi` the outputs of corresponding rows
//! ([`sobol_indices`]):
//!
//! - first order, the estimator of Saltelli et al., "Variance based
//!   sensitivity analysis of model output. Design and estimator for the total
//!   sensitivity index", 2010: `S_i = mean(f_B (f_ABi − f_A)) / V`;
//! - total, Jansen's, "Analysis of variance designs for model output", 1999:
//!   `ST_i = mean((f_A − f_ABi)²) / 2 / V`;
//!
//! with `V` the variance of `f_A` and `f_B` together. Before the first-order
//! product the outputs are centred on the mean of `f_A` and `f_B`: that leaves
//! the estimator's expectation as it is (the mean of `f_ABi − f_A` is zero in
//! expectation) and stops a large constant part of the output, a force of
//! 1000 N varying by 1 N, from swamping it with noise.
//!
//! The 95 % intervals are bootstrap percentile intervals (Efron & Tibshirani,
//! "An introduction to the bootstrap", 1993): the base rows are resampled
//! with replacement, each with its `k + 2` runs, and all indices recomputed
//! (their `V` included). With quasi-random points the bootstrap, which
//! treats rows as independent, tends to give intervals wider than the
//! estimates' actual error.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::sample::{self, Method};

/// The Saltelli design for `k` variables: rows of the unit cube in blocks of
/// `n`: `A` (`n` rows), `B` (`n` rows), then `AB_1 … AB_k` (`A` with column
/// `i` from `B`), `n` rows each, `n (k + 2)` rows in all. `A` and `B` are
/// the two halves of the `2k`-dimensional point set
/// `sample::unit_points(method, n, 2k, seed)`.
pub fn saltelli_design(
    method: Method,
    n: usize,
    k: usize,
    seed: u64,
) -> Result<Vec<Vec<f64>>, String> {
    if k == 0 {
        return Err("at least one variable for Sobol indices, found none".into());
    }
    if n < 2 {
        return Err(format!(
            "at least 2 base points for Sobol indices, found {n}"
        ));
    }
    let dims = k
        .checked_mul(2)
        .ok_or_else(|| format!("fewer variables, found {k}"))?;
    n.checked_mul(k + 2)
        .ok_or_else(|| format!("fewer base points: {n} × ({k} + 2) runs overflow"))?;
    let base = sample::unit_points(method, n, dims, seed)?;
    let a = base.iter().map(|r| r[..k].to_vec());
    let b = base.iter().map(|r| r[k..].to_vec());
    let mut out: Vec<Vec<f64>> = a.clone().chain(b).collect();
    for i in 0..k {
        out.extend(base.iter().map(|r| {
            let mut row = r[..k].to_vec();
            row[i] = r[k + i];
            row
        }));
    }
    Ok(out)
}

/// One variable's Sobol indices.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Indices {
    /// First-order index `S_i`: the share of the output's variance due to
    /// this variable alone.
    pub first: f64,
    /// The bootstrap 95 % interval of `first`, `[lo, hi]`.
    pub first_95: [f64; 2],
    /// Total index `ST_i`: the share due to this variable with all its
    /// interactions.
    pub total: f64,
    /// The bootstrap 95 % interval of `total`, `[lo, hi]`.
    pub total_95: [f64; 2],
}

/// The indices of every variable from the outputs `y` of the rows of
/// [`saltelli_design`] (`n (k + 2)` values, in the design's order).
///
/// A base row whose output is not finite in any of its `k + 2` runs (NaN: a
/// metric undefined there) is dropped whole. The 95 % intervals come from
/// `resamples` bootstrap resamples of the remaining base rows, drawn by a
/// ChaCha8 generator seeded with `seed`; a resample whose outputs do not
/// vary is left out of them (both ends are NaN if every one is). Refused when
/// `y` has the wrong length, fewer than 2 base rows remain, `resamples` is
/// 0, or the output does not vary.
pub fn sobol_indices(
    y: &[f64],
    n: usize,
    k: usize,
    resamples: usize,
    seed: u64,
) -> Result<Vec<Indices>, String> {
    if k == 0 {
        return Err("at least one variable for Sobol indices, found none".into());
    }
    let expected = n.checked_mul(k + 2);
    if expected != Some(y.len()) {
        return Err(format!(
            "{n} × ({k} + 2) outputs of Saltelli's design, found {}",
            y.len()
        ));
    }
    if resamples == 0 {
        return Err("at least 1 bootstrap resample, found 0".into());
    }
    // Block b of the design: A (0), B (1), AB_i (2 + i).
    let at = |block: usize, row: usize| y[block * n + row];
    let kept: Vec<usize> = (0..n)
        .filter(|&r| (0..k + 2).all(|b| at(b, r).is_finite()))
        .collect();
    if kept.len() < 2 {
        return Err(format!(
            "at least 2 base points where the output is defined in all {} runs, found {} of {n}",
            k + 2,
            kept.len()
        ));
    }
    let rows: Vec<Row> = kept
        .iter()
        .map(|&r| Row {
            a: at(0, r),
            b: at(1, r),
            ab: (0..k).map(|i| at(2 + i, r)).collect(),
        })
        .collect();
    let all: Vec<usize> = (0..rows.len()).collect();
    let Some(point) = estimate(&rows, &all, k) else {
        let v = rows[0].a;
        return Err(format!(
            "an output that varies over the design, found {v} at every point \
             (or a variance that overflows)"
        ));
    };

    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut draws = vec![0_usize; rows.len()];
    let mut firsts: Vec<Vec<f64>> = vec![Vec::with_capacity(resamples); k];
    let mut totals: Vec<Vec<f64>> = vec![Vec::with_capacity(resamples); k];
    for _ in 0..resamples {
        for d in draws.iter_mut() {
            *d = rng.random_range(0..rows.len());
        }
        if let Some(est) = estimate(&rows, &draws, k) {
            for (i, (s, st)) in est.into_iter().enumerate() {
                firsts[i].push(s);
                totals[i].push(st);
            }
        }
    }
    Ok(point
        .into_iter()
        .enumerate()
        .map(|(i, (first, total))| Indices {
            first,
            first_95: interval95(&mut firsts[i]),
            total,
            total_95: interval95(&mut totals[i]),
        })
        .collect())
}

/// One base row's outputs: `f_A`, `f_B` and `f_ABi` for every `i`.
struct Row {
    a: f64,
    b: f64,
    ab: Vec<f64>,
}

/// `(S_i, ST_i)` for every variable over the rows `take` (a row may repeat),
/// or `None` when their outputs do not vary.
fn estimate(rows: &[Row], take: &[usize], k: usize) -> Option<Vec<(f64, f64)>> {
    let m = take.len() as f64;
    let mean = take.iter().map(|&r| rows[r].a + rows[r].b).sum::<f64>() / (2.0 * m);
    let v = take
        .iter()
        .map(|&r| (rows[r].a - mean).powi(2) + (rows[r].b - mean).powi(2))
        .sum::<f64>()
        / (2.0 * m);
    if !(v > 0.0 && v.is_finite()) {
        return None;
    }
    Some(
        (0..k)
            .map(|i| {
                let (mut first, mut total) = (0.0, 0.0);
                for &r in take {
                    let row = &rows[r];
                    let diff = row.ab[i] - row.a;
                    first += (row.b - mean) * diff;
                    total += diff * diff;
                }
                (first / m / v, total / m / 2.0 / v)
            })
            .collect(),
    )
}

/// The 2.5 % and 97.5 % percentiles of `values` (linear interpolation
/// between order statistics); NaN when there are none.
fn interval95(values: &mut [f64]) -> [f64; 2] {
    if values.is_empty() {
        return [f64::NAN; 2];
    }
    values.sort_by(f64::total_cmp);
    let at = |p: f64| {
        let x = p * (values.len() - 1) as f64;
        let lo = x.floor() as usize;
        let hi = (lo + 1).min(values.len() - 1);
        values[lo] + (x - lo as f64) * (values[hi] - values[lo])
    };
    [at(0.025), at(0.975)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Runs `f` over the design, `x` mapped from the unit cube by `map`.
    fn outputs(
        design: &[Vec<f64>],
        map: impl Fn(f64) -> f64,
        f: impl Fn(&[f64]) -> f64,
    ) -> Vec<f64> {
        design
            .iter()
            .map(|u| f(&u.iter().map(|&u| map(u)).collect::<Vec<_>>()))
            .collect()
    }

    fn ishigami(x: &[f64]) -> f64 {
        x[0].sin() + 7.0 * x[1].sin().powi(2) + 0.1 * x[2].powi(4) * x[0].sin()
    }

    /// Ishigami's analytic indices (a = 7, b = 0.1).
    fn ishigami_truth() -> ([f64; 3], [f64; 3]) {
        let (a, b) = (7.0_f64, 0.1_f64);
        let v1 = 0.5 * (1.0 + b * PI.powi(4) / 5.0).powi(2);
        let v2 = a * a / 8.0;
        let v13 = b * b * PI.powi(8) * (1.0 / 18.0 - 1.0 / 50.0);
        let v = v1 + v2 + v13;
        ([v1 / v, v2 / v, 0.0], [(v1 + v13) / v, v2 / v, v13 / v])
    }

    #[test]
    fn design_layout() {
        let (n, k) = (8, 3);
        let design = saltelli_design(Method::Sobol, n, k, 5).unwrap();
        let base = sample::unit_points(Method::Sobol, n, 2 * k, 5).unwrap();
        assert_eq!(design.len(), n * (k + 2));
        for r in 0..n {
            assert_eq!(design[r], base[r][..k]);
            assert_eq!(design[n + r], base[r][k..]);
            for i in 0..k {
                let ab = &design[(2 + i) * n + r];
                for j in 0..k {
                    let want = if j == i { base[r][k + j] } else { base[r][j] };
                    assert_eq!(ab[j], want);
                }
            }
        }
        assert!(saltelli_design(Method::Sobol, 8, 0, 0).is_err());
        assert!(saltelli_design(Method::Sobol, 1, 2, 0).is_err());
        assert!(saltelli_design(Method::Sobol, 8, sample::SOBOL_MAX_DIMS, 0).is_err());
        assert!(saltelli_design(Method::Latin, 8, 40, 0).is_ok());
    }

    #[test]
    fn ishigami_indices() {
        let (n, k) = (8192, 3);
        let design = saltelli_design(Method::Sobol, n, k, 11).unwrap();
        let y = outputs(&design, |u| -PI + 2.0 * PI * u, ishigami);
        let ix = sobol_indices(&y, n, k, 500, 3).unwrap();
        let (s, st) = ishigami_truth();
        assert!((s[0] - 0.3139).abs() < 1e-4 && (st[2] - 0.2437).abs() < 1e-4);
        for i in 0..k {
            let x = &ix[i];
            assert!(
                (x.first - s[i]).abs() < 0.02,
                "S{} = {}, want {}",
                i + 1,
                x.first,
                s[i]
            );
            assert!(
                (x.total - st[i]).abs() < 0.02,
                "ST{} = {}, want {}",
                i + 1,
                x.total,
                st[i]
            );
            assert!(
                x.first_95[0] <= s[i] && s[i] <= x.first_95[1],
                "S{}: {:?} misses {}",
                i + 1,
                x.first_95,
                s[i]
            );
            assert!(
                x.total_95[0] <= st[i] && st[i] <= x.total_95[1],
                "ST{}: {:?} misses {}",
                i + 1,
                x.total_95,
                st[i]
            );
            assert!(x.first_95[0] <= x.first && x.first <= x.first_95[1]);
            assert!(x.total_95[0] <= x.total && x.total <= x.total_95[1]);
        }
        // A large constant offset changes nothing that matters.
        let shifted: Vec<f64> = y.iter().map(|v| v + 1000.0).collect();
        let off = sobol_indices(&shifted, n, k, 10, 3).unwrap();
        for i in 0..k {
            assert!((off[i].first - ix[i].first).abs() < 1e-9);
            assert!((off[i].total - ix[i].total).abs() < 1e-9);
        }
    }

    #[test]
    fn linear_function_indices() {
        let a = [1.0, 2.0, 3.0, 0.5];
        let (n, k) = (4096, a.len());
        let design = saltelli_design(Method::Sobol, n, k, 2).unwrap();
        let y = outputs(
            &design,
            |u| u,
            |x| x.iter().zip(&a).map(|(x, a)| x * a).sum(),
        );
        let ix = sobol_indices(&y, n, k, 200, 1).unwrap();
        let sum_sq: f64 = a.iter().map(|a| a * a).sum();
        for i in 0..k {
            let want = a[i] * a[i] / sum_sq;
            assert!(
                (ix[i].first - want).abs() < 0.01,
                "S{i} = {}, want {want}",
                ix[i].first
            );
            assert!(
                (ix[i].total - want).abs() < 0.01,
                "ST{i} = {}, want {want}",
                ix[i].total
            );
            assert!((ix[i].first - ix[i].total).abs() < 0.01);
        }
    }

    #[test]
    fn variable_without_effect_has_zero_indices() {
        let (n, k) = (1024, 2);
        for method in [Method::Random, Method::Latin, Method::Sobol] {
            let design = saltelli_design(method, n, k, 9).unwrap();
            let y = outputs(&design, |u| u, |x| (3.0 * x[0]).exp());
            let ix = sobol_indices(&y, n, k, 100, 4).unwrap();
            assert_eq!(ix[1].first, 0.0, "{method:?}");
            assert_eq!(ix[1].total, 0.0, "{method:?}");
            assert_eq!(ix[1].total_95, [0.0, 0.0]);
            // Plain random points converge slowest.
            let tol = if method == Method::Random { 0.1 } else { 0.05 };
            assert!(
                (ix[0].first - 1.0).abs() < tol,
                "{method:?}: {}",
                ix[0].first
            );
            assert!(
                (ix[0].total - 1.0).abs() < tol,
                "{method:?}: {}",
                ix[0].total
            );
        }
    }

    #[test]
    fn undefined_outputs_drop_their_base_rows() {
        let (n, k) = (64, 2);
        let design = saltelli_design(Method::Sobol, n, k, 1).unwrap();
        let y = outputs(&design, |u| u, |x| x[0] + 2.0 * x[1] * x[0]);
        let mut holed = y.clone();
        let dropped = [3_usize, 10, 40];
        holed[3] = f64::NAN; // A, row 3
        holed[n + 10] = f64::INFINITY; // B, row 10
        holed[3 * n + 40] = f64::NAN; // AB_2, row 40
        let got = sobol_indices(&holed, n, k, 50, 8).unwrap();
        // The same as a design without those base rows.
        let m = n - dropped.len();
        let reduced: Vec<f64> = (0..k + 2)
            .flat_map(|b| {
                let y = &y;
                (0..n)
                    .filter(|r| !dropped.contains(r))
                    .map(move |r| y[b * n + r])
            })
            .collect();
        assert_eq!(got, sobol_indices(&reduced, m, k, 50, 8).unwrap());
        assert!(
            got.iter()
                .all(|x| x.first.is_finite() && x.total.is_finite())
        );

        // Fewer than two base rows left.
        let mut sparse = vec![f64::NAN; n * (k + 2)];
        for b in 0..k + 2 {
            sparse[b * n + 5] = 1.0 + b as f64;
        }
        let err = sobol_indices(&sparse, n, k, 10, 0).unwrap_err();
        assert!(err.contains("found 1 of 64"), "{err}");
    }

    #[test]
    fn refusals() {
        let (n, k) = (16, 2);
        let err = sobol_indices(&vec![2.5; n * (k + 2)], n, k, 10, 0).unwrap_err();
        assert!(err.contains("varies"), "{err}");
        let err = sobol_indices(&[1.0; 10], n, k, 10, 0).unwrap_err();
        assert!(err.contains("found 10"), "{err}");
        let y: Vec<f64> = (0..n * (k + 2)).map(|i| i as f64).collect();
        assert!(sobol_indices(&y, n, k, 0, 0).is_err());
        assert!(sobol_indices(&y, n, 0, 10, 0).is_err());
        assert!(sobol_indices(&y, n, k, 10, 0).is_ok());
    }

    #[test]
    fn bootstrap_is_seeded() {
        let (n, k) = (256, 3);
        let design = saltelli_design(Method::Latin, n, k, 4).unwrap();
        let y = outputs(&design, |u| -PI + 2.0 * PI * u, ishigami);
        let a = sobol_indices(&y, n, k, 100, 1).unwrap();
        assert_eq!(a, sobol_indices(&y, n, k, 100, 1).unwrap());
        let b = sobol_indices(&y, n, k, 100, 2).unwrap();
        assert_eq!(a[0].first, b[0].first);
        assert_ne!(a[0].first_95, b[0].first_95);
    }

    #[test]
    fn percentile_interval() {
        let mut v: Vec<f64> = (0..=100).rev().map(f64::from).collect();
        assert_eq!(interval95(&mut v), [2.5, 97.5]);
        assert_eq!(interval95(&mut [4.0]), [4.0, 4.0]);
        assert!(interval95(&mut []).iter().all(|x| x.is_nan()));
    }
}
