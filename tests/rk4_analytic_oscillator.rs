//! Proves the classic RK4 of the hand-written oracle (tests/oracle) reproduces
//! the closed-form damped single-mass oscillator in all three damping regimes,
//! both by plain steps and through `Integrator::run` on rigfit's `SampleGrid`
//! with a prologue (which checks the grid's step times, `walk_grid`'s, too).

mod oracle;

use std::ops::ControlFlow;

use oracle::rk4::Integrator;
use oracle::systems::{DampedOscillator, Damping, integrate_fixed};
use rigfit::base::SampleGrid;

/// Load-cell-like oscillator: 7.9 kg on 8.4e9 N/m (≈ 5.19 kHz), `c` chosen for the
/// regime.
fn oscillator(c: f64) -> DampedOscillator {
    DampedOscillator {
        m: 7.9,
        k: 8.4e9,
        c,
        x0: 1e-6,
        v0: -0.02,
        t0: 0.0,
    }
}

/// Largest error in `x` over 2 ms with 400 steps per undamped period
/// (`ω₀·h ≈ 0.0157`), relative to the initial amplitude scale.
fn max_error(sys: DampedOscillator) -> f64 {
    let h = std::f64::consts::TAU / sys.omega0() / 400.0;
    let scale = sys.x0.abs().max(sys.v0.abs() / sys.omega0());
    let mut y = vec![sys.x0, sys.v0];
    let mut s = sys;
    let mut worst = 0.0_f64;
    for i in 0..(2e-3 / h) as usize {
        y = integrate_fixed(&mut s, i as f64 * h, h, 1, &y);
        let (x, _) = sys.exact((i + 1) as f64 * h);
        worst = worst.max((y[0] - x).abs() / scale);
    }
    worst
}

/// Tolerance 5e-8 of the amplitude scale: RK4's phase error per step is about
/// `(ω₀h)⁵/120 ≈ 7.9e-12` rad, ≈ 3.3e-8 after the ~4150 steps of 2 ms; damping only
/// shrinks it. Measured: 1.2e-8 (ζ = 0.018), 1.2e-10 (ζ = 1), 1.8e-8 (ζ = 3, whose
/// fast root has `|λ|·h ≈ 0.09`).
const TOL: f64 = 5e-8;

#[test]
fn underdamped_matches_closed_form() {
    let sys = oscillator(9.22e3);
    assert_eq!(sys.regime(), Damping::Under);
    let e = max_error(sys);
    println!("underdamped ζ = {:.4}: max rel error {e:.3e}", sys.zeta());
    assert!(e < TOL, "error {e:e}");
}

#[test]
fn critically_damped_matches_closed_form() {
    let c = 2.0 * (7.9_f64 * 8.4e9).sqrt();
    let sys = oscillator(c);
    assert_eq!(sys.regime(), Damping::Critical);
    let e = max_error(sys);
    println!("critical: max rel error {e:.3e}");
    assert!(e < TOL, "error {e:e}");
}

#[test]
fn overdamped_matches_closed_form() {
    let sys = oscillator(3.0 * 2.0 * (7.9_f64 * 8.4e9).sqrt());
    assert_eq!(sys.regime(), Damping::Over);
    let e = max_error(sys);
    println!("overdamped ζ = 3: max rel error {e:.3e}");
    assert!(e < TOL, "error {e:e}");
}

#[test]
fn closed_form_satisfies_its_own_initial_conditions_and_ode() {
    for c in [9.22e3, 2.0 * (7.9_f64 * 8.4e9).sqrt(), 1e6] {
        let sys = DampedOscillator {
            t0: 0.3,
            ..oscillator(c)
        };
        let (x, v) = sys.exact(0.3);
        assert!((x - sys.x0).abs() < 1e-18 && (v - sys.v0).abs() < 1e-12);
        // m·a + c·v + k·x = 0 with a by central difference of v.
        let (t, d) = (0.3 + 1e-4, 1e-8);
        let (x, v) = sys.exact(t);
        let a = (sys.exact(t + d).1 - sys.exact(t - d).1) / (2.0 * d);
        let r = sys.m * a + sys.c * v + sys.k * x;
        assert!(
            r.abs() < 1e-6 * sys.k * 1e-6,
            "ODE residual {r:e} for c = {c}"
        );
    }
}

#[test]
fn sample_grid_run_with_prologue_matches_closed_form() {
    let sys0 = oscillator(9.22e3);
    let grid = SampleGrid {
        t0: 0.37e-3,
        dt: 1e-6,
        samples: 1500,
        substeps: 2,
    };
    let mut sys = sys0;
    let mut y = vec![sys0.x0, sys0.v0];
    let mut worst = 0.0_f64;
    Integrator::new(2).run(&mut sys, &grid, &mut y, |_, t, _, y| {
        worst = worst
            .max((y[0] - sys0.exact(t).0).abs() / sys0.x0.abs().max(sys0.v0.abs() / sys0.omega0()));
        ControlFlow::Continue(())
    });
    println!("grid run: max rel error {worst:.3e}");
    assert!(worst < 1e-7, "error {worst:e}");
}
