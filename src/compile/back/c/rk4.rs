//! `rig_rk4`: one RK4 step over the blocks of the register file, the
//! instructions that depend on time and per-run constants alone hoisted out
//! of its loop, and the hit test of the event list at the step's end.

use std::fmt::Write;

use super::statements::{declare, inputs, load, statement};
use crate::compile::exec::lane_code::{LaneCode, List, Reg};
use crate::compile::ir::{Op, operands};
use crate::compile::program::Direction;

/// Table values per derivative in `rig_rk4`'s `tab` (one past the highest
/// table any list reads).
pub fn table_stride(code: &LaneCode) -> usize {
    code.lists()
        .iter()
        .flat_map(|l| l.tables.iter().map(|&(k, _)| k as usize + 1))
        .max()
        .unwrap_or(0)
}

/// Which instructions of `list` depend on time, tables and per-run
/// constants alone (not on a state or a mode), and the constant registers
/// those read.
fn time_only(code: &LaneCode, list: &List) -> (Vec<bool>, Vec<Reg>) {
    let constant: std::collections::HashSet<Reg> = code.constants.iter().map(|&(_, r)| r).collect();
    let mut tc = vec![false; code.registers];
    tc[code.time as usize] = true;
    for &(_, reg) in &list.tables {
        tc[reg as usize] = true;
    }
    for &reg in &constant {
        tc[reg as usize] = true;
    }
    let mut reads = vec![];
    let flags = list
        .code
        .iter()
        .map(|ins| {
            let ops = operands(&ins.op);
            let t = ops.iter().all(|&o| tc[o as usize]);
            if t {
                for &o in &ops {
                    let o = o as Reg;
                    if constant.contains(&o) && !reads.contains(&o) {
                        reads.push(o);
                    }
                }
            }
            tc[ins.dest as usize] = t;
            t
        })
        .collect();
    (flags, reads)
}

/// The instructions of the derivative and of the event list that depend on
/// time, tables and per-run constants alone, and the constant registers
/// those read. Where every lane holds the same value in each of those
/// constants (as when the drive's parameters are fixed), `rig_rk4` computes
/// these instructions once per call instead of once per block.
#[derive(Debug, Clone)]
pub struct Hoistable {
    /// Per derivative instruction.
    pub deriv: Vec<bool>,
    /// Per event-list instruction (the list `rig_rk4` runs at the step's
    /// end).
    pub events: Vec<bool>,
    /// The constant registers either reads.
    pub reads: Vec<Reg>,
}

/// [`Hoistable`] of `code`.
pub fn hoistable(code: &LaneCode) -> Hoistable {
    let (deriv, mut reads) = time_only(code, &code.deriv);
    let (events, more) = time_only(code, &code.events);
    for r in more {
        if !reads.contains(&r) {
            reads.push(r);
        }
    }
    Hoistable {
        deriv,
        events,
        reads,
    }
}

/// The time and table registers `list` reads (the derivative's at its
/// `stage`, 0–3; the event list's at the step's end, stage 3): `tt[stage]`
/// and that stage's row of `tab`.
fn stage_inputs(s: &mut String, code: &LaneCode, list: &List, stage: usize) {
    if list.uses_time {
        let _ = writeln!(s, "    r{} = splat(tt[{stage}]);", code.time);
    }
    for &(k, reg) in &list.tables {
        let _ = writeln!(
            s,
            "    r{reg} = splat(tab[{} + {k}]);",
            stage * table_stride(code)
        );
    }
}

/// `list`'s hoisted instructions (`hoisted[j]`) at `stage`, each result kept
/// in the vector `<keep><j>`.
pub(super) fn hoist(
    s: &mut String,
    code: &LaneCode,
    list: &List,
    hoisted: &[bool],
    stage: usize,
    keep: &str,
) {
    stage_inputs(s, code, list, stage);
    for (j, ins) in list.code.iter().enumerate().filter(|&(j, _)| hoisted[j]) {
        // Every lane holds the same value here: the C library's functions
        // are called once, not lane by lane.
        s.push_str(&match ins.op {
            Op::Ln(a) => format!("    r{} = ulog(r{a});\n", ins.dest),
            Op::Sin(a) => format!("    r{} = usin(r{a});\n", ins.dest),
            Op::Cos(a) => format!("    r{} = ucos(r{a});\n", ins.dest),
            _ => statement(ins.dest, &ins.op, 'v'),
        });
        let _ = writeln!(s, "    v {keep}{j} = r{};", ins.dest);
    }
}

