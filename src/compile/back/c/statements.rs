//! One instruction, and one list of instructions, as C statements on the
//! register locals `rN`; a register's load from and store into its row.

use std::fmt::Write;

use crate::compile::exec::lane_code::{LaneCode, List, Reg};
use crate::compile::ir::{Id, Op, operands};

/// Rust's select, `<=`, `==` (1 or 0), `min` and `max` (a NaN operand gives
/// the other) on vectors of type `ty` with masks of type `mask`, as
/// `{p}sel`, `{p}le`, … built on the vectors' `splat` and `pick`: the lanes'
/// (`v…` on `v`) and the redo's (`w…` on the f64 `d`) from one text.
pub(super) fn vector_ops(p: char, ty: &str, mask: &str, splat: &str, pick: &str) -> String {
    format!(
        "F {ty} {p}sel({ty} c, {ty} a, {ty} b) {{ return {pick}(c != {splat}(0.0), a, b); }}
F {ty} {p}le({ty} a, {ty} b) {{ return ({ty})((a <= b) & ({mask}){splat}(1.0)); }}
F {ty} {p}eq({ty} a, {ty} b) {{ return ({ty})((a == b) & ({mask}){splat}(1.0)); }}
/* Rust's f64::min / f64::max: a NaN operand gives the other. */
F {ty} {p}min({ty} a, {ty} b) {{ {ty} r = {pick}(a < b, a, b); r = {pick}(a != a, b, r); return {pick}(b != b, a, r); }}
F {ty} {p}max({ty} a, {ty} b) {{ {ty} r = {pick}(a > b, a, b); r = {pick}(a != a, b, r); return {pick}(b != b, a, r); }}
"
    )
}

/// One instruction as a C statement on the register locals `rN`, with the
/// helpers for vectors (`p = 'v'`) or scalars (`'s'`).
pub(super) fn statement(dest: Reg, op: &Op, p: char) -> String {
    let r = |i: Id| format!("r{i}");
    let e = match *op {
        Op::Add(a, b) => format!("{} + {}", r(a), r(b)),
        Op::Sub(a, b) => format!("{} - {}", r(a), r(b)),
        Op::Mul(a, b) => format!("{} * {}", r(a), r(b)),
        Op::Div(a, b) => format!("{} / {}", r(a), r(b)),
        Op::Min(a, b) => format!("{p}min({}, {})", r(a), r(b)),
        Op::Max(a, b) => format!("{p}max({}, {})", r(a), r(b)),
        Op::Le(a, b) => format!("{p}le({}, {})", r(a), r(b)),
        Op::Eq(a, b) => format!("{p}eq({}, {})", r(a), r(b)),
        Op::Neg(a) => format!("-{}", r(a)),
        Op::Abs(a) => format!("{p}abs({})", r(a)),
        Op::Exp(a) => format!("{p}exp({})", r(a)),
        Op::Expm1(a) => format!("{p}expm1({})", r(a)),
        Op::Ln(a) => format!("{p}log({})", r(a)),
        Op::Sin(a) => format!("{p}sin({})", r(a)),
        Op::Cos(a) => format!("{p}cos({})", r(a)),
        Op::Select(c, a, b) => format!("{p}sel({}, {}, {})", r(c), r(a), r(b)),
        Op::Const(_) | Op::In(_) => unreachable!("registers filled before the list runs"),
    };
    format!("    r{dest} = {e};\n")
}

/// The registers `list` reads before it writes them (its inputs), in order.
pub(super) fn inputs(list: &List) -> Vec<Reg> {
    let mut written = std::collections::HashSet::new();
    let mut read = vec![];
    for ins in &list.code {
        for o in operands(&ins.op) {
            let o = o as Reg;
            if !written.contains(&o) && !read.contains(&o) {
                read.push(o);
            }
        }
        written.insert(ins.dest);
    }
    for &root in &list.roots {
        if !written.contains(&root) && !read.contains(&root) {
            read.push(root);
        }
    }
    read
}

/// Declares every register local the code uses, of type `ty`.
pub(super) fn declare(out: &mut String, code: &LaneCode, ty: &str) {
    let _ = writeln!(
        out,
        "    {ty} {};",
        (0..code.registers)
            .map(|i| format!("r{i}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    // Unread locals are fine; silence the compiler about them.
    let _ = writeln!(out, "    (void)r0;");
}

/// Loads input register `reg` of block `b`, unless it is the time or a table
/// (`time`: its C value; `tables`: register → C value).
pub(super) fn load(
    out: &mut String,
    reg: Reg,
    time: &str,
    code: &LaneCode,
    tables: &dyn Fn(Reg) -> Option<String>,
) {
    let src = if reg == code.time {
        format!("splat({time})")
    } else if let Some(t) = tables(reg) {
        format!("splat({t})")
    } else if packed(code, reg) {
        format!("LDP(R, {reg})")
    } else {
        format!("LD(R, {reg})")
    };
    let _ = writeln!(out, "    r{reg} = {src};");
}

/// Whether register `reg`'s row holds its lanes packed (as f32, at the
/// row's start, in [`super::Arith::F32`] code; as f64 rows otherwise): a state's or
/// a per-run constant's ([`crate::compile::exec::lanes::LaneRunner`] packs
/// them so).
fn packed(code: &LaneCode, reg: Reg) -> bool {
    (reg as usize) < code.slopes.len() || code.constants.iter().any(|&(_, r)| r == reg)
}

/// Stores register `reg` into its row.
pub(super) fn store(out: &mut String, code: &LaneCode, reg: Reg) {
    let st = if packed(code, reg) { "STP" } else { "ST" };
    let _ = writeln!(out, "    {st}(R, {reg}, r{reg});");
}

/// `list` as a C function of one run or one vector of runs: `head` (its
/// signature and opening), a local of type `ty.0` per register, each input
/// from `input`, the instructions with the helpers of prefix `ty.1`
/// ([`statement`]), and the roots into `out`.
pub(super) fn list_fn(
    s: &mut String,
    code: &LaneCode,
    list: &List,
    head: &str,
    ty: (&str, char),
    input: &dyn Fn(Reg) -> String,
) {
    let _ = writeln!(s, "{head}");
    declare(s, code, ty.0);
    for &reg in &inputs(list) {
        let _ = writeln!(s, "    r{reg} = {};", input(reg));
    }
    for ins in &list.code {
        s.push_str(&statement(ins.dest, &ins.op, ty.1));
    }
    for (i, &root) in list.roots.iter().enumerate() {
        let _ = writeln!(s, "    out[{i}] = r{root};");
    }
    s.push_str("}\n");
}
