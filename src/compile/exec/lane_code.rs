//! A program's tape translated for the lane ensemble ([`crate::compile::exec::lanes`]): each
//! list (derivative, events, report, measured output) becomes register
//! instructions, with the
//! operations in the tape's order and their values in a few reused registers,
//! so a batch's working set stays in the first-level cache.
//!
//! Register file: the states first (`0..n`, where RK4 writes each stage's
//! input), then time, the regime variables, the held states, the tables, the per-run constants the
//! lists read (filled once per batch), then temporaries, reused once their last
//! reader has run, then the copies of the derivative's roots that are states
//! (see [`LaneCode::slopes`]).

use crate::compile::exec::tape::Tape;
use crate::compile::ir::{Id, Input, Op, map_operands, operands};
use crate::compile::program::{Direction, Program};

/// Register index.
pub type Reg = u16;

/// One instruction: an operation of the graph whose operands are register
/// indices, and the register it writes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ins {
    /// The register written.
    pub dest: Reg,
    /// What is computed, operands as registers (never a constant or an input:
    /// those are registers filled before the list runs).
    pub op: Op,
}

/// One list's instructions.
#[derive(Debug, Clone, Default)]
pub struct List {
    /// In tape order.
    pub code: Vec<Ins>,
    /// Where each root's value is once the list has run.
    pub roots: Vec<Reg>,
    /// Whether it reads the time register.
    pub uses_time: bool,
    /// Tables it reads: (table index, register).
    pub tables: Vec<(u32, Reg)>,
}

/// A program's lists in register form.
#[derive(Debug, Clone)]
pub struct LaneCode {
    /// The derivative; roots are `Program::deriv`.
    pub deriv: List,
    /// The event functions; roots are each transition's `g`.
    pub events: List,
    /// Outputs then full state.
    pub report: List,
    /// Output 0 alone (the quantity fitted to the measurement): the report's
    /// operations it needs, in the same order, so its value is the report's.
    pub measured: List,
    /// The held states' updates at a sample instant (empty without
    /// controllers); the runner copies each root to its held register once
    /// all have run.
    pub update: List,
    /// Where RK4 reads each state's slope once the derivative has run: its
    /// root's register, or, for a root that is the register of an earlier
    /// state (which the next stage's input, written state by state in order,
    /// has overwritten by then), the register [`Self::slope_copies`] copies
    /// it to. A displacement whose rate is a later velocity state needs no
    /// copy.
    pub slopes: Vec<Reg>,
    /// (state register, copy) pairs to copy after each derivative.
    pub slope_copies: Vec<(Reg, Reg)>,
    /// Per event root (transition), what arms it and which way it fires:
    /// (its regime variable's register, the value that arms it, direction).
    pub armed: Vec<(Reg, f64, Direction)>,
    /// Per event root, the further (mode register, value) pairs that must
    /// hold for it to be armed ([`Transition::guard`]).
    ///
    /// [`Transition::guard`]: crate::compile::program::Transition::guard
    pub guards: Vec<Vec<(Reg, f64)>>,
    /// Per event root, the value its transition sets its regime variable to.
    pub sets: Vec<f64>,
    /// The time register.
    pub time: Reg,
    /// Each regime variable's register.
    pub regimes: Vec<Reg>,
    /// Each held state's register.
    pub held: Vec<Reg>,
    /// Per-run constants the lists read: (operation, register).
    pub constants: Vec<(Id, Reg)>,
    /// Registers in all.
    pub registers: usize,
}

impl List {
    /// Which instructions give every lane the same value, given which
    /// registers hold one value for every lane before the list runs
    /// (`uniform`, updated as the list writes).
    pub fn uniform(&self, uniform: &mut [bool]) -> Vec<bool> {
        self.code
            .iter()
            .map(|ins| {
                let u = operands(&ins.op).iter().all(|&r| uniform[r as usize]);
                uniform[ins.dest as usize] = u;
                u
            })
            .collect()
    }
}

impl LaneCode {
    /// Every list of the program, in one order: the derivative, the events,
    /// the report, output 0, the held states' updates.
    pub fn lists(&self) -> [&List; 5] {
        [
            &self.deriv,
            &self.events,
            &self.report,
            &self.measured,
            &self.update,
        ]
    }

