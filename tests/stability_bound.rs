//! Proves the compiled tensile rig's `omega_bound`, the bound used to choose or
//! refuse the RK4 step: for random parameter vectors inside the bounds, and
//! tangent stiffnesses anywhere on the specimen and slack-adapter laws, the
//! largest |eigenvalue| of the linearised first-order system
//! `[[0, I], [−M⁻¹K, −M⁻¹C]]` never exceeds it; RK4 with `h·bound ≤ 2` is stable
//! on that system, and a step far above it blows up. The matrices come from the
//! hand-written oracle (tests/oracle), independent of the compiled rig.

mod oracle;
mod tensile_common;

use nalgebra::DMatrix;
use oracle::systems::{LinearSystem, integrate_fixed};
use oracle::tensile::{MAX_POLY_DEGREE, REFERENCE, ix, linearise, slack_knee};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rigfit::base::{Drive, PiecewiseLinear};
use tensile_common::tensile4;

/// Search bounds around the reference: ×0.5…×2 on every positive parameter,
/// explicit ranges where the reference is zero or signed.
fn bounds() -> (Vec<f64>, Vec<f64>) {
    let r = REFERENCE;
    let (mut lo, mut hi): (Vec<f64>, Vec<f64>) = r.iter().map(|&x| (0.5 * x, 2.0 * x)).unzip();
    let mut set = |i: usize, a: f64, b: f64| {
        lo[i] = a;
        hi[i] = b;
    };
    set(ix::A0 + 2, -2e9, 0.0);
    set(ix::A0 + 4, -1e13, 1e13);
    set(ix::A0 + 5, -1e16, 1e16);
    set(ix::C2, 0.0, 2e3);
    set(ix::C3, 0.0, 5e3);
    set(ix::E_YIELD, 3e-5, 8e-5);
    set(ix::E_FRACTURE, 1e-4, 2e-3);
    (lo, hi)
}

/// Largest |eigenvalue| of the first-order system for mass `m`, tangent stiffness
/// `k` and damping `c` matrices, and that matrix itself (row-major).
fn first_order(m: &[f64], k: &[f64], c: &[f64]) -> (f64, Vec<f64>) {
    let n = m.len();
    let a = DMatrix::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
        (true, true) => 0.0,
        (true, false) => f64::from(u8::from(j - n == i)),
        (false, true) => -k[(i - n) * n + j] / m[i - n],
        (false, false) => -c[(i - n) * n + (j - n)] / m[i - n],
    });
    let lam = a
        .complex_eigenvalues()
        .iter()
        .map(|z| z.norm())
        .fold(0.0, f64::max);
    (lam, a.transpose().as_slice().to_vec())
}

/// M, tangent K and C of `p` at specimen strain `e` and slack opening `d`, from
/// the oracle's linearisation with the tangent stiffnesses put in the springs'
/// slots. The damping matrix has the springs' topology, so it is assembled the
/// same way with the dampers in the springs' slots.
fn matrices(
    p: &[f64],
    drive: &Drive,
    e: f64,
    d: f64,
    broken: bool,
) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut q = p.to_vec();
    q[ix::K_LIN] = if e <= p[ix::E_YIELD] {
        p[ix::K_LIN]
    } else {
        (1..=MAX_POLY_DEGREE)
            .map(|i| i as f64 * p[ix::A0 + i] * e.powi(i as i32 - 1))
            .sum()
    };
    let ds = slack_knee(
        p[ix::SLACK_A],
        p[ix::SLACK_B],
        p[ix::SLACK_C],
        p[ix::K4_LIN],
    );
    if d <= ds {
        q[ix::K4_LIN] = p[ix::SLACK_A] * (p[ix::SLACK_B] * d).exp() + p[ix::SLACK_C];
    }
    let lin = linearise(&q, drive);
    let mut cq = p.to_vec();
    cq[ix::K1] = if broken { p[ix::C1_POST] } else { p[ix::C1] };
    cq[ix::K_LIN] = p[ix::C2];
    cq[ix::K3] = p[ix::C3];
    cq[ix::K4_LIN] = p[ix::C4];
    let c = linearise(&cq, drive).stiffness;
    (lin.mass, lin.stiffness, c)
}

fn force_drive() -> Drive {
    Drive::Force(PiecewiseLinear {
        t: vec![0.0],
        value: vec![0.0],
    })
}

