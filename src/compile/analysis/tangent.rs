//! Forward-mode derivatives of a compiled graph: how every operation's value
//! changes with one state, at the point a [`Frame`] last evaluated. The
//! linearisation that `rigfit modes` needs comes from here (the derivative's
//! Jacobian, column by column), so a new rig gets it from its description.
//!
//! The rules are the graph's own operations differentiated exactly. At a kink
//! (`|a|` at 0, `min`/`max` with equal operands) the tangent is the mean of
//! the two one-sided ones, which is what a central difference sees; a
//! comparison has tangent 0, and a select takes its chosen operand's.

use crate::compile::exec::tape::{Frame, Point, Tape};
use crate::compile::ir::{Id, Input, Op};
use crate::compile::program::Program;

/// d(value)/d(state `j`) of every operation of `ops` (graph order) at the point
/// `frame` last evaluated them, into `dot` (indexed by operation; operations
/// not in `ops`, such as per-run constants, have tangent 0).
pub fn state_tangent(prog: &Program, ops: &[Id], frame: &Frame<'_>, j: u32, dot: &mut [f64]) {
    dot.fill(0.0);
    for &i in ops {
        let v = |k: Id| frame.get(k);
        let d = |k: Id| dot[k as usize];
        let x = match prog.graph.ops[i as usize] {
            Op::In(Input::State(s)) => f64::from(u8::from(s == j)),
            Op::Const(_) | Op::In(_) | Op::Le(..) | Op::Eq(..) => 0.0,
            Op::Add(p, q) => d(p) + d(q),
            Op::Sub(p, q) => d(p) - d(q),
            Op::Mul(p, q) => d(p) * v(q) + v(p) * d(q),
            Op::Div(p, q) => (d(p) - v(i) * d(q)) / v(q),
            Op::Neg(p) => -d(p),
            Op::Abs(p) => v(p).signum() * d(p) * f64::from(u8::from(v(p) != 0.0)),
            Op::Min(p, q) => kink(v(p), v(q), d(p), d(q), true),
            Op::Max(p, q) => kink(v(p), v(q), d(p), d(q), false),
            Op::Exp(p) => v(i) * d(p),
            Op::Expm1(p) => (v(i) + 1.0) * d(p),
            Op::Ln(p) => d(p) / v(p),
            Op::Sin(p) => v(p).cos() * d(p),
            Op::Cos(p) => -v(p).sin() * d(p),
            Op::Select(c, p, q) => {
                if v(c) != 0.0 {
                    d(p)
                } else {
                    d(q)
                }
            }
        };
        dot[i as usize] = x;
    }
}

/// Tangent of `min(a, b)` (`smaller`) or `max(a, b)`.
fn kink(a: f64, b: f64, da: f64, db: f64, smaller: bool) -> f64 {
    if a == b {
        0.5 * (da + db)
    } else if (a < b) == smaller {
        da
    } else {
        db
    }
}

