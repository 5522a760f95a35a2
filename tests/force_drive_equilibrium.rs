//! Proves the force-driven actuator behaves physically: before the slack adapter
//! engages, the actuator mass moves exactly as `m4·ÿ4 = F_drive(t)` predicts, and
//! under a slow force ramp the rig passes through quasi-static equilibrium, every
//! element carrying the drive force.

use std::ops::ControlFlow;

use rigfit::integrate::SampleGrid;
use rigfit::model::{Drive, PiecewiseLinear, RigModel, tensile};
use tensile::{TensileSystem, ix};

/// Samples `(t, state)` of a force-driven reference rig on `grid`.
fn run(drive: &Drive, grid: &SampleGrid) -> Vec<(f64, Vec<f64>)> {
    let mut out = Vec::new();
    tensile::TENSILE4.simulate(&tensile::REFERENCE, drive, grid, &mut |s| {
        out.push((s.t, s.state.to_vec()));
        ControlFlow::Continue(())
    });
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
    let p = tensile::REFERENCE;
    // F = F_max·t/T on the free mass: y4 = F_max·t³/(6·T·m4); it reaches the gap at
    // ≈ 4.7 ms, so 4 ms is still free flight.
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-5,
        samples: 401,
        substeps: 10,
    };
    for (t, y) in run(&drive, &grid) {
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
    let sys = TensileSystem::new(&tensile::REFERENCE, &drive);
    let mut worst: f64 = 0.0;
    for (t, y) in samples.iter().filter(|(t, _)| *t > 6e-3) {
        let f = sys.forces(*t, y);
        for fi in &f[1..] {
            worst = worst.max((fi - f[0]).abs());
        }
        assert!(f[0] > 0.0, "rig unloaded at {t} s: {f:?}");
    }
    let (t, y) = samples.last().expect("samples");
    let f = sys.forces(*t, y);
    println!("largest |Fi − F1| after engagement {worst:.2} N; at {t:.2} s: F1..F4 = {f:.3?} N");
    assert!(worst < 0.01 * f_max, "elements disagree by {worst} N");
    assert!(
        f.iter().all(|fi| (fi - f_max).abs() < 0.5),
        "not settled at the drive force: {f:?}"
    );
}