    /// Translates `tape`'s lists of `prog`.
    pub fn new(prog: &Program, tape: &Tape) -> Self {
        let ops = &prog.graph.ops;
        let n = prog.deriv.len();
        let mut fixed: Vec<Option<Reg>> = vec![None; ops.len()];
        let time = n as Reg;
        let regimes: Vec<Reg> = (0..prog.mode_count()).map(|m| (n + 1 + m) as Reg).collect();
        let held0 = n + 1 + regimes.len();
        let held: Vec<Reg> = (0..prog.held_count()).map(|k| (held0 + k) as Reg).collect();
        let tables0 = held0 + held.len();
        for (i, op) in ops.iter().enumerate() {
            fixed[i] = match *op {
                Op::In(Input::State(s)) => Some(s as Reg),
                Op::In(Input::Time) => Some(time),
                Op::In(Input::Regime(m)) => Some(regimes[m as usize]),
                Op::In(Input::Held(k)) => Some(held[k as usize]),
                Op::In(Input::Table(k)) => Some((tables0 + k as usize) as Reg),
                _ => None,
            };
        }
        // Per-run constants read by a list, or a list's root.
        let mut next = tables0 + prog.tables.len();
        let mut constants = vec![];
        let live0 = prog.graph.live(&prog.outputs[..prog.outputs.len().min(1)]);
        let measured_ops: Vec<Id> = tape
            .report_ops
            .iter()
            .copied()
            .filter(|&i| live0[i as usize])
            .collect();
        let lists: [(&[Id], Vec<Id>); 5] = [
            (&tape.deriv_ops, prog.deriv.clone()),
            (
                &tape.event_ops,
                prog.transitions.iter().map(|t| t.g).collect(),
            ),
            (
                &tape.report_ops,
                prog.outputs
                    .iter()
                    .chain(&prog.full_state)
                    .copied()
                    .collect(),
            ),
            (
                &measured_ops,
                prog.outputs.iter().take(1).copied().collect(),
            ),
            (&tape.update_ops, prog.update_roots()),
        ];
        for (list, roots) in &lists {
            let read = list.iter().flat_map(|&i| operands(&ops[i as usize]));
            for id in read.chain(roots.iter().copied()) {
                let i = id as usize;
                if prog.run_constant[i] && fixed[i].is_none() {
                    fixed[i] = Some(next as Reg);
                    constants.push((id, next as Reg));
                    next += 1;
                }
            }
        }
        let mut registers = next;
        let [deriv, events, report, measured, update] = lists.map(|(list, roots)| {
            let (l, top) = translate(prog, list, &roots, &fixed, next);
            registers = registers.max(top);
            l
        });
        let mut slope_copies = vec![];
        let slopes = deriv
            .roots
            .iter()
            .enumerate()
            .map(|(i, &r)| {
                if usize::from(r) >= i {
                    return r;
                }
                let copy = registers as Reg;
                registers += 1;
                slope_copies.push((r, copy));
                copy
            })
            .collect();
        assert!(registers <= usize::from(Reg::MAX), "too many registers");
        Self {
            deriv,
            events,
            report,
            measured,
            update,
            slopes,
            slope_copies,
            armed: prog
                .transitions
                .iter()
                .map(|tr| (regimes[tr.var as usize], f64::from(tr.from), tr.dir))
                .collect(),
            guards: prog
                .transitions
                .iter()
                .map(|tr| {
                    tr.guard
                        .iter()
                        .map(|&(v, x)| (regimes[v as usize], f64::from(x)))
                        .collect()
                })
                .collect(),
            sets: prog.transitions.iter().map(|tr| f64::from(tr.to)).collect(),
            time,
            regimes,
            held,
            constants,
            registers,
        }
    }
}

/// Translates `list` (operations in order) with roots `roots`; temporaries
/// from `first` on. Returns the list and one past its highest register.
fn translate(
    prog: &Program,
    list: &[Id],
    roots: &[Id],
    fixed: &[Option<Reg>],
    first: usize,
) -> (List, usize) {
    let ops = &prog.graph.ops;
    let computed: Vec<Id> = list
        .iter()
        .copied()
        .filter(|&i| fixed[i as usize].is_none())
        .collect();
    // Position of each value's last reader (roots live to the end).
    let mut last: Vec<Option<usize>> = vec![None; ops.len()];
    for (j, &i) in computed.iter().enumerate() {
        for o in operands(&ops[i as usize]) {
            last[o as usize] = Some(j);
        }
    }
    let mut root = vec![false; ops.len()];
    for &r in roots {
        root[r as usize] = true;
    }
    let mut reg: Vec<Option<Reg>> = fixed.to_vec();
    let mut free: Vec<Reg> = vec![];
    let mut top = first;
    let mut out = List::default();
    for &i in list {
        match ops[i as usize] {
            Op::In(Input::Time) => out.uses_time = true,
            Op::In(Input::Table(k)) => out.tables.push((k, fixed[i as usize].expect("fixed"))),
            _ => {}
        }
    }
    for (j, &i) in computed.iter().enumerate() {
        let op = ops[i as usize];
        let r = |o: Id| reg[o as usize].expect("an operand before its reader");
        // Operands read for the last time free their registers first, so the
        // result may take one of them (instructions copy operands in).
        let mut opnds = operands(&op);
        opnds.sort_unstable();
        opnds.dedup();
        for &o in &opnds {
            if last[o as usize] == Some(j) && !root[o as usize] && fixed[o as usize].is_none() {
                free.push(r(o));
            }
        }
        let d = free.pop().unwrap_or_else(|| {
            top += 1;
            (top - 1) as Reg
        });
        debug_assert!(!matches!(op, Op::Const(_) | Op::In(_)), "fixed registers");
        let ins = Ins {
            dest: d,
            op: map_operands(op, |o| Id::from(r(o))),
        };
        reg[i as usize] = Some(d);
        // A value nobody reads (not a root) frees its register at once.
        if last[i as usize].is_none() && !root[i as usize] {
            free.push(d);
        }
        out.code.push(ins);
    }
    out.roots = roots
        .iter()
        .map(|&r| reg[r as usize].expect("a root the list computes"))
        .collect();
    (out, top)
}
