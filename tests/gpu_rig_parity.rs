//! Compiled rigs on the GPU reproduce the f64 CPU reference (`EventStepper`):
//! every output and every state of every candidate's history, the fitness and
//! divergence, for every shipped rig and for runs with many located switches
//! (a stick-slip block under a slow sine, a mass in free play between two stops
//! closing and opening every half cycle, a backlash element taking up and
//! leaving its play state every half cycle), and every shipped campaign that names
//! a rig, over candidates spread through its search box. f64 within
//! [`F64_HISTORY_TOLERANCE`] of each series' largest magnitude; f32 within
//! [`F32_HISTORY_TOLERANCE`].
mod oracle;
mod tensile_common;

mod gpu_common;
use gpu_common as common;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use rigfit::base::{Drive, PiecewiseLinear};
use rigfit::campaign::Campaign;
use rigfit::eval::{
    Batch, Evaluator, ExperimentData, Precision, Problem, score_one, simulate_history,
};
use rigfit::gpu::{F32_HISTORY_TOLERANCE, F64_HISTORY_TOLERANCE, GpuContext};
use rigfit::model::compiled::CompiledRig;
use rigfit::search::GeneSpec;

/// One rig, one drive, a seeded spread of candidates around `centre`.
struct Case {
    name: &'static str,
    rig: std::sync::Arc<CompiledRig>,
    drive: Drive,
    centre: Vec<f64>,
    /// Which parameters vary between candidates (log-uniform ×/÷ `spread`).
    vary: Vec<usize>,
    spread: f64,
    dt: f64,
    samples: usize,
    substeps: usize,
    /// Located switches the centre candidate must take (so the case tests events).
    min_events: usize,
    /// Samples over which f32 is held to its tolerance (all when `None`).
    f32_samples: Option<usize>,
}

fn shipped(id: &str) -> std::sync::Arc<CompiledRig> {
    CompiledRig::shared(rigfit::rig::shipped(id).unwrap(), id).unwrap()
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

/// A mass on a soft spring between two stiff stops (free play ±gap), pushed by
/// the experiment's force table: contact closes and opens every half cycle.
const FREE_PLAY: &str = r#"{
  "id": "free_play_oscillator",
  "params": [
    {"name": "m", "unit": "kg", "scale": "log"},
    {"name": "k", "unit": "N/m", "scale": "log"},
    {"name": "k_stop", "unit": "N/m", "scale": "log"},
    {"name": "gap", "unit": "m"},
    {"name": "c", "unit": "N·s/m"}
  ],
  "nodes": [{"name": "mass", "mass": "m"}],
  "elements": [
    {"name": "spring", "between": ["ground", "mass"], "spring": {"law": "linear", "k": "k"},
     "damper": {"law": "viscous", "c": "c"}},
    {"name": "stops", "between": ["ground", "mass"], "spring": {"law": "linear", "k": "k_stop"},
     "gap": {"kind": "free_play", "size": "gap"}}
  ],
  "drives": [{"mode": "force", "node": "mass", "law": {"type": "force_table"}}],
  "outputs": [
    {"name": "stop_force", "unit": "N", "sum": [{"force": "stops"}]},
    {"name": "displacement", "unit": "m", "sum": [{"displacement": "mass"}]}
  ],
  "reach": {"elongation": 0.01, "rate": 1.0}
}"#;

