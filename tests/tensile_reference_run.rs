//! Proves the published reference parameters give the published behaviour (peak
//! ≈ 5.7 kN, fracture after ≈ 0.5 ms, ringing at √(k1/m1)/2π ≈ 5.19 kHz), and
//! that the model's building blocks keep their contract: the slack-adapter law is
//! continuous in force and stiffness at the knee `d*`, and the velocity drive's
//! displacement, velocity and acceleration are consistent.

use std::ops::ControlFlow;

use rigfit::fixtures::{REFERENCE_DT, REFERENCE_SAMPLES, REFERENCE_SUBSTEPS};
use rigfit::integrate::SampleGrid;
use rigfit::model::{Drive, RigModel, tensile};
use rustfft::{FftPlanner, num_complex::Complex};
use tensile::{Prepared, TensileSystem, ix, slack_exp_law, slack_knee, velocity_drive};

/// Load-cell force history of the reference run on the reference grid, and the
/// located fracture time.
fn reference_run() -> (Vec<f64>, f64) {
    let p = tensile::REFERENCE;
    let grid = SampleGrid {
        t0: 0.0,
        dt: REFERENCE_DT,
        samples: REFERENCE_SAMPLES,
        substeps: REFERENCE_SUBSTEPS,
    };
    let mut f1 = Vec::with_capacity(grid.samples);
    tensile::TENSILE4.simulate(&p, &Drive::Velocity, &grid, &mut |s| {
        f1.push(s.outputs[0]);
        ControlFlow::Continue(())
    });
    // The same run through the integrator directly, for the fracture time.
    let drive = Drive::Velocity;
    let mut sys = TensileSystem::new(&p, &drive);
    let mut y = vec![0.0; 8];
    rigfit::integrate::Integrator::new(8).run(&mut sys, &grid, &mut y, |_, _, _, _| {
        ControlFlow::Continue(())
    });
    (
        f1,
        sys.fracture_time.expect("the reference specimen breaks"),
    )
}

#[test]
fn reference_peak_fracture_and_ringing_match_the_publication() {
    let (f1, tf) = reference_run();
    let peak = f1.iter().copied().fold(f64::MIN, f64::max);
    println!(
        "peak load-cell force {peak:.1} N, fracture at {:.4} ms",
        tf * 1e3
    );
    assert!((peak - 5700.0).abs() <= 0.05 * 5700.0, "peak {peak} N");
    assert!((0.4e-3..=0.7e-3).contains(&tf), "fracture at {tf} s");

    // Dominant frequency of F1 after fracture: Hann window, zero-padded FFT with
    // 1.9 Hz bins, parabolic peak interpolation.
    let first = (tf / REFERENCE_DT).ceil() as usize + 1;
    let tail = &f1[first..];
    let n = 1 << 19;
    let mut buf: Vec<Complex<f64>> = (0..n)
        .map(|i| {
            let x = tail.get(i).copied().unwrap_or(0.0);
            let w = if i < tail.len() {
                0.5 - 0.5 * (std::f64::consts::TAU * i as f64 / (tail.len() - 1) as f64).cos()
            } else {
                0.0
            };
            Complex::new(x * w, 0.0)
        })
        .collect();
    FftPlanner::new().plan_fft_forward(n).process(&mut buf);
    let mag: Vec<f64> = buf[..n / 2].iter().map(|c| c.norm()).collect();
    let k = (1..n / 2 - 1)
        .max_by(|&a, &b| mag[a].total_cmp(&mag[b]))
        .expect("bins");
    let (a, b, c) = (mag[k - 1].ln(), mag[k].ln(), mag[k + 1].ln());
    let bin = k as f64 + 0.5 * (a - c) / (a - 2.0 * b + c);
    let f = bin / (n as f64 * REFERENCE_DT);
    let p = tensile::REFERENCE;
    let f_cell = (p[ix::K1] / p[ix::M1]).sqrt() / std::f64::consts::TAU;
    println!("post-fracture dominant frequency {f:.1} Hz, √(k1/m1)/2π = {f_cell:.1} Hz");
    assert!((f - f_cell).abs() < 10.0, "ringing at {f} Hz");
    assert!((f - 5190.0).abs() < 20.0);
}

