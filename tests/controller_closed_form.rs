//! A held (sampled, zero-order-hold) controller against its exact solution,
//! and the CPU lanes against the f64 reference on controlled rigs.
//!
//! The mass of `tests/rigs/held_pd.json` feels only its controller's force,
//! which is constant between sample instants, so over each piece the exact
//! solution is the double integrator's step: `x += v·τ + u·τ²/(2m)`,
//! `v += u·τ/m` (the matrix exponential of one period with the held input).
//! RK4 integrates that polynomial exactly, so the rig must match it to
//! rounding, at one step per sample and at a period of 0.7 samples, whose
//! instants fall inside steps.

use std::ops::ControlFlow;

use rigfit::base::{Drive, Report, SampleGrid};
use rigfit::model::compiled::CompiledRig;
use rigfit::rig::desc::RigDesc;

fn rig_desc(file: &str) -> RigDesc {
    let path = format!("{}/tests/rigs/{file}", env!("CARGO_MANIFEST_DIR"));
    serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap()
}

const M: f64 = 2.0;
const KP: f64 = 400.0;
const KD: f64 = 12.0;
const X0: f64 = 0.01;

/// The exact held PD loop at period `p`: position and command at every time
/// of `times` (the command as set at the last instant at or before it).
fn exact(p: f64, times: &[f64]) -> Vec<(f64, f64)> {
    let (mut x, mut v, mut x_prev, mut u) = (X0, 0.0, X0, 0.0);
    let mut tk = 0.0;
    let mut k = 0u64;
    let mut out = vec![];
    for &t in times {
        // Every instant up to t (within rounding), the state carried exactly.
        while (k as f64) * p <= t + 1e-9 * p {
            let t_next = k as f64 * p;
            let tau = t_next - tk;
            x += v * tau + u * tau * tau / (2.0 * M);
            v += u * tau / M;
            tk = t_next;
            let u_new = -KP * x - KD * (x - x_prev) / p;
            x_prev = x;
            u = u_new;
            k += 1;
        }
        let tau = t - tk;
        out.push((x + v * tau + u * tau * tau / (2.0 * M), u));
    }
    out
}

fn simulate(desc: RigDesc, grid: &SampleGrid) -> Vec<(f64, f64)> {
    let r = CompiledRig::new(desc, "held_pd").unwrap();
    let p = vec![M, KP, KD, X0];
    let mut out = vec![];
    r.simulate(&p, &Drive::Velocity, grid, &mut |s| {
        out.push((s.outputs[0], s.outputs[1]));
        ControlFlow::Continue(())
    });
    out
}

fn worst(got: &[(f64, f64)], want: &[(f64, f64)]) -> (f64, f64) {
    let xs = want.iter().map(|w| w.0.abs()).fold(0.0, f64::max);
    let us = want.iter().map(|w| w.1.abs()).fold(0.0, f64::max);
    got.iter().zip(want).fold((0.0, 0.0), |(ex, eu), (g, w)| {
        (
            f64::max(ex, (g.0 - w.0).abs() / xs),
            f64::max(eu, (g.1 - w.1).abs() / us),
        )
    })
}

#[test]
fn a_held_pd_loop_matches_its_exact_discrete_solution_at_one_step_per_sample() {
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-3,
        samples: 400,
        substeps: 1,
    };
    let got = simulate(rig_desc("held_pd.json"), &grid);
    let times: Vec<f64> = (0..grid.samples).map(|k| grid.time(k)).collect();
    let want = exact(1e-3, &times);
    // The loop rings down: the position changes sign and decays.
    assert!(want.iter().any(|w| w.0 < -1e-3), "no overshoot");
    let (ex, eu) = worst(&got, &want);
    assert!(
        ex <= 1e-10 && eu <= 1e-10,
        "position {ex:e}, command {eu:e}"
    );
}

#[test]
fn a_period_of_seven_tenths_of_a_sample_hits_its_instants_exactly() {
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-3,
        samples: 300,
        substeps: 1,
    };
    let mut desc = rig_desc("held_pd.json");
    desc.controllers[0].period = 0.7e-3;
    let got = simulate(desc, &grid);
    let times: Vec<f64> = (0..grid.samples).map(|k| grid.time(k)).collect();
    let want = exact(0.7e-3, &times);
    let (ex, eu) = worst(&got, &want);
    assert!(
        ex <= 1e-10 && eu <= 1e-10,
        "position {ex:e}, command {eu:e}"
    );
    // Taken at whole steps instead, the instants would be up to 0.3 ms
    // late: the same test fails by far more than its tolerance.
    let late = exact(1e-3, &times);
    assert!(worst(&late, &want).0 > 1e-3);
}

