//! The lane-batched CPU ensemble of a compiled rig gives every run the same
//! bits as the scalar f64 reference, switches and all, whatever the lane count
//! of the last group.
mod oracle;
mod tensile_common;

use std::ops::ControlFlow;

use rigfit::base::SampleGrid;
use rigfit::base::{Drive, Report};
use rigfit::compile::{Arith, Isa, LANES, LaneCode, LaneRunner, Native, Tape};
use rigfit::model::compiled::CompiledRig;
use rigfit::rig::desc::{DriveLaw, TableDesc};
use tensile_common::REFERENCE_DT;
use tensile_common::{REFERENCE, ix};

fn histories_many(
    r: &CompiledRig,
    ps: &[Vec<f64>],
    drive: &Drive,
    grid: &SampleGrid,
) -> Vec<Vec<u64>> {
    let refs: Vec<&[f64]> = ps.iter().map(|p| p.as_slice()).collect();
    let mut h = vec![vec![]; ps.len()];
    r.simulate_many(&refs, drive, grid, Report::Full, &mut |l, s| {
        h[l].extend(s.outputs.iter().chain(s.state).map(|v| v.to_bits()));
        ControlFlow::Continue(())
    });
    h
}

fn histories_one(
    r: &CompiledRig,
    ps: &[Vec<f64>],
    drive: &Drive,
    grid: &SampleGrid,
) -> Vec<Vec<u64>> {
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

#[test]
fn tensile_lanes_match_the_scalar_reference_bit_for_bit() {
    let r = CompiledRig::new(rigfit::rig::shipped("tensile4").unwrap(), "tensile4").unwrap();
    // Eleven candidates (a full group of eight and a partial one), spread so the
    // slack engages, the specimen yields and breaks at different steps.
    let ps: Vec<Vec<f64>> = (0..11)
        .map(|i| {
            let mut p = REFERENCE.to_vec();
            let f = 1.0 + 0.05 * i as f64;
            p[ix::K1] *= f;
            p[ix::GAP] *= f;
            p[ix::E_FRACTURE] *= 2.0 - f;
            p
        })
        .collect();
    let grid = SampleGrid {
        t0: 0.0,
        dt: REFERENCE_DT,
        samples: 1500,
        substeps: 1,
    };
    let many = histories_many(&r, &ps, &Drive::Velocity, &grid);
    let one = histories_one(&r, &ps, &Drive::Velocity, &grid);
    assert_eq!(many.len(), 11);
    for (i, (a, b)) in many.iter().zip(&one).enumerate() {
        assert_eq!(a.len(), b.len());
        assert!(a == b, "candidate {i} differs");
    }
}

/// The shipped stick-slip rig driven by a 1 Hz, 20 N sine force table: a
/// slow sine, so the slider sticks and slips many times.
fn stick_slip_under_a_sine() -> rigfit::rig::desc::RigDesc {
    let mut desc = rigfit::rig::shipped("stick_slip").unwrap();
    let (t, f): (Vec<f64>, Vec<f64>) = (0..=400)
        .map(|i| {
            let t = i as f64 * 0.005;
            (t, 20.0 * (2.0 * std::f64::consts::PI * t).sin())
        })
        .unzip();
    desc.drives[0].law = DriveLaw::ForceTable(TableDesc {
        t: Some(t),
        value: Some(f),
        gain: None,
    });
    desc
}

#[test]
fn stick_slip_lanes_match_the_scalar_reference_through_many_events() {
    let desc = stick_slip_under_a_sine();
    let r = CompiledRig::new(desc, "stick_slip").unwrap();
    let ps: Vec<Vec<f64>> = (0..5)
        .map(|i| vec![1.0, 8.0 + i as f64, 1e4, 0.5 * i as f64])
        .collect();
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-3,
        samples: 2000,
        substeps: 2,
    };
    assert_eq!(
        histories_many(&r, &ps, &Drive::Velocity, &grid),
        histories_one(&r, &ps, &Drive::Velocity, &grid)
    );
}