fn cases() -> Vec<Case> {
    let tensile = shipped("tensile4");
    let reference = tensile_common::REFERENCE.to_vec();
    let ix = |r: &CompiledRig, n: &str| r.params().iter().position(|p| p.name == n).unwrap();
    let free_play = CompiledRig::shared(
        serde_json::from_str(FREE_PLAY).unwrap(),
        "free_play_oscillator (test)",
    )
    .unwrap();
    let duffing = shipped("duffing_base");
    let mut formula: serde_json::Value = serde_json::from_str(
        rigfit::rig::SHIPPED
            .iter()
            .find(|(i, _)| *i == "duffing_base")
            .unwrap()
            .1,
    )
    .unwrap();
    formula["elements"][0]["spring"] =
        serde_json::json!({"law": "expression", "force": "k*x + k3*x^3 + 0.01*k*spow(x, 1.5)"});
    formula["elements"][0]["damper"] = serde_json::json!({
        "law": "expression",
        "force": "c*v + 0.5*c*v*abs(v) + 0.1*c*tanh(v/0.01)"
    });
    let formula = CompiledRig::shared(
        serde_json::from_value(formula).unwrap(),
        "duffing with expression laws (test)",
    )
    .unwrap();
    let stick = shipped("stick_slip");
    let backlash_file = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/backlash_sdof.json");
    let backlash = CompiledRig::shared(
        rigfit::rig::parse(
            &std::fs::read_to_string(backlash_file).unwrap(),
            &rigfit::rig::RigSource::File(backlash_file.into()),
        )
        .unwrap(),
        backlash_file,
    )
    .unwrap();
    vec![
        Case {
            name: "tensile4 (slack engagement, yield, fracture)",
            rig: tensile.clone(),
            drive: Drive::Velocity,
            vary: ["k1", "c1", "k3", "k4_lin", "c4", "gap", "e_fracture", "m2"]
                .iter()
                .map(|n| ix(&tensile, n))
                .collect(),
            centre: reference,
            spread: 1.5,
            dt: tensile_common::REFERENCE_DT,
            samples: 600,
            substeps: tensile_common::REFERENCE_SUBSTEPS,
            min_events: 3,
            f32_samples: None,
        },
        Case {
            name: "duffing_base (inline base-acceleration table)",
            rig: duffing,
            drive: Drive::Velocity,
            centre: vec![1.0, 4e4, 4e10, 20.0],
            vary: vec![0, 1, 2, 3],
            spread: 2.0,
            dt: 2e-4,
            samples: 500,
            substeps: 2,
            min_events: 0,
            f32_samples: None,
        },
        Case {
            name: "expression laws (spow, abs, tanh) on the Duffing rig",
            rig: formula,
            drive: Drive::Velocity,
            centre: vec![1.0, 4e4, 4e10, 20.0],
            vary: vec![0, 1, 2, 3],
            spread: 2.0,
            dt: 2e-4,
            samples: 500,
            substeps: 2,
            min_events: 0,
            f32_samples: None,
        },
        Case {
            name: "stick_slip under a slow sine (force table)",
            rig: stick,
            drive: sine_table(20.0, 2.0, 1.0, 401),
            centre: vec![1.0, 10.0, 1e4, 2.0],
            vary: vec![0, 1, 2, 3],
            spread: 1.3,
            dt: 1e-3,
            samples: 1000,
            substeps: 4,
            min_events: 6,
            f32_samples: None,
        },
        Case {
            name: "free play closing and opening every half cycle",
            rig: free_play,
            drive: sine_table(30.0, 5.0, 0.6, 601),
            centre: vec![1.0, 1e3, 1e5, 0.01, 20.0],
            vary: vec![0, 1, 2, 3, 4],
            spread: 1.3,
            dt: 2e-4,
            samples: 3000,
            substeps: 2,
            min_events: 10,
            // An impact oscillator magnifies rounding at every impact, grazing
            // ones most: f32 holds 2e-4 over the first 2000 of the 3000 samples,
            // and some candidates exceed it later (4e-4 by sample 2730); f64
            // holds 1e-9 throughout.
            f32_samples: Some(2000),
        },
        Case {
            name: "backlash taking up and leaving its play every half cycle",
            rig: backlash,
            drive: sine_table(20.0, 5.0, 1.0, 1001),
            // m, k, c, b (f0 and freq drive the velocity mode only).
            centre: vec![1.0, 1e4, 60.0, 1e-3, 20.0, 5.0],
            vary: vec![0, 1, 2, 3],
            spread: 1.3,
            dt: 1e-3,
            samples: 1000,
            substeps: 4,
            min_events: 16,
            f32_samples: None,
        },
    ]
}

const CANDIDATES: usize = 96;

/// Samples of a shipped campaign's records over which f32 is held to its
/// tolerance: f32 time carries the phase of a sine drive to ~1e-7 relative, and
/// a resonant rig integrates that error (the inertial rig's velocity reaches
/// 2.3e-4 of the largest acceleration by sample 1495 of its swept-sine record).
const F32_CAMPAIGN_SAMPLES: usize = 1000;

fn params_of(case: &Case) -> Vec<Vec<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    (0..CANDIDATES)
        .map(|i| {
            let mut p = case.centre.clone();
            if i > 0 {
                for &j in &case.vary {
                    p[j] *= case.spread.powf(rng.random_range(-1.0..=1.0));
                }
            }
            p
        })
        .collect()
}

