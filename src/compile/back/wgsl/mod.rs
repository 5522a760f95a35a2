//! The WGSL emitter: one [`Program`] written as the rig functions that the
//! generic event run loop (`shaders/shared/rig_run.wgsl`) calls.
//!
//! Each function evaluates the operations its roots need, in graph order, the
//! order [`crate::compile::exec::tape::Frame`] evaluates them on the CPU. Operations that
//! depend on per-run values only (the program's run constants: parameters,
//! `1/m`, a law's logarithm) are evaluated once per run on the host by the CPU
//! reference's own code ([`GpuRig::pack`]) and uploaded as the run's slots, so
//! the kernels read them as values and never recompute them; where every run of
//! a batch has the same value, the specialised kernel folds it to a constant.
//!
//! What the emitted source defines (names prefixed `rig_` or `RigState`/`RigRegime`/`RunConsts`):
//! - `RIG_STATES`, `RIG_REGIMES`, `RIG_REPORT`, and `RIG_SWITCHES` (whether the
//!   program has any located switch);
//! - `struct RigState` (continuous state, fields `s0…`), `struct RigRegime` (mode
//!   variables, `m0…`; with controllers also the held states `h0…` and the
//!   next sample instant's index `kn`), `struct RunConsts` (the run's
//!   constants and table offsets);
//! - `rig_load(base, ex) -> RunConsts`, `rig_state_load(sb)`, `rig_state_store(sb, y, rg)`,
//!   `rig_regimes_load(sb)`, `rig_initial(base, &y, &rg)` (the run's initial
//!   state and regimes, packed per run where the program has initial-state
//!   parameters);
//! - `st_axpy(y, a, k)` (`y + a·k`), `st_rk4(y, h6, k1, k2, k3, k4)`,
//!   `st_hermite(y0, f0, y1, f1, c00, c10, c01, c11)`;
//! - `rig_deriv(kc, t, y, rg) -> RigState`, `rig_events(kc, t, y, rg) -> RigEventValues` (every
//!   event function), `rig_hits(g0, g1, rg) -> u32` (the armed transitions
//!   that fire over a step from `g0` to `g1`, one bit each: the exact test of
//!   the located-step path), `rig_bases_c`, `rig_window(kc, rg)` and
//!   `rig_outside(w, b)` (the flat loop's conservative test at every step:
//!   `Emitter::window`), `rig_oriented(g, i) -> real` (transition `i`'s
//!   event function oriented so that `>= 0` is past its switch, from
//!   `rig_events`' values), `rig_fire(i, rg)`;
//! - `rig_output0_c(kc, t, y, rg, ck) -> real` (the scored output) and
//!   `rig_report_c(kc, t, y, rg, ck) -> RigReport` (every output, then the full state);
//! - the drive clocks: `struct DriveClocks`, `rig_clock(kc, t)` and
//!   `rig_clock_shift(kc, c, q, t)`, which also carry each table's value at
//!   the clock's time (a stage reads `ck.tab<k>`). An `exp` or `expm1` whose exponent is `c·t` (`c`
//!   a run constant; the velocity drive's ramp `e^{−v·t/r}`) is read from `ck`,
//!   which the run loop computes once per step and carries to the stage times
//!   by `m + q + m·q`. The derivative, the events and the outputs are emitted
//!   as `rig_deriv_c`, `rig_events_c`, `rig_output0_c` and `rig_report_c`,
//!   taking `ck`; `rig_deriv` and `rig_events` (for the located-switch path)
//!   compute it at `t`, as the CPU reference computes the exponential.
//! - with controllers, the sample clock (`Emitter::sample_functions`):
//!   `RIG_SAMPLED`, `SAMPLE_PERIOD`, `SAMPLE_PHASE`, `rig_instant(rg)` and `rig_sample_c(kc, t, y, rg, ck) -> RigRegime`
//!   (every held state from its update, the next instant counted), with
//!   `rig_sample` computing the clocks at `t`; the state buffer keeps the
//!   held states and the index after the regimes (`SAMPLE_SNAP`, which
//!   depends on the precision, is the prelude's). Without controllers none
//!   of it is written (`shaders/shared/no_controllers.wgsl` stands in).

