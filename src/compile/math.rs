//! `eˣ`, `eˣ − 1`, `ln x`, `sin x` and `cos x` for the compiled rigs, the
//! same bits on every CPU path. `eˣ`, `eˣ − 1` and `ln` are written with `+`,
//! `·`, `/`, comparisons and bit operations only, so a loop over lanes of
//! candidates vectorises ([`crate::compile::exec::lanes`]) where a call into
//! the C library's `exp` or `log` does not; `sin` and `cos` here take the
//! branches one value needs, and the C lanes
//! ([`crate::compile::back::c`]) a branch-free vector form with the same
//! bits (a power law's `|x|^β` is `exp(β·ln|x|)`: on the inertial rig the C
//! library's `log`, called lane by lane, took 40 % of a CPU job; on the
//! friction rig, whose sine drive's frequency is fitted, its `sin` took
//! 43 %).
//!
//! The scalar reference ([`crate::compile::ir::eval_op`]), the lane ensemble and the
//! constant folder all call these, so every CPU path rounds alike. The algorithm
//! is `shaders/shared/exp.wgsl`'s f64 form: Cody–Waite reduction `x = k·ln2 + r`
//! with `|r| ≤ ln2/2` (fdlibm's split of ln 2), the degree-13 Taylor polynomial
//! of `(eʳ − 1)/r` by Estrin's scheme, then `2ᵏ` built in the exponent bits. The
//! one difference from the WGSL: `k` is `x/ln2` rounded to nearest by the
//! 1.5·2⁵² shift rather than `floor(x/ln2 + ½)` (they differ only on exact
//! ties). Held within 2 ulp of the C library over the whole range by the tests
//! below.
//!
//! `ln` is fdlibm's `__ieee754_log` (Sun Microsystems, 1993) without its
//! branches: `x = 2ᵏ·(1 + f)` with `√2/2 ≤ 1 + f < √2` (a subnormal `x`
//! scaled by 2⁵⁴ first), `s = f/(2 + f)`, `ln(1 + f) = f − ½f² + s·(½f² + R(s²))`
//! with fdlibm's degree-7 minimax `R`, and `k·ln2` added in the two parts
//! `exp` reduces by; the
//! cases fdlibm branches on (`f = 0`, `k = 0`) are the same formula with
//! zeros, so every input takes one path, and zero, negative, infinite and
//! NaN inputs are picked at the end. Within 1 ulp of the C library (tests
//! below).
//!
//! `sin` and `cos` are fdlibm's (`__ieee754_rem_pio2`'s medium-size case,
//! `__kernel_sin`, and `__kernel_cos` in the form without its high-word
//! split): `x = n·π/2 + (y₀ + y₁)` by `π/2` in three 33-bit splits, a round
//! taken only where the one before cancelled, then the kernel `n mod 4` asks
//! for on `y₀ + y₁`, signed by it (the C lanes compute both kernels and every
//! round any lane needs, and pick per lane: the same bits). Beyond
//! [`TRIG_REDUCED_UP_TO`] (where `n·π/2`'s first split stops being exact),
//! and at ±∞ and NaN, they call the C library, as the C lanes do lane by lane.
//! Within 1 ulp of the C library (tests below).

const INV_LN2: f64 = std::f64::consts::LOG2_E;
const LN2_HI: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000);
const LN2_LO: f64 = 1.908_214_929_270_587_7e-10;
/// 1.5·2⁵²: `(v + SHIFT) − SHIFT` rounds `|v| < 2⁵¹` to the nearest integer,
/// and the low bits of `v + SHIFT` hold it.
const SHIFT: f64 = 6_755_399_441_055_744.0;
/// Largest `x` with a finite `eˣ`.
const EXP_MAX: f64 = 709.782_712_893_384;

/// `(eʳ − 1)` for `|r| ≤ ln2/2`: `r·Σ rⁱ/(i+1)!`, `i = 0..12`.
#[inline(always)]
fn expm1_poly(r: f64) -> f64 {
    let r2 = r * r;
    let r4 = r2 * r2;
    let r8 = r4 * r4;
    let a0 = 1.0 + 0.5 * r;
    let a1 = 1.0 / 6.0 + 1.0 / 24.0 * r;
    let a2 = 1.0 / 120.0 + 1.0 / 720.0 * r;
    let a3 = 1.0 / 5040.0 + 1.0 / 40320.0 * r;
    let a4 = 1.0 / 362_880.0 + 1.0 / 3_628_800.0 * r;
    let a5 = 1.0 / 39_916_800.0 + 1.0 / 479_001_600.0 * r;
    let a6 = 1.0 / 6_227_020_800.0;
    let b0 = a0 + a1 * r2;
    let b1 = a2 + a3 * r2;
    let b2 = a4 + a5 * r2;
    let d0 = b0 + b1 * r4;
    let d1 = b2 + a6 * r4;
    (d0 + d1 * r8) * r
}