/// A problem whose record is the centre candidate's first output.
fn problem(case: &Case) -> Problem {
    let mut exp = ExperimentData {
        output: 0,
        name: case.name.into(),
        drive: case.drive.clone(),
        t_first: 0.0,
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
    let h = simulate_history(&p, 0, &case.centre, 0.0);
    exp.measured = h.outputs[0]
        .iter()
        .enumerate()
        .map(|(k, f)| f * (1.0 + 0.01 * (k as f64 * 0.37).sin()))
        .collect();
    p.experiments[0] = exp;
    p
}

/// Located switches the centre candidate takes over the whole record.
fn events(case: &Case) -> usize {
    let mut st = case.rig.stepper(&case.centre, &case.drive).unwrap();
    let mut y = vec![0.0; case.rig.state_names().len()];
    let h = case.dt / case.substeps as f64;
    for i in 0..(case.samples - 1) * case.substeps {
        st.step(i as f64 * h, h, &mut y);
    }
    assert!(!st.chattered, "{}: the centre run chatters", case.name);
    st.fired.len()
}

/// Largest relative history difference over every output and state of
/// `batch` on `problem`'s experiments (the first `span` samples, or all; in f32
/// `F32_HISTORY_TOLERANCE`, in f64 `F64_HISTORY_TOLERANCE`); checks fitness and
/// divergence on the way.
fn compare_batch(
    ctx: &GpuContext,
    precision: Precision,
    name: &str,
    problem: &Problem,
    batch: &Batch,
    span: Option<usize>,
) -> f64 {
    let mut gpu = common::evaluator(ctx, problem, precision);
    let scores = gpu.fitness(batch).unwrap();
    let which: Vec<usize> = (0..batch.candidates).collect();
    let hist = gpu.histories(batch, &which).unwrap();
    let tol = match precision {
        Precision::F64 => F64_HISTORY_TOLERANCE,
        Precision::F32 => F32_HISTORY_TOLERANCE,
    };
    let mut worst = 0.0_f64;
    let mut compared = 0;
    for (e, exp) in problem.experiments.iter().enumerate() {
        let samples = exp.window.end;
        let span = match precision {
            Precision::F64 => samples,
            Precision::F32 => span.unwrap_or(samples).min(samples),
        };
        for (i, h) in hist.iter().enumerate() {
            let (p, offset) = (batch.params_of(e, i), batch.offsets[e][i]);
            let (cpu_score, diverged) = score_one(problem, e, p, offset);
            let g_score = scores.get(i, e);
            assert_eq!(
                g_score >= rigfit::eval::DIVERGED,
                diverged,
                "{name} experiment {e} candidate {i}: GPU {g_score:e} vs CPU {cpu_score:e}"
            );
            if diverged {
                continue;
            }
            compared += 1;
            let cpu = simulate_history(problem, e, p, offset);
            let g = &h[e];
            let series = cpu
                .outputs
                .iter()
                .zip(&g.outputs)
                .chain(cpu.states.iter().zip(&g.states));
            for (s, (c, gg)) in series.enumerate() {
                assert_eq!(c.len(), gg.len());
                let scale = c.iter().fold(f64::MIN_POSITIVE, |m, v| m.max(v.abs()));
                for k in 0..c.len().min(span) {
                    let err = (gg[k] - c[k]).abs() / scale;
                    assert!(
                        err <= tol,
                        "{name} {precision:?} experiment {e} candidate {i} series {s} sample {k}: GPU {} vs CPU {} ({err:.2e} of {scale:.3e})",
                        gg[k],
                        c[k]
                    );
                    worst = worst.max(err);
                }
            }
            if span < samples {
                continue;
            }
            // 1 − R² from residuals of ~1 % of the record: its relative accuracy
            // is the history's over the residual's size.
            let f_tol = tol * 1e3 * (1.0 + cpu_score);
            assert!(
                (g_score - cpu_score).abs() <= f_tol * cpu_score.max(1e-3),
                "{name} experiment {e} candidate {i}: fitness GPU {g_score:e} vs CPU {cpu_score:e}"
            );
        }
    }
    let runs = batch.candidates * problem.experiments.len();
    assert!(
        compared >= runs / 2,
        "{name}: only {compared} of {runs} runs ran"
    );
    worst
}

/// [`compare_batch`] for a case.
fn compare(ctx: &GpuContext, precision: Precision, case: &Case) -> f64 {
    let problem = problem(case);
    let params = params_of(case);
    let batch = Batch {
        candidates: params.len(),
        params: vec![params.concat()],
        offsets: vec![vec![0.0; params.len()]],
    };
    compare_batch(
        ctx,
        precision,
        case.name,
        &problem,
        &batch,
        case.f32_samples,
    )
}

/// Every shipped campaign that names a rig (`campaigns/*.json` with `"rig"`),
/// but those that fit several measured channels: their kernels come in one
/// group per channel, held to the CPU by `gpu_channels_parity.rs`.
fn rig_campaigns() -> Vec<Campaign> {
    common::campaign_files()
        .into_iter()
        .filter(|p| {
            let v: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap();
            v.get("rig").is_some()
        })
        .map(|p| Campaign::load(&p).unwrap())
        .filter(|c| c.problem.experiments.iter().all(|x| x.output == 0))
        .collect()
}

/// Genomes through a campaign's search box: the start point, then each gene
/// moved by up to a fifth of its range (in its search scale), seeded.
fn genomes(c: &Campaign, n: usize) -> Vec<Vec<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let start: Vec<f64> = c
        .genes
        .iter()
        .map(|g| {
            let spec = GeneSpec::new(g.name.clone(), g.lower, g.upper, g.scale);
            g.init.unwrap_or_else(|| spec.at_fraction(0.5))
        })
        .collect();
    (0..n)
        .map(|i| {
            c.genes
                .iter()
                .zip(&start)
                .map(|(g, &v)| {
                    if i == 0 {
                        return v;
                    }
                    let spec = GeneSpec::new(g.name.clone(), g.lower, g.upper, g.scale);
                    let (lo, hi) = spec.scaled_bounds();
                    let x = spec.to_scaled(v) + 0.2 * (hi - lo) * rng.random_range(-1.0..=1.0);
                    spec.to_value(x.clamp(lo, hi))
                })
                .collect()
        })
        .collect()
}

