//! Design variables drawn from distributions: each variable's distribution,
//! and the points of the unit cube its quantile function maps onto values.
//!
//! A sampled sweep writes each variable as a distribution
//! ([`Distribution`]): `{"uniform": [lo, hi]}`, `{"loguniform": [lo, hi]}`,
//! `{"normal": [mean, sd]}`, `{"lognormal": [median, sigma_of_ln]}` or
//! `{"triangular": [lo, mode, hi]}`. Points are drawn in the open unit cube
//! `(0, 1)^dims` ([`unit_points`]) and each coordinate is mapped through its
//! variable's inverse CDF ([`Distribution::quantile`]), so one set of unit
//! points serves any distributions.
//!
//! Three ways of drawing the unit points ([`Method`]):
//!
//! - **random**: independent uniform draws from a seeded ChaCha8 generator.
//! - **latin**: Latin hypercube sampling (McKay, Beckman & Conover, "A
//!   comparison of three methods for selecting values of input variables in
//!   the analysis of output from a computer code", 1979): each dimension is cut
//!   into `n` equal strata, a random permutation assigns one stratum to each
//!   point, and the point is placed uniformly inside it, so every
//!   one-dimensional projection has exactly one point per stratum.
//! - **sobol**: the Sobol low-discrepancy sequence (Sobol, "On the
//!   distribution of points in a cube and the approximate evaluation of
//!   integrals", 1967) in Gray-code order (Antonov & Saleev, "An economic
//!   method of computing LP_tau-sequences", 1979), with the direction numbers
//!   of Joe & Kuo, "Constructing Sobol sequences with better two-dimensional
//!   projections", 2008 (the file `new-joe-kuo-6.21201`; the first
//!   [`SOBOL_MAX_DIMS`] dimensions are embedded, the first being van der
//!   Corput's sequence). The first point of the sequence (the origin) is
//!   skipped, and each dimension is XOR-ed with a random 32-bit word drawn from
//!   the seed (a random digital shift), so different seeds give different,
//!   equally well spread point sets. Coordinates are `(x + 0.5) / 2^32` for a
//!   32-bit integer `x`, so no coordinate is 0 or 1.
//!
//! The normal quantile is Acklam's rational approximation (relative error
//! below 1.15e-9) followed by one Halley step on `Φ(x) − u`, with `Φ`
//! computed from a complementary error function accurate to about 1e-14
//! relative: a positive-term power series below 1.5 and Lentz's evaluation of
//! Laplace's continued fraction above. The refined quantile is accurate to
//! about 1e-15 relative.

use rand::seq::SliceRandom;
use rand::{RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A design variable's distribution, as written in a sweep file.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum Distribution {
    /// `[lo, hi]`: uniform between `lo` and `hi` (finite, `lo < hi`).
    Uniform([f64; 2]),
    /// `[lo, hi]`: uniform in `ln` between `lo` and `hi` (`0 < lo < hi`).
    Loguniform([f64; 2]),
    /// `[mean, sd]`: normal (`sd > 0`).
    Normal([f64; 2]),
    /// `[median, sigma]`: `ln` of the value is normal with mean `ln median`
    /// and standard deviation `sigma` (`median > 0`, `sigma > 0`).
    Lognormal([f64; 2]),
    /// `[lo, mode, hi]`: triangular (`lo <= mode <= hi`, `lo < hi`).
    Triangular([f64; 3]),
}

impl Distribution {
    /// `Ok` when the parameters are in range; otherwise what was expected
    /// and what was found (for the message).
    pub fn check(&self) -> Result<(), (String, String)> {
        let all_finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        let (ok, expected, found) = match *self {
            Self::Uniform([lo, hi]) => (
                all_finite(&[lo, hi]) && lo < hi,
                "a uniform range [lo, hi] with finite lo < hi",
                format!("[{lo}, {hi}]"),
            ),
            Self::Loguniform([lo, hi]) => (
                all_finite(&[lo, hi]) && 0.0 < lo && lo < hi,
                "a loguniform range [lo, hi] with finite 0 < lo < hi",
                format!("[{lo}, {hi}]"),
            ),
            Self::Normal([mean, sd]) => (
                all_finite(&[mean, sd]) && sd > 0.0,
                "a normal [mean, sd] with finite mean and finite sd > 0",
                format!("[{mean}, {sd}]"),
            ),
            Self::Lognormal([median, sigma]) => (
                all_finite(&[median, sigma]) && median > 0.0 && sigma > 0.0,
                "a lognormal [median, sigma] with finite median > 0 and finite sigma > 0",
                format!("[{median}, {sigma}]"),
            ),
            Self::Triangular([lo, mode, hi]) => (
                all_finite(&[lo, mode, hi]) && lo <= mode && mode <= hi && lo < hi,
                "a triangular [lo, mode, hi] with finite lo <= mode <= hi and lo < hi",
                format!("[{lo}, {mode}, {hi}]"),
            ),
        };
        if ok {
            Ok(())
        } else {
            Err((expected.to_owned(), found))
        }
    }

