//! Fixed-step RK4 over a compiled rig with every switch located inside the step.
//!
//! A step from `(t, y)` in the current regimes is taken whole; then every armed
//! transition (its regime variable holds its `from` value) that fires over the
//! step ([`crate::compile::Transition::fires`]: past the switch at the step's end, and
//! on the armed side at its start or going further past) is located on the cubic Hermite
//! interpolant of the step (the state and its derivative at both ends, error
//! O(h⁴)) by [`locate_crossing`], a bracketing secant search. The earliest one fires: the step is
//! redone from its start to the crossing, the mode changes, and the rest of the
//! step is taken the same way. More than [`MAX_EVENTS_PER_STEP`] events in one
//! step flag the run as chattering and stop it (it is never hung).
//!
//! A rig with controllers takes each step in pieces between its sample
//! instants ([`SampleClock::step`]), the held states updated at each
//! ([`EventStepper::sample`]); switches are located inside each piece, so a
//! switch and an instant in the same step are taken in time order.

use crate::compile::exec::lane_code::LaneCode;
use crate::compile::exec::native_calls::Native;
use crate::compile::exec::sampling::SampleClock;
use crate::compile::exec::tape::{Frame, Point, Tape, table_value};
use crate::compile::program::Program;

/// Events one step may take before the run is flagged as chattering.
pub const MAX_EVENTS_PER_STEP: usize = 16;

/// A fired switch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fired {
    /// Model time (s).
    pub t: f64,
    /// Transition index in the program.
    pub transition: usize,
}

/// A stepper's native derivative ([`EventStepper::with_native_deriv`]).
#[derive(Debug)]
struct NativeDeriv<'p> {
    code: &'p LaneCode,
    native: &'p Native,
    /// The run's scalar register file: per-run constants filled once, states
    /// and regimes at each call.
    r: Vec<f64>,
    tab: Vec<f64>,
    /// The event functions' values from `native`.
    g: Vec<f64>,
}

/// One run's integrator: scratch space, regimes and what fired.
#[derive(Debug)]
pub struct EventStepper<'p> {
    prog: &'p Program,
    tape: &'p Tape,
    /// The run's evaluated values.
    pub frame: Frame<'p>,
    /// Regime variables.
    pub regimes: Vec<u32>,
    /// Held (controller) states.
    pub held: Vec<f64>,
    /// The next sample instant.
    pub clock: SampleClock,
    /// The state the run starts from ([`crate::compile::exec::initial`]).
    pub y0: Vec<f64>,
    /// Switches fired so far, in time order.
    pub fired: Vec<Fired>,
    /// Whether a step took more than [`MAX_EVENTS_PER_STEP`] events.
    pub chattered: bool,
    k: [Vec<f64>; 4],
    tmp: Vec<f64>,
    start: Vec<f64>,
    f_end: Vec<f64>,
    interp: Vec<f64>,
    /// The state at a piece's end, while a switch inside it is located.
    y1: Vec<f64>,
    /// The transitions that fired over a piece.
    hits: Vec<usize>,
    /// Event-function values at the current step's start.
    g_start: Vec<f64>,
    /// Event-function values at the current step's end.
    g_end: Vec<f64>,
    /// The derivative from native code, where a lane runner gave it.
    native: Option<NativeDeriv<'p>>,
}

impl<'p> EventStepper<'p> {
    /// A run of `prog` with the full parameter vector `params`, in the regimes
    /// its initial state `y0` implies ([`crate::compile::exec::initial`]; at rest in the
    /// regimes' value 0 without initial-state parameters).
    pub fn new(
        prog: &'p Program,
        tape: &'p Tape,
        params: &[f64],
        force: Option<&'p crate::base::PiecewiseLinear>,
    ) -> Self {
        let n = prog.deriv.len();
        let z = vec![0.0; n];
        let mut frame = Frame::new(prog, tape, params, force);
        let (y0, regimes) = crate::compile::exec::initial::initial_state(prog, tape, &mut frame);
        let held = crate::compile::exec::initial::initial_held(prog, &frame);
        Self {
            prog,
            tape,
            frame,
            regimes,
            held,
            clock: SampleClock::default(),
            y0,
            fired: vec![],
            chattered: false,
            k: [z.clone(), z.clone(), z.clone(), z.clone()],
            tmp: z.clone(),
            start: z.clone(),
            f_end: z.clone(),
            y1: z.clone(),
            hits: vec![],
            interp: z,
            g_start: vec![0.0; prog.transitions.len()],
            g_end: vec![0.0; prog.transitions.len()],
            native: None,
        }
    }

