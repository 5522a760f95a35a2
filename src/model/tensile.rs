//! The 4-DOF high-speed tensile rig: load cell, specimen, sliding bar and
//! actuator, with an exponential slack adapter and specimen fracture.
//!
//! Keep in sync with `shaders/model_tensile4.wgsl`, which states the same
//! equations for the ensemble kernels.
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

use super::{Drive, Linearised, ParamInfo, RigModel, Sample};
use crate::integrate::{Integrator, SampleGrid, System};

/// The tensile rig model (`"model": "tensile4"`).
#[derive(Debug, Clone, Copy)]
pub struct Tensile4;

/// The registered instance.
pub static TENSILE4: Tensile4 = Tensile4;

/// Highest degree of the specimen's plastic polynomial.
pub const MAX_POLY_DEGREE: usize = 5;

pub use super::tensile_params::{PARAMS, REFERENCE, ix};

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

const STATES: [&str; 8] = ["y1", "y2", "y3", "y4", "v1", "v2", "v3", "v4"];
const OUTPUTS: [(&str, &str); 2] = [("load_cell_force", "N"), ("specimen_force", "N")];

impl RigModel for Tensile4 {
    fn id(&self) -> &'static str {
        "tensile4"
    }

    fn params(&self) -> &'static [ParamInfo] {
        &PARAMS
    }

    fn state_names(&self) -> &'static [&'static str] {
        &STATES
    }

    fn output_names(&self) -> &'static [(&'static str, &'static str)] {
        &OUTPUTS
    }

    fn check(&self, params: &[f64]) -> Result<(), (&'static str, String)> {
        for (i, info) in PARAMS.iter().enumerate() {
            // e_fracture = +∞ (omitted or null): the specimen never breaks.
            let never = i == ix::E_FRACTURE && params[i] == f64::INFINITY;
            if !params[i].is_finite() && !never {
                return Err((info.name, "a finite number".into()));
            }
        }
        let positive = [
            ix::M1,
            ix::M2,
            ix::M3,
            ix::M4,
            ix::K1,
            ix::K3,
            ix::SLACK_A,
            ix::SLACK_B,
            ix::K4_LIN,
        ];
        for i in positive {
            if params[i] <= 0.0 {
                return Err((PARAMS[i].name, "a value > 0".into()));
            }
        }
        let non_negative = [
            ix::C1,
            ix::C1_POST,
            ix::K_LIN,
            ix::C2,
            ix::C3,
            ix::C4,
            ix::GAP,
            ix::RAMP,
            ix::E_FRACTURE,
        ];
        for i in non_negative {
            if params[i] < 0.0 {
                return Err((PARAMS[i].name, "a value ≥ 0".into()));
            }
        }
        Ok(())
    }

    fn simulate(
        &self,
        params: &[f64],
        drive: &Drive,
        grid: &SampleGrid,
        observe: &mut dyn FnMut(&Sample<'_>) -> ControlFlow<()>,
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

    fn linearisation_point(&self) -> String {
        "linearised rig (slack adapter engaged, specimen elastic)".into()
    }

    fn linearise(&self, params: &[f64], drive: &Drive) -> Linearised {
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

    fn omega_bound(&self, lower: &[f64], upper: &[f64], drive: &Drive) -> (f64, &'static str) {
        self.omega_bound_in_run(lower, upper, drive, f64::INFINITY)
    }

    /// The specimen's polynomial is scanned up to the largest elongation the
    /// run can reach: `e_fracture` (beyond it the specimen carries nothing), and
    /// under a velocity drive twice the actuator's travel `|v|·t_end` (every
    /// spring in the chain stretches with it; twice, for the overshoot of a
    /// suddenly loaded spring). A specimen that never breaks is then bounded
    /// by the travel alone.
    fn omega_bound_in_run(
        &self,
        lower: &[f64],
        upper: &[f64],
        drive: &Drive,
        t_end: f64,
    ) -> (f64, &'static str) {
        // Largest tangent stiffness of each element inside the bounds.
        let e_fracture = upper[ix::E_FRACTURE].abs().max(lower[ix::E_FRACTURE].abs());
        let travel = match drive {
            Drive::Velocity => {
                2.0 * upper[ix::VELOCITY].abs().max(lower[ix::VELOCITY].abs()) * t_end.max(0.0)
            }
            Drive::Force(_) => f64::INFINITY,
        };
        let (e_max, by_fracture) = if travel < e_fracture {
            (travel, false)
        } else {
            (e_fracture, true)
        };
        let mut poly_slope = 0.0;
        let mut largest = (0.0, 0);
        for i in 1..=MAX_POLY_DEGREE {
            let ai = upper[ix::A0 + i].abs().max(lower[ix::A0 + i].abs());
            let term = if ai == 0.0 {
                0.0
            } else {
                i as f64 * ai * e_max.powi(i as i32 - 1)
            };
            poly_slope += term;
            if term > largest.0 {
                largest = (term, i);
            }
        }
        let ks = upper[ix::K_LIN].max(poly_slope);
        // Name what drives the polynomial's tangent: e_fracture when a higher
        // term dominates at the elongation it allows (narrowing its range
        // helps), else the dominant coefficient.
        const A: [&str; MAX_POLY_DEGREE + 1] = ["a0", "a1", "a2", "a3", "a4", "a5"];
        let poly_name = if by_fracture && largest.1 >= 2 {
            "e_fracture"
        } else {
            A[largest.1]
        };
        let spring = [
            (upper[ix::K1], "k1"),
            (
                ks,
                if ks > upper[ix::K_LIN] {
                    poly_name
                } else {
                    "k_lin"
                },
            ),
            (upper[ix::K3], "k3"),
            // The exponential branch's tangent `a·e^{bd} + c` runs from `a + c` to
            // `k4_lin`; `check` allows `c < −a`, where it is negative, so bound its
            // magnitude.
            (
                upper[ix::K4_LIN]
                    .max((upper[ix::SLACK_A] + upper[ix::SLACK_C]).abs())
                    .max((lower[ix::SLACK_A] + lower[ix::SLACK_C]).abs()),
                "k4_lin",
            ),
        ];
        let damper = [
            (upper[ix::C1].max(upper[ix::C1_POST]), "c1"),
            (upper[ix::C2], "c2"),
            (upper[ix::C3], "c3"),
            (upper[ix::C4], "c4"),
        ];
        let masses = [
            (lower[ix::M1], "m1"),
            (lower[ix::M2], "m2"),
            (lower[ix::M3], "m3"),
            (lower[ix::M4], "m4"),
        ];
        let n = if matches!(drive, Drive::Velocity) {
            3
        } else {
            4
        };
        // Gershgorin on each row of M⁻¹K and M⁻¹C: a dof touches elements i and
        // i+1; |λ| ≤ C_row/m + sqrt(K_row/m).
        let mut best = (0.0, "m1");
        for i in 0..n {
            let (m, mname) = masses[i];
            let kr = 2.0 * (spring[i].0 + if i + 1 < 4 { spring[i + 1].0 } else { 0.0 });
            let cr = 2.0 * (damper[i].0 + if i + 1 < 4 { damper[i + 1].0 } else { 0.0 });
            let lam = cr / m + (kr / m).sqrt();
            if lam > best.0 {
                let stiffest = if i + 1 < 4 && spring[i + 1].0 > spring[i].0 {
                    spring[i + 1].1
                } else {
                    spring[i].1
                };
                let name = if (kr / m).sqrt() >= cr / m {
                    stiffest
                } else {
                    damper[i].1
                };
                best = (lam, if m < 1e-300 { mname } else { name });
            }
        }
        best
    }

    fn gpu(&self, _drive: &Drive) -> Option<super::GpuModel> {
        Some(super::tensile_gpu::TENSILE4_GPU)
    }
}