    /// The inverse CDF at `u`, for `u` in `(0, 1)`. At 0 and 1 it gives the
    /// ends of the support (infinite for the normal, 0 and infinity for the
    /// lognormal); outside `[0, 1]` the result is meaningless. Assumes
    /// [`Distribution::check`] passed.
    pub fn quantile(&self, u: f64) -> f64 {
        match *self {
            Self::Uniform([lo, hi]) => {
                if u >= 1.0 {
                    hi
                } else {
                    lo + u * (hi - lo)
                }
            }
            Self::Loguniform([lo, hi]) => {
                if u <= 0.0 {
                    lo
                } else if u >= 1.0 {
                    hi
                } else {
                    (lo.ln() + u * (hi.ln() - lo.ln())).exp().clamp(lo, hi)
                }
            }
            Self::Normal([mean, sd]) => mean + sd * normal_quantile(u),
            Self::Lognormal([median, sigma]) => median * (sigma * normal_quantile(u)).exp(),
            Self::Triangular([lo, mode, hi]) => {
                let width = hi - lo;
                let cut = (mode - lo) / width;
                let x = if u < cut {
                    lo + (u * width * (mode - lo)).sqrt()
                } else {
                    hi - ((1.0 - u) * width * (hi - mode)).sqrt()
                };
                x.clamp(lo, hi)
            }
        }
    }

    /// `[quantile(0.001), quantile(0.999)]`: where nearly all values lie,
    /// for choosing a step that serves every drawn value.
    pub fn support_hint(&self) -> [f64; 2] {
        [self.quantile(0.001), self.quantile(0.999)]
    }
}

/// How points are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Independent uniform draws.
    Random,
    /// Latin hypercube sampling: one point per stratum in every dimension.
    Latin,
    /// The digitally shifted Sobol sequence.
    Sobol,
}

/// The most dimensions [`Method::Sobol`] has direction numbers for.
pub const SOBOL_MAX_DIMS: usize = JOE_KUO.len() + 1;

/// The most points [`Method::Sobol`] gives (its 32-bit integers run out).
pub const SOBOL_MAX_POINTS: usize = 1 << 31;

/// `n` points in the open unit cube `(0, 1)^dims`, as `n` rows of `dims`
/// coordinates, the same for the same arguments. Refused for
/// [`Method::Sobol`] with more than [`SOBOL_MAX_DIMS`] dimensions or more
/// than [`SOBOL_MAX_POINTS`] points.
pub fn unit_points(
    method: Method,
    n: usize,
    dims: usize,
    seed: u64,
) -> Result<Vec<Vec<f64>>, String> {
    match method {
        Method::Random => {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            Ok((0..n)
                .map(|_| (0..dims).map(|_| open01(&mut rng)).collect())
                .collect())
        }
        Method::Latin => Ok(latin(n, dims, seed)),
        Method::Sobol => {
            if dims > SOBOL_MAX_DIMS {
                return Err(format!(
                    "at most {SOBOL_MAX_DIMS} dimensions for Sobol points (Joe & Kuo's \
                     direction numbers held here), found {dims}"
                ));
            }
            if n > SOBOL_MAX_POINTS {
                return Err(format!(
                    "at most {SOBOL_MAX_POINTS} Sobol points (2^31), found {n}"
                ));
            }
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let shifts: Vec<u32> = (0..dims).map(|_| rng.next_u32()).collect();
            Ok(sobol_integers(n, dims)
                .into_iter()
                .map(|row| {
                    row.iter()
                        .zip(&shifts)
                        .map(|(&x, &s)| to_unit(x ^ s))
                        .collect()
                })
                .collect())
        }
    }
}