/// The derivative's Jacobian `∂(dy/dt)_i / ∂y_j` at `(t, y)` in `regimes`, row
/// major, from the graph's tangents.
pub fn deriv_jacobian(
    prog: &Program,
    tape: &Tape,
    frame: &mut Frame<'_>,
    t: f64,
    y: &[f64],
    regimes: &[u32],
) -> Vec<f64> {
    let n = prog.deriv.len();
    // Held states at their values before the first instant: constant over a
    // step, they add nothing to the Jacobian.
    let held = crate::compile::exec::initial::initial_held(prog, frame);
    frame.eval(
        &tape.deriv_ops,
        Point {
            t,
            y,
            regimes,
            held: &held,
        },
    );
    let mut dot = vec![0.0; prog.graph.ops.len()];
    let mut jac = vec![0.0; n * n];
    for j in 0..n {
        state_tangent(prog, &tape.deriv_ops, frame, j as u32, &mut dot);
        for (i, &id) in prog.deriv.iter().enumerate() {
            jac[i * n + j] = dot[id as usize];
        }
    }
    jac
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compile::{Graph, Input, Tape};

    #[test]
    fn tangents_of_each_operation_match_central_differences() {
        // One graph using every differentiable operation of one state.
        let mut g = Graph::new();
        let x = g.input(Input::State(0));
        let two = g.c(2.0);
        let a = g.push(Op::Mul(x, x));
        let b = g.push(Op::Div(a, two));
        let c = g.push(Op::Exp(b));
        let d = g.push(Op::Expm1(x));
        let e = g.push(Op::Sin(d));
        let f = g.push(Op::Cos(c));
        let abs = g.push(Op::Abs(x));
        let sum = g.push(Op::Add(e, f));
        let l = g.push(Op::Add(abs, two));
        let ln = g.push(Op::Ln(l));
        let mx = g.push(Op::Max(sum, ln));
        let mn = g.push(Op::Min(mx, c));
        let neg = g.push(Op::Neg(mn));
        let le = g.push(Op::Le(x, two));
        let sel = g.push(Op::Select(le, neg, a));
        let root = g.push(Op::Sub(sel, b));
        let mut prog = Program {
            mode: "test".into(),
            graph: g,
            deriv: vec![root],
            outputs: vec![],
            full_state: vec![],
            transitions: vec![],
            run_constant: vec![],
            tables: vec![],
            initial: vec![],
            sampling: None,
        };
        prog.mark_run_constants();
        let tape = Tape::new(&prog);
        for xv in [-1.1, -0.3, 0.45, 1.2, 2.5] {
            let mut frame = Frame::new(&prog, &tape, &[], None);
            let jac = deriv_jacobian(&prog, &tape, &mut frame, 0.0, &[xv], &[]);
            let at = |x: f64, frame: &mut Frame<'_>| {
                frame.eval(
                    &tape.deriv_ops,
                    crate::compile::Point {
                        t: 0.0,
                        y: &[x],
                        regimes: &[],
                        held: &[],
                    },
                );
                frame.get(root)
            };
            let hd = 1e-6;
            let fd = (at(xv + hd, &mut frame) - at(xv - hd, &mut frame)) / (2.0 * hd);
            assert!(
                (jac[0] - fd).abs() <= 1e-7 * fd.abs().max(1.0),
                "x = {xv}: tangent {} vs central difference {fd}",
                jac[0]
            );
        }
    }

    /// Every shipped rig's Jacobian, from the tangents, against central
    /// differences of the tape, at a state away from every switch, in the
    /// regimes at rest and with every regime variable at 1 where it has a value 1.
    #[test]
    fn every_shipped_rig_jacobian_matches_central_differences() {
        use crate::compile::Point;
        let table = crate::base::PiecewiseLinear {
            t: vec![0.0, 1.0],
            value: vec![10.0, 20.0],
        };
        for (id, _) in crate::rig::SHIPPED {
            let desc = crate::rig::shipped(id).expect("a shipped rig");
            let params: Vec<f64> = desc
                .params
                .iter()
                .map(|p| p.default.unwrap_or(1.0))
                .collect();
            let rig = crate::model::compiled::CompiledRig::new(desc, id).expect("compiles");
            for prog in &rig.lowered.programs {
                let tape = Tape::new(prog);
                let n = prog.deriv.len();
                let mut frame = Frame::new(prog, &tape, &params, Some(&table));
                let held = crate::compile::exec::initial::initial_held(prog, &frame);
                // Small displacements and rates, different in every slot.
                let y: Vec<f64> = (0..n).map(|i| 1e-5 * (1.0 + 0.37 * i as f64)).collect();
                for ones in [false, true] {
                    let regimes: Vec<u32> = (0..prog.mode_count())
                        .map(|v| {
                            u32::from(
                                ones && prog
                                    .transitions
                                    .iter()
                                    .any(|t| t.var as usize == v && t.to == 1),
                            )
                        })
                        .collect();
                    let t = 1e-4;
                    let jac = deriv_jacobian(prog, &tape, &mut frame, t, &y, &regimes);
                    let mut at = |y: &[f64]| -> Vec<f64> {
                        frame.eval(
                            &tape.deriv_ops,
                            Point {
                                t,
                                y,
                                regimes: &regimes,
                                held: &held,
                            },
                        );
                        prog.deriv.iter().map(|&d| frame.get(d)).collect()
                    };
                    for j in 0..n {
                        let h = 1e-4 * y[j].abs();
                        let (mut up, mut down) = (y.clone(), y.clone());
                        up[j] += h;
                        down[j] -= h;
                        let (fu, fdn) = (at(&up), at(&down));
                        for i in 0..n {
                            let fd = (fu[i] - fdn[i]) / (2.0 * h);
                            let scale = (0..n).map(|c| jac[i * n + c].abs()).fold(1e-300, f64::max);
                            assert!(
                                (jac[i * n + j] - fd).abs() <= 1e-6 * scale,
                                "{id} ({}), regimes {regimes:?}: ∂f{i}/∂y{j} = {} by tangents, {fd} by differences",
                                prog.mode,
                                jac[i * n + j]
                            );
                        }
                    }
                }
            }
        }
    }
}
