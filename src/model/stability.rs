//! The stability bound of a compiled rig: an upper bound on the highest
//! natural frequency over a parameter box, which chooses or refuses the RK4
//! step. Two bounds, the per-law one (Gershgorin from each element law's
//! largest tangent) and the interval one (the compiled Jacobian enclosed over
//! an input box); the tighter finite one wins.

use super::compiled::{CompiledRig, prescribed};
use crate::base::Drive;
use crate::rig::desc::{Coef, DamperLaw, FrictionLaw, SpringLaw};

/// Where the stability bound takes the slope of a power law with exponent
/// below 1 (whose slope is unbounded at 0), as a fraction of the rig's reach.
/// No step is stable right at 0; below this the force is too small to do harm:
/// an overshooting RK4 step maps `|v|` to about `(h·c/m)·|v|^α`, which stays
/// bounded (a dither of `(h·c/m)^{1/(1−α)}` about zero), never a divergence.
pub const SUBLINEAR_FLOOR: f64 = 1e-3;

impl CompiledRig {
    fn coef_bound(&self, c: &Coef, lo: &[f64], hi: &[f64]) -> f64 {
        match c {
            Coef::Number(v) => v.abs(),
            Coef::Param(n) => {
                let i = self.param_index(n);
                lo[i].abs().max(hi[i].abs())
            }
            Coef::Switch(s) => self
                .coef_bound(&s.before, lo, hi)
                .max(self.coef_bound(&s.after, lo, hi)),
        }
    }

    fn coef_lower(&self, c: &Coef, lo: &[f64]) -> f64 {
        match c {
            Coef::Number(v) => *v,
            Coef::Param(n) => lo[self.param_index(n)],
            Coef::Switch(s) => self
                .coef_lower(&s.before, lo)
                .min(self.coef_lower(&s.after, lo)),
        }
    }

    /// Reach (elongation m, rate m/s) used by the stability bound.
    fn reach(&self, lo: &[f64], hi: &[f64]) -> (f64, f64) {
        if let Some(r) = self.desc.reach {
            return (r.elongation, r.rate);
        }
        let e = self
            .desc
            .elements
            .iter()
            .filter_map(|e| e.breaks_at.as_ref())
            .map(|c| self.coef_bound(c, lo, hi))
            .fold(0.0, f64::max);
        (if e > 0.0 { e } else { 0.01 }, 10.0)
    }

    /// Largest tangent stiffness (N/m) and damping (N·s/m) of element `i` over
    /// the parameter box, with the names that set them.
    fn element_bound(&self, i: usize, lo: &[f64], hi: &[f64]) -> (f64, f64, String, String) {
        let e = &self.desc.elements[i];
        let (ex, rx) = self.reach(lo, hi);
        let b = |c: &Coef| self.coef_bound(c, lo, hi);
        let name = |c: &Coef| limiting_name(c, &b).unwrap_or_else(|| e.name.clone());
        let (mut k, mut kname) = (0.0, e.name.clone());
        if let Some(s) = &e.spring {
            let (kk, nn) = match s {
                SpringLaw::Linear { k } => (b(k), name(k)),
                SpringLaw::Polynomial { coeffs } => (poly_slope(coeffs, &b, ex), e.name.clone()),
                SpringLaw::LinearThenPolynomial { k, coeffs, .. } => {
                    let ps = poly_slope(coeffs, &b, ex);
                    if ps > b(k) {
                        (ps, format!("{}.coeffs", e.name))
                    } else {
                        (b(k), name(k))
                    }
                }
                SpringLaw::ExpLinear { a, c, k, .. } => (b(k).max(b(a) + b(c)), name(k)),
                SpringLaw::Expression { force } => (
                    self.expression_tangent(force, "x", ex, lo, hi),
                    format!("{}.spring.force", e.name),
                ),
                SpringLaw::PowerLaw { k, beta } => {
                    let bl = self.coef_lower(beta, lo);
                    let bh = b(beta);
                    // k·β·|e|^{β−1}: largest at the reach for β ≥ 1; for β < 1 it
                    // grows without bound at 0, so take it at SUBLINEAR_FLOOR of
                    // the reach (see there).
                    let x = if bl < 1.0 { SUBLINEAR_FLOOR * ex } else { ex };
                    (
                        b(k) * bh * x.powf(bl.min(bh) - 1.0).max(x.powf(bh - 1.0)),
                        name(k),
                    )
                }
            };
            k = kk;
            kname = nn;
        }
        if let Some(FrictionLaw::StickSlip { k_t, .. }) = &e.friction
            && b(k_t) > k
        {
            k = b(k_t);
            kname = name(k_t);
        }
        // The damper's own parameter names its tangent (the element where
        // it has none, or several).
        let cname = match &e.damper {
            Some(
                DamperLaw::Viscous { c }
                | DamperLaw::PowerLaw { c, .. }
                | DamperLaw::Saturating { c, .. },
            ) => name(c),
            _ => e.name.clone(),
        };
        let c = match &e.damper {
            None => 0.0,
            Some(DamperLaw::Viscous { c }) => b(c),
            Some(DamperLaw::PowerLaw { c, alpha }) => {
                let a = b(alpha);
                let x = if self.coef_lower(alpha, lo) < 1.0 {
                    SUBLINEAR_FLOOR * rx
                } else {
                    rx
                };
                b(c) * a
                    * x.powf(self.coef_lower(alpha, lo) - 1.0)
                        .max(x.powf(a - 1.0))
            }
            Some(DamperLaw::Saturating { c, c_high, .. }) => b(c).max(b(c_high)),
            Some(DamperLaw::Asymmetric {
                c_tension,
                c_compression,
            }) => b(c_tension).max(b(c_compression)),
            Some(DamperLaw::Expression { force }) => {
                self.expression_tangent(force, "v", rx, lo, hi)
            }
        };
        (k, c, kname, cname)
    }

