// ln, sin and cos for the compiled rigs (src/compile/back/wgsl/mod.rs),
// precision-generic like shared/exp.wgsl: the built-in functions in f32 (EXP_NATIVE, from the
// prelude), our own in f64, where the SPIR-V extended instructions are not
// defined and lavapipe returns wrong values. Held against f64::ln, sin and cos
// by tests/gpu_exp_matches_std.rs.

// One step of ln_r's scaling: (m, k) to (m·2^∓n, k ± n) where m ≥ 2^n or
// m < 2^-n (up = 2^n and down = 2^-n, from the prelude: f32 cannot hold them).
// Multiplications by powers of two are exact; selected, not branched: lavapipe
// runs both sides of a branch, and a loop cost it more than these steps.
fn ln_scale(mk: vec2<real>, n: real, up: real, down: real) -> vec2<real> {
    let huge = mk.x >= up;
    let tiny = mk.x < down;
    let by = select(select(real(1.0), down, huge), up, tiny);
    let dk = select(select(real(0.0), n, huge), -n, tiny);
    return vec2<real>(mk.x * by, mk.y + dk);
}

// ln x for x > 0 (a run's constants never reach here: the host evaluates them),
// as fdlibm's e_log.c: x = 2^k·m with m in [√2/2, √2), f = m − 1,
// s = f/(2 + f), and ln m = f − f²/2 + s·(f²/2 + R(s²)) with fdlibm's minimax
// R (|error| < 2^-58.45), its even and odd terms in two chains.
fn ln_r(x: real) -> real {
    if EXP_NATIVE {
        return real(log(f32(x)));
    }
    // x into [2^-114, 2^64], where f32 holds it as a normal number, by 2^±512,
    // 2^±256, 2^±128 and 2^±64 where beyond each.
    var mk = vec2<real>(x, real(0.0));
    mk = ln_scale(mk, real(512.0), LN_2P512, real(1.0) / LN_2P512);
    mk = ln_scale(mk, real(256.0), LN_2P256, real(1.0) / LN_2P256);
    mk = ln_scale(mk, real(128.0), LN_2P128, real(1.0) / LN_2P128);
    mk = ln_scale(mk, real(64.0), LN_2P64, real(1.0) / LN_2P64);
    var m = mk.x;
    var k = mk.y;
    // m's exponent from f32's frexp (m's fraction in f64 lies in [0.5, 1),
    // or at 1 where f32's rounding carried into the exponent), then the
    // fraction taken into [√2/2, √2).
    let e = frexp(f32(m)).exp;
    m = ldexp(m, -e);
    let low = m < real(0.70710678118654752440);
    m = select(m, m * real(2.0), low);
    k += real(e - select(0, 1, low));
    let f = m - real(1.0);
    let s = f / (real(2.0) + f);
    let z = s * s;
    let w = z * z;
    let t1 = w * (real(3.999999999940941908e-01) + w * (real(2.222219843214978396e-01)
        + w * real(1.531383769920937332e-01)));
    let t2 = z * (real(6.666666666666735130e-01) + w * (real(2.857142874366239149e-01)
        + w * (real(1.818357216161805012e-01) + w * real(1.479819860511658591e-01))));
    let hfsq = real(0.5) * f * f;
    return k * EXP_LN2_HI - ((hfsq - (s * (hfsq + (t2 + t1)) + k * EXP_LN2_LO)) - f);
}

// sin r and cos r on |r| ≤ π/4 (fdlibm's kernel polynomials).
fn sincos_kernel(r: real) -> vec2<real> {
    let z = r * r;
    let sp = real(-1.66666666666666324348e-01) + z * (real(8.33333333332248946124e-03)
        + z * (real(-1.98412698298579493134e-04) + z * (real(2.75573137070700676789e-06)
        + z * (real(-2.50507602534068634195e-08) + z * real(1.58969099521155010221e-10)))));
    let cp = real(4.16666666666666019037e-02) + z * (real(-1.38888888888741095749e-03)
        + z * (real(2.48015872894767294178e-05) + z * (real(-2.75573143513906633035e-07)
        + z * (real(2.08757232129817482790e-09) + z * real(-1.13596475577881948265e-11)))));
    return vec2<real>(r + r * z * sp, (real(1.0) - real(0.5) * z) + z * z * cp);
}

// (sin x, cos x): x = k·π/2 + r with π/2 in three parts (fdlibm's), exact for
// |k| < 2^20, i.e. |x| up to about 1.6e6 rad.
fn sincos_r(x: real) -> vec2<real> {
    let k = floor(x * real(6.36619772367581382433e-01) + real(0.5));
    let r = ((x - k * real(1.57079632673412561417e+00)) - k * real(6.07710050630396597660e-11))
        - k * real(2.02226624871116645580e-21);
    let sc = sincos_kernel(r);
    let q = i32(k) & 3;
    let s = select(select(select(-sc.y, -sc.x, q == 2), sc.y, q == 1), sc.x, q == 0);
    let c = select(select(select(sc.x, -sc.y, q == 2), -sc.x, q == 1), sc.y, q == 0);
    return vec2<real>(s, c);
}

fn sin_r(x: real) -> real {
    if EXP_NATIVE {
        return real(sin(f32(x)));
    }
    return sincos_r(x).x;
}

fn cos_r(x: real) -> real {
    if EXP_NATIVE {
        return real(cos(f32(x)));
    }
    return sincos_r(x).y;
}
