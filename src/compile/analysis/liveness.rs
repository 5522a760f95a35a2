//! Which switches can still reach the measured output.
//!
//! A fitness run reads one output (the measured signal's model). Once the
//! rig's regimes cut that output off from part of the network for good (the
//! tensile rig's specimen broken: the load cell no longer feels the grip, the
//! sliding bar or the slack adapter), the switches of that part (the adapter's
//! contact, the specimen's yield) change nothing the fit sees; locating them
//! only costs steps. [`fitness_variant`] finds them and guards each such
//! transition ([`Transition::guard`](crate::compile::program::Transition::guard)) with the mode values where it can still
//! matter, so the fitness paths (GPU fitness kernel, CPU fitted lanes) skip
//! it elsewhere, on both paths alike. Histories and reports keep every switch.
//!
//! For each combination of mode values `c`, the relevant states and regimes are
//! the closure, from the measured output, of what the output, the derivatives of
//! relevant states and the event functions of the transitions armed at `c` on
//! relevant regimes read, where a `select` whose condition depends on regimes alone follows only
//! its taken side. A transition may be skipped at `c` when its regime variable
//! is irrelevant at every combination reachable from `c` by any transition
//! (a superset of the reachable ones): its mode then never reaches the output
//! again, whatever stale value it keeps. The guard is the conjunction of mode
//! equalities that holds exactly on the combinations where the transition is
//! armed and not skippable; where no conjunction says that, the transition
//! stays unguarded (always safe: it is then located as before).

use crate::compile::ir::{Id, Input, Op, operands};
use crate::compile::program::Program;

/// Mode-value combinations past which the analysis is not tried (it walks
/// the graph once per combination and the combinations reachable from each).
const MAX_COMBINATIONS: usize = 256;

/// `prog` with a guard on each transition that cannot reach output 0 from
/// some of its armed regime combinations; `prog` unchanged where none can be
/// skipped (or the rig has too many regime combinations to enumerate).
pub fn fitness_variant(prog: &Program) -> Program {
    let mut out = prog.clone();
    let Some(&root) = prog.outputs.first() else {
        return out;
    };
    let counts = mode_counts(prog);
    let total = counts.iter().try_fold(1usize, |a, &n| a.checked_mul(n));
    let Some(total) = total.filter(|&t| t <= MAX_COMBINATIONS && !counts.is_empty()) else {
        return out;
    };
    let combos: Vec<Vec<u32>> = (0..total).map(|i| decode(i, &counts)).collect();
    let relevant: Vec<Vec<bool>> = combos
        .iter()
        .map(|c| relevant_regimes(prog, root, c))
        .collect();
    let reach: Vec<Vec<usize>> = (0..total).map(|i| reachable(prog, i, &counts)).collect();
    for (t, tr) in prog.transitions.iter().enumerate() {
        let v = tr.var as usize;
        let armed: Vec<usize> = (0..total).filter(|&i| combos[i][v] == tr.from).collect();
        let live: Vec<usize> = armed
            .iter()
            .copied()
            .filter(|&i| reach[i].iter().any(|&j| relevant[j][v]))
            .collect();
        if live.len() == armed.len() {
            continue;
        }
        if let Some(guard) = conjunction(&combos, &armed, &live, v) {
            out.transitions[t].guard = guard;
        }
    }
    out
}

/// [`fitness_variant`] where it skips some switch; `None` where it is `prog`
/// itself, so that the fitness paths can share `prog`'s builds.
pub fn skipping_variant(prog: &Program) -> Option<Program> {
    let v = fitness_variant(prog);
    (v.transitions != prog.transitions).then_some(v)
}

/// Values each regime variable takes: one past the largest a transition reads
/// or sets.
fn mode_counts(prog: &Program) -> Vec<usize> {
    let mut n = vec![1usize; prog.mode_count()];
    for tr in &prog.transitions {
        let v = tr.var as usize;
        n[v] = n[v].max(tr.from.max(tr.to) as usize + 1);
    }
    n
}

fn decode(mut i: usize, counts: &[usize]) -> Vec<u32> {
    counts
        .iter()
        .map(|&n| {
            let v = (i % n) as u32;
            i /= n;
            v
        })
        .collect()
}

fn encode(c: &[u32], counts: &[usize]) -> usize {
    c.iter()
        .zip(counts)
        .rev()
        .fold(0, |a, (&v, &n)| a * n + v as usize)
}

/// Combinations reachable from combination `i` by any sequence of
/// transitions (including `i`).
fn reachable(prog: &Program, i: usize, counts: &[usize]) -> Vec<usize> {
    let mut seen = vec![false; counts.iter().product()];
    let mut stack = vec![i];
    seen[i] = true;
    while let Some(j) = stack.pop() {
        let c = decode(j, counts);
        for tr in &prog.transitions {
            if c[tr.var as usize] == tr.from {
                let mut d = c.clone();
                d[tr.var as usize] = tr.to;
                let k = encode(&d, counts);
                if !seen[k] {
                    seen[k] = true;
                    stack.push(k);
                }
            }
        }
    }
    (0..seen.len()).filter(|&k| seen[k]).collect()
}