    /// Largest |dF/d`var`| of an expression law for `var` in `[−reach, reach]`,
    /// with every parameter at its lower and then at its upper bound: central
    /// differences at 401 points. A sampled estimate, not a rigorous bound.
    fn expression_tangent(&self, src: &str, var: &str, reach: f64, lo: &[f64], hi: &[f64]) -> f64 {
        let Ok(e) = crate::compile::front::expr::parse(src) else {
            return 0.0;
        };
        let mut best: f64 = 0.0;
        for bound in [lo, hi] {
            let value = |x: f64| {
                e.eval(&|n| {
                    if n == var {
                        return x;
                    }
                    self.desc
                        .params
                        .iter()
                        .position(|p| p.name == n)
                        .map_or(f64::NAN, |i| bound[i])
                })
            };
            let dx = reach * 1e-4;
            for j in 0..=400 {
                let x = reach * (j as f64 / 200.0 - 1.0);
                let d = (value(x + dx) - value(x - dx)) / (2.0 * dx);
                if d.is_finite() {
                    best = best.max(d.abs());
                }
            }
        }
        best
    }

    /// The per-law bound: Gershgorin on each free node's row of M⁻¹K and
    /// M⁻¹C from each element law's largest tangent (`element_bound`),
    /// `c/m + √(k/m)` per row.
    pub fn per_law_omega(&self, lower: &[f64], upper: &[f64], drive: &Drive) -> (f64, String) {
        // Gershgorin on each free node's row of M⁻¹K and M⁻¹C, with every
        // element's largest tangent stiffness and damping over the box and the
        // reach. A node whose motion the drive prescribes (its displacement
        // slot's derivative is the constant 0) is not integrated: no row.
        let bounds: Vec<(f64, f64, String, String)> = (0..self.desc.elements.len())
            .map(|i| self.element_bound(i, lower, upper))
            .collect();
        let prog = self.program_for(drive).map(|i| &self.lowered.programs[i]);
        let driven = |k: usize| prog.is_some_and(|p| prescribed(p, k));
        let mut best = (
            0.0,
            self.params
                .first()
                .map_or(String::new(), |p| p.name.clone()),
        );
        for (k, node) in self.desc.nodes.iter().enumerate() {
            if driven(k) {
                continue;
            }
            let m = self.coef_lower(&node.mass, lower);
            let (mut kr, mut cr) = (0.0, 0.0);
            let mut stiffest = (0.0, String::new());
            let mut most_damped = (0.0, String::new());
            for (e, b) in self.desc.elements.iter().zip(&bounds) {
                if e.between.contains(&node.name) {
                    let both = 1.0 + f64::from(u8::from(!e.between.iter().any(|x| x == "ground")));
                    kr += both * b.0;
                    cr += both * b.1;
                    if b.0 >= stiffest.0 {
                        stiffest = (b.0, b.2.clone());
                    }
                    if b.1 > most_damped.0 {
                        most_damped = (b.1, b.3.clone());
                    }
                }
            }
            let lam = cr / m + (kr / m).sqrt();
            if lam > best.0 || !lam.is_finite() {
                // The row's damping term names the bound where it is the
                // larger part of it.
                let limiter = if cr / m > (kr / m).sqrt() && !most_damped.1.is_empty() {
                    &most_damped.1
                } else {
                    &stiffest.1
                };
                best = (lam, limiter.clone());
            }
        }
        // A backlash element's play relaxes at the rate F_s'/c (its row of
        // the Jacobian in play: ṗ = ė + F_s(e − p)/c), a real eigenvalue of
        // at most the largest tangent stiffness over the smallest damping.
        for (e, b) in self.desc.elements.iter().zip(&bounds) {
            if let (Some(_), Some(DamperLaw::Viscous { c })) = (&e.backlash, &e.damper) {
                let lam = b.0 / self.coef_lower(c, lower);
                let lam = if lam >= 0.0 { lam } else { f64::INFINITY };
                if lam > best.0 || !lam.is_finite() {
                    let name = match c {
                        Coef::Param(n) => n.clone(),
                        _ => b.2.clone(),
                    };
                    best = (lam, name);
                }
            }
        }
        best
    }

