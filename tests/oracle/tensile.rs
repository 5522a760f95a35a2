//! The 4-DOF high-speed tensile rig written out by hand: the independent
//! implementation `rigs/tensile4.json` is held to. The product runs the compiled
//! rig only; these equations, on their own classic RK4 (`rk4.rs`), locate the
//! fracture alone (slack engagement and yield are taken where a step lands), so
//! they agree with the compiled rig to RK4's local error where a step holds one
//! of those events. Load cell, specimen, sliding bar and actuator, with an
//! exponential slack adapter and specimen fracture.
//!
//! Displacements `y1..y4` (m) are positive in the pulling direction, ground is the
//! fixed crosshead:
//! - load cell: `F1 = k1·y1 + c1·v1` (`c1 → c1_post` after fracture), measured;
//! - specimen, `e = y2 − y1`: `F2 = S(e) + c2·(v2 − v1)`, `S(e) = k_lin·e` for
//!   `e ≤ e_yield`, `Σ a_i·e^i` above; `F2 = 0` once `e` has reached `e_fracture`;
//! - sliding bar: `F3 = k3·(y3 − y2) + c3·(v3 − v2)`;
//! - slack adapter, `d = y4 − y3 − gap`: `F4 = 0` for `d ≤ 0`, else
//!   `G(d) + c4·(v4 − v3)` with `G(d) = (a/b)(e^{bd} − 1) + c·d` up to `d*` and
//!   `G(d*) + k4_lin·(d − d*)` beyond, `d* = ln((k4_lin − c)/a)/b`;
//! - `m1·ÿ1 = F2 − F1`, `m2·ÿ2 = F3 − F2`, `m3·ÿ3 = F4 − F3`; the actuator either
//!   follows `y4 = v·t − r·(1 − e^{−vt/r})` or obeys `m4·ÿ4 = F_drive(t) − F4`.

use std::ops::ControlFlow;

use rigfit::base::Drive;
use rigfit::base::SampleGrid;

use super::rk4::{Integrator, System};

/// Highest degree of the specimen's plastic polynomial.
pub const MAX_POLY_DEGREE: usize = 5;

/// Slack-adapter opening where the exponential law hands over to `k4_lin`:
/// `d* = ln((k4_lin − c)/a)/b`, or 0 when `k4_lin ≤ a + c`.
pub fn slack_knee(a: f64, b: f64, c: f64, k4_lin: f64) -> f64 {
    if k4_lin <= a + c {
        0.0
    } else {
        ((k4_lin - c) / a).ln() / b
    }
}

/// Exponential part of the slack-adapter law, `(a/b)(e^{bd} − 1) + c·d`.
pub fn slack_exp_law(a: f64, b: f64, c: f64, d: f64) -> f64 {
    a / b * (b * d).exp_m1() + c * d
}

/// Prescribed actuator displacement, velocity and acceleration at `t` for target
/// velocity `v` and ramp length `r`; at rest for `t ≤ 0`.
pub fn velocity_drive(v: f64, r: f64, t: f64) -> (f64, f64, f64) {
    if t <= 0.0 {
        return (0.0, 0.0, 0.0);
    }
    if r <= 0.0 {
        return (v * t, v, 0.0);
    }
    let m = (-v * t / r).exp_m1(); // e^{-vt/r} − 1
    (v * t + r * m, -v * m, v * v / r * (m + 1.0))
}

/// Parameters with the derived slack-adapter constants, ready to integrate.
#[derive(Debug, Clone)]
pub struct Prepared {
    p: [f64; 27],
    /// `d*` (m).
    pub d_star: f64,
    /// `G(d*)` (N).
    pub g_star: f64,
}

impl Prepared {
    /// Derives the constants from a full parameter vector.
    pub fn new(params: &[f64]) -> Self {
        let mut p = [0.0; 27];
        p.copy_from_slice(&params[..27]);
        let (a, b, c, k4) = (
            p[ix::SLACK_A],
            p[ix::SLACK_B],
            p[ix::SLACK_C],
            p[ix::K4_LIN],
        );
        let d_star = slack_knee(a, b, c, k4);
        let g_star = slack_exp_law(a, b, c, d_star);
        Self { p, d_star, g_star }
    }

    /// Specimen law `S(e)` (N).
    pub fn specimen_law(&self, e: f64) -> f64 {
        let p = &self.p;
        if e <= p[ix::E_YIELD] {
            return p[ix::K_LIN] * e;
        }
        let mut s = p[ix::A0 + MAX_POLY_DEGREE];
        for i in (0..MAX_POLY_DEGREE).rev() {
            s = s * e + p[ix::A0 + i];
        }
        s
    }

