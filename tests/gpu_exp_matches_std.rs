//! The shaders' own exp/expm1 (`shaders/shared/exp.wgsl`), run on the GPU, agree
//! with `f64::exp` and `f64::exp_m1` over their whole useful range: to a few ulp
//! in f64, to f32 rounding in f32 (where expm1 is the built-in exp minus 1).
mod oracle;
mod tensile_common;

mod gpu_common;
use gpu_common as common;

use rigfit::eval::Precision;
use rigfit::gpu::probe_exp;

/// Points over [lo, hi]: uniform, plus tiny magnitudes and multiples of ln 2
/// (the reduction's boundaries).
fn points(lo: f64, hi: f64) -> Vec<f64> {
    let mut xs: Vec<f64> = (0..=20_000)
        .map(|i| lo + (hi - lo) * i as f64 / 20_000.0)
        .collect();
    for e in -300..=0 {
        let x = 10f64.powf(e as f64 / 10.0);
        xs.extend([x, -x]);
    }
    let ln2 = std::f64::consts::LN_2;
    for k in (lo / ln2) as i64..=(hi / ln2) as i64 {
        let x = k as f64 * ln2;
        xs.extend([x, x + 0.5 * ln2, x - 0.5 * ln2, x + 1e-12, x - 1e-12]);
    }
    xs.retain(|x| (lo..=hi).contains(x));
    xs
}

fn rel(a: f64, b: f64) -> f64 {
    if a == b { 0.0 } else { (a - b).abs() / b.abs() }
}

#[test]
fn f64_exp_and_expm1_match_std_on_the_gpu() {
    let Some(ctx) = common::gpu() else { return };
    if !ctx.has_f64() {
        assert!(
            !rigfit::gpu::gpu_required(),
            "adapter {} has no SHADER_F64",
            ctx.describe()
        );
        eprintln!("adapter has no SHADER_F64; f64 exp test skipped");
        return;
    }
    let xs = points(-708.0, 709.0);
    let got = probe_exp(&ctx, Precision::F64, &xs).unwrap();
    let (mut worst_exp, mut worst_m1) = ((0.0, 0.0), (0.0, 0.0));
    for (&x, &(e, m1)) in xs.iter().zip(&got) {
        let re = rel(e, x.exp());
        let rm = rel(m1, x.exp_m1());
        if re > worst_exp.0 {
            worst_exp = (re, x);
        }
        if rm > worst_m1.0 {
            worst_m1 = (rm, x);
        }
    }
    eprintln!("f64 exp worst rel {worst_exp:?}, expm1 worst rel {worst_m1:?}");
    assert!(worst_exp.0 <= 1e-15, "exp: {worst_exp:?}");
    assert!(worst_m1.0 <= 1e-15, "expm1: {worst_m1:?}");
}

#[test]
fn f32_exp_and_expm1_match_std_to_f32_rounding() {
    let Some(ctx) = common::gpu() else { return };
    let xs = points(-80.0, 80.0);
    let got = probe_exp(&ctx, Precision::F32, &xs).unwrap();
    for (&x, &(e, m1)) in xs.iter().zip(&got) {
        let x32 = x as f32 as f64;
        assert!(rel(e, x32.exp()) <= 1e-6, "exp({x}) = {e}");
        // f32 expm1 is the built-in exp − 1: absolute error near 0, relative
        // elsewhere; lavapipe's f32 exp is good to about 1e-6 (≈ 8 ulp).
        let want = x32.exp_m1();
        assert!(
            (m1 - want).abs() <= 4e-6 * want.abs().max(1.0),
            "expm1({x}) = {m1}"
        );
    }
}