#[test]
fn full_and_partial_groups_on_every_vector_width_match_the_scalar_reference() {
    let desc = rigfit::rig::shipped("tensile4").unwrap();
    let r = CompiledRig::new(desc.clone(), "tensile4").unwrap();
    let lowered = rigfit::compile::lower(&desc, "tensile4").unwrap();
    let prog = &lowered.programs[0];
    assert_eq!(prog.mode, "velocity");
    let tape = Tape::new(prog);
    let code = LaneCode::new(prog, &tape);
    // A full group whose lanes differ in two parameters (the rest, and every
    // value computed from them alone, shared), then a partial group of
    // identical runs (every per-run value shared).
    let mut ps: Vec<Vec<f64>> = (0..LANES)
        .map(|i| {
            let mut p = REFERENCE.to_vec();
            let f = 1.0 + 0.3 * i as f64 / LANES as f64;
            p[ix::K1] *= f;
            p[ix::GAP] *= f;
            p
        })
        .collect();
    ps.extend(std::iter::repeat_n(REFERENCE.to_vec(), 11));
    let grid = SampleGrid {
        t0: 0.0,
        dt: REFERENCE_DT,
        samples: 1200,
        substeps: 1,
    };
    let one = histories_one(&r, &ps, &Drive::Velocity, &grid);
    // Output 0 alone, as the fitness asks for it.
    let outputs = r.output_names().len();
    let width = outputs + r.state_names().len();
    let fitted: Vec<Vec<u64>> = one
        .iter()
        .map(|h| h.chunks(width).map(|s| s[0]).collect())
        .collect();
    let isas = Isa::available();
    assert!(isas.contains(&Isa::Base));
    for isa in isas {
        for (report, want) in [(Report::Full, &one), (Report::Measured, &fitted)] {
            let mut many = vec![vec![]; ps.len()];
            for (c, chunk) in ps.chunks(LANES).enumerate() {
                let refs: Vec<&[f64]> = chunk.iter().map(|p| p.as_slice()).collect();
                LaneRunner::new(prog, &tape, &code, &refs, None)
                    .with_isa(isa)
                    .run(&grid, report, &mut |l, s| {
                        many[c * LANES + l]
                            .extend(s.outputs.iter().chain(s.state).map(|v| v.to_bits()));
                        ControlFlow::Continue(())
                    });
            }
            for (i, (a, b)) in many.iter().zip(want).enumerate() {
                assert!(a == b, "{isa:?}, {report:?}: candidate {i} differs");
            }
        }
    }
}

#[test]
fn the_measured_report_is_output_zero_of_the_full_one() {
    let r = CompiledRig::new(rigfit::rig::shipped("tensile4").unwrap(), "tensile4").unwrap();
    assert!(r.output_names().len() > 1, "a rig with more than output 0");
    let ps: Vec<Vec<f64>> = (0..9)
        .map(|i| {
            let mut p = REFERENCE.to_vec();
            p[ix::E_FRACTURE] *= 1.0 - 0.04 * i as f64;
            p
        })
        .collect();
    let refs: Vec<&[f64]> = ps.iter().map(|p| p.as_slice()).collect();
    let grid = SampleGrid {
        t0: 0.0,
        dt: REFERENCE_DT,
        samples: 1500,
        substeps: 2,
    };
    // Each report by the lanes.
    for m in [&r] {
        let mut got = [vec![vec![]; ps.len()], vec![vec![]; ps.len()]];
        for (h, report) in got.iter_mut().zip([Report::Full, Report::Measured]) {
            m.simulate_many(&refs, &Drive::Velocity, &grid, report, &mut |l, s| {
                if report == Report::Measured {
                    assert_eq!((s.outputs.len(), s.state.len()), (1, 0));
                }
                h[l].push(s.outputs[0].to_bits());
                ControlFlow::Continue(())
            });
        }
        assert_eq!(got[0].len(), ps.len());
        assert_eq!(got[0][0].len(), grid.samples);
        assert_eq!(got[0], got[1], "{}", m.id());
        // The same values a group at a time (`simulate_measured`, f64), with a
        // run stopped after 100 samples and the rest left to the end.
        let mut grouped = vec![vec![]; ps.len()];
        let ran_f32 = m.simulate_measured(&refs, &Drive::Velocity, &grid, false, &mut |s, live| {
            for (j, v) in s.values.iter().enumerate() {
                if *live >> j & 1 == 1 {
                    grouped[s.first + j].push(v.to_bits());
                }
            }
            if s.index == 99 && (s.first..s.first + s.values.len()).contains(&4) {
                *live &= !(1 << (4 - s.first));
            }
        });
        assert!(!ran_f32);
        for (i, (a, b)) in grouped.iter().zip(&got[1]).enumerate() {
            let n = if i == 4 { 100 } else { grid.samples };
            assert_eq!(a.len(), n, "{} run {i}", m.id());
            assert_eq!(a[..], b[..n], "{} run {i}", m.id());
        }
    }
}

