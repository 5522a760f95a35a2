//! `rigs/tensile4.json`, compiled, against the hand-written oracle
//! (tests/oracle) and against itself at finer steps: where the two agree on the
//! physics they agree to rounding, the located switches (slack engagement,
//! yield, fracture) make the compiled run fourth order in dt, and the oracle's
//! unlocated ones leave it first order.

mod oracle;
mod tensile_common;

use std::ops::ControlFlow;

use oracle::tensile::{REFERENCE, ix};
use rigfit::base::SampleGrid;
use rigfit::base::{Drive, PiecewiseLinear};
use rigfit::compile::analysis::liveness::fitness_variant;
use rigfit::compile::{EventStepper, Program, Tape};
use rigfit::model::compiled::CompiledRig;
use rigfit::model::param_index;
use tensile_common::{REFERENCE_DT, REFERENCE_SAMPLES, tensile4};

fn compiled() -> &'static CompiledRig {
    tensile4()
}

/// The reference grid with `substeps` RK4 steps per sample.
fn grid(substeps: usize) -> SampleGrid {
    SampleGrid {
        t0: 0.0,
        dt: REFERENCE_DT,
        samples: REFERENCE_SAMPLES,
        substeps,
    }
}

/// Output `out` of the compiled rig at every sample of the reference grid.
fn history(p: &[f64], drive: &Drive, substeps: usize, out: usize) -> Vec<f64> {
    let grid = grid(substeps);
    let mut h = Vec::with_capacity(grid.samples);
    compiled().simulate(p, drive, &grid, &mut |s| {
        h.push(s.outputs[out]);
        ControlFlow::Continue(())
    });
    h
}

/// The same from the hand-written oracle.
fn oracle_history(p: &[f64], drive: &Drive, substeps: usize, out: usize) -> Vec<f64> {
    let grid = grid(substeps);
    let mut h = Vec::with_capacity(grid.samples);
    oracle::tensile::simulate(p, drive, &grid, |s| {
        h.push(s.outputs[out]);
        ControlFlow::Continue(())
    });
    h
}

fn rel_rms(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let num: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
    let den: f64 = b.iter().map(|y| y * y).sum();
    (num / den).sqrt()
}

#[test]
fn the_compiled_rig_has_the_oracles_parameters_outputs_and_states() {
    let c = compiled();
    // The oracle's parameter vector order (`ix`), name by name.
    let order = [
        ("m1", ix::M1),
        ("m2", ix::M2),
        ("m3", ix::M3),
        ("m4", ix::M4),
        ("k1", ix::K1),
        ("c1", ix::C1),
        ("c1_post", ix::C1_POST),
        ("k_lin", ix::K_LIN),
        ("e_yield", ix::E_YIELD),
        ("a0", ix::A0),
        ("a1", ix::A0 + 1),
        ("a2", ix::A0 + 2),
        ("a3", ix::A0 + 3),
        ("a4", ix::A0 + 4),
        ("a5", ix::A0 + 5),
        ("e_fracture", ix::E_FRACTURE),
        ("c2", ix::C2),
        ("k3", ix::K3),
        ("c3", ix::C3),
        ("slack_a", ix::SLACK_A),
        ("slack_b", ix::SLACK_B),
        ("slack_c", ix::SLACK_C),
        ("k4_lin", ix::K4_LIN),
        ("c4", ix::C4),
        ("gap", ix::GAP),
        ("velocity", ix::VELOCITY),
        ("ramp", ix::RAMP),
    ];
    assert_eq!(c.params().len(), REFERENCE.len());
    for (name, i) in order {
        assert_eq!(param_index(c, name), Some(i), "{name}");
    }
    // The oracle's outputs: load-cell force (fitted), then specimen force.
    let names: Vec<&str> = c.output_names().iter().map(|o| o.0.as_str()).collect();
    assert_eq!(names, ["load_cell_force", "specimen_force"]);
    assert!(c.output_names().iter().all(|o| o.1 == "N"));
    // The oracle's state: displacements y1..y4, then velocities v1..v4.
    assert_eq!(
        c.state_names(),
        [
            "x_load_cell",
            "x_specimen",
            "x_bar",
            "x_actuator",
            "v_load_cell",
            "v_specimen",
            "v_bar",
            "v_actuator"
        ]
    );
    assert!(c.check(&REFERENCE).is_ok());
}

#[test]
fn without_switches_inside_the_run_the_rig_and_the_oracle_agree_to_rounding() {
    // No gap, elastic throughout (e_yield and e_fracture out of reach): the only
    // switch is the slack engagement at t = 0, the same on both.
    let mut p = REFERENCE;
    p[ix::GAP] = 0.0;
    p[ix::E_YIELD] = 1.0;
    p[ix::E_FRACTURE] = 1.0;
    for out in [0, 1] {
        let hand = oracle_history(&p, &Drive::Velocity, 1, out);
        let comp = history(&p, &Drive::Velocity, 1, out);
        let e = rel_rms(&comp, &hand);
        println!("output {out}: relative RMS difference {e:.3e}");
        assert!(e < 1e-12, "output {out}: {e}");
    }
}

#[test]
fn force_driven_runs_agree_with_the_oracle() {
    let mut p = REFERENCE;
    p[ix::GAP] = 0.0;
    p[ix::E_YIELD] = 1.0;
    p[ix::E_FRACTURE] = 1.0;
    let drive = Drive::Force(PiecewiseLinear {
        t: vec![0.0, 1e-3, 2.5e-3],
        value: vec![0.0, 3e4, 3e4],
    });
    let hand = oracle_history(&p, &drive, 4, 0);
    let comp = history(&p, &drive, 4, 0);
    let e = rel_rms(&comp, &hand);
    println!("relative RMS difference {e:.3e}");
    assert!(e < 1e-10, "{e}");
}

/// Errors of the reference run at 1, 2, 4, 8 steps per sample against 256.
fn errors(run: impl Fn(&[f64], &Drive, usize, usize) -> Vec<f64>) -> Vec<f64> {
    let p = REFERENCE;
    let fine = run(&p, &Drive::Velocity, 256, 0);
    [1, 2, 4, 8]
        .iter()
        .map(|&s| rel_rms(&run(&p, &Drive::Velocity, s, 0), &fine))
        .collect()
}

#[test]
fn located_switches_make_the_reference_run_fourth_order() {
    let e = errors(history);
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
    // The oracle, with only fracture located, for the record.
    let h = errors(oracle_history);
    println!("hand-written oracle: errors {h:?}");
    assert!(
        h[0] > 10.0 * e[0],
        "the located switches gain little: {h:?} vs {e:?}"
    );
}

#[test]
fn the_located_switches_fire_in_the_order_the_physics_says() {
    let c = compiled();
    let p = REFERENCE;
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
// (src/compile/analysis/liveness.rs): once the specimen breaks, the slack adapter's
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
    let rig = compiled();
    let prog = &rig.lowered.programs[0];
    let fit = fitness_variant(prog);
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
