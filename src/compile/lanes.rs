//! The CPU ensemble of a compiled rig: [`LANES`] runs of one experiment (one
//! sample grid) advanced together, every operation of the tape applied to all
//! lanes in one tight loop (structure of arrays), so the compiler vectorises it.
//!
//! Plain steps, event checks and reports run over the lanes. A lane whose step
//! ends past a switch is handed to its own [`EventStepper`], which redoes that
//! step from its start with the switch located: the lanes evaluate the same
//! operations in the same order as the scalar reference, so every lane's history
//! is bit-identical to [`EventStepper`]'s (`tests/rig_cpu_ensemble.rs`).

#![expect(
    clippy::needless_range_loop,
    reason = "lane loops index several arrays in step, the shape the vectoriser wants"
)]

use std::ops::ControlFlow;

use super::events::EventStepper;
use super::ir::{Id, Input, Op};
use super::program::Program;
use super::tape::{Tape, table_value};
use crate::integrate::{SampleGrid, walk_grid};
use crate::model::{PiecewiseLinear, Sample};

/// Runs advanced together.
pub const LANES: usize = 16;

type V = [f64; LANES];

/// `out = f(a, b)` lane by lane; generic, so `f` inlines and the loop
/// vectorises.
#[inline(always)]
fn bin(head: &[V], out: &mut V, a: Id, b: Id, f: impl Fn(f64, f64) -> f64) {
    let (a, b) = (&head[a as usize], &head[b as usize]);
    for l in 0..LANES {
        out[l] = f(a[l], b[l]);
    }
}

/// `out = f(a)` lane by lane.
#[inline(always)]
fn un(head: &[V], out: &mut V, a: Id, f: impl Fn(f64) -> f64) {
    let a = &head[a as usize];
    for l in 0..LANES {
        out[l] = f(a[l]);
    }
}

/// Up to [`LANES`] runs of one program on one grid.
#[derive(Debug)]
pub struct LaneRunner<'p> {
    prog: &'p Program,
    tape: &'p Tape,
    force: Option<&'p PiecewiseLinear>,
    vals: Vec<V>,
    steppers: Vec<EventStepper<'p>>,
    modes: Vec<[u32; LANES]>,
    k: [Vec<V>; 4],
    tmp: Vec<V>,
    start: Vec<V>,
    /// One lane's state, for a step its stepper redoes.
    lane_y: Vec<f64>,
}

impl<'p> LaneRunner<'p> {
    /// Runs of `prog` for each parameter vector of `params` (at most [`LANES`]).
    pub fn new(
        prog: &'p Program,
        tape: &'p Tape,
        params: &[&[f64]],
        force: Option<&'p PiecewiseLinear>,
    ) -> Self {
        assert!(!params.is_empty() && params.len() <= LANES);
        let steppers: Vec<EventStepper<'p>> = params
            .iter()
            .map(|p| EventStepper::new(prog, tape, p, force))
            .collect();
        let mut vals = vec![[0.0; LANES]; prog.graph.ops.len()];
        for &i in &tape.run_ops {
            for (l, s) in steppers.iter().enumerate() {
                vals[i as usize][l] = s.frame.get(i);
            }
            // Idle lanes repeat lane 0, so they compute something finite.
            for l in steppers.len()..LANES {
                vals[i as usize][l] = vals[i as usize][0];
            }
        }
        let n = prog.deriv.len();
        let z = vec![[0.0; LANES]; n];
        let mut modes = vec![[0; LANES]; prog.mode_count()];
        for (l, s) in steppers.iter().enumerate() {
            for (m, &v) in s.modes.iter().enumerate() {
                modes[m][l] = v;
            }
        }
        Self {
            prog,
            tape,
            force,
            vals,
            steppers,
            modes,
            k: [z.clone(), z.clone(), z.clone(), z.clone()],
            tmp: z.clone(),
            start: z,
            lane_y: vec![0.0; n],
        }
    }

    fn eval(&mut self, ops: &[Id], t: f64, y: &[V]) {
        let g = &self.prog.graph;
        for &i in ops {
            let (head, tail) = self.vals.split_at_mut(i as usize);
            let out = &mut tail[0];
            match g.ops[i as usize] {
                Op::Const(c) => *out = [c; LANES],
                Op::In(Input::Time) => *out = [t; LANES],
                Op::In(Input::Slot(_)) => {}
                Op::In(Input::State(s)) => *out = y[s as usize],
                Op::In(Input::Mode(m)) => {
                    for l in 0..LANES {
                        out[l] = f64::from(self.modes[m as usize][l]);
                    }
                }
                Op::In(Input::Table(k)) => {
                    *out = [table_value(self.prog, self.force, k, t); LANES];
                }
                Op::Add(a, b) => bin(head, out, a, b, |x, y| x + y),
                Op::Sub(a, b) => bin(head, out, a, b, |x, y| x - y),
                Op::Mul(a, b) => bin(head, out, a, b, |x, y| x * y),
                Op::Div(a, b) => bin(head, out, a, b, |x, y| x / y),
                Op::Min(a, b) => bin(head, out, a, b, f64::min),
                Op::Max(a, b) => bin(head, out, a, b, f64::max),
                Op::Le(a, b) => bin(head, out, a, b, |x, y| f64::from(u8::from(x <= y))),
                Op::Eq(a, b) => bin(head, out, a, b, |x, y| f64::from(u8::from(x == y))),
                Op::Neg(a) => un(head, out, a, |x| -x),
                Op::Abs(a) => un(head, out, a, f64::abs),
                Op::Exp(a) => un(head, out, a, f64::exp),
                Op::Expm1(a) => un(head, out, a, f64::exp_m1),
                Op::Ln(a) => un(head, out, a, f64::ln),
                Op::Sin(a) => un(head, out, a, f64::sin),
                Op::Cos(a) => un(head, out, a, f64::cos),
                Op::Select(c, a, b) => {
                    let (c, a, b) = (&head[c as usize], &head[a as usize], &head[b as usize]);
                    for l in 0..LANES {
                        out[l] = if c[l] != 0.0 { a[l] } else { b[l] };
                    }
                }
            }
        }
    }

