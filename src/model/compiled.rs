//! A rig described as data (`rigs/*.json` or a campaign's `"rig"`), compiled
//! once and run through the [`RigModel`] interface like any model.

use std::ops::ControlFlow;

use super::{Linearised, RigModel};
use crate::base::{Drive, FittedSample, ParamInfo, Report, Sample};
use crate::base::{SampleGrid, walk_grid};
use crate::compile::Arith;
use crate::compile::back::native::{Native, NativeSlot};
use crate::compile::{EventStepper, GpuRig, LANES, LaneCode, LaneRunner, Lowered, Tape, lower};
use crate::rig::RigError;
use crate::rig::desc::{Coef, DamperLaw, FrictionLaw, GapKind, RigDesc, SpringLaw};

/// A compiled rig. Built once per job; its names live for the whole process.
#[derive(Debug)]
pub struct CompiledRig {
    id: &'static str,
    params: &'static [ParamInfo],
    states: &'static [&'static str],
    outputs: &'static [(&'static str, &'static str)],
    /// The description it was compiled from.
    pub desc: RigDesc,
    /// The compiled programs, one per drive mode.
    pub lowered: Lowered,
    tapes: Vec<Tape>,
    /// Each tape in the lane ensemble's register form.
    lane_code: Vec<LaneCode>,
    /// Each lane code's native build, made once it pays.
    native: Vec<NativeSlot>,
    /// Each lane code's f32 build, made when first asked for.
    native_f32: Vec<NativeSlot>,
    /// Each program prepared for the GPU kernels (`None`: it cannot run there).
    gpu: Vec<Option<std::sync::Arc<GpuRig>>>,
    /// Each program's fitness variant, where it skips switches that can no
    /// longer reach the fitted output ([`crate::compile::analysis::liveness`]); `None`
    /// where it would skip none.
    fitted: Vec<Option<Fitted>>,
}

/// A program's fitness variant and its lane code and native builds (its
/// graph, and so its tape, is the program's own).
#[derive(Debug)]
struct Fitted {
    program: crate::compile::Program,
    lane_code: LaneCode,
    native: NativeSlot,
    native_f32: NativeSlot,
}

/// What one program's lane runs read: the program, its tape and lane code.
type LaneParts<'a> = (&'a crate::compile::Program, &'a Tape, &'a LaneCode);

/// How a group of lane runs reports ([`CompiledRig::run_lanes`]).
enum Observe<'a> {
    /// Each run at each sample, as [`RigModel::simulate_many`].
    Each(
        Report,
        &'a mut dyn FnMut(usize, &Sample<'_>) -> ControlFlow<()>,
    ),
    /// Output 0 of the group at each sample, as [`RigModel::simulate_fitted`].
    Fitted(&'a mut dyn FnMut(&FittedSample<'_>, &mut u64)),
}

fn leak(s: &str) -> &'static str {
    Box::leak(s.to_string().into_boxed_str())
}

impl CompiledRig {
    /// Index of parameter `name`, which validation has checked exists.
    fn param_index(&self, name: &str) -> usize {
        self.params
            .iter()
            .position(|p| p.name == name)
            .expect("a parameter validation checked")
    }