    /// Takes the derivative from `native`, the build of `code` (this
    /// stepper's program's lane code), instead of the tape: the same bits,
    /// several times faster. Only a build without `rig_redo` has it
    /// (`Native::redoes`: one with it redoes the steps itself).
    pub fn with_native_deriv(&mut self, code: &'p LaneCode, native: &'p Native) {
        let mut r = vec![0.0; code.registers];
        for &(id, reg) in &code.constants {
            r[reg as usize] = self.frame.get(id);
        }
        self.native = Some(NativeDeriv {
            code,
            native,
            r,
            tab: vec![0.0; native.table_stride],
            g: vec![0.0; code.events.roots.len()],
        });
    }

    /// The native code's inputs at `(t, y)` in the current regimes and held
    /// states: its register file and tables.
    fn native_inputs(&mut self, t: f64, y: &[f64]) -> Option<&mut NativeDeriv<'p>> {
        let nd = self.native.as_mut()?;
        nd.r[..y.len()].copy_from_slice(y);
        for (&m, &v) in nd.code.regimes.iter().zip(&self.regimes) {
            nd.r[m as usize] = f64::from(v);
        }
        for (&m, &v) in nd.code.held.iter().zip(&self.held) {
            nd.r[m as usize] = v;
        }
        for (k, v) in nd.tab.iter_mut().enumerate() {
            *v = table_value(self.prog, self.frame.force(), k as u32, t);
        }
        Some(nd)
    }

    /// `dy/dt` at `(t, y)` in the current regimes, into `out`.
    pub fn deriv(&mut self, t: f64, y: &[f64], out: &mut [f64]) {
        if let Some(nd) = self.native_inputs(t, y) {
            nd.native.deriv1(&nd.r, t, &nd.tab, out);
            return;
        }
        let pt = Point {
            t,
            y,
            regimes: &self.regimes,
            held: &self.held,
        };
        self.frame.eval(&self.tape.deriv_ops, pt);
        for (o, &id) in out.iter_mut().zip(&self.prog.deriv) {
            *o = self.frame.get(id);
        }
    }

    /// One RK4 step; `first_known`: `self.k[0]` already holds the slope at
    /// `(t, y)` in the current regimes.
    fn rk4(&mut self, t: f64, h: f64, y: &mut [f64], first_known: bool) {
        let n = y.len();
        let mut k = std::mem::take(&mut self.k);
        let mut tmp = std::mem::take(&mut self.tmp);
        if !first_known {
            self.deriv(t, y, &mut k[0]);
        }
        for i in 0..n {
            tmp[i] = y[i] + 0.5 * h * k[0][i];
        }
        self.deriv(t + 0.5 * h, &tmp, &mut k[1]);
        for i in 0..n {
            tmp[i] = y[i] + 0.5 * h * k[1][i];
        }
        self.deriv(t + 0.5 * h, &tmp, &mut k[2]);
        for i in 0..n {
            tmp[i] = y[i] + h * k[2][i];
        }
        self.deriv(t + h, &tmp, &mut k[3]);
        for i in 0..n {
            y[i] += h / 6.0 * (k[0][i] + 2.0 * k[1][i] + 2.0 * k[2][i] + k[3][i]);
        }
        self.k = k;
        self.tmp = tmp;
    }

    /// Event-function values at `(t, y)` in the current regimes, each at
    /// its transition's root in the frame.
    fn events_at(&mut self, t: f64, y: &[f64]) {
        let prog = self.prog;
        if self.native_inputs(t, y).is_some() {
            let nd = self.native.as_mut().expect("native code");
            nd.native.events1(&nd.r, t, &nd.tab, &mut nd.g);
            for (tr, &g) in prog.transitions.iter().zip(&nd.g) {
                self.frame.vals[tr.g as usize] = g;
            }
            return;
        }
        let pt = Point {
            t,
            y,
            regimes: &self.regimes,
            held: &self.held,
        };
        self.frame.eval(&self.tape.event_ops, pt);
    }

    /// Armed transitions that fire over the step from `g_start` to `g_end`.
    fn triggered(&self) -> impl Iterator<Item = usize> + '_ {
        self.prog
            .transitions
            .iter()
            .enumerate()
            .filter(|(i, tr)| tr.armed(&self.regimes) && tr.fires(self.g_start[*i], self.g_end[*i]))
            .map(|(i, _)| i)
    }

    /// One step of length `h` from `(t, y)`, switches located inside it and,
    /// with controllers, split at their sample instants.
    pub fn step(&mut self, t: f64, h: f64, y: &mut [f64]) {
        let mut clock = self.clock;
        clock.step(
            self.prog.sampling.as_ref(),
            &mut (&mut *self, &mut *y),
            t,
            h,
            &mut |(me, y), ta, len| me.step_known(ta, len, y, None),
            &mut |(me, y), tn| me.sample(tn, y),
        );
        self.clock = clock;
    }

    /// Every held state set from its update at `(t, y)`, all from the values
    /// before (a sample instant).
    pub fn sample(&mut self, t: f64, y: &[f64]) {
        let Some(s) = &self.prog.sampling else {
            return;
        };
        let pt = Point {
            t,
            y,
            regimes: &self.regimes,
            held: &self.held,
        };
        self.frame.eval(&self.tape.update_ops, pt);
        for (h, &id) in self.held.iter_mut().zip(&s.update) {
            // Every update is evaluated above, before any held state changes.
            *h = self.frame.get(id);
        }
    }

    /// Takes the sample instants not yet taken at or before `t` (the first,
    /// at `t = 0`, before the first step or report).
    pub fn catch_up(&mut self, t: f64, y: &[f64]) {
        let mut clock = self.clock;
        clock.catch_up(
            self.prog.sampling.as_ref(),
            &mut (&mut *self, y),
            t,
            &mut |(me, y), t| me.sample(t, y),
        );
        self.clock = clock;
    }

    /// One piece of a step ([`Self::step`] between sample instants) where
    /// the plain RK4 step from `(t, y)` over `h` is known to end at `y_end`
    /// (the lane ensemble took it): of that step only the first slope (which
    /// locating a switch needs) is computed again. (Native code that redoes
    /// steps, `Native::redo`, takes a runner's lanes together instead.)
    pub fn step_ending_at(&mut self, t: f64, h: f64, y: &mut [f64], y_end: &[f64]) {
        self.step_known(t, h, y, Some(y_end));
    }

    fn step_known(&mut self, t: f64, h: f64, y: &mut [f64], mut known_end: Option<&[f64]>) {
        if self.chattered {
            return;
        }
        let n = y.len();
        let (mut ta, mut rem) = (t, h);
        for _ in 0..=MAX_EVENTS_PER_STEP {
            self.start.copy_from_slice(y);
            self.events_at(ta, y);
            for (g0, tr) in self.g_start.iter_mut().zip(&self.prog.transitions) {
                *g0 = self.frame.get(tr.g);
            }
            if let Some(end) = known_end.take() {
                let mut k0 = std::mem::take(&mut self.k[0]);
                self.deriv(ta, y, &mut k0);
                self.k[0] = k0;
                y.copy_from_slice(end);
            } else {
                self.rk4(ta, rem, y, false);
            }
            self.events_at(ta + rem, y);
            for (g1, tr) in self.g_end.iter_mut().zip(&self.prog.transitions) {
                *g1 = self.frame.get(tr.g);
            }
            if self.triggered().next().is_none() {
                return;
            }
            let mut hits = std::mem::take(&mut self.hits);
            hits.clear();
            hits.extend(self.triggered());
            // The slope at the piece's start, kept for the step to the
            // switch (same point, same regimes).
            let f0 = std::mem::take(&mut self.k[0]);
            let mut f_end = std::mem::take(&mut self.f_end);
            self.deriv(ta + rem, y, &mut f_end);
            self.f_end = f_end;
            let mut y1 = std::mem::take(&mut self.y1);
            y1.copy_from_slice(y);
            let mut best: Option<(f64, usize)> = None;
            for &tr in &hits {
                let theta = self.locate(tr, ta, rem, &f0, &y1);
                if best.is_none_or(|(b, _)| theta < b) {
                    best = Some((theta, tr));
                }
            }
            (self.k[0], self.y1, self.hits) = (f0, y1, hits);
            let (theta, tr) = best.expect("a hit");
            let s = theta * rem;
            y.copy_from_slice(&self.start);
            self.rk4(ta, s, y, true);
            let tr_def = &self.prog.transitions[tr];
            self.regimes[tr_def.var as usize] = tr_def.to;
            self.fired.push(Fired {
                t: ta + s,
                transition: tr,
            });
            ta += s;
            rem -= s;
            if rem <= 0.0 {
                return;
            }
            debug_assert_eq!(y.len(), n);
        }
        self.chattered = true;
    }

    /// Fraction of the step `[ta, ta + h]` where transition `tr`'s event
    /// function first passes its switch, on the Hermite interpolant between
    /// `self.start` (derivative `f0`) and `y1` (derivative `self.f_end`), by
    /// [`locate_crossing`] from its oriented values at the step's ends
    /// (`g_start`, `g_end`).
    fn locate(&mut self, tr: usize, ta: f64, h: f64, f0: &[f64], y1: &[f64]) -> f64 {
        let prog = self.prog;
        let def = &prog.transitions[tr];
        let (v0, v1) = (def.oriented(self.g_start[tr]), def.oriented(self.g_end[tr]));
        locate_crossing(v0, v1, LOCATE_TOLERANCE, |theta| {
            let s2 = theta * theta;
            let s3 = s2 * theta;
            let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
            let h10 = (s3 - 2.0 * s2 + theta) * h;
            let h01 = -2.0 * s3 + 3.0 * s2;
            let h11 = (s3 - s2) * h;
            for i in 0..y1.len() {
                self.interp[i] =
                    h00 * self.start[i] + h10 * f0[i] + h01 * y1[i] + h11 * self.f_end[i];
            }
            let interp = std::mem::take(&mut self.interp);
            self.events_at(ta + theta * h, &interp);
            self.interp = interp;
            def.oriented(self.frame.get(def.g))
        })
    }

    /// Outputs and full state at `(t, y)`, into `outputs` and `state`
    /// (sample instants up to `t` taken first).
    pub fn report(&mut self, t: f64, y: &[f64], outputs: &mut [f64], state: &mut [f64]) {
        self.catch_up(t, y);
        let pt = Point {
            t,
            y,
            regimes: &self.regimes,
            held: &self.held,
        };
        self.frame.eval(&self.tape.report_ops, pt);
        for (o, &id) in outputs.iter_mut().zip(&self.prog.outputs) {
            *o = self.frame.get(id);
        }
        for (o, &id) in state.iter_mut().zip(&self.prog.full_state) {
            *o = self.frame.get(id);
        }
    }
}

