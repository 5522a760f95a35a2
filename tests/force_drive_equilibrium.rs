//! Proves the compiled tensile rig's force-driven actuator behaves physically:
//! before the slack adapter engages, the actuator mass moves exactly as
//! `m4·ÿ4 = F_drive(t)` predicts, and under a slow force ramp the rig passes
//! through quasi-static equilibrium, every element carrying the drive force
//! (the element forces of its states taken from the hand-written oracle,
//! tests/oracle, which also agrees with the rig's own force outputs).

mod oracle;
mod tensile_common;

use std::ops::ControlFlow;

use oracle::tensile::{REFERENCE, TensileSystem, ix};
use rigfit::base::SampleGrid;
use rigfit::base::{Drive, PiecewiseLinear};
use tensile_common::tensile4;

/// One sample of a run: time, full state and outputs.
struct Sampled {
    t: f64,
    state: Vec<f64>,
    outputs: Vec<f64>,
}

/// Samples of the force-driven compiled reference rig on `grid`.
fn run(drive: &Drive, grid: &SampleGrid) -> Vec<Sampled> {
    let mut out = Vec::new();
    tensile4().simulate(&REFERENCE, drive, grid, &mut |s| {
        out.push(Sampled {
            t: s.t,
            state: s.state.to_vec(),
            outputs: s.outputs.to_vec(),
        });
        ControlFlow::Continue(())
    });
    assert_eq!(out.len(), grid.samples);
    out
}

/// A ramp from 0 to `f_max` over `t_ramp`, then held.
fn ramp(f_max: f64, t_ramp: f64) -> Drive {
    Drive::Force(PiecewiseLinear {
        t: vec![0.0, t_ramp],
        value: vec![0.0, f_max],
    })
}

#[test]
fn free_actuator_accelerates_as_the_drive_force_predicts() {
    let (f_max, t_ramp) = (2000.0, 0.05);
    let drive = ramp(f_max, t_ramp);
    let p = REFERENCE;
    // F = F_max·t/T on the free mass: y4 = F_max·t³/(6·T·m4); it reaches the gap at
    // ≈ 4.7 ms, so 4 ms is still free flight.
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-5,
        samples: 401,
        substeps: 10,
    };
    for Sampled { t, state: y, .. } in run(&drive, &grid) {
        let exact_y = f_max * t.powi(3) / (6.0 * t_ramp * p[ix::M4]);
        let exact_v = f_max * t * t / (2.0 * t_ramp * p[ix::M4]);
        assert!(y[3] < p[ix::GAP], "engaged already at {t}");
        assert!(
            (y[3] - exact_y).abs() < 1e-12 * p[ix::GAP],
            "y4({t}) = {} vs {exact_y}",
            y[3]
        );
        assert!((y[7] - exact_v).abs() < 1e-12, "v4({t})");
        assert_eq!(y[0..3], [0.0; 3], "rig moved before engagement at {t}");
    }
}

/// The light, stiff rig above the actuator (highest mode ≈ 10.8 kHz) follows the
/// actuator quasi-statically, so all four elements carry the same force while the
/// 37.4 kg actuator itself still swings about the drive force on the soft slack
/// adapter (≈ 10 % after engagement, decaying with a time constant ≈ 25 ms). Held
/// long enough, the rig settles into static equilibrium at the drive force.
#[test]
fn slow_force_ramp_loads_every_element_with_the_drive_force() {
    let (f_max, t_ramp) = (2000.0, 0.05);
    let drive = ramp(f_max, t_ramp);
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-4,
        samples: 2501,
        substeps: 100,
    };
    let samples = run(&drive, &grid);
    let sys = TensileSystem::new(&REFERENCE, &drive);
    let mut worst: f64 = 0.0;
    for s in &samples {
        // The rig's load-cell and specimen forces are the oracle's laws on its
        // state.
        let f = sys.forces(s.t, &s.state);
        for (out, fi) in s.outputs.iter().zip(&f) {
            assert!(
                (out - fi).abs() <= 1e-9 * f_max,
                "output {out} N vs the oracle's {fi} N at {} s",
                s.t
            );
        }
        if s.t > 6e-3 {
            for fi in &f[1..] {
                worst = worst.max((fi - f[0]).abs());
            }
            assert!(f[0] > 0.0, "rig unloaded at {} s: {f:?}", s.t);
        }
    }
    let last = samples.last().expect("samples");
    let (t, f) = (last.t, sys.forces(last.t, &last.state));
    println!("largest |Fi − F1| after engagement {worst:.2} N; at {t:.2} s: F1..F4 = {f:.3?} N");
    assert!(worst < 0.01 * f_max, "elements disagree by {worst} N");
    assert!(
        f.iter().all(|fi| (fi - f_max).abs() < 0.5),
        "not settled at the drive force: {f:?}"
    );
}