/// Every run of `ps` through the lane code of `desc`'s program for `force`'s
/// drive (velocity without one), built to native code, each output and state
/// as bits, as `report` asks.
fn histories_native(
    desc: &rigfit::rig::desc::RigDesc,
    ps: &[Vec<f64>],
    force: Option<&rigfit::base::PiecewiseLinear>,
    grid: &SampleGrid,
    report: Report,
) -> Vec<Vec<u64>> {
    let lowered = rigfit::compile::lower(desc, "native").unwrap();
    let mode = if force.is_some() { "force" } else { "velocity" };
    let prog = lowered.programs.iter().find(|p| p.mode == mode).unwrap();
    let tape = Tape::new(prog);
    let code = LaneCode::new(prog, &tape);
    // No C compiler here is a failure, not a skip.
    let native = Native::build(&code, Arith::F64).expect("the C compiler builds the lane code");
    let mut many = vec![vec![]; ps.len()];
    for (c, chunk) in ps.chunks(LANES).enumerate() {
        let refs: Vec<&[f64]> = chunk.iter().map(|p| p.as_slice()).collect();
        LaneRunner::new(prog, &tape, &code, &refs, force)
            .with_native(&native)
            .run(grid, report, &mut |l, s| {
                many[c * LANES + l].extend(s.outputs.iter().chain(s.state).map(|v| v.to_bits()));
                ControlFlow::Continue(())
            });
    }
    many
}

#[test]
fn native_lanes_match_the_scalar_reference_bit_for_bit() {
    let desc = rigfit::rig::shipped("tensile4").unwrap();
    let r = CompiledRig::new(desc.clone(), "tensile4").unwrap();
    // A full group with the drive shared (its time-only part computed once
    // per step), then a partial one whose ramps differ (computed per block).
    let ps: Vec<Vec<f64>> = (0..LANES + 13)
        .map(|i| {
            let mut p = REFERENCE.to_vec();
            let f = 1.0 + 0.3 * i as f64 / LANES as f64;
            p[ix::K1] *= f;
            p[ix::GAP] *= f;
            p[ix::E_FRACTURE] *= 2.0 - f;
            if i >= LANES {
                p[ix::RAMP] *= f;
            }
            p
        })
        .collect();
    let grid = SampleGrid {
        t0: 0.0,
        dt: REFERENCE_DT,
        samples: 1500,
        substeps: 1,
    };
    let one = histories_one(&r, &ps, &Drive::Velocity, &grid);
    let width = r.output_names().len() + r.state_names().len();
    let fitted: Vec<Vec<u64>> = one
        .iter()
        .map(|h| h.chunks(width).map(|s| s[0]).collect())
        .collect();
    for (report, want) in [(Report::Full, &one), (Report::Measured, &fitted)] {
        let many = histories_native(&desc, &ps, None, &grid, report);
        for (i, (a, b)) in many.iter().zip(want).enumerate() {
            assert_eq!(a.len(), b.len());
            assert!(a == b, "{report:?}: candidate {i} differs");
        }
    }
}

#[test]
fn native_stick_slip_lanes_match_through_many_events() {
    // A force table (a table input) and many stick–slip switches.
    let desc = stick_slip_under_a_sine();
    let r = CompiledRig::new(desc.clone(), "stick_slip").unwrap();
    let ps: Vec<Vec<f64>> = (0..9)
        .map(|i| vec![1.0, 8.0 + i as f64, 1e4, 0.5 * i as f64])
        .collect();
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-3,
        samples: 2000,
        substeps: 2,
    };
    let one = histories_one(&r, &ps, &Drive::Velocity, &grid);
    assert_eq!(histories_native(&desc, &ps, None, &grid, Report::Full), one);
}