/// Most event-function evaluations [`locate_crossing`] makes: enough for the
/// bracket to reach [`LOCATE_TOLERANCE`] when it only halves every fourth one.
pub const LOCATE_ITERATIONS: usize = 200;

/// Width of the bracket (a fraction of the step) at which [`locate_crossing`]
/// stops in f64. An event function near its root is a difference of nearly
/// equal values (an elongation minus its limit), so its rounding noise, as a
/// fraction of the step, is the unit roundoff times the value's size over its
/// change across the step: about 1e-14 on the tensile rig, where a narrower
/// bracket is decided by noise and the search only bisects (up to 27
/// evaluations at 1e-15 on the benchmark's candidates; at 1e-12 at most 18,
/// 2–5 for most). A looser bracket saves little more and lets the GPU and the
/// reference stop further apart: the f64 parity cases differed by up to 2e-10
/// at 1e-10, 2.4e-11 at 1e-12 and 4e-14 at 1e-15. A switch 1e-12 of a step late
/// moves the run by far less than the step's own error.
pub const LOCATE_TOLERANCE: f64 = 1e-12;

/// The same for the f32 kernels, by the same reckoning with f32's unit
/// roundoff: the f32 parity cases stay where they were at 2.5e-7 (stick-slip
/// 2.4e-5 of its largest value; 9.9e-5 at 1e-4).
pub const LOCATE_TOLERANCE_F32: f64 = 1e-5;

