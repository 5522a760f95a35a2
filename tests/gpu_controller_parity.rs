//! Rigs with digital controllers on the GPU reproduce the f64 CPU reference
//! (`CompiledRig::simulate`, whose steps `SampleClock::step` splits at the
//! sample instants): every output (the held command among them) and every
//! state of every candidate's history, and the fitness `1 − R²`, for
//! - the held PD loop of `tests/rigs/held_pd.json` at one step per period
//!   (every instant at a step's end), at a period of 0.7 steps (instants
//!   inside steps: each step cut there), at 0.7 ms with two substeps, a
//!   phase and a prologue (`t_first > 0`), and in force mode with its update
//!   reading the experiment's table (`reference`, as the EMPS servo does);
//! - `tests/rigs/held_stick_slip.json`, whose instants and stick-slip
//!   switches fall in the same steps.
//!
//! The runs are cut into many dispatches (`chunk_steps`), so the held states
//! and the instant counter travel through the state buffer between them, and
//! a batch of more than `specialise::MIN_RUNS` runs scores through a
//! specialised kernel.
//!
//! Tolerances, each as a fraction of a series' largest magnitude. f64:
//! [`F64_HISTORY_TOLERANCE`] (1e-9) and the fitness within 1e-9 relative
//! (measured on lavapipe: the PD loop bit for bit but in force mode, 7e-15;
//! the stick-slip controller 7e-12). f32: the PD loop within
//! [`F32_HISTORY_TOLERANCE`] (2e-4; measured at most 2.9e-5) and
//! [`F32_PD_FITNESS`]; the stick-slip controller, whose loop magnifies
//! rounding, within [`F32_STICK_SLIP`] over its first
//! [`F32_STICK_SLIP_SAMPLES`] samples and [`F32_STICK_SLIP_FITNESS`].
mod oracle;
mod tensile_common;

mod gpu_common;
use gpu_common as common;

use std::sync::Arc;

use rigfit::base::{Drive, PiecewiseLinear};
use rigfit::eval::{Batch, Evaluator, ExperimentData, Precision, Problem, score_one};
use rigfit::eval::{DIVERGED, simulate_history};
use rigfit::gpu::{F32_HISTORY_TOLERANCE, F64_HISTORY_TOLERANCE, GpuContext, GpuEvaluator};
use rigfit::gpu::{GpuOptions, kernels_for};
use rigfit::model::compiled::CompiledRig;
use rigfit::rig::desc::RigDesc;

/// f32 histories of the stick-slip controller against the f64 reference,
/// over its first [`F32_STICK_SLIP_SAMPLES`] samples. The loop magnifies
/// rounding: its integral and command saturate, and a rounding near a
/// clamp or a stick-slip switch moves every later command, so a difference
/// grows about 5e6-fold over 1.2 s (f64 kernels: 7e-12 at 0.8 s, 6e-10 at
/// 1.2 s; f32: 5e-5 at 0.2 s, 1e-3 at 0.6 s, 3e-2 at 1 s, 0.3 at 1.2 s,
/// measured on lavapipe). Measured: at most 1.0e-3.
const F32_STICK_SLIP: f64 = 3e-3;
/// Samples over which [`F32_STICK_SLIP`] holds (of the case's 800).
const F32_STICK_SLIP_SAMPLES: usize = 600;
/// f32 fitness of the stick-slip controller over its whole record,
/// relative (measured: at most 3.0e-3).
const F32_STICK_SLIP_FITNESS: f64 = 1e-2;
/// f32 fitness of the PD loop, relative: the residual is 1 % of the record,
/// so the fitness is about twenty times less accurate than the histories
/// (measured: at most 5.1e-4).
const F32_PD_FITNESS: f64 = 5e-3;

/// f32 histories and fitness of the EMPS rig, relative: its loop gain
/// kv·kp·gtau is 1.4e6 N/m, so f32's rounding of a 0.06 m position (4e-9 m)
/// is 5e-3 N in every force (the shipped campaign pins f64). Measured on
/// lavapipe: histories 1.3e-3, fitness 4.7e-7; f64 bit for bit.
const F32_EMPS: f64 = 1e-2;

fn rig_desc(file: &str) -> RigDesc {
    let path = format!("{}/tests/rigs/{file}", env!("CARGO_MANIFEST_DIR"));
    serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap()
}

