//! The CPU reference of a compiled rig: the [`Program`]'s operations evaluated
//! one run at a time in f64, in graph order (the order the WGSL emitter writes
//! them), with the per-run constants evaluated once per run.

use crate::compile::ir::{Id, Input, eval_op, operands};
use crate::compile::program::Program;

/// Which operations each evaluation needs, in graph order.
#[derive(Debug, Clone)]
pub struct Tape {
    /// Per-run constants (depend on slots and literals only).
    pub run_ops: Vec<Id>,
    /// The derivative's other operations.
    pub deriv_ops: Vec<Id>,
    /// The event functions' other operations.
    pub event_ops: Vec<Id>,
    /// Outputs' and full state's other operations.
    pub report_ops: Vec<Id>,
    /// The held states' updates' other operations (empty without
    /// controllers).
    pub update_ops: Vec<Id>,
}

fn needed(p: &Program, roots: &[Id], run: bool) -> Vec<Id> {
    let live = p.graph.live(roots);
    (0..p.graph.ops.len() as Id)
        .filter(|&i| live[i as usize] && p.run_constant[i as usize] == run)
        .collect()
}

impl Tape {
    /// The operation lists of `p`.
    pub fn new(p: &Program) -> Self {
        let mut all: Vec<Id> = p.deriv.clone();
        all.extend(p.event_roots());
        all.extend(&p.outputs);
        all.extend(&p.full_state);
        all.extend(&p.initial);
        if let Some(s) = &p.sampling {
            all.extend(&s.update);
            all.extend(&s.initial);
        }
        let mut report = p.outputs.clone();
        report.extend(&p.full_state);
        Self {
            run_ops: needed(p, &all, true),
            deriv_ops: needed(p, &p.deriv, false),
            event_ops: needed(p, &p.event_roots(), false),
            report_ops: needed(p, &report, false),
            update_ops: needed(p, &p.update_roots(), false),
        }
    }
}

/// What varies within a run, seen by the input operations.
#[derive(Debug, Clone, Copy)]
pub struct Point<'a> {
    /// Model time (s).
    pub t: f64,
    /// Continuous state.
    pub y: &'a [f64],
    /// Regime variables.
    pub regimes: &'a [u32],
    /// Held (controller) states.
    pub held: &'a [f64],
}

/// One run's values: the per-run constants filled once, the rest per call.
#[derive(Debug, Clone)]
pub struct Frame<'p> {
    prog: &'p Program,
    /// Value of every operation (only the evaluated ones are meaningful).
    pub vals: Vec<f64>,
    /// The experiment's force table, for a `None` table.
    force: Option<&'p crate::base::PiecewiseLinear>,
}

impl<'p> Frame<'p> {
    /// The experiment's force table, if any.
    pub(crate) fn force(&self) -> Option<&'p crate::base::PiecewiseLinear> {
        self.force
    }

    /// A frame for one run with packed values `slots` (the full parameter
    /// vector) and the experiment's force table, if any.
    pub fn new(
        prog: &'p Program,
        tape: &Tape,
        slots: &[f64],
        force: Option<&'p crate::base::PiecewiseLinear>,
    ) -> Self {
        let mut f = Self {
            prog,
            vals: vec![0.0; prog.graph.ops.len()],
            force,
        };
        let none = Point {
            t: 0.0,
            y: &[],
            regimes: &[],
            held: &[],
        };
        f.eval_with(&tape.run_ops, none, slots);
        f
    }

    /// Evaluates `ops` at `pt`.
    pub fn eval(&mut self, ops: &[Id], pt: Point<'_>) {
        self.eval_with(ops, pt, &[]);
    }

    fn eval_with(&mut self, ops: &[Id], pt: Point<'_>, slots: &[f64]) {
        let g = &self.prog.graph;
        for &i in ops {
            let v = &self.vals;
            let x = eval_op(
                g.ops[i as usize],
                |k| v[k as usize],
                |input| match input {
                    Input::Time => pt.t,
                    Input::Slot(s) => slots[s as usize],
                    Input::State(s) => pt.y[s as usize],
                    Input::Regime(m) => f64::from(pt.regimes[m as usize]),
                    Input::Table(k) => table_value(self.prog, self.force, k, pt.t),
                    Input::Held(k) => pt.held[k as usize],
                },
            );
            self.vals[i as usize] = x;
        }
    }

    /// The value of `id` after an evaluation that included it.
    pub fn get(&self, id: Id) -> f64 {
        self.vals[id as usize]
    }
}

/// Table `k` of `prog` at `t` (the experiment's `force` table for a `None`
/// table); 0 before `t = 0`, where the rig is at rest.
pub fn table_value(
    prog: &Program,
    force: Option<&crate::base::PiecewiseLinear>,
    k: u32,
    t: f64,
) -> f64 {
    match prog.tables[k as usize].as_ref().or(force) {
        Some(tab) if t >= 0.0 => tab.at(t),
        _ => 0.0,
    }
}

/// Whether every operand of every operation comes before it (the SSA order the
/// evaluators rely on).
pub fn is_topological(p: &Program) -> bool {
    p.graph
        .ops
        .iter()
        .enumerate()
        .all(|(i, op)| operands(op).iter().all(|&o| (o as usize) < i))
}