/// A uniform draw in the open interval `(0, 1)`: 53 random bits and half a
/// step, so never 0 or 1.
fn open01(rng: &mut ChaCha8Rng) -> f64 {
    ((rng.next_u64() >> 11) as f64 + 0.5) / (1_u64 << 53) as f64
}

/// The largest `f64` below 1.
const BELOW_ONE: f64 = 1.0 - f64::EPSILON / 2.0;

/// Latin hypercube points: per dimension a random permutation of the strata,
/// jittered uniformly inside each.
fn latin(n: usize, dims: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = vec![vec![0.0; dims]; n];
    let mut strata: Vec<usize> = (0..n).collect();
    for d in 0..dims {
        strata.shuffle(&mut rng);
        for (row, &stratum) in out.iter_mut().zip(&strata) {
            let u = (stratum as f64 + open01(&mut rng)) / n as f64;
            // Rounding may reach 1 in the last stratum.
            row[d] = u.min(BELOW_ONE);
        }
    }
    out
}

/// A 32-bit fraction `x / 2^32` moved half a step in: in `(0, 1)`.
fn to_unit(x: u32) -> f64 {
    (f64::from(x) + 0.5) / 4_294_967_296.0
}

/// Joe & Kuo's direction numbers (`new-joe-kuo-6.21201`) for dimensions
/// 2, 3, …: the degree `s` of the primitive polynomial, its inner
/// coefficients `a` as bits (highest power first), and the initial direction
/// numbers `m_1 … m_s`. The numbers are the authors' published data (S. Joe
/// and F. Y. Kuo, web.maths.unsw.edu.au/~fkuo/sobol, released by them under a
/// BSD-style licence that asks for this notice: Copyright (c) 2008, Frances Y.
/// Kuo and Stephen Joe. All rights reserved.); the test below checks every
/// row's polynomial is primitive and distinct and every `m_i` odd and below
/// `2^i`.
const JOE_KUO: [(u32, u32, &[u32]); 63] = [
    (1, 0, &[1]),
    (2, 1, &[1, 3]),
    (3, 1, &[1, 3, 1]),
    (3, 2, &[1, 1, 1]),
    (4, 1, &[1, 1, 3, 3]),
    (4, 4, &[1, 3, 5, 13]),
    (5, 2, &[1, 1, 5, 5, 17]),
    (5, 4, &[1, 1, 5, 5, 5]),
    (5, 7, &[1, 1, 7, 11, 19]),
    (5, 11, &[1, 1, 5, 1, 1]),
    (5, 13, &[1, 1, 1, 3, 11]),
    (5, 14, &[1, 3, 5, 5, 31]),
    (6, 1, &[1, 3, 3, 9, 7, 49]),
    (6, 13, &[1, 1, 1, 15, 21, 21]),
    (6, 16, &[1, 3, 1, 13, 27, 49]),
    (6, 19, &[1, 1, 1, 15, 7, 5]),
    (6, 22, &[1, 3, 1, 15, 13, 25]),
    (6, 25, &[1, 1, 5, 5, 19, 61]),
    (7, 1, &[1, 3, 7, 11, 23, 15, 103]),
    (7, 4, &[1, 3, 7, 13, 13, 15, 69]),
    (7, 7, &[1, 1, 3, 13, 7, 35, 63]),
    (7, 8, &[1, 3, 5, 9, 1, 25, 53]),
    (7, 14, &[1, 3, 1, 13, 9, 35, 107]),
    (7, 19, &[1, 3, 1, 5, 27, 61, 31]),
    (7, 21, &[1, 1, 5, 11, 19, 41, 61]),
    (7, 28, &[1, 3, 5, 3, 3, 13, 69]),
    (7, 31, &[1, 1, 7, 13, 1, 19, 1]),
    (7, 32, &[1, 3, 7, 5, 13, 19, 59]),
    (7, 37, &[1, 1, 3, 9, 25, 29, 41]),
    (7, 41, &[1, 3, 5, 13, 23, 1, 55]),
    (7, 42, &[1, 3, 7, 3, 13, 59, 17]),
    (7, 50, &[1, 3, 1, 3, 5, 53, 69]),
    (7, 55, &[1, 1, 5, 5, 23, 33, 13]),
    (7, 56, &[1, 1, 7, 7, 1, 61, 123]),
    (7, 59, &[1, 1, 7, 9, 13, 61, 49]),
    (7, 62, &[1, 3, 3, 5, 3, 55, 33]),
    (8, 14, &[1, 3, 1, 15, 31, 13, 49, 245]),
    (8, 21, &[1, 3, 5, 15, 31, 59, 63, 97]),
    (8, 22, &[1, 3, 1, 11, 11, 11, 77, 249]),
    (8, 38, &[1, 3, 1, 11, 27, 43, 71, 9]),
    (8, 47, &[1, 1, 7, 15, 21, 11, 81, 45]),
    (8, 49, &[1, 3, 7, 3, 25, 31, 65, 79]),
    (8, 50, &[1, 3, 1, 1, 19, 11, 3, 205]),
    (8, 52, &[1, 1, 5, 9, 19, 21, 29, 157]),
    (8, 56, &[1, 3, 7, 11, 1, 33, 89, 185]),
    (8, 67, &[1, 3, 3, 3, 15, 9, 79, 71]),
    (8, 70, &[1, 3, 7, 11, 15, 39, 119, 27]),
    (8, 84, &[1, 1, 3, 1, 11, 31, 97, 225]),
    (8, 97, &[1, 1, 1, 3, 23, 43, 57, 177]),
    (8, 103, &[1, 3, 7, 7, 17, 17, 37, 71]),
    (8, 115, &[1, 3, 1, 5, 27, 63, 123, 213]),
    (8, 122, &[1, 1, 3, 5, 11, 43, 53, 133]),
    (9, 8, &[1, 3, 5, 5, 29, 17, 47, 173, 479]),
    (9, 13, &[1, 3, 3, 11, 3, 1, 109, 9, 69]),
    (9, 16, &[1, 1, 1, 5, 17, 39, 23, 5, 343]),
    (9, 22, &[1, 3, 1, 5, 25, 15, 31, 103, 499]),
    (9, 25, &[1, 1, 1, 11, 11, 17, 63, 105, 183]),
    (9, 44, &[1, 1, 5, 11, 9, 29, 97, 231, 363]),
    (9, 47, &[1, 1, 5, 15, 19, 45, 41, 7, 383]),
    (9, 52, &[1, 3, 7, 7, 31, 19, 83, 137, 221]),
    (9, 55, &[1, 1, 1, 3, 23, 15, 111, 223, 83]),
    (9, 59, &[1, 1, 5, 13, 31, 15, 55, 25, 161]),
    (9, 62, &[1, 1, 3, 13, 25, 47, 39, 87, 257]),
];

