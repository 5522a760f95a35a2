//! Classic fixed-step RK4 with one-way switches located inside the step: the
//! independent integrator the tensile oracle runs on. rigfit's own reference
//! (the compiled rig's `EventStepper`) shares no code with it beyond the sample
//! grid's walk.

use std::ops::ControlFlow;

use rigfit::base::{SampleGrid, walk_grid};

/// A system of first-order ODEs, `dy/dt = f(t, y)`, in the current regime.
pub trait System {
    /// Number of state variables.
    fn dim(&self) -> usize;

    /// Writes `dy/dt` at `(t, y)` into `dy`.
    fn deriv(&self, t: f64, y: &[f64], dy: &mut [f64]);

    /// While a one-way switch is still pending, returns the switching function
    /// `g(t, y)` and its time derivative `dg/dt`; the switch fires when `g`
    /// reaches zero from below. `None` once nothing is pending.
    fn pending_switch(&self, _t: f64, _y: &[f64]) -> Option<(f64, f64)> {
        None
    }

    /// Moves the system into its post-switch regime.
    fn fire_switch(&mut self, _t: f64) {}
}

/// Number of bisection iterations used to locate a switch inside a step. 52
/// halvings resolve the crossing to the last bit of an f64 step fraction.
pub const CROSSING_ITERATIONS: usize = 52;

/// Scratch buffers for RK4, reused across steps.
#[derive(Debug, Clone)]
pub struct Integrator {
    k1: Vec<f64>,
    k2: Vec<f64>,
    k3: Vec<f64>,
    k4: Vec<f64>,
    tmp: Vec<f64>,
    start: Vec<f64>,
}

impl Integrator {
    /// Scratch space for a system of `dim` states.
    pub fn new(dim: usize) -> Self {
        let z = vec![0.0; dim];
        Self {
            k1: z.clone(),
            k2: z.clone(),
            k3: z.clone(),
            k4: z.clone(),
            tmp: z.clone(),
            start: z,
        }
    }

    /// One step of length `h` from `(t, y)`, splitting it at a pending switch if
    /// the switching function crosses zero inside the step.
    pub fn step<S: System>(&mut self, sys: &mut S, t: f64, h: f64, y: &mut [f64]) {
        let Some((g0, dg0)) = sys.pending_switch(t, y) else {
            self.plain(sys, t, h, y);
            return;
        };
        if g0 >= 0.0 {
            sys.fire_switch(t);
            self.plain(sys, t, h, y);
            return;
        }
        self.start.copy_from_slice(y);
        self.plain(sys, t, h, y);
        let Some((g1, dg1)) = sys.pending_switch(t + h, y) else {
            return;
        };
        if g1 < 0.0 {
            return;
        }
        let theta = hermite_crossing(g0, dg0 * h, g1, dg1 * h);
        let s = theta * h;
        y.copy_from_slice(&self.start);
        self.plain(sys, t, s, y);
        sys.fire_switch(t + s);
        self.plain(sys, t + s, h - s, y);
    }

    fn plain<S: System>(&mut self, sys: &S, t: f64, h: f64, y: &mut [f64]) {
        rk4_step(
            sys,
            t,
            h,
            y,
            [
                &mut self.k1,
                &mut self.k2,
                &mut self.k3,
                &mut self.k4,
                &mut self.tmp,
            ],
        );
    }

    /// Integrates `sys` from rest (`y` as given, normally zeros) over `grid`,
    /// calling `observe(k, t_k, sys, y)` at every sample. The observer may stop the
    /// run early with [`ControlFlow::Break`].
    pub fn run<S: System>(
        &mut self,
        sys: &mut S,
        grid: &SampleGrid,
        y: &mut [f64],
        mut observe: impl FnMut(usize, f64, &S, &[f64]) -> ControlFlow<()>,
    ) {
        let mut state = (sys, y);
        walk_grid(
            grid,
            &mut state,
            |(sys, y), t, h| self.step(&mut **sys, t, h, y),
            |(sys, y), k, t| observe(k, t, &**sys, y),
        );
    }
}

/// One classic RK4 step of length `h`, in place, with caller-provided scratch
/// `[k1, k2, k3, k4, tmp]`.
pub fn rk4_step<S: System + ?Sized>(
    sys: &S,
    t: f64,
    h: f64,
    y: &mut [f64],
    [k1, k2, k3, k4, tmp]: [&mut Vec<f64>; 5],
) {
    let n = y.len();
    sys.deriv(t, y, k1);
    for i in 0..n {
        tmp[i] = y[i] + 0.5 * h * k1[i];
    }
    sys.deriv(t + 0.5 * h, tmp, k2);
    for i in 0..n {
        tmp[i] = y[i] + 0.5 * h * k2[i];
    }
    sys.deriv(t + 0.5 * h, tmp, k3);
    for i in 0..n {
        tmp[i] = y[i] + h * k3[i];
    }
    sys.deriv(t + h, tmp, k4);
    for i in 0..n {
        y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    }
}

/// Fraction `θ ∈ [0, 1]` of a step at which the cubic Hermite interpolant of the
/// switching function crosses zero, given `g` at both ends (`g0 < 0 ≤ g1`) and
/// its derivatives already scaled by the step length. Bisection with a fixed
/// iteration count keeps the CPU and GPU paths operation-for-operation alike.
pub fn hermite_crossing(g0: f64, d0: f64, g1: f64, d1: f64) -> f64 {
    let p = |s: f64| {
        let s2 = s * s;
        let s3 = s2 * s;
        (2.0 * s3 - 3.0 * s2 + 1.0) * g0
            + (s3 - 2.0 * s2 + s) * d0
            + (-2.0 * s3 + 3.0 * s2) * g1
            + (s3 - s2) * d1
    };
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    for _ in 0..CROSSING_ITERATIONS {
        let mid = 0.5 * (lo + hi);
        if p(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}
