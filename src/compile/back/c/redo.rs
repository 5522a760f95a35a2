//! `rig_redo` ([`REDO`]): the steps of an f64 vector's lanes redone with
//! their switches located, for a program with switches and no tables.

use std::fmt::Write;

use super::statements::{list_fn, vector_ops};
use crate::compile::exec::lane_code::LaneCode;
use crate::compile::program::Direction;

/// The f64 vector arithmetic of [`REDO`] (its derivative and event functions
/// call it as `w…`, whatever the lanes' arithmetic), and its switches' tests.
const REDO_OPS: &str = include_str!("redo_ops.h");

/// Steps redone in C with their switches located (`rig_redo`), for the
/// lanes of one f64 vector ([`crate::compile::exec::lanes::LaneRunner`]
/// hands it those of its lanes past a switch):
/// [`crate::compile::exec::events::EventStepper`]'s `step_known` and
/// `locate_crossing` step for step in every lane, so each lane's bits are
/// the scalar reference's. The lanes go through the same loop together,
/// each with its own times, switches and search, a lane that is done kept
/// as it is by a mask: a rig driven through a switch takes its lanes past
/// it a few steps apart (the quarter car: 3.8 of 16 lanes in a step that
/// has any; with friction, 7.9), which one lane at a time took half of
/// their CPU jobs.
const REDO: &str = include_str!("redo.c");

/// Whether `rig_redo` is built for `code`: it has switches, and its
/// derivative and event functions read no table (whose values the caller
/// computes at each time).
pub fn redoes(code: &LaneCode) -> bool {
    !code.events.roots.is_empty() && code.deriv.tables.is_empty() && code.events.tables.is_empty()
}

/// `rig_redo` ([`REDO`]) for `code`, with its switches' tables (what arms
/// each, `armedw`; which way it fires, the regime register it sets and the
/// value), and its derivative and event functions on f64 vectors (`derivw`,
/// `eventsw`: the states from `x`, every other input from its row of `R`).
pub(super) fn redo(s: &mut String, code: &LaneCode) {
    use crate::compile::exec::events::{LOCATE_ITERATIONS, LOCATE_TOLERANCE, MAX_EVENTS_PER_STEP};
    let list = |v: Vec<String>| v.join(", ");
    let _ = writeln!(
        s,
        "#define NS {}\n#define NT {}\n#define MAX_EVENTS {MAX_EVENTS_PER_STEP}\n#define LOCATE_ITER {LOCATE_ITERATIONS}\n#define LOCATE_TOL {LOCATE_TOLERANCE:?}",
        code.slopes.len(),
        code.events.roots.len()
    );
    let _ = writeln!(
        s,
        "static const int DIR_UP[NT] = {{{}}};\nstatic const long MODE[NT] = {{{}}};\nstatic const double TO[NT] = {{{}}};",
        list(
            code.armed
                .iter()
                .map(|a| u8::from(a.2 == Direction::Up).to_string())
                .collect()
        ),
        list(code.armed.iter().map(|a| a.0.to_string()).collect()),
        list(code.sets.iter().map(|v| format!("{v:?}")).collect())
    );
    s.push_str("/* A row of the caller's register file: DW lanes, only 8-byte aligned. */\ntypedef double dr __attribute__((vector_size(VBYTES), aligned(8)));\n/* The lanes of R where transition i is armed: its variable at its value, its guard held. */\nstatic dm armedw(const dr *R, int i) {\n  switch (i) {\n");
    for (i, (&(mode, from, _), guard)) in code.armed.iter().zip(&code.guards).enumerate() {
        let guard: String = guard
            .iter()
            .map(|&(m, v)| format!(" & (R[{m}] == dsplat({v:?}))"))
            .collect();
        let _ = writeln!(
            s,
            "  case {i}: return (R[{mode}] == dsplat({from:?})){guard};"
        );
    }
    s.push_str("  }\n  return (dm){0};\n}\n");
    s.push_str(&vector_ops('w', "d", "dm", "dsplat", "dpick"));
    s.push_str(REDO_OPS);
    let states = code.slopes.len();
    for (name, list) in [("derivw", &code.deriv), ("eventsw", &code.events)] {
        let head = format!(
            "static __attribute__((noinline)) void {name}(const dr *restrict R, d t, const d *restrict x, d *restrict out) {{\n    (void)t; (void)x;"
        );
        list_fn(s, code, list, &head, ("d", 'w'), &|reg| {
            if reg == code.time {
                "t".to_string()
            } else if (reg as usize) < states {
                format!("x[{reg}]")
            } else {
                format!("R[{reg}]")
            }
        });
    }
    s.push_str(REDO);
}