use std::fmt::Write as _;

use crate::compile::exec::tape::{Frame, Tape};
use crate::compile::ir::{Id, Input, Op, operands};
use crate::compile::program::Program;
use window::{armed, fires, oriented};

/// Most located switches one program may have on the GPU (`rig_hits` is a
/// 32-bit mask).
pub const MAX_SWITCHES: usize = 32;

/// Why a program cannot run in the kernels.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum EmitError {
    /// More located switches than [`MAX_SWITCHES`].
    #[error("{0} located switches; the GPU kernels take at most {MAX_SWITCHES}")]
    TooManySwitches(usize),
}

/// A program prepared for the kernels: which run constants become slots, and the
/// tables the data buffer must hold.
#[derive(Debug, Clone)]
pub struct GpuRig {
    prog: Program,
    tape: Tape,
    /// Graph ids of the run constants the kernels read, in slot order.
    pub slots: Vec<Id>,
    /// Inline tables (index into `prog.tables`) with their offset in the data
    /// buffer's prefix ([`GpuRig::table_data`]).
    inline: Vec<(u32, u32, u32)>,
    table_data: Vec<f64>,
    /// The fitness kernel's program where it skips switches that can no
    /// longer reach the measured output ([`crate::compile::analysis::liveness`]); the same graph,
    /// slots and tables, only the transitions' guards differ.
    fitness: Option<Box<GpuRig>>,
}

/// Whether `id` is a run constant that a kernel reads as a slot (not a literal).
fn is_slot(p: &Program, id: Id) -> bool {
    p.run_constant[id as usize] && !matches!(p.graph.ops[id as usize], Op::Const(_))
}

mod clock;
mod window;

impl GpuRig {
    /// Prepares `prog` for the kernels, its fitness kernel skipping the
    /// switches that can no longer reach the measured output
    /// ([`crate::compile::analysis::liveness::skipping_variant`]).
    pub fn new(prog: &Program) -> Result<Self, EmitError> {
        Self::with_fitness(
            prog,
            crate::compile::analysis::liveness::skipping_variant(prog),
        )
    }

    /// Prepares `prog` for the kernels, with `fitted`, `prog`'s fitness
    /// variant where it differs (the same graph; guards only), for the fitness
    /// kernel.
    pub fn with_fitness(prog: &Program, fitness: Option<Program>) -> Result<Self, EmitError> {
        if prog.transitions.len() > MAX_SWITCHES {
            return Err(EmitError::TooManySwitches(prog.transitions.len()));
        }
        let tape = Tape::new(prog);
        // Run constants read by a per-step operation or used as a root.
        let mut roots: Vec<Id> = prog.deriv.clone();
        roots.extend(prog.event_roots());
        roots.extend(&prog.outputs);
        roots.extend(&prog.full_state);
        // The controllers' updates, and their held states' values before the
        // first instant (read by `rig_initial`).
        if let Some(s) = &prog.sampling {
            roots.extend(&s.update);
            roots.extend(&s.initial);
        }
        let live = prog.graph.live(&roots);
        let mut wanted = vec![false; prog.graph.ops.len()];
        for (i, op) in prog.graph.ops.iter().enumerate() {
            if live[i] && !prog.run_constant[i] {
                for o in operands(op) {
                    wanted[o as usize] = true;
                }
            }
        }
        for &r in &roots {
            wanted[r as usize] = true;
        }
        let slots: Vec<Id> = (0..prog.graph.ops.len() as Id)
            .filter(|&i| wanted[i as usize] && is_slot(prog, i))
            .collect();
        let mut inline = Vec::new();
        let mut table_data = Vec::new();
        for (k, t) in prog.tables.iter().enumerate() {
            if let Some(t) = t {
                table_data.push(t.kernel_header());
                inline.push((k as u32, table_data.len() as u32, t.t.len() as u32));
                table_data.extend_from_slice(&t.t);
                table_data.extend_from_slice(&t.value);
            }
        }
        let fitness = fitness.map(|variant| {
            Box::new(Self {
                prog: variant,
                tape: tape.clone(),
                slots: slots.clone(),
                inline: inline.clone(),
                table_data: table_data.clone(),
                fitness: None,
            })
        });
        Ok(Self {
            prog: prog.clone(),
            tape,
            slots,
            inline,
            table_data,
            fitness,
        })
    }