/// Fraction θ ∈ [0, 1] of a step where an event function first passes its
/// switch, given its oriented value `v(θ)` (≥ 0: past; see
/// [`crate::compile::Transition::oriented`]) with `v0 = v(0)` and `v1 = v(1) ≥ 0`.
///
/// A run already past the switch at the step's start (`v0 ≥ 0`, a transition
/// pushed further past) fires at θ = 0. Otherwise the bracket `[lo, hi]`, with
/// `v(lo) < 0 ≤ v(hi)`, is narrowed by regula falsi in the Anderson–Björck
/// form (the value kept at an end that survives twice in a row is scaled
/// down), each trial point kept at least `tol / 2` inside the bracket, and a
/// bisection whenever the bracket is not half as wide as three trials before,
/// so it halves at least every fourth evaluation. It stops when the bracket is
/// no wider than `tol`, on an exact zero, or after [`LOCATE_ITERATIONS`]
/// evaluations, and returns `hi`: the first point found past the switch. A
/// crossing inside one step, where the event function is close to linear,
/// takes about seven evaluations (bisection takes 34). The kernels'
/// `rig_locate` (shaders/shared/rig_run.wgsl) is the same search, step for
/// step.
pub fn locate_crossing(v0: f64, v1: f64, tol: f64, mut v: impl FnMut(f64) -> f64) -> f64 {
    if v0 >= 0.0 || v0.is_nan() {
        return 0.0;
    }
    let (mut lo, mut hi, mut vlo, mut vhi) = (0.0_f64, 1.0_f64, v0, v1);
    // Which end moved last: -1 lo, 1 hi, 0 none yet.
    let mut side = 0_i32;
    // Bracket widths before the last three trials, oldest first.
    let mut widths = [2.0_f64; 3];
    let nudge = 0.5 * tol;
    for _ in 0..LOCATE_ITERATIONS {
        let w = hi - lo;
        if w <= tol || w.is_nan() {
            break;
        }
        let secant = lo + w * (vlo / (vlo - vhi));
        let m = if w > 0.5 * widths[0] || !(lo..=hi).contains(&secant) {
            lo + 0.5 * w
        } else {
            secant
        };
        let m = m.max(lo + nudge).min(hi - nudge);
        widths = [widths[1], widths[2], w];
        let vm = v(m);
        if vm == 0.0 {
            return m;
        }
        if vm > 0.0 {
            if side == 1 {
                let f = 1.0 - vm / vhi;
                vlo *= if f > 0.0 { f } else { 0.5 };
            }
            hi = m;
            vhi = vm;
            side = 1;
        } else {
            if side == -1 {
                let f = 1.0 - vm / vlo;
                vhi *= if f > 0.0 { f } else { 0.5 };
            }
            lo = m;
            vlo = vm;
            side = -1;
        }
    }
    hi
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A test crossing: name, root, oriented value, most evaluations allowed.
    type Case = (&'static str, f64, fn(f64) -> f64, usize);

    /// Roots found, with the number of evaluations each took.
    fn located(v0: f64, v1: f64, v: impl Fn(f64) -> f64) -> (f64, usize) {
        let mut n = 0;
        let theta = locate_crossing(v0, v1, LOCATE_TOLERANCE, |x| {
            n += 1;
            v(x)
        });
        (theta, n)
    }

    #[test]
    fn crossings_are_found_to_the_tolerance() {
        // Near-linear crossings, as inside one step, in about seven
        // evaluations; strongly curved ones take longer.
        let cases: [Case; 7] = [
            ("linear", 0.3, |x| x - 0.3, 1),
            (
                "mildly curved",
                (1.24f64.sqrt() - 1.0) / 0.4,
                |x| x - 0.3 + 0.2 * x * x,
                8,
            ),
            (
                "sine",
                std::f64::consts::PI / 12.0,
                |x| (2.0 * x).sin() - 0.5,
                8,
            ),
            (
                "exponential",
                0.5 * 2f64.ln(),
                |x| (2.0 * x).exp_m1() - 1.0,
                8,
            ),
            (
                "root at the first secant point",
                0.5,
                |x| -(std::f64::consts::PI * x).cos(),
                3,
            ),
            ("cubic", 0.1, |x| x * x * x - 1e-3, 24),
            (
                "steep exponential",
                0.05f64.ln_1p() / 40.0,
                |x| (40.0 * x).exp_m1() - 0.05,
                16,
            ),
        ];
        for (name, root, v, most) in cases {
            let (theta, n) = located(v(0.0), v(1.0), v);
            assert!(v(theta) >= 0.0, "{name}: {theta} is not past the switch");
            assert!(
                (theta - root).abs() <= LOCATE_TOLERANCE,
                "{name}: {theta} against {root}"
            );
            assert!(
                n <= most,
                "{name}: {n} evaluations, expected at most {most}"
            );
        }
    }

    /// Deterministic noise in [-0.5, 0.5) from the bits of `x`.
    fn noise(x: f64) -> f64 {
        let mut h = x.to_bits().wrapping_mul(0x9e37_79b9_7f4a_7c15);
        h ^= h >> 29;
        h = h.wrapping_mul(0xbf58_476d_1ce4_e5b9);
        h ^= h >> 32;
        (h >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }

    #[test]
    fn a_root_in_rounding_noise_is_not_chased_below_it() {
        // A crossing whose value near the root carries noise of 1e-13, as an
        // event function that is a difference of nearly equal numbers does:
        // the search stops above the noise (a tolerance of 1e-15 took 11
        // evaluations here, bisecting on noise), and the noise leaves the
        // root within the tolerance.
        let v = |x: f64| (x - 0.37) * (1.0 + 0.3 * x) + 1e-13 * noise(x);
        let (theta, n) = located(v(0.0), v(1.0), v);
        assert!((theta - 0.37).abs() <= LOCATE_TOLERANCE, "{theta}");
        assert!(n <= 7, "{n} evaluations");
    }

    #[test]
    fn a_jump_is_bracketed_by_bisection_to_the_tolerance() {
        // No secant step helps: the value jumps at 0.7.
        let v = |x: f64| if x < 0.7 { -1.0 } else { 1e6 };
        let (theta, n) = located(-1.0, 1e6, v);
        assert!(
            theta >= 0.7 && theta - 0.7 <= 2.0 * LOCATE_TOLERANCE,
            "{theta}"
        );
        assert!(n <= LOCATE_ITERATIONS, "{n}");
    }

    #[test]
    fn past_at_the_start_fires_at_once_and_nan_never_hangs() {
        assert_eq!(located(0.0, 1.0, |_| panic!("no evaluation")).0, 0.0);
        assert_eq!(located(0.5, 1.0, |_| panic!("no evaluation")).0, 0.0);
        let (theta, n) = located(-1.0, 1.0, |_| f64::NAN);
        assert!((0.0..=1.0).contains(&theta) && n <= LOCATE_ITERATIONS);
    }
}
