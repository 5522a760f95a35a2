//! `rigs/tensile4.json`, compiled, against the hand-written tensile model (the
//! oracle) and against itself at finer steps: where the two agree on the
//! physics they agree to rounding, the located switches (slack engagement,
//! yield, fracture) make the compiled run fourth order in dt, and the hand
//! model's unlocated ones leave it first order.

use std::ops::ControlFlow;

use rigfit::compile::liveness::fitted_variant;
use rigfit::compile::{EventStepper, Program, Tape};
use rigfit::fixtures::{REFERENCE_DT, REFERENCE_SAMPLES};
use rigfit::integrate::SampleGrid;
use rigfit::model::compiled::CompiledRig;
use rigfit::model::tensile::ix;
use rigfit::model::{Drive, PiecewiseLinear, RigModel, tensile};

fn compiled() -> CompiledRig {
    CompiledRig::new(
        rigfit::rig::shipped("tensile4").unwrap(),
        "rigs/tensile4.json",
    )
    .unwrap()
}

fn history(
    model: &dyn RigModel,
    p: &[f64],
    drive: &Drive,
    substeps: usize,
    out: usize,
) -> Vec<f64> {
    let grid = SampleGrid {
        t0: 0.0,
        dt: REFERENCE_DT,
        samples: REFERENCE_SAMPLES,
        substeps,
    };
    let mut h = Vec::with_capacity(grid.samples);
    model.simulate(p, drive, &grid, &mut |s| {
        h.push(s.outputs[out]);
        ControlFlow::Continue(())
    });
    h
}

fn rel_rms(a: &[f64], b: &[f64]) -> f64 {
    let num: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
    let den: f64 = b.iter().map(|y| y * y).sum();
    (num / den).sqrt()
}

#[test]
fn the_compiled_rig_has_the_hand_models_parameters() {
    let c = compiled();
    // The same parameters, except that only the hand-written model reads an
    // omitted e_fracture as "never breaks" (a JSON rig file cannot hold ∞).
    let strip = |p: &[rigfit::model::ParamInfo]| -> Vec<_> {
        p.iter()
            .map(|i| {
                (
                    i.name,
                    i.unit,
                    i.scope,
                    i.scale,
                    (i.name != "e_fracture").then_some(i.default),
                )
            })
            .collect()
    };
    assert_eq!(strip(c.params()), strip(tensile::TENSILE4.params()));
    assert_eq!(c.output_names(), tensile::TENSILE4.output_names());
    assert_eq!(c.state_names().len(), 8);
}

#[test]
fn without_switches_inside_the_run_both_models_agree_to_rounding() {
    // No gap, elastic throughout (e_yield and e_fracture out of reach): the only
    // switch is the slack engagement at t = 0, the same on both.
    let mut p = tensile::REFERENCE;
    p[tensile::ix::GAP] = 0.0;
    p[tensile::ix::E_YIELD] = 1.0;
    p[tensile::ix::E_FRACTURE] = 1.0;
    let hand = history(&tensile::TENSILE4, &p, &Drive::Velocity, 1, 0);
    let comp = history(&compiled(), &p, &Drive::Velocity, 1, 0);
    let e = rel_rms(&comp, &hand);
    println!("relative RMS difference {e:.3e}");
    assert!(e < 1e-12, "{e}");
}

#[test]
fn force_driven_runs_agree_with_the_hand_model() {
    let mut p = tensile::REFERENCE;
    p[tensile::ix::GAP] = 0.0;
    p[tensile::ix::E_YIELD] = 1.0;
    p[tensile::ix::E_FRACTURE] = 1.0;
    let drive = Drive::Force(PiecewiseLinear {
        t: vec![0.0, 1e-3, 2.5e-3],
        value: vec![0.0, 3e4, 3e4],
    });
    let hand = history(&tensile::TENSILE4, &p, &drive, 4, 0);
    let comp = history(&compiled(), &p, &drive, 4, 0);
    let e = rel_rms(&comp, &hand);
    println!("relative RMS difference {e:.3e}");
    assert!(e < 1e-10, "{e}");
}

/// Errors of the reference run at 1, 2, 4, 8 steps per sample against 256.
fn errors(model: &dyn RigModel) -> Vec<f64> {
    let p = tensile::REFERENCE;
    let fine = history(model, &p, &Drive::Velocity, 256, 0);
    [1, 2, 4, 8]
        .iter()
        .map(|&s| rel_rms(&history(model, &p, &Drive::Velocity, s, 0), &fine))
        .collect()
}

#[test]
fn located_switches_make_the_reference_run_fourth_order() {
    let e = errors(&compiled());
    let orders: Vec<f64> = e.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
    println!("compiled: errors {e:?}, orders {orders:.2?}");
    for o in &orders {
        assert!(*o >= 3.5, "order {o} (errors {e:?})");
    }
    assert!(
        e[0] <= 1e-5,
        "relative RMS error at the automatic step: {}",
        e[0]
    );
    // The hand model, with only fracture located, for the record.
    let h = errors(&tensile::TENSILE4);
    println!("hand-written: errors {h:?}");
    assert!(
        h[0] > 10.0 * e[0],
        "the located switches gain little: {h:?} vs {e:?}"
    );
}

#[test]
fn the_located_switches_fire_in_the_order_the_physics_says() {
    let c = compiled();
    let p = tensile::REFERENCE;
    let drive = Drive::Velocity;
    let mut st = c.stepper(&p, &drive).unwrap();
    let mut y = vec![0.0; 8];
    let h = REFERENCE_DT;
    for i in 0..REFERENCE_SAMPLES {
        st.step(i as f64 * h, h, &mut y);
    }
    let prog = &c.lowered.programs[0];
    let names: Vec<&str> = st
        .fired
        .iter()
        .map(|f| prog.transitions[f.transition].name.as_str())
        .collect();
    println!("{names:?}");
    let pos = |n: &str| {
        names
            .iter()
            .position(|x| *x == n)
            .unwrap_or_else(|| panic!("{n} never fired: {names:?}"))
    };
    assert!(pos("slack closes") < pos("specimen yields"));
    assert!(pos("specimen yields") < pos("specimen breaks"));
    assert!(!st.chattered);
    let tf = st.fired[pos("specimen breaks")].t;
    assert!((0.4e-3..=0.7e-3).contains(&tf), "fracture at {tf}");
}

// Fitness runs skip the switches that can no longer reach the load cell
// (src/compile/liveness.rs): once the specimen breaks, the slack adapter's
// contact and the specimen's yield are not located any more. Checked on the
// f64 reference against the program with every switch, over candidates whose
// sliding bar bounces on the adapter after the break: the skipped switches are
// exactly those after the break, and the load-cell force differs only by RK4's
// error where a skipped switch would have split a step.

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
            let mut p = tensile::REFERENCE;
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