/// `(k, r)` with `x = k·ln2 + r`, `k` an integer-valued float.
#[inline(always)]
fn reduce(x: f64) -> (f64, f64) {
    let k = (x * INV_LN2 + SHIFT) - SHIFT;
    (k, (x - k * LN2_HI) - k * LN2_LO)
}

/// `2ᵏ` for an integer-valued `k` in `[−1022, 1023]`, from the exponent bits.
#[inline(always)]
fn pow2(k: f64) -> f64 {
    f64::from_bits((k + (1023.0 + SHIFT)).to_bits() << 52)
}

/// `eˣ`: 0 below −745.2, +∞ above `EXP_MAX` (709.78…), NaN for NaN.
#[inline(always)]
pub fn exp(x: f64) -> f64 {
    let (k, r) = reduce(x.clamp(-746.0, EXP_MAX));
    // 2ᵏ in two factors, each normal, so subnormal results round once.
    let k1 = (0.5 * k + SHIFT) - SHIFT;
    let e = (expm1_poly(r) + 1.0) * pow2(k1) * pow2(k - k1);
    if x < -745.2 {
        0.0
    } else if x > EXP_MAX {
        f64::INFINITY
    } else {
        e
    }
}

/// `eˣ − 1`, accurate near 0: exactly −1 below −40, `e⁷⁰⁹ − 1` from 709 to
/// `EXP_MAX` (saturated, as the WGSL form is: a run that far has diverged
/// anyway), +∞ above, NaN for NaN.
#[inline(always)]
pub fn expm1(x: f64) -> f64 {
    let (k, r) = reduce(x.clamp(-41.0, 709.0));
    let p = expm1_poly(r);
    // 2ᵏ·p + (2ᵏ − 1): the second term is exact, so nothing cancels near k = ±1,
    // and for k = 0 this is p exactly.
    let two_k = pow2(k);
    let v = two_k * p + (two_k - 1.0);
    if x < -40.0 {
        -1.0
    } else if x > EXP_MAX {
        f64::INFINITY
    } else {
        v
    }
}

/// fdlibm's `Lg1`–`Lg7`: `R(z) ≈ Σ Lgᵢ·zⁱ` with `z = s²`.
const LG: [f64; 7] = [
    f64::from_bits(0x3fe5_5555_5555_5593),
    f64::from_bits(0x3fd9_9999_9997_fa04),
    f64::from_bits(0x3fd2_4924_9422_9359),
    f64::from_bits(0x3fcc_71c5_1d8e_78af),
    f64::from_bits(0x3fc7_4664_96cb_03de),
    f64::from_bits(0x3fc3_9a09_d078_c69f),
    f64::from_bits(0x3fc2_f112_df3e_5244),
];
/// 2⁵⁴, which scales a subnormal input to a normal one.
const TWO54: f64 = 18_014_398_509_481_984.0;
/// The bits added to move `1 + f` into `[√2/2, √2)` (fdlibm's `0x3fe6a09e`
/// in the high word).
const SQRT_HALF_BITS: u64 = 0x3fe6_a09e_0000_0000;

/// `ln x`: −∞ at ±0, NaN below 0 and for NaN, +∞ at +∞.
#[inline(always)]
pub fn ln(x: f64) -> f64 {
    let tiny = x < f64::MIN_POSITIVE;
    let xs = if tiny { x * TWO54 } else { x };
    // The exponent of x with its significand moved into [√2/2, √2).
    let b = xs
        .to_bits()
        .wrapping_add(0x3ff0_0000_0000_0000 - SQRT_HALF_BITS);
    let k = ((b >> 52) & 0x7ff) as f64 - 1023.0 - if tiny { 54.0 } else { 0.0 };
    let f = f64::from_bits((b & 0x000f_ffff_ffff_ffff) + SQRT_HALF_BITS) - 1.0;
    let hfsq = 0.5 * f * f;
    let s = f / (2.0 + f);
    let z = s * s;
    let w = z * z;
    let t1 = w * (LG[1] + w * (LG[3] + w * LG[5]));
    let t2 = z * (LG[0] + w * (LG[2] + w * (LG[4] + w * LG[6])));
    let r = t2 + t1;
    let v = k * LN2_HI - ((hfsq - (s * (hfsq + r) + k * LN2_LO)) - f);
    if x > 0.0 {
        if x == f64::INFINITY { x } else { v }
    } else if x == 0.0 {
        f64::NEG_INFINITY
    } else {
        f64::NAN
    }
}