    /// The rig as the fitness kernel runs it: with the switches that cannot
    /// reach the measured output skipped where they cannot.
    pub fn fitness(&self) -> &GpuRig {
        self.fitness.as_deref().unwrap_or(self)
    }

    /// The program.
    pub fn program(&self) -> &Program {
        &self.prog
    }

    /// Continuous states.
    pub fn states(&self) -> usize {
        self.prog.deriv.len()
    }

    /// Regime variables.
    pub fn regimes(&self) -> usize {
        self.prog.mode_count()
    }

    /// Held (controller) states.
    pub fn held(&self) -> usize {
        self.prog.held_count()
    }

    /// Whether the rig has controllers (sample instants).
    pub fn sampled(&self) -> bool {
        self.prog.sampling.is_some()
    }

    /// The controllers' sample period (s), if the rig has controllers.
    pub fn sample_period(&self) -> Option<f64> {
        self.prog.sampling.as_ref().map(|s| s.period)
    }

    /// Values per run in the state buffer: the states, the regimes, with
    /// controllers the held states and the next instant's index, then the
    /// residual sum.
    pub fn state_stride(&self) -> u32 {
        (self.states() + self.regimes() + self.held() + usize::from(self.sampled()) + 1) as u32
    }

    /// Values per history record: t, every output, the full state.
    pub fn hist_values(&self) -> u32 {
        (1 + self.prog.outputs.len() + self.prog.full_state.len()) as u32
    }

    /// The inline tables, which the data buffer holds first: per table its
    /// [`crate::base::PiecewiseLinear::kernel_header`] (`table_header` reads it just
    /// before the breakpoints), the breakpoint times, then the values.
    pub fn table_data(&self) -> &[f64] {
        &self.table_data
    }

    /// The inline tables' headers (`table_header`), one per table.
    pub fn inline_table_headers(&self) -> impl Iterator<Item = f64> + '_ {
        self.inline
            .iter()
            .map(|&(_, off, _)| self.table_data[off as usize - 1])
    }

    /// Slot names (`K<id>`), for the prelude's `P_*` indices; a program with
    /// initial-state parameters adds the run's initial state (`Y0_<i>`) and
    /// initial regimes (`R0_<j>`).
    pub fn slot_names(&self) -> Vec<String> {
        let mut names: Vec<String> = self.slots.iter().map(|i| format!("K{i}")).collect();
        if self.prog.has_initial() {
            names.extend((0..self.states()).map(|i| format!("Y0_{i}")));
            names.extend((0..self.regimes()).map(|j| format!("R0_{j}")));
        }
        names
    }

    /// Appends the run's slots for the full parameter vector `params`: the run
    /// constants evaluated by the CPU reference's own code, then (with
    /// initial-state parameters) the initial state and regimes as the reference
    /// chooses them ([`crate::compile::exec::initial`]; the event functions do not read the
    /// experiment's table, which the host does not pass here).
    pub fn pack(&self, params: &[f64], out: &mut Vec<f64>) {
        let mut frame = Frame::new(&self.prog, &self.tape, params, None);
        out.extend(self.slots.iter().map(|&i| frame.get(i)));
        if self.prog.has_initial() {
            let (y0, regimes) =
                crate::compile::exec::initial::initial_state(&self.prog, &self.tape, &mut frame);
            out.extend(y0);
            out.extend(regimes.into_iter().map(f64::from));
        }
    }

    /// The WGSL source of the rig functions; `literal` writes a constant in
    /// the kernel's precision.
    pub fn source(&self, literal: &dyn Fn(f64) -> String) -> String {
        let mut e = Emitter {
            rig: self,
            literal,
            clocks: vec![],
        };
        e.clocks = e.find_clocks();
        e.emit()
    }
}

