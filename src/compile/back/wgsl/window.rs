//! The event windows: each event function that is a base minus a run
//! constant is tested against one window per base (`rig_bases_c`,
//! `rig_window`, `rig_outside`), and the exact test of which armed events fire
//! over a step.

use std::fmt::Write as _;

use super::Emitter;
use crate::compile::ir::{Id, Op};
use crate::compile::program::{Direction, Transition};

impl Emitter<'_> {
    /// The flat loop's test, for its every step: whether an armed transition
    /// may fire over the step. Each event function is split into a base and a
    /// threshold where it is `base − c` with `c` a run constant (else the base
    /// is the whole function and `c` is 0), and the transitions on one base
    /// share a window: `struct EventBases` (each base, from `rig_bases_c`), `struct
    /// EventWindows` and `rig_window(kc, rg)` (per base, the least threshold of the
    /// armed upward transitions and the greatest of the armed downward ones,
    /// found once per block: the regimes change only on a located step), and
    /// `rig_outside(w, b)` (the base at or past an end of its window).
    ///
    /// The test is conservative, never exact: a transition that fires is past
    /// its switch at the step's end (`fl(base − c) ≥ 0` upward, `≤ 0`
    /// downward), and subtraction rounds monotonically, so the base is then
    /// outside the window too. A step it flags where none fires costs the
    /// located-step path one plain step (`rig_hits`, the exact test, finds
    /// nothing); it never decides which transition fires. Two subtractions
    /// and two comparisons per base, however many transitions share it (the
    /// tensile rig's yield, its reverse and fracture all on the specimen's
    /// elongation), joined by the non-short-circuit `|` (a short-circuit `||`
    /// becomes a branch, which a CPU driver runs under a mask).
    pub(super) fn window(&self) -> String {
        let p = self.prog();
        let rc = |k: Id| p.run_constant[k as usize];
        let mut bases: Vec<(Id, Vec<(usize, String)>)> = Vec::new();
        for (i, tr) in p.transitions.iter().enumerate() {
            let (b, c) = match p.graph.ops[tr.g as usize] {
                Op::Sub(a, c) if rc(c) && !rc(a) => (a, self.name(c)),
                _ => (tr.g, "real(0.0)".to_string()),
            };
            match bases.iter_mut().find(|e| e.0 == b) {
                Some(e) => e.1.push((i, c)),
                None => bases.push((b, vec![(i, c)])),
            }
        }
        let roots: Vec<Id> = bases.iter().map(|e| e.0).collect();
        let sig = "kc: RunConsts, t: real, y: RigState, rg: RigRegime, ck: DriveClocks";
        let mut s = format!(
            "struct EventBases {{\n{}}}\n\nfn rig_bases_c({sig}) -> EventBases {{\n{}    var r: EventBases;\n",
            self.fields("b", roots.len().max(1), "real"),
            self.body(&roots)
        );
        if roots.is_empty() {
            s.push_str("    r.b0 = real(0.0);\n");
        }
        for (j, &b) in roots.iter().enumerate() {
            let _ = writeln!(s, "    r.b{j} = {};", self.name(b));
        }
        let _ = write!(
            s,
            "    return r;\n}}\n\nstruct EventWindows {{\n{}{}}}\n\nfn rig_window(kc: RunConsts, rg: RigRegime) -> EventWindows {{\n    var w: EventWindows;\n",
            self.fields("lo", roots.len().max(1), "real"),
            self.fields("hi", roots.len().max(1), "real"),
        );
        let mut terms = Vec::new();
        for (j, (_, trs)) in bases.iter().enumerate() {
            let _ = writeln!(s, "    w.lo{j} = -REAL_MAX;\n    w.hi{j} = REAL_MAX;");
            for dir in [Direction::Up, Direction::Down] {
                let mut any = false;
                for (i, c) in trs.iter().filter(|(i, _)| p.transitions[*i].dir == dir) {
                    let tr = &p.transitions[*i];
                    let (side, pick) = match dir {
                        Direction::Up => ("hi", "min"),
                        Direction::Down => ("lo", "max"),
                    };
                    let _ = writeln!(
                        s,
                        "    w.{side}{j} = select(w.{side}{j}, {pick}(w.{side}{j}, {c}), {});",
                        armed(tr)
                    );
                    any = true;
                }
                if any {
                    terms.push(match dir {
                        Direction::Up => format!("b.b{j} - w.hi{j} >= real(0.0)"),
                        Direction::Down => format!("b.b{j} - w.lo{j} <= real(0.0)"),
                    });
                }
            }
        }
        if roots.is_empty() {
            s.push_str("    w.lo0 = -REAL_MAX;\n    w.hi0 = REAL_MAX;\n");
        }
        if terms.is_empty() {
            terms.push("false".into());
        }
        let _ = write!(
            s,
            "    return w;\n}}\n\nfn rig_outside(w: EventWindows, b: EventBases) -> bool {{\n    return {};\n}}\n\n",
            terms.join("\n        | ")
        );
        s
    }
}

/// Whether `tr` is armed at the regimes `rg` (`Transition::armed`): its
/// variable at its `from` value and every pair of its guard held.
pub(super) fn armed(tr: &Transition) -> String {
    std::iter::once((tr.var, tr.from))
        .chain(tr.guard.iter().copied())
        .map(|(v, x)| format!("rg.r{v} == {x}u"))
        .collect::<Vec<_>>()
        .join(" && ")
}

/// An event value `g` oriented so that `>= 0` is past its switch
/// (`Transition::oriented`): `g` for an upward switch, `−g` (exact) for a
/// downward one.
pub(super) fn oriented(dir: Direction, g: &str) -> String {
    match dir {
        Direction::Up => g.to_string(),
        Direction::Down => format!("-({g})"),
    }
}

/// Whether an armed transition fires over a step, from its oriented event
/// values at the step's end `o1` and start `o0` (`Transition::fires`): past
/// the switch at the end, and before it at the start or further past.
pub(super) fn fires(o1: &str, o0: &str) -> String {
    format!("{o1} >= real(0.0) && (!({o0} >= real(0.0)) || {o1} > {o0})")
}
