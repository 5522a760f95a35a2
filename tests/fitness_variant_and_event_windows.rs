//! What the analyses and the WGSL back end make of the shipped rigs' events:
//! fitness runs of `tensile4` skip the slack and yield events once the
//! specimen has broken (nothing after the break reaches the load cell), rigs
//! whose every event reaches output 0 keep every event, and the GPU kernels
//! test the events on one base (an elongation, an opening) against one
//! window.

use rigfit::compile::analysis::liveness::fitness_variant;
use rigfit::compile::{GpuRig, Program, lower};

fn program(id: &str) -> Program {
    let desc = rigfit::rig::shipped(id).expect("a shipped rig");
    lower(&desc, id).expect("lowers").programs[0].clone()
}

#[test]
fn the_broken_tensile_rig_skips_the_events_behind_the_break() {
    let prog = program("tensile4");
    let fit = fitness_variant(&prog);
    let fracture = prog
        .transitions
        .iter()
        .find(|t| t.name.contains("fracture") || t.name.contains("breaks"))
        .unwrap_or_else(|| panic!("a fracture event in {:#?}", prog.transitions));
    for (a, b) in prog.transitions.iter().zip(&fit.transitions) {
        assert!(a.guard.is_empty());
        if a.var == fracture.var {
            // The break itself still decides the load cell's damping.
            assert!(b.guard.is_empty(), "{}", b.name);
        } else {
            // Slack contact and yield: only while the specimen is whole.
            assert_eq!(b.guard, vec![(fracture.var, fracture.from)], "{}", b.name);
        }
    }
    // Same graph and roots: only the guards differ.
    assert_eq!(fit.graph.ops, prog.graph.ops);
    assert_eq!(fit.deriv, prog.deriv);
}

#[test]
fn an_event_that_always_reaches_the_output_keeps_no_guard() {
    // The slider's stick and slip set the friction force (output 0) in every
    // regime; the base-excited Duffing oscillator has no event.
    for id in ["stick_slip", "duffing_base", "quarter_car"] {
        let prog = program(id);
        assert_eq!(fitness_variant(&prog).transitions, prog.transitions, "{id}");
    }
}

#[test]
fn events_on_one_base_share_a_window() {
    let prog = program("tensile4");
    let src = GpuRig::new(&prog)
        .expect("emits")
        .source(&|v| format!("real({v:e})"));
    // Slack closing and opening on the adapter's gap; yield, its reverse and
    // fracture on the specimen's elongation.
    assert_eq!(prog.transitions.len(), 5);
    let eb = &src[src.find("struct EventBases {").expect("struct EventBases")..];
    assert_eq!(eb[..eb.find('}').unwrap()].matches(": real").count(), 2);
    let out = &src[src.find("fn rig_outside(").expect("rig_outside")..];
    let out = &out[..out.find('}').unwrap()];
    assert_eq!(out.matches("w.hi").count(), 2, "{out}");
    assert_eq!(out.matches("w.lo").count(), 2, "{out}");
    assert!(!out.contains("||"), "short-circuit test: {out}");
}