#[test]
fn native_power_law_lanes_match_the_scalar_reference_bit_for_bit() {
    // The inertial rig's power laws, `|x|^β` as `exp(β·ln|x|)`, with β and α
    // different in every lane, so `ln` runs per lane in the vector code (the
    // branch-free form) and per run in the reference: the same bits. The
    // parameters are the shipped record's truth, spread.
    let desc = rigfit::rig::shipped("inertial_sdof").unwrap();
    let r = CompiledRig::new(desc.clone(), "inertial_sdof").unwrap();
    let truth = [
        9.0, 352.38, -61700.0, 365.17, 0.64, 1.41e6, 8.66e12, -8.74e8, 1.81, 11.768, 5.0, 12.5,
    ];
    let ps = spread(&truth, LANES + 5, &[(4, 0.6, 0.1), (8, 1.78, 0.06)]);
    let grid = SampleGrid {
        t0: 0.0,
        dt: 5e-4,
        samples: 1500,
        substeps: 8,
    };
    let one = histories_one(&r, &ps, &Drive::Velocity, &grid);
    assert_same_bits(
        &histories_native(&desc, &ps, None, &grid, Report::Full),
        &one,
    );
    // Every value finite (a NaN's sign is not compared), and the runs
    // moved: a history that is all zeros would agree vacuously.
    assert!(one.iter().flatten().all(|&b| f64::from_bits(b).is_finite()));
    let moved = one[3].iter().filter(|&&b| f64::from_bits(b) != 0.0).count();
    assert!(moved > one[3].len() / 2, "{moved} of {}", one[3].len());
}

/// `runs` copies of `base`, each parameter `(index, from, span)` of `varied`
/// set to `from + span · run / LANES`, so every lane of a full group differs.
fn spread(base: &[f64], runs: usize, varied: &[(usize, f64, f64)]) -> Vec<Vec<f64>> {
    (0..runs)
        .map(|i| {
            let mut p = base.to_vec();
            for &(k, from, span) in varied {
                p[k] = from + span * (i as f64 / LANES as f64);
            }
            p
        })
        .collect()
}

/// `many` differs from `want` nowhere; else where it first does.
fn assert_same_bits(many: &[Vec<u64>], want: &[Vec<u64>]) {
    for (i, (a, b)) in many.iter().zip(want).enumerate() {
        assert_eq!(a.len(), b.len());
        let first = a.iter().zip(b).position(|(x, y)| x != y);
        assert!(
            first.is_none(),
            "candidate {i} differs first at value {first:?}: {:?} against {:?}",
            first.map(|k| f64::from_bits(a[k])),
            first.map(|k| f64::from_bits(b[k]))
        );
    }
}

#[test]
fn native_trig_drive_lanes_match_the_scalar_reference_bit_for_bit() {
    // A sine and a chirp whose frequencies differ in every lane, so `sin`
    // and `cos` run per lane in the vector code (the branch-free forms) and
    // per run in the reference, through the friction rig's stick-slip and
    // the quarter car's lift-off and backlash. One friction lane's phase
    // passes 10⁶ half-way, where both take the C library's `sin`.
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-3,
        samples: 1500,
        substeps: 4,
    };
    let friction = [5.0, 6.4e4, 20.0, 10.0, 1.6e6, 30.0, 10.0];
    let mut ps = spread(&friction, LANES + 3, &[(6, 8.0, 4.0)]);
    ps[5][6] = 1e6 / (2.0 * std::f64::consts::PI * 0.75);
    let quarter_car = [
        40.0, 350.0, 1.751e5, 1751.0, 3.0e4, 2500.0, 800.0, 0.01, 2.0e4, 3.0e-4, 5e-4, 1.0, 2.8,
    ];
    let qs = spread(&quarter_car, LANES + 3, &[(11, 1.0, 20.0), (12, 2.0, 60.0)]);
    for (rig, ps) in [("friction_sdof", ps), ("quarter_car", qs)] {
        let desc = rigfit::rig::shipped(rig).unwrap();
        let r = CompiledRig::new(desc.clone(), rig).unwrap();
        let one = histories_one(&r, &ps, &Drive::Velocity, &grid);
        assert_same_bits(
            &histories_native(&desc, &ps, None, &grid, Report::Full),
            &one,
        );
        // Every value finite, and the runs moved.
        assert!(
            one.iter().flatten().all(|&b| f64::from_bits(b).is_finite()),
            "{rig}"
        );
        let moved = one[3].iter().filter(|&&b| f64::from_bits(b) != 0.0).count();
        assert!(
            moved > one[3].len() / 2,
            "{rig}: {moved} of {}",
            one[3].len()
        );
    }
}

