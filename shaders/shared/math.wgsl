// ln, sin and cos for the compiled rigs (src/compile/wgsl.rs), precision-generic
// like shared/exp.wgsl: the built-in functions in f32 (EXP_NATIVE, from the
// prelude), our own in f64, where the SPIR-V extended instructions are not
// defined and lavapipe returns wrong values. Held against f64::ln, sin and cos
// by tests/gpu_math_matches_std.rs.

// ln x for x > 0 (a run's constants never reach here: the host evaluates them).
// x = 2^k·m with |ln m| ≤ ln2/2 (k from an f32 log2 after scaling x into f32's
// range), then ln m = 2·atanh(s), s = (m − 1)/(m + 1), |s| ≤ 0.172, by its series
// to s^23 (truncation below 1e-17 relative).
fn ln_r(x: real) -> real {
    if EXP_NATIVE {
        return real(log(f32(x)));
    }
    // Scale m into [1e-30, 1e30], where f32 holds it: by 2^±340 while beyond
    // LN_COARSE = 1e150 (three times reach 1e±308; the prelude defines it, as
    // f32 cannot hold it), then by 2^±100 (four times).
    var m = x;
    var k = real(0.0);
    for (var i = 0u; i < 3u; i += 1u) {
        let tiny = m < real(1.0) / LN_COARSE;
        let huge = m > LN_COARSE;
        m = select(select(m, ldexp(m, -340), huge), ldexp(m, 340), tiny);
        k += select(select(real(0.0), real(340.0), huge), real(-340.0), tiny);
    }
    for (var i = 0u; i < 4u; i += 1u) {
        let tiny = m < real(1e-30);
        let huge = m > real(1e30);
        m = select(select(m, ldexp(m, -100), huge), ldexp(m, 100), tiny);
        k += select(select(real(0.0), real(100.0), huge), real(-100.0), tiny);
    }
    let e = floor(real(log2(f32(m))) + real(0.5));
    m = ldexp(m, -i32(e));
    k += e;
    let s = (m - real(1.0)) / (m + real(1.0));
    let z = s * s;
    var p = real(1.0 / 23.0);
    p = p * z + real(1.0 / 21.0);
    p = p * z + real(1.0 / 19.0);
    p = p * z + real(1.0 / 17.0);
    p = p * z + real(1.0 / 15.0);
    p = p * z + real(1.0 / 13.0);
    p = p * z + real(1.0 / 11.0);
    p = p * z + real(1.0 / 9.0);
    p = p * z + real(1.0 / 7.0);
    p = p * z + real(1.0 / 5.0);
    p = p * z + real(1.0 / 3.0);
    let lnm = real(2.0) * s + real(2.0) * s * z * p;
    return k * EXP_LN2_HI + (k * EXP_LN2_LO + lnm);
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