    /// Compiles `desc` (read from `file`, for messages).
    pub fn new(desc: RigDesc, file: &str) -> Result<Self, RigError> {
        let lowered = lower(&desc, file)?;
        let params: Vec<ParamInfo> = desc
            .params
            .iter()
            .map(|p| ParamInfo {
                name: leak(&p.name),
                unit: leak(&p.unit),
                doc: leak(&p.doc),
                scope: p.scope,
                default: p.default,
                scale: p.scale,
            })
            .collect();
        let states: Vec<&'static str> = lowered.states.iter().map(|s| leak(s)).collect();
        let outputs: Vec<(&'static str, &'static str)> = desc
            .outputs
            .iter()
            .map(|o| (leak(&o.name), leak(&o.unit)))
            .collect();
        let tapes: Vec<Tape> = lowered.programs.iter().map(Tape::new).collect();
        let lane_code = lowered
            .programs
            .iter()
            .zip(&tapes)
            .map(|(p, t)| LaneCode::new(p, t))
            .collect();
        let variants: Vec<Option<crate::compile::Program>> = lowered
            .programs
            .iter()
            .map(crate::compile::analysis::liveness::skipping_variant)
            .collect();
        let gpu = lowered
            .programs
            .iter()
            .zip(&variants)
            .map(|(p, v)| {
                GpuRig::with_fitted(p, v.clone())
                    .ok()
                    .map(std::sync::Arc::new)
            })
            .collect();
        let fitted = variants
            .into_iter()
            .zip(&tapes)
            .map(|(v, t)| {
                v.map(|v| Fitted {
                    lane_code: LaneCode::new(&v, t),
                    program: v,
                    native: NativeSlot::default(),
                    native_f32: NativeSlot::default(),
                })
            })
            .collect();
        Ok(Self {
            id: leak(&desc.id),
            params: Box::leak(params.into_boxed_slice()),
            states: Box::leak(states.into_boxed_slice()),
            outputs: Box::leak(outputs.into_boxed_slice()),
            desc,
            lowered,
            native: std::iter::repeat_with(NativeSlot::default)
                .take(tapes.len())
                .collect(),
            native_f32: std::iter::repeat_with(NativeSlot::default)
                .take(tapes.len())
                .collect(),
            tapes,
            lane_code,
            gpu,
            fitted,
        })
    }

