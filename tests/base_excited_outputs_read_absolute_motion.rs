//! Under base acceleration an output term reads the frame it states: a linear
//! oscillator (mass m, spring k and damper c to the base) driven by the base
//! acceleration `A·sin(ωt)` from rest. Its absolute acceleration matches the
//! exact solution from rest at every sample and, once the transient has
//! decayed, the closed-form steady state `A·|T(ω)|·sin(ωt + arg T(ω))` with
//! the transmissibility `T = (k + icω)/(k − mω² + icω)`; its relative
//! acceleration is the absolute one minus `A·sin(ωt)`; its absolute velocity
//! and displacement add the base's own, `A(1 − cos ωt)/ω` and
//! `A(t/ω − sin(ωt)/ω²)`. The same on the GPU's history path, within its
//! documented f32 tolerance. A motion term that does not say its frame is
//! refused with its JSON path.

mod gpu_common;
mod oracle;
mod tensile_common;

use std::f64::consts::TAU;
use std::ops::ControlFlow;
use std::sync::Arc;

use rigfit::base::{Drive, SampleGrid};
use rigfit::eval::{Batch, Evaluator, ExperimentData, Precision, Problem};
use rigfit::gpu::{F32_HISTORY_TOLERANCE, F64_HISTORY_TOLERANCE, GpuEvaluator, GpuOptions};
use rigfit::model::compiled::CompiledRig;
use rigfit::rig::{RigSource, parse};
use serde_json::{Value, json};

const M: f64 = 2.0;
const K: f64 = 3.2e4;
const C: f64 = 100.0;
const A: f64 = 4.905;
const F: f64 = 15.0;
const DT: f64 = 1e-3;
const SAMPLES: usize = 2000;
const SUBSTEPS: usize = 4;

/// Outputs: absolute acceleration, relative acceleration, absolute velocity,
/// absolute displacement, relative displacement.
fn rig_json(frames: [Option<&str>; 5]) -> Value {
    let terms = [
        ("acceleration", frames[0]),
        ("acceleration", frames[1]),
        ("velocity", frames[2]),
        ("displacement", frames[3]),
        ("displacement", frames[4]),
    ];
    let names = ["a_abs", "a_rel", "v_abs", "x_abs", "x_rel"];
    let units = ["m/s²", "m/s²", "m/s", "m", "m"];
    let outputs: Vec<Value> = terms
        .iter()
        .zip(names.iter().zip(units))
        .map(|((what, frame), (name, unit))| {
            let mut term = json!({ *what: "mass" });
            if let Some(f) = frame {
                term["frame"] = json!(f);
            }
            json!({"name": name, "unit": unit, "sum": [term]})
        })
        .collect();
    json!({
        "id": "base_excited",
        "params": [
            {"name": "m", "unit": "kg"}, {"name": "k", "unit": "N/m"},
            {"name": "c", "unit": "N·s/m"}, {"name": "a0", "unit": "m/s²"},
            {"name": "f", "unit": "Hz"}
        ],
        "nodes": [{"name": "mass", "mass": "m"}],
        "elements": [{"name": "mount", "between": ["ground", "mass"],
                      "spring": {"law": "linear", "k": "k"},
                      "damper": {"law": "viscous", "c": "c"}}],
        "drives": [{"law": {"type": "sine", "quantity": "base_acceleration",
                            "amplitude": "a0", "frequency": "f"}}],
        "outputs": outputs
    })
}

fn compile(v: &Value) -> Result<CompiledRig, String> {
    let src = RigSource::File("base_excited.json".into());
    let desc = parse(&v.to_string(), &src).map_err(|e| e.to_string())?;
    CompiledRig::new(desc, &src.label()).map_err(|e| e.to_string())
}

fn rig() -> CompiledRig {
    compile(&rig_json([
        Some("absolute"),
        Some("relative"),
        Some("absolute"),
        Some("absolute"),
        Some("relative"),
    ]))
    .unwrap()
}

const PARAMS: [f64; 5] = [M, K, C, A, F];