    /// Slack-adapter spring law `G(d)` for `d > 0` (N).
    pub fn slack_law(&self, d: f64) -> f64 {
        let p = &self.p;
        if d <= self.d_star {
            slack_exp_law(p[ix::SLACK_A], p[ix::SLACK_B], p[ix::SLACK_C], d)
        } else {
            self.g_star + p[ix::K4_LIN] * (d - self.d_star)
        }
    }
}

/// One run of the tensile rig: prepared parameters, drive and fracture state.
/// State `y = [y1, y2, y3, y4, v1, v2, v3, v4]`.
#[derive(Debug, Clone)]
pub struct TensileSystem<'a> {
    prep: Prepared,
    drive: &'a Drive,
    /// Whether the specimen has fractured.
    pub broken: bool,
    /// Model time of fracture (s), once broken.
    pub fracture_time: Option<f64>,
}

impl<'a> TensileSystem<'a> {
    /// A fresh, unbroken run.
    pub fn new(params: &[f64], drive: &'a Drive) -> Self {
        Self {
            prep: Prepared::new(params),
            drive,
            broken: false,
            fracture_time: None,
        }
    }

    /// Actuator displacement and velocity at `t` given the state.
    fn actuator(&self, t: f64, y: &[f64]) -> (f64, f64, f64) {
        match self.drive {
            Drive::Velocity => velocity_drive(self.prep.p[ix::VELOCITY], self.prep.p[ix::RAMP], t),
            Drive::Force(_) => (y[3], y[7], 0.0),
        }
    }

    /// Element forces `[F1, F2, F3, F4]` (N) at `(t, y)`.
    pub fn forces(&self, t: f64, y: &[f64]) -> [f64; 4] {
        let (y4, v4, _) = self.actuator(t, y);
        self.forces_with_actuator(y, y4, v4)
    }

    /// Element forces given the actuator's displacement and velocity.
    fn forces_with_actuator(&self, y: &[f64], y4: f64, v4: f64) -> [f64; 4] {
        let p = &self.prep.p;
        let c1 = if self.broken {
            p[ix::C1_POST]
        } else {
            p[ix::C1]
        };
        let f1 = p[ix::K1] * y[0] + c1 * y[4];
        let f2 = if self.broken {
            0.0
        } else {
            self.prep.specimen_law(y[1] - y[0]) + p[ix::C2] * (y[5] - y[4])
        };
        let f3 = p[ix::K3] * (y[2] - y[1]) + p[ix::C3] * (y[6] - y[5]);
        let d = y4 - y[2] - p[ix::GAP];
        let f4 = if d <= 0.0 {
            0.0
        } else {
            self.prep.slack_law(d) + p[ix::C4] * (v4 - y[6])
        };
        [f1, f2, f3, f4]
    }

    /// The state with the actuator slots filled from the prescribed motion.
    pub fn full_state(&self, t: f64, y: &[f64], out: &mut [f64; 8]) {
        out.copy_from_slice(&y[..8]);
        let (y4, v4, _) = self.actuator(t, y);
        out[3] = y4;
        out[7] = v4;
    }
}

impl System for TensileSystem<'_> {
    fn dim(&self) -> usize {
        8
    }

    fn deriv(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let p = &self.prep.p;
        let (y4, v4, a4) = self.actuator(t, y);
        let [f1, f2, f3, f4] = self.forces_with_actuator(y, y4, v4);
        dy[0] = y[4];
        dy[1] = y[5];
        dy[2] = y[6];
        dy[4] = (f2 - f1) / p[ix::M1];
        dy[5] = (f3 - f2) / p[ix::M2];
        dy[6] = (f4 - f3) / p[ix::M3];
        match self.drive {
            Drive::Velocity => {
                dy[3] = v4;
                dy[7] = a4;
            }
            Drive::Force(table) => {
                let fd = if t < 0.0 { 0.0 } else { table.at(t) };
                dy[3] = y[7];
                dy[7] = (fd - f4) / p[ix::M4];
            }
        }
    }

    fn pending_switch(&self, _t: f64, y: &[f64]) -> Option<(f64, f64)> {
        let e_fracture = self.prep.p[ix::E_FRACTURE];
        (!self.broken && e_fracture.is_finite()).then(|| (y[1] - y[0] - e_fracture, y[5] - y[4]))
    }

    fn fire_switch(&mut self, t: f64) {
        self.broken = true;
        self.fracture_time = Some(t);
    }
}