    /// The box of inputs the interval bound encloses the Jacobian over, for
    /// parameters in `[lower, upper]` and a run of model time `0..t_end`:
    /// every parameter slot over its range (fixed ones are points), time over
    /// `[0, t_end]`, every regime variable over all its values, each node's
    /// displacement and every internal state (slider, play) in `[−e, e]` and
    /// each node's velocity in `[−r, r]`, with `(e, r)` the rig's reach as
    /// `element_bound` reads it (its `"reach"`, else the largest break
    /// limit and 10 m/s). An element's elongation then lies in `[−2e, 2e]`
    /// and its rate in `[−2r, 2r]`, which holds the `[−e, e]`, `[−r, r]`
    /// the per-law bound assumes: the box is sound exactly where the reach
    /// bounds each node's excursion from rest (as it does for the shipped
    /// rigs whose nodes move by less than their elements stretch), and for
    /// every law whose slope does not depend on the state (linear springs
    /// and dampers, the friction's tangential stiffness) it is sound whatever
    /// the run reaches. A prescribed node's position comes from the drive
    /// over the time span, so its elements' elongations are as wide as the
    /// drive goes in `t_end`; the experiment's force table (a force drive)
    /// enters as the hull of its values.
    pub fn input_box(
        &self,
        prog: &crate::compile::Program,
        drive: &Drive,
        lower: &[f64],
        upper: &[f64],
        t_end: f64,
    ) -> crate::compile::analysis::interval::InputBox {
        use crate::compile::analysis::interval::{Interval, all_regimes};
        let (e, r) = self.reach(lower, upper);
        let nodes = self.desc.nodes.len();
        let y = (0..prog.deriv.len())
            .map(|k| {
                let w = if (nodes..2 * nodes).contains(&k) {
                    r
                } else {
                    e
                };
                Interval::new(-w, w)
            })
            .collect();
        crate::compile::analysis::interval::InputBox {
            slots: lower
                .iter()
                .zip(upper)
                .map(|(&a, &b)| Interval::new(a, b))
                .collect(),
            t: Interval::new(0.0, t_end),
            y,
            regimes: all_regimes(prog),
            force: match drive {
                Drive::Force(tab) => Some(crate::compile::analysis::interval::table_hull(tab)),
                Drive::Velocity => None,
            },
        }
    }

    /// The stability bound from the compiled graph: every entry of the
    /// derivative's Jacobian enclosed by interval forward-mode tangents over
    /// [`Self::input_box`], and the spectral radius of every matrix in that
    /// enclosure bounded by [`crate::compile::analysis::interval::spectral_bound`]
    /// (a row-scaled Gershgorin bound). The name is the parameter whose range
    /// drives it most: the one that, fixed at its more favourable end, lowers
    /// the bound most. Infinite where an entry is unbounded over the box (a
    /// power law with exponent below 1, whose slope is unbounded at 0; a
    /// drive whose reach grows without bound in `t_end`). `None` without a
    /// program for `drive`.
    pub fn interval_omega(
        &self,
        lower: &[f64],
        upper: &[f64],
        drive: &Drive,
        t_end: f64,
    ) -> Option<(f64, String)> {
        use crate::compile::analysis::interval::{Interval, deriv_jacobian_box, spectral_bound};
        let prog = &self.lowered.programs[self.program_for(drive)?];
        let n = prog.deriv.len();
        let bx = self.input_box(prog, drive, lower, upper, t_end);
        let bound = |bx: &crate::compile::analysis::interval::InputBox| {
            spectral_bound(&deriv_jacobian_box(prog, bx), n)
        };
        let all = bound(&bx);
        let mut driver: Option<(f64, usize)> = None;
        if all.is_finite() {
            for p in 0..lower.len().min(self.params.len()) {
                if lower[p] >= upper[p] {
                    continue;
                }
                let mut best = f64::INFINITY;
                for v in [lower[p], upper[p]] {
                    let mut b = bx.clone();
                    b.slots[p] = Interval::point(v);
                    best = best.min(bound(&b));
                }
                if best < all && driver.is_none_or(|d| best < d.0) {
                    driver = Some((best, p));
                }
            }
        }
        let name = match driver {
            Some((_, p)) => self.params[p].name.clone(),
            None => self.per_law_omega(lower, upper, drive).1,
        };
        Some((all, name))
    }
}

/// The parameter that sets a coefficient's largest value: its own, or for a
/// coefficient that switches when an element breaks, the larger side's.
fn limiting_name(c: &Coef, bound: &dyn Fn(&Coef) -> f64) -> Option<String> {
    match c {
        Coef::Number(_) => None,
        Coef::Param(n) => Some(n.clone()),
        Coef::Switch(s) => {
            let side = if bound(&s.before) >= bound(&s.after) {
                &s.before
            } else {
                &s.after
            };
            limiting_name(side, bound)
        }
    }
}

fn poly_slope(coeffs: &[Coef], b: &impl Fn(&Coef) -> f64, e: f64) -> f64 {
    coeffs
        .iter()
        .enumerate()
        .skip(1)
        .map(|(i, c)| i as f64 * b(c) * e.powi(i as i32 - 1))
        .sum()
}