#[test]
fn ten_instants_in_every_step_are_each_taken() {
    // A controller ten times faster than the record: each 1 ms step is cut
    // into ten pieces (none of them a located switch).
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-3,
        samples: 200,
        substeps: 1,
    };
    let mut desc = rig_desc("held_pd.json");
    desc.controllers[0].period = 1e-4;
    let got = simulate(desc, &grid);
    let times: Vec<f64> = (0..grid.samples).map(|k| grid.time(k)).collect();
    let want = exact(1e-4, &times);
    let (ex, eu) = worst(&got, &want);
    assert!(
        ex <= 1e-10 && eu <= 1e-10,
        "position {ex:e}, command {eu:e}"
    );
}

/// Every output and state of every run, as bits.
fn histories(r: &CompiledRig, ps: &[Vec<f64>], grid: &SampleGrid, many: bool) -> Vec<Vec<u64>> {
    driven_histories(r, ps, &Drive::Velocity, grid, many)
}

/// [`histories`] under `drive`.
fn driven_histories(
    r: &CompiledRig,
    ps: &[Vec<f64>],
    drive: &Drive,
    grid: &SampleGrid,
    many: bool,
) -> Vec<Vec<u64>> {
    if many {
        let refs: Vec<&[f64]> = ps.iter().map(|p| p.as_slice()).collect();
        let mut h = vec![vec![]; ps.len()];
        r.simulate_many(&refs, drive, grid, Report::Full, &mut |l, s| {
            h[l].extend(s.outputs.iter().chain(s.state).map(|v| v.to_bits()));
            ControlFlow::Continue(())
        });
        h
    } else {
        ps.iter()
            .map(|p| {
                let mut h = vec![];
                r.simulate(p, drive, grid, &mut |s| {
                    h.extend(s.outputs.iter().chain(s.state).map(|v| v.to_bits()));
                    ControlFlow::Continue(())
                });
                h
            })
            .collect()
    }
}

#[test]
fn lanes_match_the_reference_on_a_held_controller_with_stick_slip() {
    // Sample instants every 0.7 ms and stick-slip switches in the same
    // steps; nine candidates (a full block of eight and one more).
    let r = CompiledRig::new(rig_desc("held_stick_slip.json"), "held_stick_slip").unwrap();
    let base: Vec<f64> = r.params().iter().map(|p| p.default.unwrap()).collect();
    let ps: Vec<Vec<f64>> = (0..9)
        .map(|i| {
            let mut p = base.clone();
            p[1] *= 1.0 + 0.1 * i as f64;
            p[3] *= 1.0 - 0.05 * i as f64;
            p
        })
        .collect();
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-3,
        samples: 1200,
        substeps: 2,
    };
    let one = histories(&r, &ps, &grid, false);
    let many = histories(&r, &ps, &grid, true);
    for (i, (a, b)) in many.iter().zip(&one).enumerate() {
        assert!(a == b, "candidate {i} differs");
    }
    // The run both sticks and slips, and its command saturates.
    let drive = Drive::Velocity;
    let mut st = r.stepper(&ps[0], &drive).unwrap();
    let mut y = st.y0.clone();
    let h = grid.step();
    let mut saturated = false;
    for i in 0..(grid.samples - 1) * grid.substeps {
        st.step(i as f64 * h, h, &mut y);
        saturated |= st.held[1].abs() == 12.0;
    }
    assert!(st.fired.len() > 8, "{} switches", st.fired.len());
    assert!(saturated, "the command never saturates");
}

/// Every run of `ps` through the lane code of `desc`'s program for `drive`,
/// on vector instructions `isa`, or built to native f64 code.
fn lane_histories(
    desc: &RigDesc,
    ps: &[Vec<f64>],
    drive: &Drive,
    grid: &SampleGrid,
    isa: Option<rigfit::compile::Isa>,
) -> Vec<Vec<u64>> {
    use rigfit::compile::{Arith, LANES, LaneCode, LaneRunner, Native, Tape};
    let lowered = rigfit::compile::lower(desc, "lanes").unwrap();
    let mode = match drive {
        Drive::Velocity => "velocity",
        Drive::Force(_) => "force",
    };
    let prog = lowered.programs.iter().find(|p| p.mode == mode).unwrap();
    let tape = Tape::new(prog);
    let code = LaneCode::new(prog, &tape);
    let native = match isa {
        Some(_) => None,
        // No C compiler here is a failure, not a skip.
        None => {
            Some(Native::build(&code, Arith::F64).expect("the C compiler builds the lane code"))
        }
    };
    let mut many = vec![vec![]; ps.len()];
    for (c, chunk) in ps.chunks(LANES).enumerate() {
        let refs: Vec<&[f64]> = chunk.iter().map(|p| p.as_slice()).collect();
        let runner = LaneRunner::new(prog, &tape, &code, &refs, drive.force_table());
        let mut runner = match (&native, isa) {
            (Some(n), _) => runner.with_native(n),
            (None, Some(isa)) => runner.with_isa(isa),
            (None, None) => unreachable!(),
        };
        runner.run(grid, Report::Full, &mut |l, s| {
            many[c * LANES + l].extend(s.outputs.iter().chain(s.state).map(|v| v.to_bits()));
            ControlFlow::Continue(())
        });
    }
    many
}