/// The stage whose hoisted values stage `stage` of `rig_rk4` reads: the
/// second and third stages are both at `t + h/2` (`tt[1] == tt[2]`, as the
/// lane runner passes them), so the third reads the second's.
fn hoisted_stage(stage: usize) -> usize {
    if stage == 2 { 1 } else { stage }
}

/// `rig_rk4`'s loop over blocks: hoisted (`Some`: which instructions were
/// computed before the loop, into `u{stage}_{index}` and `e_{index}`) or
/// not.
pub(super) fn rk4_loop(s: &mut String, code: &LaneCode, hoisted: Option<&Hoistable>) {
    let n = code.slopes.len();
    s.push_str("  for (long q = 0; q < NQ(nb); q++) {\n");
    declare(s, code, "v");
    let _ = writeln!(
        s,
        "    v {};",
        (0..n)
            .map(|i| format!("y{i}, a{i}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    for reg in inputs(&code.deriv) {
        if from_rows(code, &code.deriv, reg) {
            load(s, reg, "", code, &|_| None);
        }
    }
    for i in 0..n {
        let _ = writeln!(s, "    y{i} = LDP(R, {i}); KEEP(Y, R, {i}); r{i} = y{i};");
    }
    for stage in 0..4 {
        stage_inputs(s, code, &code.deriv, stage);
        for (j, ins) in code.deriv.code.iter().enumerate() {
            if hoisted.is_some_and(|h| h.deriv[j]) {
                let _ = writeln!(s, "    r{} = u{}_{j};", ins.dest, hoisted_stage(stage));
            } else {
                s.push_str(&statement(ins.dest, &ins.op, 'v'));
            }
        }
        for &(state, copy) in &code.slope_copies {
            let _ = writeln!(s, "    r{copy} = r{state};");
        }
        for (i, &k) in code.slopes.iter().enumerate() {
            let _ = match stage {
                0 => writeln!(s, "    a{i} = r{k}; r{i} = y{i} + CH * r{k};"),
                1 => writeln!(s, "    a{i} = a{i} + TWO * r{k}; r{i} = y{i} + CH * r{k};"),
                2 => writeln!(s, "    a{i} = a{i} + TWO * r{k}; r{i} = y{i} + H * r{k};"),
                _ => writeln!(s, "    r{i} = y{i} + H6 * (a{i} + r{k});"),
            };
        }
    }
    for i in 0..n {
        let _ = writeln!(s, "    STP(R, {i}, r{i});");
    }
    step_end_events(s, code, hoisted.map(|h| &h.events[..]));
    s.push_str("  }\n");
}

/// The event list at the step's end (`tt[3]`, table row 3), run in
/// `rig_rk4`'s loop on the new state while it is still in registers, and
/// the lanes past an armed switch marked in `ks[q]` (its roots are not
/// stored: nothing after the step reads them, where the interpreter's hit
/// test reads them from the register file). `hoisted`: which instructions
/// were computed before the loop, into `e_{index}`.
fn step_end_events(s: &mut String, code: &LaneCode, hoisted: Option<&[bool]>) {
    let list = &code.events;
    if list.code.is_empty() && code.armed.is_empty() {
        return;
    }
    s.push_str("    /* the event functions at the step's end */\n");
    stage_inputs(s, code, &code.events, 3);
    let held = still_loaded(code);
    for reg in event_loads(code) {
        if from_rows(code, list, reg) && !held.contains(&reg) {
            load(s, reg, "", code, &|_| None);
        }
    }
    for (j, ins) in list.code.iter().enumerate() {
        if hoisted.is_some_and(|h| h[j]) {
            let _ = writeln!(s, "    r{} = e_{j};", ins.dest);
        } else {
            s.push_str(&statement(ins.dest, &ins.op, 'v'));
        }
    }
    hit_test(s, code);
}

/// The registers `rig_rk4`'s loop loaded at its start for the derivative
/// that still hold their rows at the step's end (no instruction or slope copy
/// of the four stages wrote them): the event list reads them from there,
/// not from the register file again (an f32 lane's load converts from f64).
fn still_loaded(code: &LaneCode) -> Vec<Reg> {
    let written: std::collections::HashSet<Reg> = code
        .deriv
        .code
        .iter()
        .map(|ins| ins.dest)
        .chain(code.slope_copies.iter().map(|&(_, copy)| copy))
        .collect();
    inputs(&code.deriv)
        .into_iter()
        .filter(|&reg| from_rows(code, &code.deriv, reg) && !written.contains(&reg))
        .collect()
}

/// Whether `list`'s input `reg` is loaded from the register file: not a
/// state (the step's own registers), the time or one of the list's tables
/// (from `tt` and `tab`).
fn from_rows(code: &LaneCode, list: &List, reg: Reg) -> bool {
    (reg as usize) >= code.slopes.len()
        && reg != code.time
        && !list.tables.iter().any(|&(_, r)| r == reg)
}

/// The registers the event list and its hit test read: its inputs, the
/// armed switches' modes and their guards' modes.
fn event_loads(code: &LaneCode) -> Vec<Reg> {
    let mut loads = inputs(&code.events);
    let guarded = code.guards.iter().flatten().map(|&(m, _)| m);
    for mode in code.armed.iter().map(|a| a.0).chain(guarded) {
        if !loads.contains(&mode) {
            loads.push(mode);
        }
    }
    loads
}

/// `LaneRunner`'s hit test on the event functions in their registers: a bit
/// per lane armed and past its switch (`Direction::past`), added to `hits`.
fn hit_test(s: &mut String, code: &LaneCode) {
    s.push_str("    m k = (m){0};\n");
    for ((&(mode, from, dir), &g), guard) in
        code.armed.iter().zip(&code.events.roots).zip(&code.guards)
    {
        let past = match dir {
            Direction::Up => ">=",
            Direction::Down => "<=",
        };
        let guard: String = guard
            .iter()
            .map(|&(m, v)| format!(" & (r{m} == splat({v:?}))"))
            .collect();
        let _ = writeln!(
            s,
            "    k |= (r{mode} == splat({from:?})) & (r{g} {past} splat(0.0)){guard};"
        );
    }
    s.push_str("    ks[q] = k; kor |= k;\n");
}

/// Stores the lanes the hit test marked in `hit`: a byte per block, a bit
/// per lane, none past block `nb`. The masks of the loop's vectors are
/// turned into bits only where one lane of them is marked (a step with no
/// switch, most of them, reduces one vector instead of one per vector).
pub(super) const STORE_HITS: &str = "  if (lanebits(kor)) for (long q = 0; q < NQ(nb); q++) hits |= lanebits(ks[q]) << (q * WV);\n  if (nb < BLOCKS) hits &= (1ULL << (nb * 8)) - 1;\n  for (int i = 0; i < BLOCKS; i++) hit[i] = hits >> (8 * i);\n";

/// `lanebits`: a bit per lane of mask `k` (lanes of `lanes`), with the lanes
/// OR-ed together by rotations instead of read one by one through memory
/// (which stalls on the store of the whole vector before it).
pub(super) fn lane_bits(lanes: usize) -> String {
    let powers = (0..lanes)
        .map(|l| (1u64 << l).to_string())
        .collect::<Vec<_>>()
        .join(", ");
    let mut s = format!("F unsigned long long lanebits(m k) {{\n  k &= (m){{{powers}}};\n");
    let mut half = lanes / 2;
    while half > 0 {
        let rotated: Vec<String> = (0..lanes)
            .map(|l| ((l + half) % lanes).to_string())
            .collect();
        let _ = writeln!(
            s,
            "  k |= __builtin_shufflevector(k, k, {});",
            rotated.join(", ")
        );
        half /= 2;
    }
    s.push_str("  return (unsigned long long)(unsigned)k[0];\n}\n");
    s
}