/// One rig and grid, candidates spread around its defaults.
struct Case {
    name: &'static str,
    rig: Arc<CompiledRig>,
    drive: Drive,
    t_first: f64,
    dt: f64,
    samples: usize,
    substeps: usize,
    /// Parameters varied from candidate to candidate (×/÷ up to `spread`).
    vary: Vec<usize>,
    spread: f64,
    candidates: usize,
    f32_tolerance: f64,
    /// Samples over which f32 histories are held to `f32_tolerance` (all
    /// when `None`).
    f32_samples: Option<usize>,
    /// f32 fitness against the f64 reference, relative.
    f32_fitness: f64,
}

fn held_pd(period: f64, phase: f64) -> RigDesc {
    let mut d = rig_desc("held_pd.json");
    d.controllers[0].period = period;
    d.controllers[0].phase = phase;
    d
}

/// The held PD loop in force mode, tracking the experiment's table.
fn held_pd_tracking() -> RigDesc {
    let text = std::fs::read_to_string(format!(
        "{}/tests/rigs/held_pd.json",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["id"] = "held_pd_tracking".into();
    let c = &mut v["controllers"][0];
    c["mode"] = "force".into();
    c["period"] = 0.7e-3.into();
    c["states"][1]["update"] = "kp*(reference - position) - kd*(position - x_prev)/period".into();
    serde_json::from_value(v).unwrap()
}

fn sine_table(amplitude: f64, freq: f64, duration: f64, points: usize) -> Drive {
    let t: Vec<f64> = (0..points)
        .map(|i| duration * i as f64 / (points - 1) as f64)
        .collect();
    let value = t
        .iter()
        .map(|&t| amplitude * (2.0 * std::f64::consts::PI * freq * t).sin())
        .collect();
    Drive::Force(PiecewiseLinear { t, value })
}

/// The shipped EMPS rig, its fitted parameters given the inverse model's
/// values as defaults, and the first `samples` of the record's reference
/// position as its table.
fn emps(samples: usize) -> (RigDesc, Drive) {
    let mut desc = rigfit::rig::shipped("emps").unwrap();
    for p in &mut desc.params {
        match p.name.as_str() {
            "m" => p.default = Some(95.09),
            "f_v" => p.default = Some(203.1),
            "f_c" => p.default = Some(20.44),
            _ => {}
        }
    }
    let path = format!(
        "{}/campaigns/emps/closed_loop.csv",
        env!("CARGO_MANIFEST_DIR")
    );
    let (t, value): (Vec<f64>, Vec<f64>) = std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .take(samples)
        .map(|l| {
            let c: Vec<f64> = l.split(',').map(|v| v.parse().unwrap()).collect();
            (c[0], c[2])
        })
        .unzip();
    (desc, Drive::Force(PiecewiseLinear { t, value }))
}

fn shared(desc: RigDesc) -> Arc<CompiledRig> {
    let id = desc.id.clone();
    CompiledRig::shared(desc, &id).unwrap()
}

fn cases() -> Vec<Case> {
    let pd = |name, desc, t_first, substeps| Case {
        name,
        rig: shared(desc),
        drive: Drive::Velocity,
        t_first,
        dt: 1e-3,
        samples: 400,
        substeps,
        // m, kp, kd
        vary: vec![0, 1, 2],
        spread: 1.5,
        candidates: 24,
        f32_tolerance: F32_HISTORY_TOLERANCE,
        f32_samples: None,
        f32_fitness: F32_PD_FITNESS,
    };
    vec![
        pd(
            "held PD, period 1 ms (instants at step ends)",
            held_pd(1e-3, 0.0),
            0.0,
            1,
        ),
        pd(
            "held PD, period 0.7 ms (instants inside steps)",
            held_pd(0.7e-3, 0.0),
            0.0,
            1,
        ),
        pd(
            "held PD, period 0.1 ms (ten instants inside every step)",
            held_pd(0.1e-3, 0.0),
            0.0,
            1,
        ),
        pd(
            "held PD, period 0.7 ms, phase 0.25 ms, two substeps, a prologue",
            held_pd(0.7e-3, 0.25e-3),
            2.6e-3,
            2,
        ),
        Case {
            drive: sine_table(0.005, 3.0, 0.5, 501),
            ..pd(
                "held PD tracking the experiment's table (force mode)",
                held_pd_tracking(),
                0.0,
                1,
            )
        },
        {
            let (desc, drive) = emps(1500);
            Case {
                name: "EMPS, its controller held, on the record's reference",
                rig: shared(desc),
                drive,
                t_first: 0.0,
                dt: 1e-3,
                samples: 1500,
                substeps: 2,
                // m, f_v, f_c
                vary: vec![0, 1, 2],
                spread: 1.2,
                candidates: 24,
                f32_tolerance: F32_EMPS,
                f32_samples: None,
                f32_fitness: F32_EMPS,
            }
        },
        Case {
            name: "held PI on a stick-slip contact",
            rig: shared(rig_desc("held_stick_slip.json")),
            drive: Drive::Velocity,
            t_first: 0.0,
            dt: 1e-3,
            samples: 800,
            substeps: 2,
            // f_c, kp, ki
            vary: vec![1, 3, 4],
            spread: 1.3,
            // More than specialise::MIN_RUNS: a specialised kernel.
            candidates: 72,
            f32_tolerance: F32_STICK_SLIP,
            f32_samples: Some(F32_STICK_SLIP_SAMPLES),
            f32_fitness: F32_STICK_SLIP_FITNESS,
        },
    ]
}

/// Candidate `i`'s parameters: the defaults, then each varied one moved
/// log-uniformly by a fixed, spread pattern (candidate 0 is the defaults).
fn params_of(case: &Case) -> Vec<Vec<f64>> {
    let base: Vec<f64> = case
        .rig
        .params()
        .iter()
        .map(|p| p.default.unwrap())
        .collect();
    (0..case.candidates)
        .map(|i| {
            let mut p = base.clone();
            for (n, &j) in case.vary.iter().enumerate() {
                let u = ((i * (2 * n + 3) + n) as f64 * 0.618_033_988_75).fract() * 2.0 - 1.0;
                if i > 0 {
                    p[j] *= case.spread.powf(u);
                }
            }
            p
        })
        .collect()
}

/// A problem whose record is the centre candidate's first output, perturbed
/// by 1 % so that the fitness is not zero.
fn problem(case: &Case) -> Problem {
    let mut exp = ExperimentData {
        output: 0,
        name: case.name.into(),
        drive: case.drive.clone(),
        t_first: case.t_first,
        dt: case.dt,
        measured: vec![0.0; case.samples],
        window: 0..case.samples,
        weight: 1.0,
    };
    let mut p = Problem {
        model: case.rig.clone(),
        experiments: vec![exp.clone()],
        substeps: case.substeps,
    };
    let centre = &params_of(case)[0];
    let h = simulate_history(&p, 0, centre, 0.0);
    exp.measured = h.outputs[0]
        .iter()
        .enumerate()
        .map(|(k, f)| f * (1.0 + 0.01 * (k as f64 * 0.37).sin()))
        .collect();
    p.experiments[0] = exp;
    p
}

/// Largest history and fitness differences of `case` in `precision`,
/// asserting each against its tolerance.
fn compare(ctx: &GpuContext, precision: Precision, case: &Case) -> (f64, f64) {
    let problem = problem(case);
    assert!(
        kernels_for(&problem, 0).is_ok(),
        "{}: no GPU kernels",
        case.name
    );
    let params = params_of(case);
    let batch = Batch {
        candidates: params.len(),
        params: vec![params.concat()],
        offsets: vec![vec![0.0; params.len()]],
    };
    let options = GpuOptions {
        // Many dispatches per run: the held states and the instant counter
        // cross them in the state buffer.
        chunk_steps: 64,
        ..GpuOptions::default()
    };
    let mut gpu = GpuEvaluator::new(ctx.clone(), problem.clone(), precision, options).unwrap();
    let scores = gpu.fitness(&batch).unwrap();
    let which: Vec<usize> = (0..batch.candidates).collect();
    let hist = gpu.histories(&batch, &which).unwrap();
    let (tol, fit_tol) = match precision {
        Precision::F64 => (F64_HISTORY_TOLERANCE, 1e-9),
        Precision::F32 => (case.f32_tolerance, case.f32_fitness),
    };
    let span = match precision {
        Precision::F64 => case.samples,
        Precision::F32 => case.f32_samples.unwrap_or(case.samples),
    };
    let name = case.name;
    let (mut worst, mut worst_fit) = (0.0_f64, 0.0_f64);
    for (i, h) in hist.iter().enumerate() {
        let p = batch.params_of(0, i);
        let (cpu_score, diverged) = score_one(&problem, 0, p, 0.0);
        assert!(!diverged, "{name} candidate {i} diverged on the CPU");
        let g_score = scores.get(i, 0);
        assert!(
            g_score < DIVERGED,
            "{name} {precision:?} candidate {i}: diverged on the GPU"
        );
        let err = (g_score - cpu_score).abs() / cpu_score.abs().max(1e-3);
        assert!(
            err <= fit_tol,
            "{name} {precision:?} candidate {i}: fitness GPU {g_score:e} vs CPU {cpu_score:e}"
        );
        worst_fit = worst_fit.max(err);
        let cpu = simulate_history(&problem, 0, p, 0.0);
        let g = &h[0];
        assert_eq!(g.outputs.len(), cpu.outputs.len());
        assert_eq!(g.states.len(), cpu.states.len());
        let series = cpu
            .outputs
            .iter()
            .zip(&g.outputs)
            .chain(cpu.states.iter().zip(&g.states));
        for (s, (c, gg)) in series.enumerate() {
            assert_eq!(c.len(), gg.len());
            let scale = c.iter().fold(f64::MIN_POSITIVE, |m, v| m.max(v.abs()));
            for (k, (x, y)) in gg.iter().zip(c).enumerate().take(span) {
                let err = (x - y).abs() / scale;
                assert!(
                    err <= tol,
                    "{name} {precision:?} candidate {i} series {s} sample {k}: GPU {x} vs CPU {y} ({err:.2e} of {scale:.3e})"
                );
                worst = worst.max(err);
            }
        }
    }
    (worst, worst_fit)
}

#[test]
fn the_cases_sample_and_switch_as_they_claim() {
    for case in cases() {
        let p = &params_of(&case)[0];
        // The command moves: the controller acts.
        let problem = problem(&case);
        let h = simulate_history(&problem, 0, p, 0.0);
        let command = &h.outputs[1];
        assert!(
            command.iter().any(|&u| u != command[0]),
            "{}: the command never changes",
            case.name
        );
    }
    // The stick-slip case: switches in steps that an instant cuts.
    let case = cases().pop().unwrap();
    let p = &params_of(&case)[0];
    let mut st = case.rig.stepper(p, &case.drive).unwrap();
    let mut y = st.y0.clone();
    let h = case.dt / case.substeps as f64;
    let steps = (case.samples - 1) * case.substeps;
    for i in 0..steps {
        st.step(i as f64 * h, h, &mut y);
    }
    assert!(!st.chattered);
    let period = 0.7e-3;
    let shared_steps = st
        .fired
        .iter()
        .filter(|f| {
            let i = (f.t / h).floor();
            // An instant strictly inside step i.
            let k = ((i * h) / period).floor() + 1.0;
            k * period < (i + 1.0) * h - 1e-9 * period
        })
        .count();
    assert!(
        st.fired.len() > 8 && shared_steps > 4,
        "{} switches, {shared_steps} in steps cut at an instant",
        st.fired.len()
    );
}

#[test]
fn every_shipped_rig_with_controllers_has_a_case() {
    let covered: Vec<String> = cases().iter().map(|c| c.rig.id().to_string()).collect();
    for (id, _) in rigfit::rig::SHIPPED {
        if !rigfit::rig::shipped(id).unwrap().controllers.is_empty() {
            assert!(covered.iter().any(|c| c == id), "rig {id} has no case here");
        }
    }
}

#[test]
fn controlled_rigs_match_the_cpu_reference_in_f64() {
    let Some(ctx) = common::gpu() else { return };
    if !ctx.has_f64() {
        panic!("the adapter has no SHADER_F64: {}", ctx.describe());
    }
    for case in cases() {
        let (h, f) = compare(&ctx, Precision::F64, &case);
        println!(
            "{} f64: histories within {h:.2e}, fitness within {f:.2e}",
            case.name
        );
    }
}

#[test]
fn controlled_rigs_match_the_cpu_reference_in_f32() {
    let Some(ctx) = common::gpu() else { return };
    for case in cases() {
        let (h, f) = compare(&ctx, Precision::F32, &case);
        println!(
            "{} f32: histories within {h:.2e}, fitness within {f:.2e}",
            case.name
        );
    }
}
