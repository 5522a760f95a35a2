//! What a rig compiles to: for each drive mode, one [`Graph`] with the roots
//! that the integrator needs (derivative, outputs, full state) and the rig's
//! located switches as [`Transition`]s of discrete regime variables.

use super::ir::{Graph, Id, Op, operands};
use crate::base::PiecewiseLinear;

/// Which way an event function must go for its transition to fire.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// Fires once `g ≥ 0` (while armed, the run keeps `g < 0`).
    Up,
    /// Fires once `g ≤ 0` (while armed, the run keeps `g > 0`).
    Down,
}

impl Direction {
    /// Whether `g` is past the switch: `g ≥ 0` ([`Direction::Up`]) or `g ≤ 0`
    /// ([`Direction::Down`]).
    #[inline(always)]
    pub fn past(self, g: f64) -> bool {
        match self {
            Self::Up => g >= 0.0,
            Self::Down => g <= 0.0,
        }
    }
}

/// A located switch: while regime variable `var` is `from`, the transition is
/// armed; it fires where `g` reaches zero in `dir`, and sets `var` to `to`.
#[derive(Debug, Clone, PartialEq)]
pub struct Transition {
    /// What it is (`"specimen fracture"`), for messages and docs.
    pub name: String,
    /// Regime variable index.
    pub var: u32,
    /// Value that arms it.
    pub from: u32,
    /// Value it sets.
    pub to: u32,
    /// Event function root.
    pub g: Id,
    /// Direction.
    pub dir: Direction,
    /// Further mode values (variable, value) that must all hold for it to be
    /// armed; empty but in the fitness variant of a program, where a switch
    /// that can no longer reach the measured output is skipped
    /// ([`super::analysis::liveness`]).
    pub guard: Vec<(u32, u32)>,
}

impl Transition {
    /// Whether it is armed at `regimes`: its variable at `from`, its guard held.
    pub fn armed(&self, regimes: &[u32]) -> bool {
        regimes[self.var as usize] == self.from
            && self.guard.iter().all(|&(v, x)| regimes[v as usize] == x)
    }

    /// Whether `g` is past the switch.
    pub fn violated(&self, g: f64) -> bool {
        self.dir.past(g)
    }

    /// `g` oriented so that `≥ 0` is past the switch: `g` for [`Direction::Up`],
    /// `−g` for [`Direction::Down`] (`violated(g)` is `oriented(g) >= 0`).
    pub fn oriented(&self, g: f64) -> f64 {
        match self.dir {
            Direction::Up => g,
            Direction::Down => -g,
        }
    }

    /// Whether an armed transition fires over a step whose event function
    /// went from `g0` to `g1`: it ends past the switch, and either started on
    /// the armed side or went further past. A transition armed by another
    /// event exactly at its own switch (a slider that sticks with its spring at
    /// ±f_c) therefore waits while the run moves back from the switch, rather
    /// than firing on the sign of a rounding error; one the run pushes on
    /// through fires at once.
    pub fn fires(&self, g0: f64, g1: f64) -> bool {
        self.violated(g1)
            && (!self.violated(g0)
                || match self.dir {
                    Direction::Up => g1 > g0,
                    Direction::Down => g1 < g0,
                })
    }
}

/// A discrete regime variable of the rig (contact, yield, fracture, stick-slip).
#[derive(Debug, Clone, PartialEq)]
pub struct RegimeVar {
    /// `"slack.contact"`.
    pub name: String,
    /// Names of its values, value 0 first (the state at rest).
    pub values: Vec<&'static str>,
}

/// A rig's digital controllers in one drive mode: their sample instants
/// `t_k = phase + k·period` (k = 0, 1, …) and the discrete (held) states they
/// set there. At an instant every held state takes its update's value, all
/// at once: the updates read the held states as they were before it.
#[derive(Debug, Clone, PartialEq)]
pub struct Sampling {
    /// Sample period (s, > 0).
    pub period: f64,
    /// First instant (s, ≥ 0).
    pub phase: f64,
    /// Each held state's name (`"servo.u"`).
    pub names: Vec<String>,
    /// Each held state's new value at an instant (roots of the graph).
    pub update: Vec<Id>,
    /// Each held state's value before the first instant (run constants).
    pub initial: Vec<Id>,
}

impl Sampling {
    /// Time of instant `k` (s), from its index (never a running sum).
    #[inline(always)]
    pub fn instant(&self, k: u64) -> f64 {
        self.phase + k as f64 * self.period
    }
}

/// One drive mode's compiled rig.
#[derive(Debug, Clone)]
pub struct Program {
    /// Drive mode (`"velocity"`, `"force"`).
    pub mode: String,
    /// The operations.
    pub graph: Graph,
    /// `dy/dt` of every state.
    pub deriv: Vec<Id>,
    /// Every output.
    pub outputs: Vec<Id>,
    /// The state as reported: prescribed nodes' slots from their drive.
    pub full_state: Vec<Id>,
    /// The located switches.
    pub transitions: Vec<Transition>,
    /// Whether op `i` depends on per-run values only (evaluated once per run).
    pub run_constant: Vec<bool>,
    /// Tables read by `Input::Table(i)`; `None` is the experiment's force table.
    pub tables: Vec<Option<PiecewiseLinear>>,
    /// The run's initial value of every state: a run constant (the literal 0,
    /// or the slot of the rig's `initial_<state>` parameter). See
    /// [`super::exec::initial`] for the regimes it starts in.
    pub initial: Vec<Id>,
    /// The controllers' sample instants and held states, if the rig has
    /// controllers in this mode.
    pub sampling: Option<Sampling>,
}

impl Program {
    /// Marks the operations that depend only on constants and slots.
    pub fn mark_run_constants(&mut self) {
        use super::ir::Input;
        let ops = &self.graph.ops;
        let mut rc = vec![false; ops.len()];
        for (i, op) in ops.iter().enumerate() {
            rc[i] = match op {
                Op::Const(_) | Op::In(Input::Slot(_)) => true,
                Op::In(_) => false,
                other => operands(other).iter().all(|&o| rc[o as usize]),
            };
        }
        self.run_constant = rc;
    }

    /// Number of regime variables read or set.
    pub fn mode_count(&self) -> usize {
        self.transitions
            .iter()
            .map(|t| t.var as usize + 1)
            .max()
            .unwrap_or(0)
    }

    /// Whether some state starts from a parameter rather than at rest.
    pub fn has_initial(&self) -> bool {
        self.initial
            .iter()
            .any(|&i| !matches!(self.graph.ops[i as usize], Op::Const(_)))
    }

    /// Number of held (controller) states.
    pub fn held_count(&self) -> usize {
        self.sampling.as_ref().map_or(0, |s| s.update.len())
    }

    /// Update roots, one per held state (none without controllers).
    pub fn update_roots(&self) -> Vec<Id> {
        self.sampling
            .as_ref()
            .map_or_else(Vec::new, |s| s.update.clone())
    }

    /// Event-function roots, one per transition.
    pub fn event_roots(&self) -> Vec<Id> {
        self.transitions.iter().map(|t| t.g).collect()
    }
}