struct Emitter<'a> {
    rig: &'a GpuRig,
    literal: &'a dyn Fn(f64) -> String,
    /// The drive clocks: exponents `c·t` (operand id, `c` as WGSL) whose
    /// `exp`/`expm1` the run loop carries from stage to stage.
    clocks: Vec<(Id, String)>,
}

impl Emitter<'_> {
    fn prog(&self) -> &Program {
        &self.rig.prog
    }

    /// How operation `id` is referred to inside a per-step function.
    fn name(&self, id: Id) -> String {
        let p = self.prog();
        match p.graph.ops[id as usize] {
            Op::Const(c) => (self.literal)(c),
            _ if p.run_constant[id as usize] => format!("kc.k{id}"),
            _ => format!("v{id}"),
        }
    }

    /// The `let` lines of every per-step operation `roots` need, in graph order.
    fn body(&self, roots: &[Id]) -> String {
        let p = self.prog();
        let live = p.graph.live(roots);
        let mut s = String::new();
        for (i, op) in p.graph.ops.iter().enumerate() {
            if !live[i] || p.run_constant[i] {
                continue;
            }
            let n = |id: Id| self.name(id);
            let e = match *op {
                Op::Const(_) => continue,
                Op::In(Input::Time) => "t".into(),
                Op::In(Input::Slot(_)) => unreachable!("slots are run constants"),
                Op::In(Input::State(k)) => format!("y.s{k}"),
                Op::In(Input::Regime(m)) => format!("real(rg.r{m})"),
                Op::In(Input::Held(k)) => format!("rg.h{k}"),
                Op::In(Input::Table(k)) => {
                    format!("ck.tab{k}")
                }
                Op::Add(a, b) => format!("{} + {}", n(a), n(b)),
                Op::Sub(a, b) => format!("{} - {}", n(a), n(b)),
                Op::Mul(a, b) => format!("{} * {}", n(a), n(b)),
                Op::Div(a, b) => format!("{} / {}", n(a), n(b)),
                Op::Neg(a) => format!("-{}", n(a)),
                Op::Abs(a) => format!("abs({})", n(a)),
                Op::Min(a, b) => format!("min({}, {})", n(a), n(b)),
                Op::Max(a, b) => format!("max({}, {})", n(a), n(b)),
                Op::Exp(a) => match self.clock_of(a) {
                    Some(j) => format!("ck.m{j} + real(1.0)"),
                    None => format!("exp_r({})", n(a)),
                },
                Op::Expm1(a) => match self.clock_of(a) {
                    Some(j) => format!("ck.m{j}"),
                    None => format!("expm1_r({})", n(a)),
                },
                Op::Ln(a) => format!("ln_r({})", n(a)),
                Op::Sin(a) => format!("sin_r({})", n(a)),
                Op::Cos(a) => format!("cos_r({})", n(a)),
                Op::Le(a, b) => format!("select(real(0.0), real(1.0), {} <= {})", n(a), n(b)),
                Op::Eq(a, b) => format!("select(real(0.0), real(1.0), {} == {})", n(a), n(b)),
                Op::Select(c, a, b) => {
                    format!("select({}, {}, {} != real(0.0))", n(b), n(a), n(c))
                }
            };
            let _ = writeln!(s, "    let v{i} = {e};");
        }
        s
    }

    fn fields(&self, prefix: &str, n: usize, ty: &str) -> String {
        (0..n)
            .map(|i| format!("    {prefix}{i}: {ty},\n"))
            .collect()
    }

    fn emit(&self) -> String {
        let p = self.prog();
        let (ns, nm) = (self.rig.states(), self.rig.regimes());
        let mut s =
            String::from("// Generated from the rig description by src/compile/back/wgsl/.\n\n");
        let _ = writeln!(s, "const RIG_STATES: u32 = {ns}u;");
        let _ = writeln!(s, "const RIG_REGIMES: u32 = {nm}u;");
        // Whether any transition is ever located: without one (and without
        // controllers) the run loop compiles its crossed-step code out.
        let _ = writeln!(
            s,
            "const RIG_SWITCHES: bool = {};",
            !p.transitions.is_empty()
        );
        let _ = writeln!(
            s,
            "const RIG_REPORT: u32 = {}u;\n",
            self.rig.hist_values() - 1
        );
        let _ = write!(
            s,
            "struct RigState {{\n{}}}\n\n",
            self.fields("s", ns, "real")
        );
        // WGSL has no empty structs: a rig without regimes keeps one unused.
        // The held states and the next instant's index ride with the
        // regimes: they too change only at a switch in time, and go wherever
        // the regimes go.
        let mut rg = self.fields("r", nm.max(1), "u32");
        if p.sampling.is_some() {
            rg.push_str(&self.fields("h", self.rig.held(), "real"));
            rg.push_str("    kn: u32,\n");
        }
        let _ = write!(s, "struct RigRegime {{\n{rg}}}\n\n");
        let mut kc = String::new();
        for &i in &self.rig.slots {
            let _ = writeln!(kc, "    k{i}: real,");
        }
        for k in 0..p.tables.len() {
            let _ = writeln!(
                kc,
                "    toff{k}: u32,\n    tlen{k}: u32,\n    tt0{k}: real,\n    tinv{k}: real,"
            );
        }
        if kc.is_empty() {
            kc.push_str("    unused: u32,\n");
        }
        let _ = write!(s, "struct RunConsts {{\n{kc}}}\n\n");
        let _ = write!(
            s,
            "struct RigReport {{\n    v: array<real, {}>,\n}}\n\n",
            self.rig.hist_values() - 1
        );
        let _ = write!(
            s,
            "struct RigEventValues {{\n    g: array<real, {}>,\n}}\n\n",
            p.transitions.len().max(1)
        );
        s.push_str(&self.loaders());
        s.push_str(&self.state_algebra());
        s.push_str(&self.clock_functions());
        s.push_str(&self.functions());
        s.push_str(&self.sample_functions());
        s
    }

    fn loaders(&self) -> String {
        let p = self.prog();
        let (ns, nm, nh) = (self.rig.states(), self.rig.regimes(), self.rig.held());
        // The next instant's index, after the held states.
        let kn = ns + nm + nh;
        let mut s = String::from(
            "fn rig_load(base: u32, ex: ExpInfo) -> RunConsts {\n    var kc: RunConsts;\n",
        );
        for &i in &self.rig.slots {
            let _ = writeln!(s, "    kc.k{i} = param(base, P_K{i});");
        }
        for k in 0..p.tables.len() {
            match self.rig.inline.iter().find(|t| t.0 == k as u32) {
                Some(&(_, off, len)) => {
                    let _ = writeln!(s, "    kc.toff{k} = {off}u;\n    kc.tlen{k} = {len}u;");
                }
                None => {
                    let _ = writeln!(
                        s,
                        "    kc.toff{k} = ex.table_offset;\n    kc.tlen{k} = ex.table_len;"
                    );
                }
            }
        }
        for k in 0..p.tables.len() {
            let _ = writeln!(
                s,
                "    kc.tt0{k} = table_start(kc.toff{k}, kc.tlen{k});\n    kc.tinv{k} = table_header(kc.toff{k}, kc.tlen{k});"
            );
        }
        s.push_str("    return kc;\n}\n\n");
        s.push_str("fn rig_state_load(sb: u32) -> RigState {\n    var y: RigState;\n");
        for i in 0..ns {
            let _ = writeln!(s, "    y.s{i} = state[sb + {i}u];");
        }
        s.push_str("    return y;\n}\n\n");
        s.push_str("fn rig_regimes_load(sb: u32) -> RigRegime {\n    var rg: RigRegime;\n");
        for j in 0..nm {
            let _ = writeln!(s, "    rg.r{j} = u32(state[sb + {}u]);", ns + j);
        }
        if p.sampling.is_some() {
            for k in 0..nh {
                let _ = writeln!(s, "    rg.h{k} = state[sb + {}u];", ns + nm + k);
            }
            let _ = writeln!(s, "    rg.kn = u32(state[sb + {kn}u]);");
        }
        s.push_str("    return rg;\n}\n\n");
        // The run's start (`advance`, before its first step): the packed
        // initial state and regimes, or nothing (the cleared state buffer is
        // rest in regimes 0).
        s.push_str("fn rig_initial(base: u32, y: ptr<function, RigState>, rg: ptr<function, RigRegime>) {\n");
        if p.has_initial() {
            for i in 0..ns {
                let _ = writeln!(s, "    (*y).s{i} = param(base, P_Y0_{i});");
            }
            for j in 0..nm {
                let _ = writeln!(s, "    (*rg).r{j} = u32(param(base, P_R0_{j}));");
            }
        }
        // The held states' values before the first instant: run constants,
        // read as slots (or written as literals), as the initial state is.
        if let Some(smp) = &p.sampling {
            for (k, &id) in smp.initial.iter().enumerate() {
                let v = match p.graph.ops[id as usize] {
                    Op::Const(c) => (self.literal)(c),
                    _ => format!("param(base, P_K{id})"),
                };
                let _ = writeln!(s, "    (*rg).h{k} = {v};");
            }
            s.push_str("    (*rg).kn = 0u;\n");
        }
        s.push_str("}\n\n");
        s.push_str("fn rig_state_store(sb: u32, y: RigState, rg: RigRegime) {\n");
        for i in 0..ns {
            let _ = writeln!(s, "    state[sb + {i}u] = y.s{i};");
        }
        for j in 0..nm {
            let _ = writeln!(s, "    state[sb + {}u] = real(rg.r{j});", ns + j);
        }
        if p.sampling.is_some() {
            for k in 0..nh {
                let _ = writeln!(s, "    state[sb + {}u] = rg.h{k};", ns + nm + k);
            }
            let _ = writeln!(s, "    state[sb + {kn}u] = real(rg.kn);");
        }
        let acc = kn + usize::from(p.sampling.is_some());
        let _ = writeln!(s, "}}\n\nconst RIG_ACC: u32 = {acc}u;\n");
        s
    }

    fn state_algebra(&self) -> String {
        let ns = self.rig.states();
        let each = |f: &dyn Fn(usize) -> String| -> String {
            (0..ns)
                .map(|i| format!("    r.s{i} = {};\n", f(i)))
                .collect()
        };
        let mut s = String::new();
        let _ = write!(
            s,
            "fn st_axpy(y: RigState, a: real, k: RigState) -> RigState {{\n    var r: RigState;\n{}    return r;\n}}\n\n",
            each(&|i| format!("y.s{i} + a * k.s{i}"))
        );
        let _ = write!(
            s,
            "fn st_rk4(y: RigState, h6: real, k1: RigState, k2: RigState, k3: RigState, k4: RigState) -> RigState {{\n    var r: RigState;\n{}    return r;\n}}\n\n",
            each(&|i| format!(
                "y.s{i} + h6 * (((k1.s{i} + real(2.0) * k2.s{i}) + real(2.0) * k3.s{i}) + k4.s{i})"
            ))
        );
        let _ = write!(
            s,
            "fn st_hermite(y0: RigState, f0: RigState, y1: RigState, f1: RigState, c00: real, c10: real, c01: real, c11: real) -> RigState {{\n    var r: RigState;\n{}    return r;\n}}\n\n",
            each(&|i| format!("((c00 * y0.s{i} + c10 * f0.s{i}) + c01 * y1.s{i}) + c11 * f1.s{i}"))
        );
        s
    }

    fn functions(&self) -> String {
        let p = self.prog();
        let sig = "kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks";
        let mut s = String::new();
        // Derivative.
        let _ = write!(
            s,
            "fn rig_deriv_c({sig}) -> RigState {{\n{}    var r: RigState;\n",
            self.body(&p.deriv)
        );
        for (i, &d) in p.deriv.iter().enumerate() {
            let _ = writeln!(s, "    r.s{i} = {};", self.name(d));
        }
        s.push_str("    return r;\n}\n\n");
        // Events: every event function, then which armed transitions fire
        // over a step (Transition::fires).
        let _ = write!(
            s,
            "fn rig_events_c({sig}) -> RigEventValues {{\n{}    var r: RigEventValues;\n",
            self.body(&p.event_roots())
        );
        for (i, tr) in p.transitions.iter().enumerate() {
            let _ = writeln!(s, "    r.g[{i}] = {};", self.name(tr.g));
        }
        s.push_str("    return r;\n}\n\n");
        s.push_str("fn rig_hits(g0: RigEventValues, g1: RigEventValues, rg: RigRegime) -> u32 {\n    var hits = 0u;\n");
        for (i, tr) in p.transitions.iter().enumerate() {
            let g = |e: &str| oriented(tr.dir, &format!("{e}.g[{i}]"));
            let _ = writeln!(
                s,
                "    hits |= select(0u, {}u, {} && {});",
                1u64 << i,
                armed(tr),
                fires(&g("g1"), &g("g0"))
            );
        }
        s.push_str("    return hits;\n}\n\n");
        s.push_str(&self.window());
        s.push_str("fn rig_oriented(g: RigEventValues, i: u32) -> real {\n    switch i {\n");
        for (i, tr) in p.transitions.iter().enumerate() {
            let _ = writeln!(
                s,
                "        case {i}u: {{ return {}; }}",
                oriented(tr.dir, &format!("g.g[{i}]"))
            );
        }
        s.push_str("        default: { return real(0.0); }\n    }\n}\n\n");
        s.push_str("fn rig_fire(i: u32, rg: ptr<function, RigRegime>) {\n    switch i {\n");
        for (i, tr) in p.transitions.iter().enumerate() {
            let _ = writeln!(
                s,
                "        case {i}u: {{ (*rg).r{} = {}u; }}",
                tr.var, tr.to
            );
        }
        s.push_str("        default: {}\n    }\n}\n\n");
        // Outputs.
        let out0 = p.outputs.first().copied();
        match out0 {
            Some(o) => {
                let _ = write!(
                    s,
                    "fn rig_output0_c({sig}) -> real {{\n{}    return {};\n}}\n\n",
                    self.body(&[o]),
                    self.name(o)
                );
            }
            None => {
                let _ = write!(
                    s,
                    "fn rig_output0_c({sig}) -> real {{\n    return real(0.0);\n}}\n\n"
                );
            }
        }
        let mut roots = p.outputs.clone();
        roots.extend(&p.full_state);
        let _ = write!(
            s,
            "fn rig_report_c({sig}) -> RigReport {{\n{}    var r: RigReport;\n",
            self.body(&roots)
        );
        for (j, &id) in roots.iter().enumerate() {
            let _ = writeln!(s, "    r.v[{j}] = {};", self.name(id));
        }
        s.push_str("    return r;\n}\n\n");
        // The same at a time whose clocks are not at hand.
        for (f, ty) in [("rig_deriv", "RigState"), ("rig_events", "RigEventValues")] {
            let _ = writeln!(
                s,
                "fn {f}(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> {ty} {{\n    return {f}_c(kc, t, y, rg, rig_clock(kc, t));\n}}\n"
            );
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rig::SHIPPED;

    #[test]
    fn every_shipped_rig_emits_its_functions() {
        for (id, _) in SHIPPED {
            let desc = crate::rig::shipped(id).expect("a shipped rig");
            let rig = crate::model::compiled::CompiledRig::new(desc, id).expect("compiles");
            for prog in &rig.lowered.programs {
                let g = GpuRig::new(prog).expect("emits");
                let src = g.source(&|v| format!("real({v:e})"));
                for f in [
                    "fn rig_deriv",
                    "fn rig_events",
                    "fn rig_hits",
                    "fn rig_window",
                    "fn rig_outside",
                    "fn rig_fire",
                    "fn rig_report",
                ] {
                    assert!(src.contains(f), "{id}: {f} missing");
                }
                let mut out = Vec::new();
                let params: Vec<f64> = rig
                    .desc
                    .params
                    .iter()
                    .map(|p| p.default.unwrap_or(1.0))
                    .collect();
                g.pack(&params, &mut out);
                assert_eq!(out.len(), g.slots.len());
            }
        }
    }
}