/// The 32 direction numbers of dimension `dim` (0-based), as 32-bit
/// fractions: `v_j = m_j / 2^(j+1)`.
fn directions(dim: usize) -> [u32; 32] {
    let mut v = [0_u32; 32];
    if dim == 0 {
        // van der Corput: every m_j = 1.
        for (j, vj) in v.iter_mut().enumerate() {
            *vj = 1 << (31 - j);
        }
        return v;
    }
    let (s, a, m) = JOE_KUO[dim - 1];
    let s = s as usize;
    for j in 0..32 {
        v[j] = if j < s {
            m[j] << (31 - j)
        } else {
            // Bratley & Fox's recurrence: the polynomial's inner coefficients
            // are the bits of `a`, highest power first.
            let mut x = v[j - s] ^ (v[j - s] >> s);
            for k in 1..s {
                if (a >> (s - 1 - k)) & 1 == 1 {
                    x ^= v[j - k];
                }
            }
            x
        };
    }
    v
}

/// Points 1 … n of the unshifted Sobol sequence in Gray-code order, as
/// 32-bit fractions (point 0, the origin, is skipped). `n <= 2^31`, `dims <=`
/// [`SOBOL_MAX_DIMS`].
fn sobol_integers(n: usize, dims: usize) -> Vec<Vec<u32>> {
    let v: Vec<[u32; 32]> = (0..dims).map(directions).collect();
    let mut x = vec![0_u32; dims];
    let mut out = Vec::with_capacity(n);
    for i in 1..=n {
        // Gray code: point i differs from point i − 1 in bit ctz(i).
        let c = i.trailing_zeros() as usize;
        for (xd, vd) in x.iter_mut().zip(&v) {
            *xd ^= vd[c];
        }
        out.push(x.clone());
    }
    out
}

