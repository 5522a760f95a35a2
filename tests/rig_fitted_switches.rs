//! Fitness runs of `rigs/tensile4.json` skip the switches that can no longer
//! reach the load cell (`src/compile/liveness.rs`): once the specimen breaks,
//! the slack adapter's contact and the specimen's yield are not located any
//! more. Checked on the f64 reference (`EventStepper`) against the program with
//! every switch, over candidates whose sliding bar bounces on the adapter
//! after the break: the skipped switches are exactly those after the break, and
//! the load-cell force differs only by RK4's error where a skipped switch
//! would have split a step.

use rigfit::compile::liveness::fitted_variant;
use rigfit::compile::{EventStepper, Program, Tape};
use rigfit::fixtures::{REFERENCE_DT, REFERENCE_SAMPLES};
use rigfit::model::compiled::CompiledRig;
use rigfit::model::tensile::{REFERENCE, ix};

/// Runs `prog` over the reference record, one step per sample: the load-cell
/// force (output 0) at every sample and the names of the switches taken, with
/// their times.
fn run(prog: &Program, p: &[f64]) -> (Vec<f64>, Vec<(String, f64)>) {
    let tape = Tape::new(prog);
    let mut st = EventStepper::new(prog, &tape, p, None);
    let mut y = st.y0.clone();
    let mut outs = vec![0.0; prog.outputs.len()];
    let mut full = vec![0.0; prog.full_state.len()];
    let mut force = Vec::with_capacity(REFERENCE_SAMPLES);
    let h = REFERENCE_DT;
    for i in 0..REFERENCE_SAMPLES {
        let t = i as f64 * h;
        st.report(t, &y, &mut outs, &mut full);
        force.push(outs[0]);
        st.step(t, h, &mut y);
    }
    assert!(!st.chattered);
    let fired = st
        .fired
        .iter()
        .map(|f| (prog.transitions[f.transition].name.clone(), f.t))
        .collect();
    (force, fired)
}

fn rel_rms(a: &[f64], b: &[f64]) -> f64 {
    let num: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
    let den: f64 = b.iter().map(|y| y * y).sum();
    (num / den).sqrt()
}

#[test]
fn fitness_runs_skip_only_the_switches_after_the_break() {
    let rig = CompiledRig::new(
        rigfit::rig::shipped("tensile4").unwrap(),
        "rigs/tensile4.json",
    )
    .unwrap();
    let prog = &rig.lowered.programs[0];
    let fit = fitted_variant(prog);
    let mut skipped_somewhere = 0;
    let mut worst: f64 = 0.0;
    for c4 in [1e3, 1e4, 1e5] {
        for gap in [0.0, 2.5e-5, 5e-5] {
            let mut p = REFERENCE;
            p[ix::C4] = c4;
            p[ix::GAP] = gap;
            let (f_all, all) = run(prog, &p);
            let (f_fit, taken) = run(&fit, &p);
            let broke = |list: &[(String, f64)]| {
                list.iter()
                    .find(|(n, _)| n == "specimen breaks")
                    .map(|&(_, t)| t)
                    .unwrap_or_else(|| panic!("no break in {list:?}"))
            };
            let tb = broke(&all);
            assert_eq!(broke(&taken), tb, "c4 {c4}, gap {gap}");
            // Up to the break both take the same switches at the same times;
            // after it the fitness run takes none.
            let before: Vec<_> = all.iter().filter(|(_, t)| *t <= tb).cloned().collect();
            assert_eq!(taken, before, "c4 {c4}, gap {gap}");
            let after = all.len() - before.len();
            skipped_somewhere += after;
            let d = rel_rms(&f_fit, &f_all);
            worst = worst.max(d);
            println!(
                "c4 {c4:e}, gap {gap:e}: {after} switches after the break skipped, load cell rel. RMS {d:.2e}"
            );
            if after == 0 {
                assert_eq!(f_fit, f_all, "the same steps give the same bits");
            }
            assert!(d <= 1e-9, "c4 {c4}, gap {gap}: {d:e}");
        }
    }
    // The cases include bounces of the bar on the adapter after the break.
    assert!(skipped_somewhere > 0);
    println!("worst rel. RMS {worst:.2e}");
}