#[test]
fn every_lane_path_matches_the_reference_bit_for_bit_on_controlled_rigs() {
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-3,
        samples: 800,
        substeps: 2,
    };
    let mut pd_07 = rig_desc("held_pd.json");
    pd_07.controllers[0].period = 0.7e-3;
    // The EMPS drive under its held controller, following a reference that
    // starts at 0.1 m/s and reverses (the Coulomb term switching sign).
    let emps = rigfit::rig::shipped("emps").unwrap();
    let t: Vec<f64> = (0..=800).map(|i| i as f64 * 1e-3).collect();
    let qg: Vec<f64> = t.iter().map(|&t| 0.02 * (7.0 * t).sin()).collect();
    let reference = Drive::Force(rigfit::base::PiecewiseLinear { t, value: qg });
    for (desc, drive) in [
        (rig_desc("held_stick_slip.json"), Drive::Velocity),
        (pd_07, Drive::Velocity),
        (emps, reference),
    ] {
        let r = CompiledRig::new(desc.clone(), "lanes").unwrap();
        let base: Vec<f64> = r
            .params()
            .iter()
            .map(|p| match (desc.id.as_str(), p.name.as_str()) {
                ("emps", "m") => 95.0,
                ("emps", "f_v") => 200.0,
                ("emps", "f_c") => 20.0,
                _ => p.default.unwrap(),
            })
            .collect();
        let ps: Vec<Vec<f64>> = (0..11)
            .map(|i| {
                let mut p = base.clone();
                p[0] *= 1.0 + 0.07 * i as f64;
                p
            })
            .collect();
        let one = driven_histories(&r, &ps, &drive, &grid, false);
        let mut paths: Vec<Option<rigfit::compile::Isa>> = rigfit::compile::Isa::available()
            .into_iter()
            .map(Some)
            .collect();
        paths.push(None);
        for isa in paths {
            let many = lane_histories(&desc, &ps, &drive, &grid, isa);
            for (i, (a, b)) in many.iter().zip(&one).enumerate() {
                assert!(
                    a == b,
                    "{}, {isa:?} (None: native): candidate {i} differs",
                    desc.id
                );
            }
        }
    }
}

/// The f32 native lanes keep each state as f32 in its row: what reads those
/// rows (the full report, output 0 for the fitness, a controller's update
/// that samples a state) reads them as f32, and the held PD loop (whose
/// output 0 is a state and whose update samples it) stays within the f32
/// tolerance the GPU's f32 kernels are held to of its exact solution.
#[test]
fn native_f32_lanes_hold_a_sampled_loop_to_the_f32_tolerance() {
    use rigfit::compile::{Arith, LaneCode, LaneRunner, Native, Tape};
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-3,
        samples: 400,
        substeps: 1,
    };
    let desc = rig_desc("held_pd.json");
    let lowered = rigfit::compile::lower(&desc, "held_pd").unwrap();
    let prog = lowered
        .programs
        .iter()
        .find(|p| p.mode == "velocity")
        .unwrap();
    let tape = Tape::new(prog);
    let code = LaneCode::new(prog, &tape);
    // No C compiler here is a failure, not a skip.
    let native = Native::build(&code, Arith::F32).expect("the C compiler builds the lane code");
    let p = [M, KP, KD, X0];
    let runs = [&p[..]; 3];
    let times: Vec<f64> = (0..grid.samples).map(|k| grid.time(k)).collect();
    let want = exact(1e-3, &times);
    let mut full = vec![vec![]; runs.len()];
    LaneRunner::new(prog, &tape, &code, &runs, None)
        .with_native(&native)
        .run(&grid, Report::Full, &mut |l, s| {
            full[l].push((s.outputs[0], s.outputs[1]));
            ControlFlow::Continue(())
        });
    let mut measured = vec![vec![]; runs.len()];
    LaneRunner::new(prog, &tape, &code, &runs, None)
        .with_native(&native)
        .run_measured(&grid, &mut |s, _| {
            for (l, &v) in s.values.iter().enumerate() {
                measured[l].push((v, full[l][s.index].1));
            }
        });
    for l in 0..runs.len() {
        let (ex, eu) = worst(&full[l], &want);
        assert!(
            ex <= 2e-4 && eu <= 2e-4,
            "run {l}: position {ex:e}, command {eu:e}"
        );
        // f32 arithmetic, not f64 under another name.
        assert!(ex > 1e-9, "run {l}: position {ex:e}");
        // Output 0 for the fitness is the full report's output 0.
        let (em, _) = worst(&measured[l], &full[l]);
        assert!(em <= 1e-12, "run {l}: output 0 for the fitness {em:e}");
    }
}
