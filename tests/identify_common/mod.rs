//! Synthetic records for the identification tests, made with the classic RK4
//! of the hand-written oracle (tests/oracle/rk4.rs): a base-excited
//! single-degree-of-freedom rig (the inertial fatigue rig paper ("A New Fatigue Testing Rig Based on Inertial Forces")) and a force-driven chain of
//! masses, both driven by multisines whose value is known exactly at every RK4
//! stage.

#![allow(dead_code, reason = "each test file uses a part of the helpers")]

use std::f64::consts::PI;
use std::ops::ControlFlow;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rigfit::base::SampleGrid;

#[path = "../oracle/rk4.rs"]
mod rk4;

pub use rk4::{Integrator, System};

/// `Σ A·sin(2π f_k t + φ_k)` over evenly spaced lines `f_k` in `[f_lo, f_hi]`,
/// random phases, scaled to the RMS asked for.
#[derive(Debug, Clone)]
pub struct Multisine {
    lines: Vec<(f64, f64)>,
    amplitude: f64,
}

impl Multisine {
    /// `count` lines in `[f_lo, f_hi]` (Hz) with RMS `rms`.
    pub fn new(f_lo: f64, f_hi: f64, count: usize, rms: f64, seed: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let lines = (0..count)
            .map(|k| {
                let f = f_lo + (f_hi - f_lo) * k as f64 / (count - 1).max(1) as f64;
                (f, rng.random::<f64>() * 2.0 * PI)
            })
            .collect();
        Self {
            lines,
            amplitude: rms * (2.0 / count as f64).sqrt(),
        }
    }

    /// Value at `t` (s).
    pub fn at(&self, t: f64) -> f64 {
        self.lines
            .iter()
            .map(|(f, phi)| (2.0 * PI * f * t + phi).sin())
            .sum::<f64>()
            * self.amplitude
    }
}

/// `m·ẍ + R(x, ẋ) = −m·a(t)`, state `(x, ẋ)`.
pub struct BaseExcited<R: Fn(f64, f64) -> f64> {
    /// Mass (kg).
    pub m: f64,
    /// Restoring force `R(x, ẋ)` (N).
    pub restoring: R,
    /// Base acceleration (m/s²).
    pub base: Multisine,
}

impl<R: Fn(f64, f64) -> f64> System for BaseExcited<R> {
    fn dim(&self) -> usize {
        2
    }

    fn deriv(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = -(self.restoring)(y[0], y[1]) / self.m - self.base.at(t);
    }
}

/// A chain of masses `m_i` joined by springs `k_i` and dampers `c_i` (the first to
/// ground), a force on mass `driven`; state `(x_1..x_n, v_1..v_n)`.
pub struct ForcedChain {
    /// Masses (kg).
    pub m: Vec<f64>,
    /// Springs (N/m): `k[0]` ground–1, `k[i]` i–(i+1).
    pub k: Vec<f64>,
    /// Dampers (N·s/m), as the springs.
    pub c: Vec<f64>,
    /// Index of the driven mass.
    pub driven: usize,
    /// The force (N).
    pub force: Multisine,
}

impl System for ForcedChain {
    fn dim(&self) -> usize {
        2 * self.m.len()
    }

    fn deriv(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let n = self.m.len();
        let (x, v) = y.split_at(n);
        for i in 0..n {
            let mut f = if i == self.driven {
                self.force.at(t)
            } else {
                0.0
            };
            let below = if i == 0 {
                (0.0, 0.0)
            } else {
                (x[i - 1], v[i - 1])
            };
            f -= self.k[i] * (x[i] - below.0) + self.c[i] * (v[i] - below.1);
            if i + 1 < n {
                f += self.k[i + 1] * (x[i + 1] - x[i]) + self.c[i + 1] * (v[i + 1] - v[i]);
            }
            dy[i] = v[i];
            dy[n + i] = f / self.m[i];
        }
    }
}

/// Integrates `sys` from rest, recording `samples` samples at `fs` (Hz) with
/// `substeps` RK4 steps each; returns the time stamps and each sample's state.
pub fn simulate<S: System>(
    sys: &mut S,
    fs: f64,
    samples: usize,
    substeps: usize,
) -> (Vec<f64>, Vec<Vec<f64>>) {
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1.0 / fs,
        samples,
        substeps,
    };
    let mut y = vec![0.0; sys.dim()];
    let mut t = Vec::with_capacity(samples);
    let mut states = Vec::with_capacity(samples);
    Integrator::new(sys.dim()).run(sys, &grid, &mut y, |_, tk, _, y| {
        t.push(tk);
        states.push(y.to_vec());
        ControlFlow::Continue(())
    });
    (t, states)
}
