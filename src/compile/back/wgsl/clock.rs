//! The drive clocks: a drive's `exp(c·t)` found in the graph, emitted as
//! `struct DriveClocks` with `rig_clock` and `rig_clock_shift`, so a block of
//! the run loop computes it once and carries it from step to step; and the
//! controllers' sample clock (`rig_instant`, `rig_sample_c`), the kernels'
//! [`crate::compile::exec::sampling::SampleClock`].

use std::fmt::Write as _;

use super::Emitter;
use crate::compile::ir::{Id, Input, Op};

impl Emitter<'_> {
    /// `c` as WGSL where operation `id` is `c·t` with `c` a run constant
    /// (the time itself, or products, quotients and negations of it by run
    /// constants).
    pub(super) fn time_coef(&self, id: Id) -> Option<String> {
        let p = self.prog();
        let rc = |k: Id| p.run_constant[k as usize];
        match p.graph.ops[id as usize] {
            Op::In(Input::Time) => Some("real(1.0)".into()),
            Op::Neg(a) => self.time_coef(a).map(|c| format!("-({c})")),
            Op::Mul(a, b) if rc(a) => self
                .time_coef(b)
                .map(|c| format!("{} * ({c})", self.name(a))),
            Op::Mul(a, b) if rc(b) => self
                .time_coef(a)
                .map(|c| format!("({c}) * {}", self.name(b))),
            Op::Div(a, b) if rc(b) => self
                .time_coef(a)
                .map(|c| format!("({c}) / {}", self.name(b))),
            _ => None,
        }
    }

    /// Every distinct exponent `c·t` of a live `exp`/`expm1`, in graph order.
    pub(super) fn find_clocks(&self) -> Vec<(Id, String)> {
        let p = self.prog();
        let mut roots: Vec<Id> = p.deriv.clone();
        roots.extend(p.event_roots());
        roots.extend(&p.outputs);
        roots.extend(&p.full_state);
        let live = p.graph.live(&roots);
        let mut clocks: Vec<(Id, String)> = Vec::new();
        for (i, op) in p.graph.ops.iter().enumerate() {
            let (Op::Exp(a) | Op::Expm1(a)) = *op else {
                continue;
            };
            if !live[i] || p.run_constant[i] || clocks.iter().any(|c| c.0 == a) {
                continue;
            }
            if let Some(c) = self.time_coef(a) {
                clocks.push((a, c));
            }
        }
        clocks
    }

    /// The clock of exponent `a`, if it is one.
    pub(super) fn clock_of(&self, a: Id) -> Option<usize> {
        self.clocks.iter().position(|c| c.0 == a)
    }

    /// `struct DriveClocks` (each clock's `expm1(c·t)`, and each table's
    /// value at `t`), `rig_clock(kc, t)` and `rig_clock_shift(kc, c, q, t)`,
    /// the clocks at `t`, `δ` later than `c`, from `c` and `q` (the clocks at
    /// `δ`): `e^{c(t+δ)} − 1 = m + q + m·q`, exact in real arithmetic and
    /// without cancellation where both are small; the tables looked up at
    /// `t` itself. A step's stages read the tables from the clocks, so the
    /// two middle stages share one lookup and the step's end is the next
    /// step's start: two lookups a step instead of four (lavapipe reads the
    /// data buffer lane by lane).
    pub(super) fn clock_functions(&self) -> String {
        let tables = self.prog().tables.len();
        let mut s = String::from("struct DriveClocks {\n");
        if self.clocks.is_empty() && tables == 0 {
            s.push_str("    unused: real,\n");
        }
        for j in 0..self.clocks.len() {
            let _ = writeln!(s, "    m{j}: real,");
        }
        for k in 0..tables {
            let _ = writeln!(s, "    tab{k}: real,");
        }
        s.push_str(
            "}\n\nfn rig_clock(kc: RunConsts, t: real) -> DriveClocks {\n    var c: DriveClocks;\n",
        );
        if self.clocks.is_empty() && tables == 0 {
            s.push_str("    c.unused = t;\n");
        }
        for (j, (_, coef)) in self.clocks.iter().enumerate() {
            let _ = writeln!(s, "    c.m{j} = expm1_r(({coef}) * t);");
        }
        for k in 0..tables {
            let _ = writeln!(s, "    c.tab{k} = {};", table_lookup(k));
        }
        s.push_str(
            "    return c;\n}\n\nfn rig_clock_shift(kc: RunConsts, c: DriveClocks, q: DriveClocks, t: real) -> DriveClocks {\n    var r = c;\n",
        );
        for j in 0..self.clocks.len() {
            let _ = writeln!(s, "    r.m{j} = (c.m{j} + q.m{j}) + c.m{j} * q.m{j};");
        }
        for k in 0..tables {
            let _ = writeln!(s, "    r.tab{k} = {};", table_lookup(k));
        }
        s.push_str("    return r;\n}\n\n");
        s
    }
}

impl Emitter<'_> {
    /// A rig with controllers: `RIG_SAMPLED`, the period and phase,
    /// `rig_instant(rg)` (the time of the next
    /// instant, from its index as [`crate::compile::program::Sampling::instant`]
    /// computes it) and `rig_sample_c(kc, t, y, rg, ck)` (every held state
    /// set from its update at `t`, all from the values before, and the next
    /// instant counted: [`crate::compile::exec::events::EventStepper::sample`]).
    /// `SAMPLE_SNAP`, which depends on the kernel's precision
    /// ([`crate::compile::exec::sampling::SAMPLE_SNAP`] or `SAMPLE_SNAP_F32`
    /// of the period), is the prelude's (`src/gpu/shaders.rs`).
    /// Nothing without controllers: the stitcher then adds
    /// `shaders/shared/no_controllers.wgsl`, whose `RIG_SAMPLED` is a
    /// compile-time false, so such a rig emits what it did before
    /// controllers existed and its kernels carry no sampling code.
    pub(super) fn sample_functions(&self) -> String {
        let p = self.prog();
        let Some(smp) = &p.sampling else {
            return String::new();
        };
        let lit = self.literal;
        let mut s = format!(
            "const RIG_SAMPLED: bool = true;\nconst SAMPLE_PERIOD: real = {};\nconst SAMPLE_PHASE: real = {};\n\n",
            lit(smp.period),
            lit(smp.phase)
        );
        s.push_str(
            "fn rig_instant(rg: RigRegime) -> real {\n    return SAMPLE_PHASE + real(rg.kn) * SAMPLE_PERIOD;\n}\n\n",
        );
        let _ = write!(
            s,
            "fn rig_sample_c(kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks) -> RigRegime {{\n{}    var r = rg;\n",
            self.body(&smp.update)
        );
        for (k, &id) in smp.update.iter().enumerate() {
            let _ = writeln!(s, "    r.h{k} = {};", self.name(id));
        }
        s.push_str("    r.kn = rg.kn + 1u;\n    return r;\n}\n\n");
        s.push_str(
            "fn rig_sample(kc: RunConsts, t: real, y: RigState, rg: RigRegime) -> RigRegime {\n    return rig_sample_c(kc, t, y, rg, rig_clock(kc, t));\n}\n\n",
        );
        s
    }
}

/// Table `k`'s value at `t` (shared/table.wgsl).
fn table_lookup(k: usize) -> String {
    format!("table_at(kc.toff{k}, kc.tlen{k}, kc.tt0{k}, kc.tinv{k}, t)")
}