/// The exact motion from rest at `t`: (absolute acceleration, relative
/// acceleration, absolute velocity, absolute displacement, relative
/// displacement).
fn exact(t: f64) -> [f64; 5] {
    let w = TAU * F;
    // Relative coordinate: m·ẍ + c·ẋ + k·x = −m·A·sin(ωt), x(0) = ẋ(0) = 0.
    // Particular: x_p = Im(X·e^{iωt}), X = −m·A/(k − m·ω² + i·c·ω).
    let (dr, di) = (K - M * w * w, C * w);
    let den = dr * dr + di * di;
    let (xr, xi) = (-M * A * dr / den, M * A * di / den);
    let (s, co) = ((w * t).sin(), (w * t).cos());
    let xp = xr * s + xi * co;
    let vp = w * (xr * co - xi * s);
    // Homogeneous part cancelling x_p(0) = X_i and ẋ_p(0) = ω·X_r.
    let wn = (K / M).sqrt();
    let zeta = C / (2.0 * (K * M).sqrt());
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let c1 = -xi;
    let c2 = (-w * xr + zeta * wn * c1) / wd;
    let e = (-zeta * wn * t).exp();
    let (sd, cd) = ((wd * t).sin(), (wd * t).cos());
    let xh = e * (c1 * cd + c2 * sd);
    let vh = e * (-zeta * wn * (c1 * cd + c2 * sd) + wd * (-c1 * sd + c2 * cd));
    let (x, v) = (xp + xh, vp + vh);
    let a_abs = -(C * v + K * x) / M;
    let base_a = A * s;
    let base_v = A * (1.0 - co) / w;
    let base_x = A * (t / w - s / (w * w));
    [a_abs, a_abs - base_a, v + base_v, x + base_x, x]
}

fn cpu_history(rig: &CompiledRig) -> (Vec<f64>, Vec<Vec<f64>>) {
    let grid = SampleGrid {
        t0: 0.0,
        dt: DT,
        samples: SAMPLES,
        substeps: SUBSTEPS,
    };
    let mut t = vec![];
    let mut h = vec![vec![]; rig.output_names().len()];
    rig.simulate(&PARAMS, &Drive::Velocity, &grid, &mut |s| {
        t.push(s.t);
        for (o, v) in h.iter_mut().zip(s.outputs) {
            o.push(*v);
        }
        ControlFlow::Continue(())
    });
    (t, h)
}

/// Largest difference of each output from the exact motion, as a fraction
/// of that output's largest magnitude.
fn worst_against_exact(t: &[f64], h: &[Vec<f64>], samples: usize) -> [f64; 5] {
    let mut worst = [0.0_f64; 5];
    for o in 0..5 {
        let peak = (0..samples).fold(0.0_f64, |m, k| m.max(exact(t[k])[o].abs()));
        for k in 0..samples {
            worst[o] = worst[o].max((h[o][k] - exact(t[k])[o]).abs() / peak);
        }
    }
    worst
}

#[test]
fn absolute_acceleration_is_the_transmitted_steady_state_on_the_cpu() {
    let rig = rig();
    let (t, h) = cpu_history(&rig);
    let worst = worst_against_exact(&t, &h, SAMPLES);
    println!("CPU f64, largest differences from the exact motion: {worst:?}");
    for (o, w) in worst.iter().enumerate() {
        assert!(*w < 1e-7, "output {o}: {w:e}");
    }
    // The relative acceleration is the absolute one less the base's, to rounding.
    for k in 0..SAMPLES {
        let base = A * (TAU * F * t[k]).sin();
        assert!((h[1][k] - (h[0][k] - base)).abs() < 1e-12 * A, "sample {k}");
    }
    // Steady state over the last 15 whole cycles (1 s in: the transient
    // has decayed by e^{−ζ·ωn·t} ≈ 1e-11): amplitude and phase against the
    // transmissibility.
    let w = TAU * F;
    let n = (15.0 / (F * DT)).round() as usize;
    let (mut re, mut im) = (0.0, 0.0);
    for k in SAMPLES - n..SAMPLES {
        re += h[0][k] * (w * t[k]).sin();
        im += h[0][k] * (w * t[k]).cos();
    }
    let (amp, phase) = (2.0 * (re * re + im * im).sqrt() / n as f64, im.atan2(re));
    let (dr, di) = (K - M * w * w, C * w);
    let transmissibility = A * ((K * K + di * di) / (dr * dr + di * di)).sqrt();
    let lag = (C * w).atan2(K) - di.atan2(dr);
    println!(
        "amplitude {amp} vs {transmissibility} m/s², phase {phase} vs {lag} rad (base {A} m/s²)"
    );
    assert!(
        (amp - transmissibility).abs() < 1e-7 * transmissibility,
        "{amp} vs {transmissibility}"
    );
    assert!((phase - lag).abs() < 1e-7, "{phase} vs {lag}");
    // Near resonance the mass moves more than the base: the test can tell.
    assert!(transmissibility > 1.5 * A);
}