#[test]
fn slack_law_is_continuous_in_force_and_stiffness_at_the_knee() {
    let p = tensile::REFERENCE;
    let (a, b, c, k4) = (
        p[ix::SLACK_A],
        p[ix::SLACK_B],
        p[ix::SLACK_C],
        p[ix::K4_LIN],
    );
    let prep = Prepared::new(&p);
    let ds = slack_knee(a, b, c, k4);
    assert_eq!(ds, prep.d_star);
    println!("d* = {:.4} µm, G(d*) = {:.2} N", ds * 1e6, prep.g_star);
    // Stiffness of the exponential branch at d* is exactly k4_lin.
    assert!((a * (b * ds).exp() + c - k4).abs() < 1e-9 * k4);
    let eps = 1e-9 * ds;
    let (below, at, above) = (
        prep.slack_law(ds - eps),
        prep.slack_law(ds),
        prep.slack_law(ds + eps),
    );
    assert!((at - slack_exp_law(a, b, c, ds)).abs() < 1e-12 * at);
    assert!(
        (above - below).abs() < 1e-6 * at,
        "force jump {} N",
        above - below
    );
    // One-sided difference quotients on both sides agree with k4_lin.
    let hd = 1e-5 * ds;
    let left = (prep.slack_law(ds) - prep.slack_law(ds - hd)) / hd;
    let right = (prep.slack_law(ds + hd) - prep.slack_law(ds)) / hd;
    assert!((left - k4).abs() < 1e-3 * k4, "left stiffness {left}");
    assert!((right - k4).abs() < 1e-9 * k4, "right stiffness {right}");
    // Law starts at zero force and zero opening.
    assert_eq!(prep.slack_law(0.0), 0.0);
}

#[test]
fn slack_knee_is_zero_when_the_linear_stiffness_is_not_above_a_plus_c() {
    assert_eq!(slack_knee(4.43e3, 4.87e5, 1.94e7, 1.94e7 + 4.43e3), 0.0);
    assert_eq!(slack_knee(4.43e3, 4.87e5, 1.94e7, 1.0e7), 0.0);
    let mut p = tensile::REFERENCE;
    p[ix::K4_LIN] = 1.0e7;
    let prep = Prepared::new(&p);
    assert_eq!(prep.d_star, 0.0);
    assert_eq!(prep.g_star, 0.0);
    assert!((prep.slack_law(1e-5) - 1.0e7 * 1e-5).abs() < 1e-9);
}

#[test]
fn velocity_drive_displacement_velocity_and_acceleration_agree() {
    let (v, r) = (2.0, 1.76e-6);
    for &t in &[1e-8, 1e-7, 8.8e-7, 3e-6, 1e-4, 1e-3] {
        let (y, yd, ydd) = velocity_drive(v, r, t);
        let closed = v * t - r * (1.0 - (-v * t / r).exp());
        assert!(
            (y - closed).abs() <= 1e-12 * closed.abs().max(1e-15),
            "y4({t})"
        );
        let d = 1e-4 * t;
        let fd_v = (velocity_drive(v, r, t + d).0 - velocity_drive(v, r, t - d).0) / (2.0 * d);
        let fd_a = (velocity_drive(v, r, t + d).1 - velocity_drive(v, r, t - d).1) / (2.0 * d);
        assert!((fd_v - yd).abs() < 1e-6 * v, "v4({t}): {yd} vs {fd_v}");
        assert!(
            (fd_a - ydd).abs() < 1e-6 * v * v / r,
            "a4({t}): {ydd} vs {fd_a}"
        );
    }
    // Starts at rest with the full ramp acceleration, ends at the target velocity
    // lagging the ideal ramp by r.
    assert_eq!(velocity_drive(v, r, 0.0), (0.0, 0.0, 0.0));
    assert_eq!(velocity_drive(v, r, -1e-6), (0.0, 0.0, 0.0));
    let (y, yd, ydd) = velocity_drive(v, r, 1e-3);
    assert!((y - (v * 1e-3 - r)).abs() < 1e-15 && (yd - v).abs() < 1e-12 && ydd < 1e-100);
    // r = 0: a step to full velocity.
    assert_eq!(velocity_drive(v, 0.0, 1e-4), (v * 1e-4, v, 0.0));
}