/// ln, sin and cos of `shaders/shared/math.wgsl` (the compiled rigs' Ln, Sin and
/// Cos operations): f64 to 1e-15 relative for ln over the whole positive range (next to 1, at
/// every power of two its reduction turns on, subnormal) and to 1e-15
/// of 1 for sin and cos up to |x| = 1e5 rad; f32 (the built-in functions) to
/// 1e-6 there.
#[test]
fn ln_sin_and_cos_match_std_on_the_gpu() {
    let Some(ctx) = common::gpu() else { return };
    let mut xs: Vec<f64> = (-3000..=3000)
        .map(|e| 10f64.powf(e as f64 / 10.0))
        .collect();
    xs.retain(|x| x.is_finite() && *x > 0.0);
    // Where ln's reduction turns: each power of two it scales by (and the
    // f64 range's ends), the fraction's √2/2, and next to 1, where ln x is
    // small and held to its own size.
    let ulp_around = |x: f64| [x.next_down(), x, x.next_up()];
    for n in [64, 128, 256, 512] {
        for x in [2f64.powi(n), 2f64.powi(-n)] {
            xs.extend(ulp_around(x));
        }
    }
    xs.extend(ulp_around(std::f64::consts::FRAC_1_SQRT_2));
    xs.extend(ulp_around(std::f64::consts::SQRT_2));
    xs.extend([f64::MAX, f64::MIN_POSITIVE, 1e-310, 5e-324]);
    for d in [1e-3, 1e-6, 1e-9, 1e-12, f64::EPSILON] {
        xs.extend([1.0 + d, 1.0 - d]);
    }
    let trig: Vec<f64> = (-20_000..=20_000)
        .map(|i| i as f64 * 5.0 + 0.123 * i as f64 / 20_000.0)
        .chain((-2000..=2000).map(|i| i as f64 * std::f64::consts::FRAC_PI_4))
        .collect();
    for precision in [Precision::F64, Precision::F32] {
        if precision == Precision::F64 && !ctx.has_f64() {
            assert!(!rigfit::gpu::gpu_required(), "no SHADER_F64");
            continue;
        }
        let (ln_tol, trig_tol, ln_range) = match precision {
            Precision::F64 => (1e-15, 1e-15, 0.0..f64::INFINITY),
            Precision::F32 => (1e-6, 1e-6, 1e-30..1e30),
        };
        let ln_points: Vec<f64> = xs
            .iter()
            .copied()
            .filter(|x| ln_range.contains(x))
            .collect();
        let got = rigfit::gpu::probe_math(&ctx, precision, &ln_points).unwrap();
        let mut worst: f64 = 0.0;
        for (x, p) in ln_points.iter().zip(&got) {
            let want = match precision {
                Precision::F64 => x.ln(),
                Precision::F32 => (*x as f32 as f64).ln(),
            };
            // Relative to ln x itself in f64 (next to 1 too); the f32
            // built-in to the larger of it and 1.
            let scale = match precision {
                Precision::F64 => want.abs().max(f64::MIN_POSITIVE),
                Precision::F32 => want.abs().max(1.0),
            };
            let err = (p.ln - want).abs() / scale;
            worst = worst.max(err);
            assert!(
                err <= ln_tol,
                "{precision:?} ln({x:e}) = {} vs {want}",
                p.ln
            );
        }
        println!("{precision:?} ln: largest error {worst:.2e}");
        let trig: Vec<f64> = match precision {
            Precision::F64 => trig.clone(),
            // f32 arguments: the kernel sees x rounded to f32, and the built-in
            // functions are accurate to a few ulp only within a few periods.
            Precision::F32 => trig.iter().map(|x| x / 1e4).collect(),
        };
        let got = rigfit::gpu::probe_math(&ctx, precision, &trig).unwrap();
        let mut worst: f64 = 0.0;
        for (x, p) in trig.iter().zip(&got) {
            let xr = match precision {
                Precision::F64 => *x,
                Precision::F32 => *x as f32 as f64,
            };
            let (es, ec) = ((p.sin - xr.sin()).abs(), (p.cos - xr.cos()).abs());
            worst = worst.max(es).max(ec);
            assert!(
                es <= trig_tol && ec <= trig_tol,
                "{precision:?} x = {x}: sin {} vs {}, cos {} vs {}",
                p.sin,
                xr.sin(),
                p.cos,
                xr.cos()
            );
        }
        println!("{precision:?} sin, cos: largest error {worst:.2e}");
    }
}
