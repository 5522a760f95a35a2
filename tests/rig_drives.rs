//! The sine, chirp and half-sine drive laws against closed forms: a half-sine
//! impact on an undamped oscillator (both pulse ends located, so the run keeps
//! fourth order), a prescribed chirp displacement and its derivatives, and a
//! base-acceleration sine that acts as the force `−m·a` would.

use std::ops::ControlFlow;

use rigfit::base::Drive;
use rigfit::base::SampleGrid;
use rigfit::model::compiled::CompiledRig;
use rigfit::rig::{RigSource, parse};
use serde_json::{Value, json};

fn compile(v: Value) -> CompiledRig {
    let src = RigSource::File("drive_test.json".into());
    CompiledRig::new(parse(&v.to_string(), &src).unwrap(), &src.label()).unwrap()
}

fn oscillator(drive: Value) -> CompiledRig {
    compile(json!({
        "id": "oscillator",
        "params": [
            {"name": "m", "unit": "kg"}, {"name": "k", "unit": "N/m"},
            {"name": "c", "unit": "N·s/m", "default": 0.0}
        ],
        "nodes": [{"name": "mass", "mass": "m"}],
        "elements": [{"name": "spring", "between": ["ground", "mass"],
                      "spring": {"law": "linear", "k": "k"}, "damper": {"law": "viscous", "c": "c"}}],
        "drives": [drive],
        "outputs": [
            {"name": "x", "unit": "m", "sum": [{"displacement": "mass", "frame": "relative"}]},
            {"name": "v", "unit": "m/s", "sum": [{"velocity": "mass", "frame": "relative"}]}
        ]
    }))
}

fn history(
    r: &CompiledRig,
    p: &[f64],
    dt: f64,
    samples: usize,
    substeps: usize,
    t0: f64,
) -> Vec<Vec<f64>> {
    let grid = SampleGrid {
        t0,
        dt,
        samples,
        substeps,
    };
    let mut h = vec![vec![]; r.output_names().len()];
    r.simulate(p, &Drive::Velocity, &grid, &mut |s| {
        for (o, v) in h.iter_mut().zip(s.outputs) {
            o.push(*v);
        }
        ControlFlow::Continue(())
    });
    h
}

#[test]
fn a_half_sine_impact_on_an_undamped_oscillator_matches_the_closed_form_at_fourth_order() {
    let (m, k, f0, tau, start): (f64, f64, f64, f64, f64) = (2.0, 8e4, 50.0, 3.3e-3, 1.234e-3);
    let r = oscillator(
        json!({"node": "mass", "law": {"type": "half_sine", "quantity": "force",
        "amplitude": f0, "duration": tau, "start": start}}),
    );
    let w = (k / m).sqrt();
    let om = std::f64::consts::PI / tau;
    // During the pulse: x = F0/(m(ω² − Ω²))·(sin Ωs − (Ω/ω)·sin ωs), s = t − start;
    // after it, free vibration from the state at its end.
    let a = f0 / (m * (w * w - om * om));
    let during = |s: f64| {
        (
            a * ((om * s).sin() - om / w * (w * s).sin()),
            a * om * ((om * s).cos() - (w * s).cos()),
        )
    };
    let (xe, ve) = during(tau);
    let exact = |t: f64| {
        let s = t - start;
        if s <= 0.0 {
            0.0
        } else if s <= tau {
            during(s).0
        } else {
            xe * (w * (s - tau)).cos() + ve / w * (w * (s - tau)).sin()
        }
    };
    let dt = 1e-3;
    let samples = 40;
    let scale = f0 / k;
    let errs: Vec<f64> = [1, 2, 4, 8]
        .iter()
        .map(|&sub| {
            let h = history(&r, &[m, k, 0.0], dt, samples, sub, -2e-3);
            h[0].iter()
                .enumerate()
                .map(|(i, x)| (x - exact(-2e-3 + i as f64 * dt)).abs())
                .fold(0.0, f64::max)
                / scale
        })
        .collect();
    let orders: Vec<f64> = errs.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
    println!("largest errors / (F0/k): {errs:?}, orders {orders:?}");
    assert!(errs[3] < 1e-6, "{errs:?}");
    for o in orders {
        assert!(o >= 3.5, "order {o}");
    }
}

#[test]
fn a_prescribed_chirp_displacement_moves_its_node_with_the_chirps_derivatives() {
    let (amp, f0, rate) = (2e-3, 1.0, 3.0);
    let r = compile(json!({
        "id": "wheel_pan",
        "params": [{"name": "m", "unit": "kg"}, {"name": "k", "unit": "N/m"}],
        "nodes": [{"name": "pan", "mass": 1.0}, {"name": "mass", "mass": "m"}],
        "elements": [{"name": "tyre", "between": ["pan", "mass"], "spring": {"law": "linear", "k": "k"}}],
        "drives": [{"node": "pan", "law": {"type": "chirp", "quantity": "displacement",
                    "amplitude": amp, "f_start": f0, "rate": rate}}],
        "outputs": [
            {"name": "x_pan", "unit": "m", "sum": [{"displacement": "pan"}]},
            {"name": "v_pan", "unit": "m/s", "sum": [{"velocity": "pan"}]},
            {"name": "a_pan", "unit": "m/s^2", "sum": [{"acceleration": "pan"}]}
        ]
    }));
    let h = history(&r, &[1.0, 1e4], 1e-3, 2000, 1, 0.0);
    let tau = std::f64::consts::TAU;
    let mut worst: f64 = 0.0;
    let (xs, vs, accs) = (&h[0], &h[1], &h[2]);
    for (i, ((xi, vi), ai)) in xs.iter().zip(vs).zip(accs).enumerate().skip(1) {
        let t = i as f64 * 1e-3;
        let phi = tau * (f0 * t + 0.5 * rate * t * t);
        let dphi = tau * (f0 + rate * t);
        let x = amp * phi.sin();
        let v = amp * phi.cos() * dphi;
        let a = amp * (phi.cos() * tau * rate - phi.sin() * dphi * dphi);
        worst = worst
            .max((xi - x).abs() / amp)
            .max((vi - v).abs() / (amp * dphi))
            .max((ai - a).abs() / (amp * dphi * dphi));
    }
    println!("largest relative difference {worst:e}");
    assert!(worst < 1e-12, "{worst}");
}

#[test]
fn a_base_acceleration_sine_acts_as_the_force_minus_m_a() {
    let (m, k, c, a0, f) = (3.0, 5e4, 12.0, 9.81, 17.0);
    let base = oscillator(
        json!({"law": {"type": "sine", "quantity": "base_acceleration",
        "amplitude": a0, "frequency": f}}),
    );
    let force = oscillator(
        json!({"node": "mass", "law": {"type": "sine", "quantity": "force",
        "amplitude": -m * a0, "frequency": f}}),
    );
    let p = [m, k, c];
    let hb = history(&base, &p, 1e-3, 500, 2, 0.0);
    let hf = history(&force, &p, 1e-3, 500, 2, 0.0);
    let peak = hf[0].iter().fold(0.0_f64, |s, x| s.max(x.abs()));
    let worst = hb[0]
        .iter()
        .zip(&hf[0])
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!("peak {peak:e} m, largest difference {worst:e} m");
    assert!(peak > 1e-4 && worst < 1e-12 * peak, "{worst}");
}