#[test]
fn every_shipped_rig_has_a_parity_case() {
    let all = cases();
    let campaigns = rig_campaigns();
    let mut covered: Vec<&str> = all.iter().map(|c| c.rig.id()).collect();
    covered.extend(campaigns.iter().map(|c| c.model.id()));
    for (id, _) in rigfit::rig::SHIPPED {
        // A rig with controllers has its cases in tests/gpu_controller_parity.rs,
        // which checks that it covers every one.
        if !rigfit::rig::shipped(id).unwrap().controllers.is_empty() {
            continue;
        }
        assert!(covered.contains(&id), "rig {id} has no GPU parity case");
    }
}

#[test]
fn the_cases_take_their_located_switches() {
    for case in cases() {
        let n = events(&case);
        println!("{}: {n} located switches", case.name);
        assert!(n >= case.min_events, "{}: {n} events", case.name);
    }
}

#[test]
fn compiled_rigs_match_the_cpu_reference_in_f64() {
    let Some(ctx) = common::gpu() else { return };
    if !ctx.has_f64() {
        panic!("the adapter has no SHADER_F64: {}", ctx.describe());
    }
    for case in cases() {
        let worst = compare(&ctx, Precision::F64, &case);
        println!("{} f64: largest history difference {worst:.2e}", case.name);
    }
    for c in rig_campaigns() {
        let batch = c.batch(&genomes(&c, 48));
        let worst = compare_batch(&ctx, Precision::F64, &c.name, &c.problem, &batch, None);
        println!(
            "campaign {} f64: largest history difference {worst:.2e}",
            c.name
        );
    }
}

#[test]
fn compiled_rigs_match_the_cpu_reference_in_f32() {
    let Some(ctx) = common::gpu() else { return };
    for case in cases() {
        let worst = compare(&ctx, Precision::F32, &case);
        println!("{} f32: largest history difference {worst:.2e}", case.name);
    }
    for c in rig_campaigns() {
        if c.solver.precision == rigfit::eval::PrecisionChoice::F64 {
            // A campaign that pins f64 says f32 cannot resolve its rig: the
            // EMPS controller's gain kv·kp·gtau is 1.4e6 N/m, so f32 positions
            // (4e-9 m at 0.06 m) put 5e-3 N into every force.
            println!("campaign {} pins f64: no f32 comparison", c.name);
            continue;
        }
        let batch = c.batch(&genomes(&c, 48));
        let worst = compare_batch(
            &ctx,
            Precision::F32,
            &c.name,
            &c.problem,
            &batch,
            Some(F32_CAMPAIGN_SAMPLES),
        );
        println!(
            "campaign {} f32: largest history difference {worst:.2e}",
            c.name
        );
    }
}
