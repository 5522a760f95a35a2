//! Proves the classic RK4 of the hand-written oracle (tests/oracle) conserves
//! the energy of an undamped chain to the accuracy its stability function
//! predicts, over hundreds of periods.
//!
//! Tolerance, and why: RK4 is not symplectic. On a mode of angular frequency ω
//! its amplification factor is `R(iωh)`, `R(z) = 1 + z + z²/2 + z³/6 + z⁴/24`, with
//! `|R(iθ)|² = 1 − θ⁶/72 + θ⁸/576 ≤ 1` for `θ < 2√2`: each step removes a fraction
//! of at most `(ω_max·h)⁶/72` of the energy and never adds any. So (a) the
//! relative drift after `N` steps is a loss bounded by `N·(ω_max·h)⁶/72`, and (b)
//! since RK4 acts on each mode of a linear system separately, the energy after `N`
//! steps is exactly `Σ_j E_j·|R(iω_j h)|^{2N}`. The test checks (b) to 1e-9 of the
//! initial energy — round-off over ~10⁵ steps is far below that — which fails on
//! any error in the integrator beyond the method's own dissipation.

mod oracle;

use oracle::systems::{LinearChain, integrate_fixed};
use rigfit::model::Linearised;
use rigfit::model::modes::ModeReport;

/// A five-mass chain with rig-like masses and stiffnesses, fixed–free.
fn chain() -> LinearChain {
    LinearChain {
        mass: vec![7.9, 0.14, 0.48, 2.0, 1.0],
        stiffness: vec![8.4e9, 8.63e7, 4.4e8, 1.19e8, 5.0e7],
    }
}

fn modes(c: &LinearChain) -> ModeReport {
    let n = c.len();
    let mut k = vec![0.0; n * n];
    for i in 0..n {
        k[i * n + i] += c.stiffness[i];
        if i > 0 {
            k[(i - 1) * n + (i - 1)] += c.stiffness[i];
            k[(i - 1) * n + i] -= c.stiffness[i];
            k[i * n + (i - 1)] -= c.stiffness[i];
        }
    }
    let lin = Linearised {
        dofs: ["a", "b", "c", "d", "e"].map(String::from).to_vec(),
        mass: c.mass.clone(),
        stiffness: k,
    };
    ModeReport::new(&lin).expect("valid chain")
}

/// `|R(iθ)|²` of classic RK4.
fn rk4_gain2(t: f64) -> f64 {
    (1.0 - t * t / 2.0 + t.powi(4) / 24.0).powi(2) + (t - t.powi(3) / 6.0).powi(2)
}

struct Drift {
    measured: f64,
    predicted: f64,
    bound: f64,
    steps: usize,
}

/// Runs the chain from a displaced state exciting every mode for
/// `periods` periods of the slowest mode with `ω_max·h = wh`.
fn drift(wh: f64, periods: f64) -> Drift {
    let c = chain();
    let r = modes(&c);
    let h = wh / r.modes.last().expect("modes").omega;
    let steps = (periods * std::f64::consts::TAU / r.modes[0].omega / h) as usize;
    let x0 = [1e-6, -2e-6, 3e-6, -1e-6, 2e-6];
    let mut y0 = x0.to_vec();
    y0.extend([0.0; 5]);
    let e0 = c.energy(&y0);
    let mut sys = c.clone();
    let y = integrate_fixed(&mut sys, 0.0, h, steps, &y0);
    // Modal energies ½ω²q², q = φᵀ·M·x0 with mass-normalised φ.
    let predicted: f64 = r
        .modes
        .iter()
        .map(|m| {
            let phi = m.mass_normalised();
            let q: f64 = (0..5).map(|i| phi[i] * c.mass[i] * x0[i]).sum();
            0.5 * (m.omega * q).powi(2) * rk4_gain2(m.omega * h).powi(steps as i32)
        })
        .sum();
    Drift {
        measured: (c.energy(&y) - e0) / e0,
        predicted: (predicted - e0) / e0,
        bound: steps as f64 * wh.powi(6) / 72.0,
        steps,
    }
}

#[test]
fn chain_loses_energy_only_as_the_stability_function_predicts() {
    for wh in [0.1, 0.3] {
        let d = drift(wh, 200.0);
        println!(
            "ω_max·h = {wh}: {} steps (200 slowest periods), relative drift {:.4e}, \
             modal prediction {:.4e}, bound {:.3e}",
            d.steps, d.measured, d.predicted, d.bound
        );
        assert!(
            d.measured <= 1e-12,
            "RK4 must not gain energy: {:e}",
            d.measured
        );
        assert!(
            -d.measured <= d.bound + 1e-12,
            "drift {:e} above bound {:e}",
            d.measured,
            d.bound
        );
        assert!(
            (d.measured - d.predicted).abs() < 1e-9,
            "drift {:e} differs from the modal prediction {:e}",
            d.measured,
            d.predicted
        );
    }
}

/// At the reference experiment's RK4 step (0.5 µs) over its 3 ms record, the
/// drift is negligible next to any force tolerance the fit uses.
#[test]
fn reference_step_conserves_energy_over_a_record() {
    let c = chain();
    let wmax = modes(&c).modes.last().expect("modes").omega;
    let (h, steps) = (0.5e-6, 6000);
    let mut y0 = vec![1e-6, -2e-6, 3e-6, -1e-6, 2e-6];
    y0.extend([0.0; 5]);
    let mut sys = c.clone();
    let y = integrate_fixed(&mut sys, 0.0, h, steps, &y0);
    let d = (c.energy(&y) - c.energy(&y0)) / c.energy(&y0);
    let bound = steps as f64 * (wmax * h).powi(6) / 72.0;
    println!(
        "h = 0.5 µs (ω_max·h = {:.4}), 3 ms: drift {d:.3e}, bound {bound:.3e}",
        wmax * h
    );
    assert!(
        d <= 1e-12 && -d <= bound + 1e-12 && d.abs() < 1e-7,
        "drift {d:e}"
    );
}
