//! The shaders' own exp/expm1 (`shaders/shared/exp.wgsl`), run on the GPU, agree
//! with `f64::exp` and `f64::exp_m1` over their whole useful range: to a few ulp
//! in f64, to f32 rounding in f32 (where expm1 is the built-in exp minus 1).

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
