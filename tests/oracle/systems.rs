//! Canonical systems with known solutions, shared by the tests and the benchmarks
//! that hold the RK4 reference to account.
//!
//! Each implements [`System`] and carries its closed form (or, for the chain, its
//! conserved energy), so a test can measure the integrator's error directly
//! instead of against another numerical run.

use super::rk4::{Integrator, System};

/// Which closed form a [`DampedOscillator`] follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Damping {
    /// `ζ < 1`: decaying oscillation at `ω_d = ω₀·√(1 − ζ²)`.
    Under,
    /// `ζ = 1` (within 1e-9): fastest non-oscillating decay.
    Critical,
    /// `ζ > 1`: sum of two decaying exponentials.
    Over,
}

/// A single mass on a spring and a damper to ground, `m·ẍ + c·ẋ + k·x = 0`.
/// State `[x, v]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DampedOscillator {
    /// Mass (kg).
    pub m: f64,
    /// Stiffness (N/m).
    pub k: f64,
    /// Viscous damping (N·s/m).
    pub c: f64,
    /// Displacement at `t0` (m).
    pub x0: f64,
    /// Velocity at `t0` (m/s).
    pub v0: f64,
    /// Time at which `(x0, v0)` holds (s).
    pub t0: f64,
}

impl DampedOscillator {
    /// Undamped natural angular frequency `ω₀ = √(k/m)` (rad/s).
    pub fn omega0(&self) -> f64 {
        (self.k / self.m).sqrt()
    }

    /// Damping ratio `ζ = c / (2√(k·m))`.
    pub fn zeta(&self) -> f64 {
        self.c / (2.0 * (self.k * self.m).sqrt())
    }

    /// Damped angular frequency `ω₀·√(1 − ζ²)` (rad/s); 0 unless underdamped.
    pub fn omega_d(&self) -> f64 {
        self.omega0() * (1.0 - self.zeta().powi(2)).max(0.0).sqrt()
    }

    /// Exponential decay rate of the envelope, `ζ·ω₀` (1/s).
    pub fn decay_rate(&self) -> f64 {
        self.zeta() * self.omega0()
    }

    /// The damping regime.
    pub fn regime(&self) -> Damping {
        let z = self.zeta();
        if (z - 1.0).abs() < 1e-9 {
            Damping::Critical
        } else if z < 1.0 {
            Damping::Under
        } else {
            Damping::Over
        }
    }

    /// Exact displacement (m) and velocity (m/s) at time `t`.
    pub fn exact(&self, t: f64) -> (f64, f64) {
        let (x0, v0, s) = (self.x0, self.v0, t - self.t0);
        let w0 = self.omega0();
        match self.regime() {
            Damping::Under => {
                let (a, wd) = (self.decay_rate(), self.omega_d());
                let b = (v0 + a * x0) / wd;
                let (sn, cs) = (wd * s).sin_cos();
                let env = (-a * s).exp();
                let x = env * (x0 * cs + b * sn);
                let v = env * (-a * (x0 * cs + b * sn) + wd * (b * cs - x0 * sn));
                (x, v)
            }
            Damping::Critical => {
                let b = v0 + w0 * x0;
                let env = (-w0 * s).exp();
                let x = (x0 + b * s) * env;
                (x, b * env - w0 * x)
            }
            Damping::Over => {
                let root = w0 * (self.zeta().powi(2) - 1.0).sqrt();
                let (r1, r2) = (-self.decay_rate() + root, -self.decay_rate() - root);
                let a = (v0 - r2 * x0) / (r1 - r2);
                let b = x0 - a;
                let (e1, e2) = ((r1 * s).exp(), (r2 * s).exp());
                (a * e1 + b * e2, a * r1 * e1 + b * r2 * e2)
            }
        }
    }
}

impl System for DampedOscillator {
    fn dim(&self) -> usize {
        2
    }

    fn deriv(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = -(self.k * y[0] + self.c * y[1]) / self.m;
    }
}

/// An undamped chain of masses joined by springs, the first tied to ground and the
/// last free. Spring `i` joins mass `i − 1` (ground for `i = 0`) and mass `i`.
/// State `[x_0 … x_{n−1}, v_0 … v_{n−1}]`.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearChain {
    /// Masses (kg).
    pub mass: Vec<f64>,
    /// Spring stiffnesses (N/m), one per mass.
    pub stiffness: Vec<f64>,
}