/// `2/π`, and `π/2` in fdlibm's three splits: each `PIO2_i` has its low bits
/// zero (33 significant bits), so `n·PIO2_i` is exact for `|n| < 2²⁰`, and
/// `PIO2_iT` is the rest of `π/2` after it.
const INV_PIO2: f64 = f64::from_bits(0x3fe4_5f30_6dc9_c883);
const PIO2_1: f64 = f64::from_bits(0x3ff9_21fb_5440_0000);
const PIO2_1T: f64 = f64::from_bits(0x3dd0_b461_1a62_6331);
const PIO2_2: f64 = f64::from_bits(0x3dd0_b461_1a60_0000);
const PIO2_2T: f64 = f64::from_bits(0x3ba3_198a_2e03_7073);
const PIO2_3: f64 = f64::from_bits(0x3ba3_198a_2e00_0000);
const PIO2_3T: f64 = f64::from_bits(0x397b_839a_2520_49c1);
/// Largest `|x|` [`sin`] and [`cos`] reduce themselves (`x·2/π` below 2²⁰,
/// so `n·PIO2_1` is exact); beyond it, and for ±∞ and NaN, they are the C
/// library's.
pub const TRIG_REDUCED_UP_TO: f64 = 1.0e6;
/// fdlibm's `S1`–`S6`: `sin r ≈ r + r³·Σ Sᵢ·r²⁽ⁱ⁻¹⁾` on `|r| ≤ π/4`.
const S: [f64; 6] = [
    f64::from_bits(0xbfc5_5555_5555_5549),
    f64::from_bits(0x3f81_1111_1110_f8a6),
    f64::from_bits(0xbf2a_01a0_19c1_61d5),
    f64::from_bits(0x3ec7_1de3_57b1_fe7d),
    f64::from_bits(0xbe5a_e5e6_8a2b_9ceb),
    f64::from_bits(0x3de5_d93a_5acf_d57c),
];
/// fdlibm's `C1`–`C6`: `cos r ≈ 1 − r²/2 + r⁴·Σ Cᵢ·r²⁽ⁱ⁻¹⁾`.
const C: [f64; 6] = [
    f64::from_bits(0x3fa5_5555_5555_554c),
    f64::from_bits(0xbf56_c16c_16c1_5177),
    f64::from_bits(0x3efa_01a0_19cb_1590),
    f64::from_bits(0xbe92_7e4f_809c_52ad),
    f64::from_bits(0x3e21_ee9e_bdb4_b1c4),
    f64::from_bits(0xbda8_fae9_be88_38d4),
];

/// The biased exponent of `x`.
#[inline(always)]
fn exponent(x: f64) -> i64 {
    ((x.to_bits() >> 52) & 0x7ff) as i64
}

/// `x = n·π/2 + (y₀ + y₁)` with `|y₀ + y₁| ≤ π/4` (about), `n mod 4` as an
/// integer: fdlibm's medium-size reduction (`__ieee754_rem_pio2`), a second
/// round where the first cancelled more than 16 bits, a third where the
/// second cancelled more than 49, for `|x| ≤` [`TRIG_REDUCED_UP_TO`]. (The C
/// lanes compute the later rounds where any lane needs them and each lane
/// keeps the round this stops at: the same bits.)
#[inline(always)]
fn reduce_pio2(x: f64) -> (f64, f64, u64) {
    let shifted = x * INV_PIO2 + SHIFT;
    let n = shifted - SHIFT;
    let j = exponent(x);
    let mut r = x - n * PIO2_1;
    let mut w = n * PIO2_1T;
    let mut y0 = r - w;
    // One further round, from the last one's `r`.
    let round = |r: &mut f64, w: &mut f64, y0: &mut f64, p: f64, pt: f64| {
        let t = *r;
        let q = n * p;
        *r = t - q;
        *w = n * pt - ((t - *r) - q);
        *y0 = *r - *w;
    };
    if j - exponent(y0) > 16 {
        round(&mut r, &mut w, &mut y0, PIO2_2, PIO2_2T);
        if j - exponent(y0) > 49 {
            round(&mut r, &mut w, &mut y0, PIO2_3, PIO2_3T);
        }
    }
    (y0, (r - y0) - w, shifted.to_bits() & 3)
}

