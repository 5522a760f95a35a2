//! Fixed-step RK4 over a compiled rig with every switch located inside the step.
//!
//! A step from `(t, y)` in the current modes is taken whole; then every armed
//! transition (its mode variable holds its `from` value) that fires over the
//! step ([`super::Transition::fires`]: past the switch at the step's end, and
//! on the armed side at its start or going further past) is located on the cubic Hermite
//! interpolant of the step (the state and its derivative at both ends, error
//! O(h⁴)) by a fixed number of bisections. The earliest one fires: the step is
//! redone from its start to the crossing, the mode changes, and the rest of the
//! step is taken the same way. More than [`MAX_EVENTS_PER_STEP`] events in one
//! step flag the run as chattering and stop it (it is never hung).

use super::program::Program;
use super::tape::{Frame, Point, Tape};
use crate::integrate::CROSSING_ITERATIONS;

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

/// One run's integrator: scratch space, modes and what fired.
#[derive(Debug)]
pub struct EventStepper<'p> {
    prog: &'p Program,
    tape: &'p Tape,
    /// The run's evaluated values.
    pub frame: Frame<'p>,
    /// Mode variables.
    pub modes: Vec<u32>,
    /// The state the run starts from ([`super::initial`]).
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
    /// Event-function values at the current step's start.
    g_start: Vec<f64>,
}

impl<'p> EventStepper<'p> {
    /// A run of `prog` with the full parameter vector `params`, in the modes
    /// its initial state `y0` implies ([`super::initial`]; at rest in the
    /// modes' value 0 without initial-state parameters).
    pub fn new(
        prog: &'p Program,
        tape: &'p Tape,
        params: &[f64],
        force: Option<&'p crate::model::PiecewiseLinear>,
    ) -> Self {
        let n = prog.deriv.len();
        let z = vec![0.0; n];
        let mut frame = Frame::new(prog, tape, params, force);
        let (y0, modes) = super::initial::initial_state(prog, tape, &mut frame);
        Self {
            prog,
            tape,
            frame,
            modes,
            y0,
            fired: vec![],
            chattered: false,
            k: [z.clone(), z.clone(), z.clone(), z.clone()],
            tmp: z.clone(),
            start: z.clone(),
            f_end: z.clone(),
            interp: z,
            g_start: vec![0.0; prog.transitions.len()],
        }
    }

    /// `dy/dt` at `(t, y)` in the current modes, into `out`.
    pub fn deriv(&mut self, t: f64, y: &[f64], out: &mut [f64]) {
        let pt = Point {
            t,
            y,
            modes: &self.modes,
        };
        self.frame.eval(&self.tape.deriv_ops, pt);
        for (o, &id) in out.iter_mut().zip(&self.prog.deriv) {
            *o = self.frame.get(id);
        }
    }

    fn rk4(&mut self, t: f64, h: f64, y: &mut [f64]) {
        let n = y.len();
        let mut k = std::mem::take(&mut self.k);
        let mut tmp = std::mem::take(&mut self.tmp);
        self.deriv(t, y, &mut k[0]);
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

    /// Event-function values at `(t, y)` in the current modes.
    fn events_at(&mut self, t: f64, y: &[f64]) {
        let pt = Point {
            t,
            y,
            modes: &self.modes,
        };
        self.frame.eval(&self.tape.event_ops, pt);
    }

    /// Armed transitions that fire over the step, after evaluating the events
    /// at its end (the start's are in `g_start`).
    fn triggered(&self) -> impl Iterator<Item = usize> + '_ {
        self.prog
            .transitions
            .iter()
            .enumerate()
            .filter(|(i, tr)| {
                self.modes[tr.var as usize] == tr.from
                    && tr.fires(self.g_start[*i], self.frame.get(tr.g))
            })
            .map(|(i, _)| i)
    }

    /// One step of length `h` from `(t, y)`, switches located inside it.
    pub fn step(&mut self, t: f64, h: f64, y: &mut [f64]) {
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
            self.rk4(ta, rem, y);
            self.events_at(ta + rem, y);
            if self.triggered().next().is_none() {
                return;
            }
            let hits: Vec<usize> = self.triggered().collect();
            let f0 = self.k[0].clone();
            let mut f_end = std::mem::take(&mut self.f_end);
            self.deriv(ta + rem, y, &mut f_end);
            self.f_end = f_end;
            let y1 = y.to_vec();
            let mut best: Option<(f64, usize)> = None;
            for &tr in &hits {
                let theta = self.locate(tr, ta, rem, &f0, &y1);
                if best.is_none_or(|(b, _)| theta < b) {
                    best = Some((theta, tr));
                }
            }
            let (theta, tr) = best.expect("a hit");
            let s = theta * rem;
            y.copy_from_slice(&self.start);
            self.rk4(ta, s, y);
            let tr_def = &self.prog.transitions[tr];
            self.modes[tr_def.var as usize] = tr_def.to;
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
    /// `self.start` (derivative `f0`) and `y1` (derivative `self.f_end`).
    fn locate(&mut self, tr: usize, ta: f64, h: f64, f0: &[f64], y1: &[f64]) -> f64 {
        let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
        for _ in 0..CROSSING_ITERATIONS {
            let mid = 0.5 * (lo + hi);
            let s2 = mid * mid;
            let s3 = s2 * mid;
            let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
            let h10 = (s3 - 2.0 * s2 + mid) * h;
            let h01 = -2.0 * s3 + 3.0 * s2;
            let h11 = (s3 - s2) * h;
            for i in 0..y1.len() {
                self.interp[i] =
                    h00 * self.start[i] + h10 * f0[i] + h01 * y1[i] + h11 * self.f_end[i];
            }
            let interp = std::mem::take(&mut self.interp);
            self.events_at(ta + mid * h, &interp);
            self.interp = interp;
            let def = &self.prog.transitions[tr];
            if def.violated(self.frame.get(def.g)) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        0.5 * (lo + hi)
    }

    /// Outputs and full state at `(t, y)`, into `outputs` and `state`.
    pub fn report(&mut self, t: f64, y: &[f64], outputs: &mut [f64], state: &mut [f64]) {
        let pt = Point {
            t,
            y,
            modes: &self.modes,
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