impl LinearChain {
    /// Number of masses.
    pub fn len(&self) -> usize {
        self.mass.len()
    }

    /// Whether the chain has no masses.
    pub fn is_empty(&self) -> bool {
        self.mass.is_empty()
    }

    /// Total mechanical energy (J): kinetic plus the energy stored in the springs.
    /// Conserved exactly by the true flow.
    pub fn energy(&self, y: &[f64]) -> f64 {
        let n = self.len();
        let mut e = 0.0;
        for i in 0..n {
            let stretch = y[i] - if i == 0 { 0.0 } else { y[i - 1] };
            e += 0.5 * self.mass[i] * y[n + i].powi(2) + 0.5 * self.stiffness[i] * stretch.powi(2);
        }
        e
    }
}

impl System for LinearChain {
    fn dim(&self) -> usize {
        2 * self.len()
    }

    fn deriv(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        let n = self.len();
        for i in 0..n {
            let left = self.stiffness[i] * (y[i] - if i == 0 { 0.0 } else { y[i - 1] });
            let right = if i + 1 < n {
                self.stiffness[i + 1] * (y[i + 1] - y[i])
            } else {
                0.0
            };
            dy[i] = y[n + i];
            dy[n + i] = (right - left) / self.mass[i];
        }
    }
}

/// An undamped oscillator driven by a cosine force from rest,
/// `ẍ + ω²·x = A·cos(Ω·t)`, `x(0) = ẋ(0) = 0`. The time-dependent forcing makes
/// every RK4 stage time matter, which a free system would not test. State `[x, v]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForcedOscillator {
    /// Natural angular frequency ω (rad/s).
    pub omega: f64,
    /// Force amplitude per unit mass A (m/s²).
    pub amplitude: f64,
    /// Forcing angular frequency Ω (rad/s), different from ω.
    pub forcing: f64,
}

impl ForcedOscillator {
    /// Exact displacement and velocity at `t`:
    /// `x = A/(ω² − Ω²)·(cos Ωt − cos ωt)`.
    pub fn exact(&self, t: f64) -> (f64, f64) {
        let (w, f) = (self.omega, self.forcing);
        let g = self.amplitude / (w * w - f * f);
        (
            g * ((f * t).cos() - (w * t).cos()),
            g * (w * (w * t).sin() - f * (f * t).sin()),
        )
    }
}

impl System for ForcedOscillator {
    fn dim(&self) -> usize {
        2
    }

    fn deriv(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = self.amplitude * (self.forcing * t).cos() - self.omega.powi(2) * y[0];
    }
}

/// A smooth nonlinear scalar system, `ẏ = −y³`, with the exact solution
/// `y = y0 / √(1 + 2·y0²·t)`. State `[y]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CubicDecay {
    /// Value at `t = 0`.
    pub y0: f64,
}

impl CubicDecay {
    /// Exact value at `t ≥ 0`.
    pub fn exact(&self, t: f64) -> f64 {
        self.y0 / (1.0 + 2.0 * self.y0 * self.y0 * t).sqrt()
    }
}

impl System for CubicDecay {
    fn dim(&self) -> usize {
        1
    }

    fn deriv(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = -y[0].powi(3);
    }
}

/// A linear first-order system `ẏ = A·y` with `A` given row-major (`dim²`
/// entries); used to probe RK4's stability against computed eigenvalues.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearSystem {
    /// The system matrix, row-major.
    pub a: Vec<f64>,
}

impl System for LinearSystem {
    fn dim(&self) -> usize {
        (self.a.len() as f64).sqrt().round() as usize
    }

    fn deriv(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        let n = y.len();
        for (i, d) in dy.iter_mut().enumerate().take(n) {
            *d = (0..n).map(|j| self.a[i * n + j] * y[j]).sum();
        }
    }
}

/// Integrates `sys` from `y` at `t0` with `steps` plain RK4 steps of `h` (no
/// switch handling), returning the final state. A convenience for tests and
/// benchmarks of the canonical systems.
pub fn integrate_fixed<S: System>(
    sys: &mut S,
    t0: f64,
    h: f64,
    steps: usize,
    y: &[f64],
) -> Vec<f64> {
    let mut integ = Integrator::new(sys.dim());
    let mut y = y.to_vec();
    for i in 0..steps {
        integ.step(sys, t0 + i as f64 * h, h, &mut y);
    }
    y
}