/// What the oracle reports at each sample.
#[derive(Debug, Clone, Copy)]
pub struct Sample<'a> {
    /// Sample index on the grid.
    pub index: usize,
    /// Model time (s).
    pub t: f64,
    /// `[y1, y2, y3, y4, v1, v2, v3, v4]`, the actuator's slots from its
    /// prescribed motion under a velocity drive.
    pub state: &'a [f64],
    /// `[load_cell_force, specimen_force]` (N).
    pub outputs: &'a [f64],
}

/// The rig linearised about its engaged, unbroken configuration.
#[derive(Debug, Clone)]
pub struct Linearised {
    /// Name of each degree of freedom.
    pub dofs: Vec<&'static str>,
    /// Diagonal of the mass matrix (kg).
    pub mass: Vec<f64>,
    /// Stiffness matrix, row-major (N/m).
    pub stiffness: Vec<f64>,
}

/// Integrates one run from rest, calling `observe` at every sample of `grid`.
pub fn simulate(
    params: &[f64],
    drive: &Drive,
    grid: &SampleGrid,
    mut observe: impl FnMut(&Sample<'_>) -> ControlFlow<()>,
) {
    let mut sys = TensileSystem::new(params, drive);
    let mut y = [0.0; 8];
    let mut full = [0.0; 8];
    let mut integ = Integrator::new(8);
    integ.run(&mut sys, grid, &mut y, |k, t, sys, y| {
        let [f1, f2, _, _] = sys.forces(t, y);
        sys.full_state(t, y, &mut full);
        observe(&Sample {
            index: k,
            t,
            state: &full,
            outputs: &[f1, f2],
        })
    });
}

/// The rig's stiffness and masses about its engaged, unbroken configuration.
pub fn linearise(params: &[f64], drive: &Drive) -> Linearised {
    let p = params;
    let (k1, ks, k3, k4) = (p[ix::K1], p[ix::K_LIN], p[ix::K3], p[ix::K4_LIN]);
    let springs = [k1, ks, k3, k4];
    let (dofs, mass): (Vec<&'static str>, Vec<f64>) = match drive {
        Drive::Velocity => (
            vec!["load cell", "specimen", "sliding bar"],
            vec![p[ix::M1], p[ix::M2], p[ix::M3]],
        ),
        Drive::Force(_) => (
            vec!["load cell", "specimen", "sliding bar", "actuator"],
            vec![p[ix::M1], p[ix::M2], p[ix::M3], p[ix::M4]],
        ),
    };
    let n = dofs.len();
    let mut k = vec![0.0; n * n];
    // Spring j joins dof j−1 (ground for j = 0) and dof j (ground when j = n,
    // i.e. the prescribed actuator in velocity drive).
    for (j, &s) in springs.iter().enumerate().take(n + 1) {
        if j < n {
            k[j * n + j] += s;
        }
        if j >= 1 {
            k[(j - 1) * n + (j - 1)] += s;
            if j < n {
                k[(j - 1) * n + j] -= s;
                k[j * n + (j - 1)] -= s;
            }
        }
    }
    Linearised {
        dofs,
        mass,
        stiffness: k,
    }
}

/// Index of each parameter in a tensile parameter vector (the order of
/// `rigs/tensile4.json`'s `params`).
pub mod ix {
    #![allow(missing_docs)]
    pub const M1: usize = 0;
    pub const M2: usize = 1;
    pub const M3: usize = 2;
    pub const M4: usize = 3;
    pub const K1: usize = 4;
    pub const C1: usize = 5;
    pub const C1_POST: usize = 6;
    pub const K_LIN: usize = 7;
    pub const E_YIELD: usize = 8;
    pub const A0: usize = 9;
    pub const E_FRACTURE: usize = 15;
    pub const C2: usize = 16;
    pub const K3: usize = 17;
    pub const C3: usize = 18;
    pub const SLACK_A: usize = 19;
    pub const SLACK_B: usize = 20;
    pub const SLACK_C: usize = 21;
    pub const K4_LIN: usize = 22;
    pub const C4: usize = 23;
    pub const GAP: usize = 24;
    pub const VELOCITY: usize = 25;
    pub const RAMP: usize = 26;
}

/// The reference values of the published AA2024-T3 calibration (velocity 2 m/s).
pub const REFERENCE: [f64; 27] = [
    7.9, 0.14, 0.48, 37.4, 8.4e9, 5.51e5, 9.22e3, 8.63e7, 5.4e-5, 4.56e3, 1.97e6, -9.26e8, 1.36e11,
    0.0, 0.0, 1e-3, 0.0, 4.4e8, 0.0, 4.43e3, 4.87e5, 1.94e7, 1.19e8, 1.57e4, 1.87e-5, 2.0, 1.76e-6,
];