    fn deriv(&mut self, t: f64, y: &[V], out: usize) {
        let tape = self.tape;
        self.eval(&tape.deriv_ops, t, y);
        for (s, &id) in self.prog.deriv.iter().enumerate() {
            self.k[out][s] = self.vals[id as usize];
        }
    }

    /// One RK4 step of every lane, written as `EventStepper`'s so the lanes
    /// round alike.
    fn rk4(&mut self, t: f64, h: f64, y: &mut [V]) {
        let n = y.len();
        self.deriv(t, y, 0);
        let mut tmp = std::mem::take(&mut self.tmp);
        for i in 0..n {
            for l in 0..LANES {
                tmp[i][l] = y[i][l] + 0.5 * h * self.k[0][i][l];
            }
        }
        self.deriv(t + 0.5 * h, &tmp, 1);
        for i in 0..n {
            for l in 0..LANES {
                tmp[i][l] = y[i][l] + 0.5 * h * self.k[1][i][l];
            }
        }
        self.deriv(t + 0.5 * h, &tmp, 2);
        for i in 0..n {
            for l in 0..LANES {
                tmp[i][l] = y[i][l] + h * self.k[2][i][l];
            }
        }
        self.deriv(t + h, &tmp, 3);
        self.tmp = tmp;
        let k = &self.k;
        for i in 0..n {
            for l in 0..LANES {
                y[i][l] +=
                    h / 6.0 * (k[0][i][l] + 2.0 * k[1][i][l] + 2.0 * k[2][i][l] + k[3][i][l]);
            }
        }
    }

    /// One step of every lane from `(t, y)`; lanes past a switch are redone by
    /// their own stepper with the switch located.
    fn step(&mut self, t: f64, h: f64, y: &mut [V]) {
        self.start.copy_from_slice(y);
        self.rk4(t, h, y);
        let tape = self.tape;
        self.eval(&tape.event_ops, t + h, y);
        let mut lane_y = std::mem::take(&mut self.lane_y);
        for l in 0..self.steppers.len() {
            let hit = self.prog.transitions.iter().any(|tr| {
                self.modes[tr.var as usize][l] == tr.from
                    && tr.violated(self.vals[tr.g as usize][l])
            });
            if !hit || self.steppers[l].chattered {
                continue;
            }
            for (s, v) in lane_y.iter_mut().enumerate() {
                *v = self.start[s][l];
            }
            let st = &mut self.steppers[l];
            st.step(t, h, &mut lane_y);
            for (s, v) in lane_y.iter().enumerate() {
                y[s][l] = *v;
            }
            for (m, v) in st.modes.iter().enumerate() {
                self.modes[m][l] = *v;
            }
        }
        self.lane_y = lane_y;
    }

    /// Runs every lane over `grid`, calling `observe(lane, sample)` at every
    /// sample until the lane's observer breaks.
    pub fn run(
        &mut self,
        grid: &SampleGrid,
        observe: &mut dyn FnMut(usize, &Sample<'_>) -> ControlFlow<()>,
    ) {
        let lanes = self.steppers.len();
        let n = self.prog.deriv.len();
        let n_out = self.prog.outputs.len();
        let mut live = vec![true; lanes];
        let mut outs = vec![0.0; n_out];
        let mut full = vec![0.0; n];
        let mut y0 = vec![[0.0; LANES]; n];
        for (l, st) in self.steppers.iter().enumerate() {
            for (s, &v) in st.y0.iter().enumerate() {
                y0[s][l] = v;
            }
        }
        let mut ctx = (self, y0);
        walk_grid(
            grid,
            &mut ctx,
            |(me, y), t, h| me.step(t, h, y),
            |(me, y), k, t| {
                let tape = me.tape;
                me.eval(&tape.report_ops, t, y);
                for l in 0..lanes {
                    if !live[l] {
                        continue;
                    }
                    for (o, &id) in outs.iter_mut().zip(&me.prog.outputs) {
                        *o = if me.steppers[l].chattered {
                            f64::NAN
                        } else {
                            me.vals[id as usize][l]
                        };
                    }
                    for (o, &id) in full.iter_mut().zip(&me.prog.full_state) {
                        *o = me.vals[id as usize][l];
                    }
                    let s = Sample {
                        index: k,
                        t,
                        state: &full,
                        outputs: &outs,
                    };
                    if observe(l, &s).is_break() {
                        live[l] = false;
                    }
                }
                if live.iter().any(|&x| x) {
                    ControlFlow::Continue(())
                } else {
                    ControlFlow::Break(())
                }
            },
        );
    }
}
