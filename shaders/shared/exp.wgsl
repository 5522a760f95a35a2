// Precision-generic exponential and expm1 built from +, *, floor and ldexp only.
//
// lavapipe compiles the f64 forms of exp/log/pow but returns wrong values (the
// SPIR-V extended instructions are only defined for 16/32-bit floats), so both
// precisions use this code. Cody-Waite reduction x = k·ln2 + r, |r| ≤ ln2/2,
// then a Taylor polynomial (degree 13 in f64: truncation < 1e-17 relative), then 2^k by
// ldexp. Tested against f64::exp / f64::exp_m1 in tests/gpu_exp_matches_std.rs.
// Range: exp_r returns 0 below -745 and saturates at x = 709 (e^709 ≈ 8.2e307);
// expm1_r returns exactly -1 below -40 (as f64::exp_m1 rounds there).

// EXP_LN2_HI (ln 2 with enough trailing zero bits that k·EXP_LN2_HI is exact)
// and EXP_LN2_LO = ln 2 − EXP_LN2_HI differ per precision; the prelude
// (src/gpu/shaders.rs) defines them.
const EXP_INV_LN2: real = 1.44269504088896338700e+00;

// e^r − 1 for |r| ≤ ln2/2: degree 13 for f64, degree 8 for f32 (truncation
// below 1e-9 relative); EXP_FULL_DEGREE comes from the prelude. The f64 form is
// evaluated by Estrin's scheme (powers r², r⁴, r⁸) rather than Horner's: the
// slack law's expm1 sits on the RK4 stages' dependency chain, and this cuts its
// latency from 13 dependent multiply-adds to about 5.
fn expm1_poly(r: real) -> real {
    if EXP_FULL_DEGREE {
        let r2 = r * r;
        let r4 = r2 * r2;
        let r8 = r4 * r4;
        // q(r) = Σ r^i/(i+1)!, i = 0..12, in pairs, then pairs of pairs.
        let a0 = real(1.0) + real(0.5) * r;
        let a1 = real(1.0 / 6.0) + real(1.0 / 24.0) * r;
        let a2 = real(1.0 / 120.0) + real(1.0 / 720.0) * r;
        let a3 = real(1.0 / 5040.0) + real(1.0 / 40320.0) * r;
        let a4 = real(1.0 / 362880.0) + real(1.0 / 3628800.0) * r;
        let a5 = real(1.0 / 39916800.0) + real(1.0 / 479001600.0) * r;
        let a6 = real(1.0 / 6227020800.0);
        let b0 = a0 + a1 * r2;
        let b1 = a2 + a3 * r2;
        let b2 = a4 + a5 * r2;
        let d0 = b0 + b1 * r4;
        let d1 = b2 + a6 * r4;
        return (d0 + d1 * r8) * r;
    }
    var p = real(1.0 / 40320.0);
    p = p * r + real(1.0 / 5040.0);
    p = p * r + real(1.0 / 720.0);
    p = p * r + real(1.0 / 120.0);
    p = p * r + real(1.0 / 24.0);
    p = p * r + real(1.0 / 6.0);
    p = p * r + real(0.5);
    p = p * r + real(1.0);
    return p * r;
}

// Splits x (already clamped) into k and r with x = k·ln2 + r.
fn exp_reduce(x: real) -> vec2<real> {
    let k = floor(x * EXP_INV_LN2 + real(0.5));
    let r = (x - k * EXP_LN2_HI) - k * EXP_LN2_LO;
    return vec2<real>(k, r);
}

// e^x. Selects, not branches: CPU drivers run both sides of a branch anyway.
fn exp_r(x: real) -> real {
    let kr = exp_reduce(clamp(x, real(-746.0), real(709.0)));
    let e = ldexp(expm1_poly(kr.y) + real(1.0), i32(kr.x));
    return select(e, real(0.0), x < real(-745.0));
}

// e^x where a few ulp do not matter: the built-in exp in f32 (EXP_NATIVE), exp_r
// in f64 (lavapipe's f64 exp is wrong).
fn exp_n(x: real) -> real {
    if EXP_NATIVE {
        return exp(x);
    }
    return exp_r(x);
}

// e^x − 1. In f64 accurate near 0; in f32 (EXP_NATIVE, from the prelude) the
// built-in exp minus 1, whose absolute error (≈ 1e-7) is below what the model's
// f32 forces resolve anyway, at less than half the cost.
fn expm1_r(x: real) -> real {
    if EXP_NATIVE {
        return exp(x) - real(1.0);
    }
    let kr = exp_reduce(clamp(x, real(-41.0), real(709.0)));
    let p = expm1_poly(kr.y);
    // 2^k·p + (2^k − 1): the second term is exact, so no cancellation near k = ±1;
    // for k = 0 it is p + 0 = p exactly.
    let two_k = ldexp(real(1.0), i32(kr.x));
    return select(two_k * p + (two_k - real(1.0)), real(-1.0), x < real(-40.0));
}