/// `sin(y₀ + y₁)` for `|y₀ + y₁| ≤ π/4`, `y₁` the tail of `y₀`.
#[inline(always)]
fn sin_kernel(x: f64, y: f64) -> f64 {
    let z = x * x;
    let w = z * z;
    let r = S[1] + z * (S[2] + z * S[3]) + z * w * (S[4] + z * S[5]);
    let v = z * x;
    x - ((z * (0.5 * y - v * r) - y) - v * S[0])
}

/// `cos(y₀ + y₁)` for `|y₀ + y₁| ≤ π/4`.
#[inline(always)]
fn cos_kernel(x: f64, y: f64) -> f64 {
    let z = x * x;
    let w = z * z;
    let r = z * (C[0] + z * (C[1] + z * C[2])) + w * w * (C[3] + z * (C[4] + z * C[5]));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    w + (((1.0 - w) - hz) + (z * r - x * y))
}

/// `sin x`, or `cos x` where `cos`: the kernel for the reduced argument's
/// quadrant, signed by it.
#[inline(always)]
fn trig(x: f64, cos: bool) -> f64 {
    if x.is_nan() || x.abs() > TRIG_REDUCED_UP_TO {
        return if cos { x.cos() } else { x.sin() };
    }
    let (y0, y1, n) = reduce_pio2(x);
    // sin: s, c, −s, −c by quadrant; cos: c, −s, −c, s.
    let n = if cos { n + 1 } else { n };
    let v = if n & 1 == 1 {
        cos_kernel(y0, y1)
    } else {
        sin_kernel(y0, y1)
    };
    if n & 2 == 2 { -v } else { v }
}

/// `sin x`: within 1 ulp of the C library (its `sin` beyond
/// [`TRIG_REDUCED_UP_TO`], at ±∞ and NaN).
#[inline(always)]
pub fn sin(x: f64) -> f64 {
    trig(x, false)
}