#[test]
fn native_lanes_redone_together_match_the_scalar_reference_bit_for_bit() {
    // The native code redoes the lanes past a switch an f64 vector at a
    // time, each with its own switch times and searches, a lane that is
    // done held by a mask while the others take more switches in the same
    // step. Seal friction's stick-slip beside the backlash, on steps long
    // enough that a step often holds two switches in one lane and one in
    // its neighbour, with the friction and the play different in every
    // lane: every lane's bits are still its scalar run's.
    let grid = SampleGrid {
        t0: 0.0,
        dt: 2.5e-3,
        samples: 1600,
        substeps: 1,
    };
    let truth = [
        40.0, 350.0, 1.751e5, 1751.0, 3.0e4, 2500.0, 800.0, 0.01, 2.0e4, 3.0e-4, 10.0, 2.0e5, 2e-3,
        1.0, 6.0,
    ];
    let ps = spread(&truth, LANES + 5, &[(9, 3.0e-4, 2.8e-4), (10, 10.0, 9.0)]);
    let desc = rigfit::rig::shipped("quarter_car_friction").unwrap();
    let r = CompiledRig::new(desc.clone(), "quarter_car_friction").unwrap();
    let one = histories_one(&r, &ps, &Drive::Velocity, &grid);
    assert_same_bits(
        &histories_native(&desc, &ps, None, &grid, Report::Full),
        &one,
    );
    assert!(one.iter().flatten().all(|&b| f64::from_bits(b).is_finite()));
}

/// The f32 tolerance the GPU's f32 kernels are held to (`tests/gpu_rig_parity.rs`):
/// each output's and state's largest difference from the f64 reference, over
/// that series' largest magnitude.
const F32_TOLERANCE: f64 = 2e-4;

#[test]
fn native_f32_lanes_stay_within_the_f32_tolerance_of_the_reference() {
    let desc = rigfit::rig::shipped("tensile4").unwrap();
    let r = CompiledRig::new(desc.clone(), "tensile4").unwrap();
    let ps: Vec<Vec<f64>> = (0..21)
        .map(|i| {
            let mut p = REFERENCE.to_vec();
            let f = 1.0 + 0.02 * i as f64;
            p[ix::K1] *= f;
            p[ix::C4] *= f;
            if i >= 16 {
                p[ix::RAMP] *= f;
            }
            p
        })
        .collect();
    let grid = SampleGrid {
        t0: 0.0,
        dt: REFERENCE_DT,
        samples: 2000,
        substeps: 1,
    };
    let width = r.output_names().len() + r.state_names().len();
    let one = histories_one(&r, &ps, &Drive::Velocity, &grid);
    let f32_runs = {
        let lowered = rigfit::compile::lower(&desc, "tensile4").unwrap();
        let prog = &lowered.programs[0];
        let tape = Tape::new(prog);
        let code = LaneCode::new(prog, &tape);
        let native = Native::build(&code, Arith::F32).expect("the C compiler builds the lane code");
        assert_eq!(native.arith, Arith::F32);
        let refs: Vec<&[f64]> = ps.iter().map(|p| p.as_slice()).collect();
        let mut h = vec![vec![]; ps.len()];
        LaneRunner::new(prog, &tape, &code, &refs, None)
            .with_native(&native)
            .run(&grid, Report::Full, &mut |l, s| {
                h[l].extend(s.outputs.iter().chain(s.state).copied());
                ControlFlow::Continue(())
            });
        h
    };
    let mut worst = 0.0_f64;
    for (i, (a, b)) in f32_runs.iter().zip(&one).enumerate() {
        assert_eq!(a.len(), b.len());
        for col in 0..width {
            let series = |h: &[f64]| {
                h.iter()
                    .skip(col)
                    .step_by(width)
                    .copied()
                    .collect::<Vec<_>>()
            };
            let (x, y) = (
                series(a),
                series(
                    b.iter()
                        .map(|&v| f64::from_bits(v))
                        .collect::<Vec<_>>()
                        .as_slice(),
                ),
            );
            let scale = y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            if scale == 0.0 {
                continue;
            }
            let err = x
                .iter()
                .zip(&y)
                .fold(0.0_f64, |m, (p, q)| m.max((p - q).abs()))
                / scale;
            assert!(
                err <= F32_TOLERANCE,
                "candidate {i}, column {col}: {err:.2e}"
            );
            worst = worst.max(err);
        }
    }
    // f32 arithmetic, not f64 under another name.
    assert!(worst > 1e-9, "{worst:e}");
    eprintln!("worst relative difference {worst:.2e}");
}