/// The value of every operation that depends on constants and the regimes
/// `c` alone.
fn known_values(prog: &Program, c: &[u32]) -> Vec<Option<f64>> {
    let ops = &prog.graph.ops;
    let mut v: Vec<Option<f64>> = Vec::with_capacity(ops.len());
    for op in ops {
        let get = |i: Id| v[i as usize];
        let r = match *op {
            Op::Const(x) => Some(x),
            Op::In(Input::Regime(j)) => c.get(j as usize).map(|&m| f64::from(m)),
            Op::In(_) => None,
            Op::Select(k, a, b) => match get(k) {
                Some(k) if k != 0.0 => get(a),
                Some(_) => get(b),
                None => None,
            },
            other => {
                let xs: Option<Vec<f64>> = operands(&other).into_iter().map(get).collect();
                xs.map(|xs| apply(&other, &xs))
            }
        };
        v.push(r);
    }
    v
}

fn apply(op: &Op, x: &[f64]) -> f64 {
    let flag = |b: bool| if b { 1.0 } else { 0.0 };
    match op {
        Op::Add(..) => x[0] + x[1],
        Op::Sub(..) => x[0] - x[1],
        Op::Mul(..) => x[0] * x[1],
        Op::Div(..) => x[0] / x[1],
        Op::Min(..) => x[0].min(x[1]),
        Op::Max(..) => x[0].max(x[1]),
        Op::Le(..) => flag(x[0] <= x[1]),
        Op::Eq(..) => flag(x[0] == x[1]),
        Op::Neg(_) => -x[0],
        Op::Abs(_) => x[0].abs(),
        Op::Exp(_) => x[0].exp(),
        Op::Expm1(_) => x[0].exp_m1(),
        Op::Ln(_) => x[0].ln(),
        Op::Sin(_) => x[0].sin(),
        Op::Cos(_) => x[0].cos(),
        Op::Const(_) | Op::In(_) | Op::Select(..) => f64::NAN,
    }
}

/// Which regimes reach output `root` at regime combination `c`.
fn relevant_regimes(prog: &Program, root: Id, c: &[u32]) -> Vec<bool> {
    let known = known_values(prog, c);
    let mut states = vec![false; prog.deriv.len()];
    let mut regimes = vec![false; c.len()];
    let mut seen = vec![false; prog.graph.ops.len()];
    let mut stack = vec![root];
    loop {
        while let Some(id) = stack.pop() {
            if std::mem::replace(&mut seen[id as usize], true) {
                continue;
            }
            match prog.graph.ops[id as usize] {
                Op::In(Input::State(i)) => {
                    if !std::mem::replace(&mut states[i as usize], true) {
                        stack.push(prog.deriv[i as usize]);
                    }
                }
                Op::In(Input::Regime(j)) => regimes[j as usize] = true,
                // A held state is what its update made it at the last
                // sample instant.
                Op::In(Input::Held(h)) => {
                    if let Some(s) = &prog.sampling {
                        stack.push(s.update[h as usize]);
                    }
                }
                Op::Select(k, a, b) => match known[k as usize] {
                    Some(kv) => stack.extend([k, if kv != 0.0 { a } else { b }]),
                    None => stack.extend([k, a, b]),
                },
                other => stack.extend(operands(&other)),
            }
        }
        // The event functions of the armed transitions on relevant regimes
        // decide when those regimes change: what they read is relevant too.
        for tr in &prog.transitions {
            if regimes[tr.var as usize] && c[tr.var as usize] == tr.from && !seen[tr.g as usize] {
                stack.push(tr.g);
            }
        }
        if stack.is_empty() {
            return regimes;
        }
    }
}

/// The mode equalities (other than on `var`) that hold on every `live`
/// combination and on no other `armed` one; `None` where no conjunction of
/// equalities separates them.
fn conjunction(
    combos: &[Vec<u32>],
    armed: &[usize],
    live: &[usize],
    var: usize,
) -> Option<Vec<(u32, u32)>> {
    let first = combos[*live.first()?].clone();
    let guard: Vec<(u32, u32)> = (0..first.len())
        .filter(|&j| j != var && live.iter().all(|&i| combos[i][j] == first[j]))
        .map(|j| (j as u32, first[j]))
        .collect();
    let holds = |i: usize| guard.iter().all(|&(j, v)| combos[i][j as usize] == v);
    let exact = armed.iter().all(|&i| holds(i) == live.contains(&i));
    (exact && !guard.is_empty()).then_some(guard)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_guard_is_a_conjunction_that_matches_exactly() {
        // Three two-valued variables; a transition on variable 0 that matters
        // only while variable 2 is 0, then one that matters in a set no
        // conjunction describes.
        let combos: Vec<Vec<u32>> = (0..8).map(|i| decode(i, &[2, 2, 2])).collect();
        let armed: Vec<usize> = (0..8).filter(|&i| combos[i][0] == 0).collect();
        let live: Vec<usize> = armed
            .iter()
            .copied()
            .filter(|&i| combos[i][2] == 0)
            .collect();
        assert_eq!(conjunction(&combos, &armed, &live, 0), Some(vec![(2, 0)]));
        let odd: Vec<usize> = armed
            .iter()
            .copied()
            .filter(|&i| combos[i][1] != combos[i][2])
            .collect();
        assert_eq!(conjunction(&combos, &armed, &odd, 0), None);
        assert_eq!(encode(&combos[5], &[2, 2, 2]), 5);
    }
}