/// `cos x`, as [`sin`].
#[inline(always)]
pub fn cos(x: f64) -> f64 {
    trig(x, true)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance in units in the last place (same sign, finite).
    fn ulps(a: f64, b: f64) -> u64 {
        if a == b {
            return 0;
        }
        assert_eq!(a.signum(), b.signum(), "{a} vs {b}");
        a.abs().to_bits().abs_diff(b.abs().to_bits())
    }

    /// Points spread over `[lo, hi]` (a seeded linear congruential sequence plus
    /// the ends and zero).
    fn points(lo: f64, hi: f64) -> Vec<f64> {
        let mut s: u64 = 0x2545_f491_4f6c_dd1d;
        let mut v: Vec<f64> = (0..200_000)
            .map(|_| {
                s = s.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
                lo + (hi - lo) * ((s >> 11) as f64 / (1u64 << 53) as f64)
            })
            .collect();
        v.extend([lo, hi, 0.0, -0.0, 1e-300, -1e-300, 1e-12, -1e-12]);
        v
    }

    #[test]
    fn exp_within_two_ulp_of_the_c_library() {
        let mut worst = 0;
        for x in points(-708.0, 709.0).into_iter().chain(points(-2.0, 2.0)) {
            worst = worst.max(ulps(exp(x), x.exp()));
        }
        assert!(worst <= 2, "{worst} ulp");
        // Subnormal results, underflow, overflow and NaN.
        for x in [-740.0, -744.5, -745.1] {
            let (a, b) = (exp(x), x.exp());
            assert!((a - b).abs() <= 2.0 * 5e-324, "{x}: {a} vs {b}");
        }
        assert_eq!(exp(-746.0), 0.0);
        assert_eq!(exp(-1e300), 0.0);
        assert_eq!(exp(710.0), f64::INFINITY);
        assert_eq!(exp(f64::INFINITY), f64::INFINITY);
        assert_eq!(exp(f64::NEG_INFINITY), 0.0);
        assert!(exp(f64::NAN).is_nan());
        assert_eq!(exp(709.7), 709.7_f64.exp());
    }

    #[test]
    fn ln_within_one_ulp_of_the_c_library() {
        let mut worst = 0;
        let ranges = [
            points(0.0, 4.0),
            points(0.5, 2.0),
            points(1.0 - 1e-6, 1.0 + 1e-6),
            points(0.0, 1e-300),
            points(0.0, 1e300),
        ];
        for x in ranges.into_iter().flatten().filter(|&x| x > 0.0) {
            worst = worst.max(ulps(ln(x), x.ln()));
        }
        // Over every binade: powers of two and their neighbours,
        // subnormals included.
        for e in -1074..1024 {
            let p = 2f64.powi(e);
            for x in [
                p,
                f64::from_bits(p.to_bits() + 1),
                1.5 * p,
                p * std::f64::consts::SQRT_2,
            ] {
                if x.is_finite() && x > 0.0 {
                    worst = worst.max(ulps(ln(x), x.ln()));
                }
            }
        }
        assert!(worst <= 1, "{worst} ulp");
        assert_eq!(ln(1.0).to_bits(), 0.0f64.to_bits());
        assert_eq!(ln(0.0), f64::NEG_INFINITY);
        assert_eq!(ln(-0.0), f64::NEG_INFINITY);
        assert_eq!(ln(5e-324), 5e-324f64.ln());
        assert_eq!(ln(f64::MAX), f64::MAX.ln());
        assert_eq!(ln(f64::INFINITY), f64::INFINITY);
        assert!(ln(-1.0).is_nan());
        assert!(ln(f64::NEG_INFINITY).is_nan());
        assert!(ln(f64::NAN).is_nan());
    }

    #[test]
    fn sin_and_cos_within_one_ulp_of_the_c_library() {
        let mut worst = (0, 0.0);
        let mut check = |x: f64| {
            for (a, b) in [(sin(x), x.sin()), (cos(x), x.cos())] {
                let u = ulps(a, b);
                if u > worst.0 {
                    worst = (u, x);
                }
            }
        };
        let ranges = [
            points(-std::f64::consts::FRAC_PI_4, std::f64::consts::FRAC_PI_4),
            points(-10.0, 10.0),
            points(-1e3, 1e3),
            points(-TRIG_REDUCED_UP_TO, TRIG_REDUCED_UP_TO),
            points(-1e-8, 1e-8),
        ];
        ranges.into_iter().flatten().for_each(&mut check);
        // Next to multiples of π/2, where the reduction cancels most, and
        // over every binade below the limit, subnormals included.
        for k in 1..200_000_i64 {
            let x = (k as f64 * std::f64::consts::FRAC_PI_2).min(TRIG_REDUCED_UP_TO);
            for d in -2..=2_i64 {
                let y = f64::from_bits(x.to_bits().wrapping_add_signed(d));
                check(y);
                check(-y);
            }
        }
        for e in -1074..20 {
            let p = 2f64.powi(e);
            for x in [p, f64::from_bits(p.to_bits() + 1), 1.5 * p] {
                check(x);
                check(-x);
            }
        }
        assert!(worst.0 <= 1, "{} ulp at {:e}", worst.0, worst.1);
        // Signed zeros, and the C library's own beyond the limit and at
        // ±∞ and NaN.
        assert_eq!(sin(-0.0).to_bits(), (-0.0f64).to_bits());
        assert_eq!(sin(0.0).to_bits(), 0.0f64.to_bits());
        assert_eq!(cos(-0.0), 1.0);
        for x in [1.5e6, -3e9, 1e300, f64::MAX] {
            assert_eq!(sin(x).to_bits(), x.sin().to_bits(), "{x}");
            assert_eq!(cos(x).to_bits(), x.cos().to_bits(), "{x}");
        }
        for x in [f64::INFINITY, f64::NEG_INFINITY, f64::NAN] {
            assert!(sin(x).is_nan() && cos(x).is_nan());
        }
    }

    #[test]
    fn expm1_within_four_ulp_of_the_c_library() {
        let mut worst = 0;
        for x in points(-45.0, 709.0)
            .into_iter()
            .chain(points(-1.0, 1.0))
            .chain(points(-1e-6, 1e-6))
        {
            worst = worst.max(ulps(expm1(x), x.exp_m1()));
        }
        // The Estrin sum's roundings show for k = 0 (|x| < ln2/2).
        assert!(worst <= 4, "{worst} ulp");
        assert_eq!(expm1(0.0), 0.0);
        assert_eq!(expm1(-50.0), -1.0);
        assert_eq!(expm1(f64::NEG_INFINITY), -1.0);
        assert_eq!(expm1(710.0), f64::INFINITY);
        assert!(expm1(f64::NAN).is_nan());
        // Saturated between 709 and EXP_MAX, as the WGSL form is.
        assert_eq!(expm1(709.5), expm1(709.0));
    }
}