#[test]
fn bound_covers_every_eigenvalue_inside_the_bounds() {
    let (lo, hi) = bounds();
    let rig = tensile4();
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    for drive in [Drive::Velocity, force_drive()] {
        let (bound, limiter) = rig.omega_bound(&lo, &hi, &drive);
        assert!(bound.is_finite(), "{drive:?}: bound {bound}");
        // The limiter names a parameter or an element law of the rig.
        assert!(
            rig.params().iter().any(|p| p.name == limiter)
                || rig
                    .desc
                    .elements
                    .iter()
                    .any(|e| limiter.starts_with(e.name.as_str())),
            "limiter {limiter:?}"
        );
        let mut tightest: f64 = 0.0;
        for _ in 0..400 {
            let p: Vec<f64> = lo
                .iter()
                .zip(&hi)
                .map(|(&a, &b)| a + (b - a) * rng.random::<f64>())
                .collect();
            let e = p[ix::E_FRACTURE] * rng.random::<f64>();
            let ds = slack_knee(
                p[ix::SLACK_A],
                p[ix::SLACK_B],
                p[ix::SLACK_C],
                p[ix::K4_LIN],
            );
            let d = 1.5 * ds * rng.random::<f64>();
            let (m, k, c) = matrices(&p, &drive, e, d, rng.random());
            let (lam, _) = first_order(&m, &k, &c);
            assert!(
                lam <= bound,
                "|λ| = {lam:e} exceeds bound {bound:e} for {p:?} (e = {e:e}, d = {d:e})"
            );
            tightest = tightest.max(lam / bound);
        }
        println!(
            "{drive:?}: bound {bound:.4e} rad/s (limited by {limiter}), largest |λ|/bound {tightest:.3}"
        );
    }
}

/// Where RK4's stability function `|R(z)| ≤ 1`; its region contains the
/// left half-disk of radius 2 (it reaches 2.785 on the real and 2√2 on the
/// imaginary axis), which is why `h·bound ≤ 2` is a safe step.
fn rk4_gain(z: nalgebra::Complex<f64>) -> f64 {
    (1.0 + z + z * z / 2.0 + z.powi(3) / 6.0 + z.powi(4) / 24.0).norm()
}

#[test]
fn rk4_region_contains_the_left_half_disk_of_radius_two() {
    for i in 0..=200 {
        for j in 0..=100 {
            let z = nalgebra::Complex::from_polar(
                2.0 * j as f64 / 100.0,
                std::f64::consts::FRAC_PI_2 * (1.0 + i as f64 / 200.0),
            );
            for z in [z, z.conj()] {
                assert!(rk4_gain(z) <= 1.0 + 1e-12, "|R({z})| = {}", rk4_gain(z));
            }
        }
    }
}

#[test]
fn rk4_is_stable_at_the_bound_and_blows_up_far_above_it() {
    let p = REFERENCE;
    let drive = Drive::Velocity;
    let (bound, _) = tensile4().omega_bound(&p, &p, &drive);
    // Pre-fracture, engaged beyond the slack knee: K from k_lin and k4_lin.
    let (m, k, c) = matrices(&p, &drive, 0.0, f64::INFINITY, false);
    let (lam, a) = first_order(&m, &k, &c);
    println!(
        "reference: true max |λ| {lam:.4e}, bound {bound:.4e} (ratio {:.3})",
        lam / bound
    );
    assert!(lam <= bound, "|λ| = {lam:e} exceeds bound {bound:e}");
    let y0: Vec<f64> = (0..6).map(|i| 1e-6 * (1.0 + i as f64)).collect();
    let norm = |y: &[f64]| y.iter().map(|x| x * x).sum::<f64>().sqrt();
    let mut sys = LinearSystem { a };

    let h = 2.0 / bound;
    let y = integrate_fixed(&mut sys, 0.0, h, 20_000, &y0);
    println!(
        "h = 2/bound = {:.3} µs: |y| {:.3e} → {:.3e} after 20000 steps",
        h * 1e6,
        norm(&y0),
        norm(&y)
    );
    assert!(norm(&y) <= norm(&y0), "unstable at h·bound = 2");

    let h = 4.0 / lam;
    let y = integrate_fixed(&mut sys, 0.0, h, 200, &y0);
    println!(
        "h = 4/|λ|max = {:.3} µs: |y| → {:.3e} after 200 steps",
        h * 1e6,
        norm(&y)
    );
    let grown = norm(&y);
    assert!(
        grown.is_nan() || grown >= 1e6 * norm(&y0),
        "no blow-up at h·|λ| = 4"
    );
}

/// Regression: `check` accepts `slack_c < −slack_a`, where the slack adapter's
/// tangent stiffness at engagement, `a + c`, is negative and can exceed `k4_lin`
/// in magnitude. A bound taking `max(k4_lin, a + c)` with sign misses it
/// (8.67e4 rad/s against a true 9.86e4 rad/s for the case below).
#[test]
fn bound_covers_a_negative_slack_tangent() {
    let mut p = REFERENCE.to_vec();
    p[ix::SLACK_C] = -5e9;
    p[ix::C1] = 0.0;
    p[ix::C1_POST] = 0.0;
    p[ix::C4] = 0.0;
    let rig = tensile4();
    assert!(rig.check(&p).is_ok());
    for drive in [Drive::Velocity, force_drive()] {
        let (bound, _) = rig.omega_bound(&p, &p, &drive);
        let (m, k, c) = matrices(&p, &drive, 0.0, 1e-12, false);
        let (lam, _) = first_order(&m, &k, &c);
        println!("{drive:?}, slack_c = −5e9 N/m: bound {bound:.4e}, true max |λ| {lam:.4e}");
        assert!(lam <= bound, "|λ| = {lam:e} exceeds bound {bound:e}");
    }
}