/// The standard normal quantile `Φ⁻¹(u)`: Acklam's approximation refined by
/// one Halley step. `-∞` at 0, `+∞` at 1, NaN outside `[0, 1]`.
pub(crate) fn normal_quantile(u: f64) -> f64 {
    if u.is_nan() || !(0.0..=1.0).contains(&u) {
        return f64::NAN;
    }
    if u == 0.0 {
        return f64::NEG_INFINITY;
    }
    if u == 1.0 {
        return f64::INFINITY;
    }
    // 1 − u is exact for u ≥ 0.5: work in the lower tail, where Φ has full
    // relative precision.
    if u > 0.5 {
        return -normal_quantile(1.0 - u);
    }
    let x = acklam(u);
    // Halley's step on Φ(x) − u, Φ(x) = erfc(−x/√2)/2 with −x ≥ 0 here.
    let e = 0.5 * erfc(-x / std::f64::consts::SQRT_2) - u;
    let t = e * (2.0 * std::f64::consts::PI).sqrt() * (0.5 * x * x).exp();
    let refined = x - t / (1.0 + 0.5 * x * t);
    if refined.is_finite() { refined } else { x }
}

/// Acklam's rational approximation of `Φ⁻¹(u)` for `u` in `(0, 0.5]`
/// (relative error below 1.15e-9).
fn acklam(u: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969683028665376e+01,
        2.209460984245205e+02,
        -2.759285104469687e+02,
        1.38357751867269e+02,
        -3.066479806614716e+01,
        2.506628277459239e+00,
    ];
    const B: [f64; 5] = [
        -5.447609879822406e+01,
        1.615858368580409e+02,
        -1.556989798598866e+02,
        6.680131188771972e+01,
        -1.328068155288572e+01,
    ];
    const C: [f64; 6] = [
        -7.784894002430293e-03,
        -3.223964580411365e-01,
        -2.400758277161838e+00,
        -2.549732539343734e+00,
        4.374664141464968e+00,
        2.938163982698783e+00,
    ];
    const D: [f64; 4] = [
        7.784695709041462e-03,
        3.224671290700398e-01,
        2.445134137142996e+00,
        3.754408661907416e+00,
    ];
    const LOW: f64 = 0.02425;
    if u < LOW {
        let q = (-2.0 * u.ln()).sqrt();
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    } else {
        let q = u - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    }
}

/// `exp(−z²)` without the rounding error of `z²`: `z = h + l` with `h` a
/// multiple of 1/16, so `h²` is exact and `z² − h² = l (z + h)`.
fn exp_neg_square(z: f64) -> f64 {
    let h = (z * 16.0).floor() / 16.0;
    (-h * h).exp() * (-(z - h) * (z + h)).exp()
}