#[test]
fn the_base_states_leave_the_step_bound_and_the_modes_alone() {
    // The absolute velocity and displacement add the base's velocity and
    // displacement as states; they feel no force, so neither the stability
    // bound nor the natural frequency changes.
    let absolute = rig();
    let relative = compile(&rig_json([Some("relative"); 5])).unwrap();
    assert_eq!(
        absolute.state_names()[absolute.state_names().len() - 2..],
        ["base_velocity", "base_displacement"]
    );
    assert_eq!(relative.state_names(), ["x_mass", "v_mass"]);
    let (lower, upper) = ([M, K / 4.0, 0.0, A, F], [M, K * 4.0, 2.0 * C, A, F]);
    let (wa, _) = absolute.omega_bound(&lower, &upper, &Drive::Velocity);
    let (wr, _) = relative.omega_bound(&lower, &upper, &Drive::Velocity);
    println!("stability bound {wa} rad/s with the base states, {wr} without");
    assert!(
        wa.is_finite() && (wa - wr).abs() <= 1e-12 * wr,
        "{wa} vs {wr}"
    );
    let modes =
        rigfit::model::modes::ModeReport::new(&absolute.linearise(&PARAMS, &Drive::Velocity))
            .unwrap();
    let f0 = (K / M).sqrt() / TAU;
    assert_eq!(modes.modes.len(), 1);
    assert!((modes.modes[0].frequency_hz - f0).abs() < 1e-9 * f0);
}

#[test]
fn absolute_acceleration_on_the_gpu_history_path() {
    let Some(ctx) = gpu_common::gpu() else {
        return;
    };
    let model = Arc::new(rig());
    let problem = Problem {
        model: model.clone(),
        experiments: vec![ExperimentData {
            output: 0,
            name: "sine".into(),
            drive: Drive::Velocity,
            t_first: 0.0,
            dt: DT,
            measured: (0..SAMPLES).map(|k| exact(k as f64 * DT)[0]).collect(),
            window: 0..SAMPLES,
            weight: 1.0,
        }],
        substeps: SUBSTEPS,
    };
    let batch = Batch {
        candidates: 1,
        params: vec![PARAMS.to_vec()],
        offsets: vec![vec![0.0]],
    };
    let mut precisions = vec![(Precision::F32, F32_HISTORY_TOLERANCE)];
    if ctx.has_f64() {
        precisions.push((Precision::F64, F64_HISTORY_TOLERANCE));
    }
    for (precision, tolerance) in precisions {
        let mut gpu = GpuEvaluator::new(
            ctx.clone(),
            problem.clone(),
            precision,
            GpuOptions::default(),
        )
        .unwrap();
        let h = &gpu.histories(&batch, &[0]).unwrap()[0][0];
        let (_, cpu) = cpu_history(&model);
        // The GPU against the exact motion, and against the f64 CPU run.
        let worst = worst_against_exact(&h.t, &h.outputs, SAMPLES);
        println!("GPU {precision:?}, largest differences from the exact motion: {worst:?}");
        for (o, w) in worst.iter().enumerate() {
            assert!(*w < tolerance.max(1e-7), "{precision:?} output {o}: {w:e}");
        }
        for (o, c) in cpu.iter().enumerate() {
            let peak = c.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            let d = c
                .iter()
                .zip(&h.outputs[o])
                .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(
                d <= tolerance * peak,
                "{precision:?} output {o}: {:e}",
                d / peak
            );
        }
    }
}

#[test]
fn a_motion_term_without_a_frame_is_refused_under_base_acceleration() {
    let Err(err) = compile(&rig_json([
        Some("absolute"),
        Some("relative"),
        None,
        Some("absolute"),
        Some("relative"),
    ])) else {
        panic!("a velocity term without a frame accepted");
    };
    println!("{err}");
    assert!(
        err.starts_with("base_excited.json: outputs[2].sum[0].frame: expected \"absolute\""),
        "{err}"
    );
    assert!(
        err.contains("\"relative\"") && err.contains("found no frame"),
        "{err}"
    );

    // A frame on a force term is refused too.
    let mut v = rig_json([Some("relative"); 5]);
    v["outputs"][1]["sum"] = json!([{"force": "mount", "frame": "absolute"}]);
    let Err(err) = compile(&v) else {
        panic!("a frame on a force term accepted");
    };
    assert!(err.contains("outputs[1].sum[0].frame"), "{err}");

    // Without base motion the frame may be left out: both are the same.
    let mut v = rig_json([None; 5]);
    v["drives"] = json!([{"node": "mass", "law": {"type": "sine", "quantity": "force",
                                                  "amplitude": "a0", "frequency": "f"}}]);
    compile(&v).unwrap();
}