    /// Compiles and leaks, for the `&'static dyn RigModel` the campaign holds.
    pub fn leaked(desc: RigDesc, file: &str) -> Result<&'static Self, RigError> {
        Ok(Box::leak(Box::new(Self::new(desc, file)?)))
    }

    /// The f64 native build of `code` in `slot` for running `params` on
    /// `grid`, once its work so far makes it pay ([`NativeSlot::get`]).
    fn native_for(
        slot: &NativeSlot,
        code: &LaneCode,
        params: &[&[f64]],
        grid: &SampleGrid,
    ) -> Option<std::sync::Arc<Native>> {
        let work = (params.len() * grid.total_steps()) as u64;
        slot.get(code, work)
    }

    /// Program `i`'s parts for lane runs.
    fn lane_parts(&self, i: usize) -> LaneParts<'_> {
        (
            &self.lowered.programs[i],
            &self.tapes[i],
            &self.lane_code[i],
        )
    }

    /// `params` run by a program's lane ensemble (`parts`), natively where
    /// `native` is its build, in groups of [`LANES`].
    fn run_lanes(
        &self,
        parts: LaneParts<'_>,
        drive: &Drive,
        params: &[&[f64]],
        grid: &SampleGrid,
        native: Option<&Native>,
        mut observe: Observe<'_>,
    ) {
        let force = drive.force_table();
        let (program, tape, code) = parts;
        for (c, chunk) in params.chunks(LANES).enumerate() {
            let mut runner = LaneRunner::new(program, tape, code, chunk, force);
            if let Some(n) = native {
                runner = runner.with_native(n);
            }
            let mut runner = runner.numbered_from(c * LANES);
            match &mut observe {
                Observe::Each(report, f) => runner.run(grid, *report, *f),
                Observe::Fitted(f) => runner.run_fitted(grid, *f),
            }
        }
    }

    /// Index of the program for `drive`.
    pub fn program_for(&self, drive: &Drive) -> Option<usize> {
        let mode = match drive {
            Drive::Velocity => "velocity",
            Drive::Force(_) => "force",
        };
        self.lowered.programs.iter().position(|p| p.mode == mode)
    }

    /// A run's integrator for `params` under `drive`.
    pub fn stepper<'a>(&'a self, params: &[f64], drive: &'a Drive) -> Option<EventStepper<'a>> {
        let i = self.program_for(drive)?;
        let force = drive.force_table();
        Some(EventStepper::new(
            &self.lowered.programs[i],
            &self.tapes[i],
            params,
            force,
        ))
    }

    fn coef_bound(&self, c: &Coef, lo: &[f64], hi: &[f64]) -> f64 {
        match c {
            Coef::Number(v) => v.abs(),
            Coef::Param(n) => {
                let i = self
                    .desc
                    .params
                    .iter()
                    .position(|p| &p.name == n)
                    .expect("checked at compile time");
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
            Coef::Param(n) => {
                lo[self
                    .desc
                    .params
                    .iter()
                    .position(|p| &p.name == n)
                    .expect("checked at compile time")]
            }
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

/// Where the stability bound takes the slope of a power law with exponent
/// below 1 (whose slope is unbounded at 0), as a fraction of the rig's reach.
/// No step is stable right at 0; below this the force is too small to do harm:
/// an overshooting RK4 step maps `|v|` to about `(h·c/m)·|v|^α`, which stays
/// bounded (a dither of `(h·c/m)^{1/(1−α)}` about zero), never a divergence.
pub const SUBLINEAR_FLOOR: f64 = 1e-3;

impl CompiledRig {
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
}

impl CompiledRig {
    /// The per-law bound: Gershgorin on each free node's row of M⁻¹K and
    /// M⁻¹C from each element law's largest tangent ([`Self::element_bound`]),
    /// `c/m + √(k/m)` per row.
    pub fn per_law_omega(
        &self,
        lower: &[f64],
        upper: &[f64],
        drive: &Drive,
    ) -> (f64, &'static str) {
        // Gershgorin on each free node's row of M⁻¹K and M⁻¹C, with every
        // element's largest tangent stiffness and damping over the box and the
        // reach. A node whose motion the drive prescribes (its displacement
        // slot's derivative is the constant 0) is not integrated: no row.
        let bounds: Vec<(f64, f64, String, String)> = (0..self.desc.elements.len())
            .map(|i| self.element_bound(i, lower, upper))
            .collect();
        let prog = self.program_for(drive).map(|i| &self.lowered.programs[i]);
        let prescribed = |k: usize| {
            prog.is_some_and(|p| {
                matches!(
                    p.graph.ops[p.deriv[k] as usize],
                    crate::compile::Op::Const(_)
                )
            })
        };
        let mut best = (0.0, self.params.first().map_or("", |p| p.name));
        for (k, node) in self.desc.nodes.iter().enumerate() {
            if prescribed(k) {
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
                best = (lam, leak(limiter));
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
                    best = (lam, leak(&name));
                }
            }
        }
        best
    }
}

impl CompiledRig {
    /// The box of inputs the interval bound encloses the Jacobian over, for
    /// parameters in `[lower, upper]` and a run of model time `0..t_end`:
    /// every parameter slot over its range (fixed ones are points), time over
    /// `[0, t_end]`, every mode variable over all its values, each node's
    /// displacement and every internal state (slider, play) in `[−e, e]` and
    /// each node's velocity in `[−r, r]`, with `(e, r)` the rig's reach as
    /// [`Self::element_bound`] reads it (its `"reach"`, else the largest break
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
        use crate::compile::analysis::interval::{Interval, all_modes};
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
            modes: all_modes(prog),
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
    ) -> Option<(f64, &'static str)> {
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
            Some((_, p)) => self.params[p].name,
            None => self.per_law_omega(lower, upper, drive).1,
        };
        Some((all, name))
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

impl RigModel for CompiledRig {
    fn id(&self) -> &'static str {
        self.id
    }

    fn params(&self) -> &'static [ParamInfo] {
        self.params
    }

    fn state_names(&self) -> &'static [&'static str] {
        self.states
    }

    fn output_names(&self) -> &'static [(&'static str, &'static str)] {
        self.outputs
    }

    fn supports(&self, drive: &Drive) -> bool {
        self.program_for(drive).is_some()
    }

    fn check(&self, params: &[f64]) -> Result<(), (&'static str, String)> {
        for (i, info) in self.params.iter().enumerate() {
            if !params[i].is_finite() {
                return Err((info.name, "a finite number".into()));
            }
        }
        for node in &self.desc.nodes {
            if let Coef::Param(n) = &node.mass {
                let i = self.param_index(n);
                if params[i] <= 0.0 {
                    return Err((self.params[i].name, "a mass > 0".into()));
                }
            }
        }
        for e in &self.desc.elements {
            if let (Some(_), Some(DamperLaw::Viscous { c: Coef::Param(n) })) =
                (&e.backlash, &e.damper)
            {
                let i = self.param_index(n);
                if params[i] <= 0.0 {
                    return Err((
                        self.params[i].name,
                        format!(
                            "a damping > 0 (backlash element {:?}: its play moves with ṗ = ė + F_s/c)",
                            e.name
                        ),
                    ));
                }
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
        let n_out = self.outputs.len();
        let n = self.states.len();
        let Some(mut st) = self.stepper(params, drive) else {
            // A drive mode the rig does not declare (refused by campaign
            // validation): every output is NaN, so the run counts as diverged.
            let nan = vec![f64::NAN; n_out.max(n)];
            for k in 0..grid.samples {
                let s = Sample {
                    index: k,
                    t: grid.time(k),
                    state: &nan[..n],
                    outputs: &nan[..n_out],
                };
                if observe(&s).is_break() {
                    return;
                }
            }
            return;
        };
        let mut y = st.y0.clone();
        let mut outs = vec![0.0; n_out];
        let mut full = vec![0.0; n];
        let mut ctx = (&mut st, &mut y);
        walk_grid(
            grid,
            &mut ctx,
            |(st, y), t, h| st.step(t, h, y),
            |(st, y), k, t| {
                st.report(t, y, &mut outs, &mut full);
                if st.chattered {
                    outs.fill(f64::NAN);
                }
                observe(&Sample {
                    index: k,
                    t,
                    state: &full,
                    outputs: &outs,
                })
            },
        );
    }

    fn simulate_many(
        &self,
        params: &[&[f64]],
        drive: &Drive,
        grid: &SampleGrid,
        report: Report,
        observe: &mut dyn FnMut(usize, &Sample<'_>) -> ControlFlow<()>,
    ) {
        let Some(i) = self.program_for(drive) else {
            for (j, p) in params.iter().enumerate() {
                self.simulate(p, drive, grid, &mut |s| observe(j, &report.of(s)));
            }
            return;
        };
        let native = Self::native_for(&self.native[i], &self.lane_code[i], params, grid);
        self.run_lanes(
            self.lane_parts(i),
            drive,
            params,
            grid,
            native.as_deref(),
            Observe::Each(report, observe),
        );
    }

    fn simulate_fitted(
        &self,
        params: &[&[f64]],
        drive: &Drive,
        grid: &SampleGrid,
        f32: bool,
        observe: &mut dyn FnMut(&FittedSample<'_>, &mut u64),
    ) -> bool {
        let Some(i) = self.program_for(drive) else {
            super::fitted_one_by_one(self, params, drive, grid, observe);
            return false;
        };
        // Output 0 only: the fitness variant where it skips switches.
        let (parts, slots) = match &self.fitted[i] {
            Some(f) => (
                (&f.program, &self.tapes[i], &f.lane_code),
                (&f.native, &f.native_f32),
            ),
            None => (self.lane_parts(i), (&self.native[i], &self.native_f32[i])),
        };
        let in_f32 = f32.then(|| slots.1.now(parts.2, Arith::F32)).flatten();
        let native = in_f32
            .clone()
            .or_else(|| Self::native_for(slots.0, parts.2, params, grid));
        self.run_lanes(
            parts,
            drive,
            params,
            grid,
            native.as_deref(),
            Observe::Fitted(observe),
        );
        in_f32.is_some()
    }

    fn lanes(&self) -> usize {
        LANES
    }

    fn gpu(&self, drive: &Drive) -> Option<super::GpuModel> {
        let i = self.program_for(drive)?;
        self.gpu[i].clone()
    }

    fn linearisation_point(&self) -> String {
        // The same mode choice as `linearise`, said only for the kinds of
        // switching element the rig has.
        let has = |suffix: &str| self.lowered.modes.iter().any(|m| m.name.ends_with(suffix));
        let mut said = Vec::new();
        if has(".contact") {
            let free_play = self
                .desc
                .elements
                .iter()
                .any(|e| e.gap.as_ref().is_some_and(|g| g.kind == GapKind::FreePlay));
            said.push(if free_play {
                "every contact closed (free play in tension)"
            } else {
                "every contact closed"
            });
        }
        match (has(".fracture"), has(".yield")) {
            (true, true) => said.push("nothing broken or yielded"),
            (true, false) => said.push("nothing broken"),
            (false, true) => said.push("nothing yielded"),
            (false, false) => {}
        }
        if has(".friction") {
            said.push("every slider stuck");
        }
        if has(".backlash") {
            said.push("backlash taken up in tension");
        }
        let mut s = format!("rig {} linearised about rest", self.id);
        if !said.is_empty() {
            s += &format!(": {}", said.join(", "));
        }
        s
    }

    fn linearise(&self, params: &[f64], drive: &Drive) -> Linearised {
        // About rest with every contact closed (a backlash element's play
        // taken up in tension), nothing broken or yielded and every slider
        // stuck, from the compiled derivative's own tangents.
        let mut st = self.stepper(params, drive).expect("a declared drive mode");
        for (v, m) in self.lowered.modes.iter().enumerate() {
            st.modes[v] = u32::from(m.name.ends_with(".contact") || m.name.ends_with(".backlash"));
        }
        let pi = self.program_for(drive).expect("declared");
        let prog = &self.lowered.programs[pi];
        let nodes = self.desc.nodes.len();
        let n = self.states.len();
        // A node is a degree of freedom unless the drive prescribes it (its
        // displacement slot's derivative is then the constant 0).
        let free: Vec<usize> = (0..nodes)
            .filter(|&k| {
                !matches!(
                    prog.graph.ops[prog.deriv[k] as usize],
                    crate::compile::Op::Const(_)
                )
            })
            .collect();
        let mass: Vec<f64> = free
            .iter()
            .map(|&k| match &self.desc.nodes[k].mass {
                Coef::Number(v) => *v,
                Coef::Param(p) => params[self.param_index(p)],
                Coef::Switch(_) => f64::NAN,
            })
            .collect();
        let d = free.len();
        let modes = st.modes.clone();
        let jac = crate::compile::analysis::tangent::deriv_jacobian(
            prog,
            &self.tapes[pi],
            &mut st.frame,
            0.0,
            &vec![0.0; n],
            &modes,
        );
        let mut kmat = vec![0.0; d * d];
        for (i, &ki) in free.iter().enumerate() {
            for (j, &kj) in free.iter().enumerate() {
                kmat[i * d + j] = -mass[i] * jac[(nodes + ki) * n + kj];
            }
        }
        Linearised {
            dofs: free
                .iter()
                .map(|&k| leak(&self.desc.nodes[k].name))
                .collect(),
            mass,
            stiffness: kmat,
        }
    }

    fn omega_bound(&self, lower: &[f64], upper: &[f64], drive: &Drive) -> (f64, &'static str) {
        self.omega_bound_in_run(lower, upper, drive, f64::INFINITY)
    }

    fn omega_bound_in_run(
        &self,
        lower: &[f64],
        upper: &[f64],
        drive: &Drive,
        t_end: f64,
    ) -> (f64, &'static str) {
        // The graph's interval bound where it is finite and no looser than the
        // per-law one; the per-law one otherwise (see `interval_omega`).
        let old = self.per_law_omega(lower, upper, drive);
        match self.interval_omega(lower, upper, drive, t_end) {
            Some(new) if new.0.is_finite() && new.0 <= old.0 => new,
            _ => old,
        }
    }
}