/// The complementary error function, relative error about 1e-14 or better
/// wherever the result is a normal `f64`.
///
/// Below 1.5 it is `1 − erf(z)` with `erf` from its positive-term series
/// `erf z = 2/√π · e^(−z²) · Σ 2^n z^(2n+1) / (1·3·…·(2n+1))`; from 1.5 on,
/// Laplace's continued fraction `erfc z = e^(−z²)/√π · 1/(z + (1/2)/(z +
/// 1/(z + (3/2)/(z + …))))`, evaluated by the modified Lentz method (at most
/// about 90 terms).
pub(crate) fn erfc(z: f64) -> f64 {
    const FRAC_1_SQRT_PI: f64 = 0.564_189_583_547_756_3;
    if z.is_nan() {
        return f64::NAN;
    }
    if z < 0.0 {
        return 2.0 - erfc(-z);
    }
    if z < 1.5 {
        let z2 = 2.0 * z * z;
        let (mut term, mut sum) = (z, z);
        let mut n = 0.0;
        while term > sum * 1e-17 {
            n += 1.0;
            term *= z2 / (2.0 * n + 1.0);
            sum += term;
        }
        return 1.0 - 2.0 * FRAC_1_SQRT_PI * exp_neg_square(z) * sum;
    }
    if z > 27.3 {
        // Below the smallest subnormal.
        return 0.0;
    }
    let (mut f, mut c, mut d) = (z, z, 0.0_f64);
    for n in 1..1000 {
        let a = 0.5 * f64::from(n);
        d = 1.0 / (z + a * d);
        c = z + a / c;
        let delta = c * d;
        f *= delta;
        if (delta - 1.0).abs() < 2.3e-16 {
            break;
        }
    }
    FRAC_1_SQRT_PI * exp_neg_square(z) / f
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * b.abs().max(f64::MIN_POSITIVE)
    }

    #[test]
    fn erfc_known_values() {
        for (z, want) in [
            (0.0, 1.0),
            (0.5, 0.4795001221869535),
            (1.0, 0.15729920705028513),
            (1.5, 0.033894853524689274),
            (3.0, 2.209049699858544e-05),
            (5.0, 1.5374597944280351e-12),
            (10.0, 2.088487583762545e-45),
            (-1.0, 1.842700792949715),
        ] {
            let got = erfc(z);
            assert!(close(got, want, 1e-13), "erfc({z}) = {got}, want {want}");
        }
        assert_eq!(erfc(30.0), 0.0);
    }

    #[test]
    fn normal_quantile_known_values() {
        for (u, want) in [
            (0.975, 1.959963984540054),
            (0.025, -1.959963984540054),
            (0.001, -3.090232306167813),
            (0.999, 3.090232306167813),
            (0.5, 0.0),
            (0.8413447460685429, 1.0),
            (1e-10, -6.361340902404057),
            (1e-300, -37.0470962993612),
        ] {
            let got = normal_quantile(u);
            assert!(
                (got - want).abs() <= 1e-12 * want.abs().max(1.0),
                "Φ⁻¹({u}) = {got}, want {want}"
            );
        }
        assert_eq!(normal_quantile(0.0), f64::NEG_INFINITY);
        assert_eq!(normal_quantile(1.0), f64::INFINITY);
        assert!(normal_quantile(1.5).is_nan());
    }

    #[test]
    fn normal_quantile_inverts_erfc() {
        for i in 1..1000 {
            let u = f64::from(i) / 1000.0;
            let x = normal_quantile(u);
            let back = 0.5 * erfc(-x / std::f64::consts::SQRT_2);
            assert!(close(back, u, 1e-13), "Φ(Φ⁻¹({u})) = {back}");
        }
    }

    #[test]
    fn quantiles_of_every_distribution() {
        let uniform = Distribution::Uniform([2.0, 6.0]);
        assert_eq!(uniform.quantile(0.25), 3.0);
        assert_eq!(uniform.quantile(0.5), 4.0);

        let log = Distribution::Loguniform([1.0, 100.0]);
        assert!(close(log.quantile(0.5), 10.0, 1e-14));
        assert!(close(log.quantile(0.25), 100.0_f64.powf(0.25), 1e-14));

        let normal = Distribution::Normal([10.0, 2.0]);
        assert!(close(
            normal.quantile(0.975),
            10.0 + 2.0 * 1.959963984540054,
            1e-14
        ));
        assert_eq!(normal.quantile(0.5), 10.0);

        let lognormal = Distribution::Lognormal([3.0, 0.5]);
        assert!(close(lognormal.quantile(0.5), 3.0, 1e-15));
        assert!(close(
            lognormal.quantile(0.975),
            3.0 * (0.5 * 1.959963984540054_f64).exp(),
            1e-14
        ));

        let tri = Distribution::Triangular([0.0, 1.0, 4.0]);
        // CDF: x²/4 up to the mode (F(1) = 1/4), 1 − (4 − x)²/12 after.
        assert!(close(tri.quantile(0.25), 1.0, 1e-15));
        assert!(close(tri.quantile(0.01), 0.2, 1e-14));
        assert!(close(
            tri.quantile(0.25 + 0.75 * 0.5),
            4.0 - 4.5_f64.sqrt(),
            1e-14
        ));
        let right = Distribution::Triangular([0.0, 4.0, 4.0]);
        assert!(close(right.quantile(0.25), 2.0, 1e-15));
        let left = Distribution::Triangular([0.0, 0.0, 4.0]);
        assert!(close(left.quantile(0.75), 2.0, 1e-15));

        let [lo, hi] = normal.support_hint();
        assert!(close(lo, 10.0 - 2.0 * 3.090232306167813, 1e-13));
        assert!(close(hi, 10.0 + 2.0 * 3.090232306167813, 1e-13));
        assert_eq!(uniform.support_hint(), [2.004, 5.996]);
    }

    #[test]
    fn check_accepts_and_refuses() {
        for good in [
            Distribution::Uniform([-1.0, 1.0]),
            Distribution::Loguniform([1e-3, 1.0]),
            Distribution::Normal([-5.0, 0.1]),
            Distribution::Lognormal([2.0, 0.3]),
            Distribution::Triangular([0.0, 0.0, 1.0]),
            Distribution::Triangular([0.0, 1.0, 1.0]),
        ] {
            assert_eq!(good.check(), Ok(()), "{good:?}");
        }
        for bad in [
            Distribution::Uniform([1.0, 1.0]),
            Distribution::Uniform([0.0, f64::INFINITY]),
            Distribution::Loguniform([0.0, 1.0]),
            Distribution::Loguniform([2.0, 1.0]),
            Distribution::Normal([0.0, 0.0]),
            Distribution::Normal([f64::NAN, 1.0]),
            Distribution::Lognormal([-1.0, 1.0]),
            Distribution::Lognormal([1.0, 0.0]),
            Distribution::Triangular([0.0, 2.0, 1.0]),
            Distribution::Triangular([1.0, 1.0, 1.0]),
        ] {
            let (expected, found) = bad.check().expect_err(&format!("{bad:?}"));
            assert!(
                !expected.is_empty() && found.starts_with('['),
                "{expected} / {found}"
            );
        }
        let (expected, found) = Distribution::Uniform([3.0, 1.0]).check().unwrap_err();
        assert_eq!(expected, "a uniform range [lo, hi] with finite lo < hi");
        assert_eq!(found, "[3, 1]");
    }

    #[test]
    fn distributions_parse_from_json() {
        let d: Distribution = serde_json::from_str(r#"{"triangular": [0, 1, 2]}"#).unwrap();
        assert_eq!(d, Distribution::Triangular([0.0, 1.0, 2.0]));
        let d: Distribution = serde_json::from_str(r#"{"loguniform": [1, 10]}"#).unwrap();
        assert_eq!(d, Distribution::Loguniform([1.0, 10.0]));
        assert!(serde_json::from_str::<Distribution>(r#"{"uniform": [0, 1, 2]}"#).is_err());
        assert!(serde_json::from_str::<Distribution>(r#"{"beta": [1, 2]}"#).is_err());
        let m: Method = serde_json::from_str(r#""latin""#).unwrap();
        assert_eq!(m, Method::Latin);
    }

    /// x^e mod p over GF(2), p given as bits.
    fn order_of_x(p: u32, degree: u32) -> u32 {
        let mut r = 1_u32;
        for e in 1..=(1_u32 << degree) {
            r <<= 1;
            if r & (1 << degree) != 0 {
                r ^= p;
            }
            if r == 1 {
                return e;
            }
        }
        0
    }

    #[test]
    fn joe_kuo_table_is_consistent() {
        let mut seen = std::collections::HashSet::new();
        let mut last_degree = 0;
        for (row, &(s, a, m)) in JOE_KUO.iter().enumerate() {
            assert_eq!(m.len(), s as usize, "row {row}");
            assert!(s >= last_degree, "row {row}: degrees in order");
            last_degree = s;
            assert!(a < 1 << (s - 1), "row {row}: a has s − 1 bits");
            assert!(seen.insert((s, a)), "row {row}: polynomial repeated");
            // x^s + a-bits + 1 is primitive: x has order 2^s − 1.
            let p = (1 << s) | (a << 1) | 1;
            assert_eq!(order_of_x(p, s), (1 << s) - 1, "row {row}: not primitive");
            for (i, &mi) in m.iter().enumerate() {
                assert!(
                    mi % 2 == 1 && mi < 1 << (i + 1),
                    "row {row}: m_{} = {mi}",
                    i + 1
                );
            }
        }
    }

    #[test]
    fn sobol_unshifted_first_points() {
        let pts = sobol_integers(8, 2);
        let unit: Vec<(f64, f64)> = pts
            .iter()
            .map(|r| {
                (
                    f64::from(r[0]) / 4_294_967_296.0,
                    f64::from(r[1]) / 4_294_967_296.0,
                )
            })
            .collect();
        assert_eq!(
            unit,
            [
                (0.5, 0.5),
                (0.75, 0.25),
                (0.25, 0.75),
                (0.375, 0.375),
                (0.875, 0.875),
                (0.625, 0.125),
                (0.125, 0.625),
                (0.1875, 0.3125),
            ]
        );
        // Third dimension (s = 2, a = 1, m = 1, 3): 0.5, 0.25, 0.75, 0.625.
        let third: Vec<f64> = sobol_integers(4, 3)
            .iter()
            .map(|r| f64::from(r[2]) / 4_294_967_296.0)
            .collect();
        assert_eq!(third, [0.5, 0.25, 0.75, 0.625]);
    }

    #[test]
    fn sobol_every_dimension_is_stratified() {
        // With the origin, the first 2^m points put one point in every
        // interval of width 2^−m, in every dimension.
        let m = 10;
        let pts = sobol_integers((1 << m) - 1, SOBOL_MAX_DIMS);
        for d in 0..SOBOL_MAX_DIMS {
            let mut hit = vec![false; 1 << m];
            hit[0] = true;
            for row in &pts {
                let cell = (row[d] >> (32 - m)) as usize;
                assert!(!hit[cell], "dimension {d}: cell {cell} twice");
                hit[cell] = true;
            }
        }
    }

    #[test]
    fn sobol_integrates_a_product() {
        // E[x1 x2 x3 x4 x5] = 1/32 over the unit cube.
        let pts = unit_points(Method::Sobol, 4096, 5, 7).unwrap();
        let mean: f64 = pts.iter().map(|r| r.iter().product::<f64>()).sum::<f64>() / 4096.0;
        assert!((mean - 1.0 / 32.0).abs() < 1e-3, "mean {mean}");
        // And every pair product: E[x_i x_j] = 1/4.
        for i in 0..5 {
            for j in i + 1..5 {
                let mean: f64 = pts.iter().map(|r| r[i] * r[j]).sum::<f64>() / 4096.0;
                assert!((mean - 0.25).abs() < 1e-3, "x{i} x{j}: mean {mean}");
            }
        }
    }

    #[test]
    fn latin_has_one_point_per_stratum() {
        for n in [1, 2, 7, 100] {
            let pts = unit_points(Method::Latin, n, 4, 3).unwrap();
            assert_eq!(pts.len(), n);
            for d in 0..4 {
                let mut hit = vec![false; n];
                for row in &pts {
                    let cell = (row[d] * n as f64).floor() as usize;
                    assert!(!hit[cell], "n {n}, dimension {d}: stratum {cell} twice");
                    hit[cell] = true;
                }
            }
        }
    }

    #[test]
    fn points_are_deterministic_inside_and_seed_dependent() {
        for method in [Method::Random, Method::Latin, Method::Sobol] {
            let a = unit_points(method, 257, 6, 1).unwrap();
            assert_eq!(a, unit_points(method, 257, 6, 1).unwrap(), "{method:?}");
            assert_ne!(a, unit_points(method, 257, 6, 2).unwrap(), "{method:?}");
            assert_ne!(a, unit_points(method, 257, 6, 0).unwrap(), "{method:?}");
            assert_eq!(a.len(), 257);
            for row in &a {
                assert_eq!(row.len(), 6);
                for &u in row {
                    assert!(u > 0.0 && u < 1.0, "{method:?}: {u}");
                }
            }
            assert!(unit_points(method, 0, 3, 1).unwrap().is_empty());
        }
    }

    #[test]
    fn sobol_refuses_what_it_cannot_give() {
        let err = unit_points(Method::Sobol, 8, SOBOL_MAX_DIMS + 1, 0).unwrap_err();
        assert!(err.contains("dimensions"), "{err}");
        let err = unit_points(Method::Sobol, SOBOL_MAX_POINTS + 1, 2, 0).unwrap_err();
        assert!(err.contains("points"), "{err}");
        assert_eq!(
            unit_points(Method::Sobol, 4, SOBOL_MAX_DIMS, 0)
                .unwrap()
                .len(),
            4
        );
    }
}
