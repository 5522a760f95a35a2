//! One GPU job over experiments of different drive modes of a compiled rig
//! (`rigs/tensile4.json`: velocity, force table, velocity, in that order): the
//! kernels of each mode score their own experiments and the results come back
//! in the campaign's order, equal to the f64 CPU reference per (candidate,
//! experiment) in fitness, histories and the polish's residuals, and
//! `rigfit run --backend gpu` runs such a campaign (`rigfit check` estimating
//! its GPU memory).
mod oracle;
mod tensile_common;

mod gpu_common;
use gpu_common as common;

use std::path::Path;
use std::process::Command;

use rigfit::base::{Drive, PiecewiseLinear};
use rigfit::eval::{
    Backend, Batch, CpuEvaluator, DIVERGED, Evaluator, ExperimentData, Precision, PrecisionChoice,
    Problem, simulate_history,
};
use rigfit::gpu::{
    F32_HISTORY_TOLERANCE, F64_HISTORY_TOLERANCE, GpuByDrive, GpuError, GpuEvaluator, GpuOptions,
    kernel_groups, open_evaluator,
};
use rigfit::model::compiled::CompiledRig;
use rigfit::model::param_index;
use rigfit::search::ResidualCost;
use serde_json::{Value, json};
use tensile_common::REFERENCE;

fn rig() -> std::sync::Arc<CompiledRig> {
    CompiledRig::shared(rigfit::rig::shipped("tensile4").unwrap(), "tensile4").unwrap()
}

fn table() -> PiecewiseLinear {
    PiecewiseLinear {
        t: vec![0.0, 5.0e-5, 2.0e-4, 6.0e-4],
        value: vec![0.0, 5.0e4, 2.0e5, 2.0e5],
    }
}

/// Reference parameters with the actuator at `velocity` (m/s).
fn reference(velocity: f64) -> Vec<f64> {
    let mut p = REFERENCE.to_vec();
    p[param_index(&rig(), "velocity").unwrap()] = velocity;
    p
}

/// An experiment whose measured force is the reference rig's own history
/// (the actuator at `velocity` m/s where the drive is a velocity).
fn experiment(
    name: &str,
    drive: Drive,
    velocity: f64,
    samples: usize,
    dt: f64,
    t_first: f64,
) -> ExperimentData {
    common::self_measured(
        &rig(),
        &reference(velocity),
        name,
        drive,
        (samples, dt, t_first),
    )
}

/// Velocity, force, velocity: the modes interleave.
fn problem() -> Problem {
    let mut fast = experiment("fast", Drive::Velocity, 2.0, 300, 1.0e-6, 2.5e-6);
    fast.window = 20..300;
    let mut force = experiment("force", Drive::Force(table()), 2.0, 200, 2.0e-6, 0.0);
    force.window = 10..150;
    let slow = experiment("slow", Drive::Velocity, 0.5, 240, 1.5e-6, 0.0);
    Problem {
        model: rig(),
        experiments: vec![fast, force, slow],
        substeps: 2,
    }
}

/// Seeded candidates around the reference; each velocity experiment at its
/// own speed, clock offsets varying by candidate.
fn batch(candidates: usize) -> Batch {
    let params = common::spread_params(candidates, 17);
    let v = param_index(&rig(), "velocity").unwrap();
    let p = rig().params().len();
    let at = |speed: f64| -> Vec<f64> {
        let mut q = params.clone();
        q.chunks_mut(p).for_each(|c| c[v] = speed);
        q
    };
    let offsets: Vec<f64> = (0..candidates).map(|i| (i % 3) as f64 * 0.7e-6).collect();
    Batch {
        candidates,
        params: vec![at(2.0), params.clone(), at(0.5)],
        offsets: vec![offsets.clone(), offsets.clone(), offsets],
    }
}

fn precisions(ctx: &rigfit::gpu::GpuContext) -> Vec<(Precision, f64, f64)> {
    let mut out = vec![(Precision::F32, 1e-3, F32_HISTORY_TOLERANCE)];
    if ctx.has_f64() {
        out.push((Precision::F64, 1e-9, F64_HISTORY_TOLERANCE));
    }
    out
}

#[test]
fn the_experiments_fall_into_one_kernel_group_per_drive_mode() {
    let problem = problem();
    let groups: Vec<Vec<usize>> = kernel_groups(&problem)
        .unwrap()
        .into_iter()
        .map(|g| g.experiments)
        .collect();
    assert_eq!(groups, vec![vec![0, 2], vec![1]]);
    assert!(matches!(
        rigfit::gpu::gpu_model(&problem),
        Err(GpuError::MixedDrives(_))
    ));
}

#[test]
fn mixed_drive_fitness_and_histories_match_cpu() {
    let Some(ctx) = common::gpu() else { return };
    let problem = problem();
    let batch = batch(48);
    let cpu = CpuEvaluator::new(problem.clone(), 0)
        .fitness(&batch)
        .unwrap();
    for e in 0..3 {
        let ok = (0..batch.candidates)
            .filter(|&i| cpu.get(i, e) < DIVERGED)
            .count();
        assert!(
            ok > batch.candidates / 2,
            "experiment {e}: {ok} finite runs"
        );
    }
    for (precision, fit_tol, hist_tol) in precisions(&ctx) {
        let mut gpu = GpuByDrive::new(
            ctx.clone(),
            problem.clone(),
            precision,
            GpuOptions::default(),
        )
        .unwrap();
        assert_eq!(gpu.groups(), vec![vec![0, 2], vec![1]]);
        let g = gpu.fitness(&batch).unwrap();
        assert_eq!(g.experiments, 3);
        assert_eq!(g.diverged, cpu.diverged, "{precision:?}");
        let mut worst = 0.0_f64;
        for i in 0..batch.candidates {
            for e in 0..3 {
                let (a, b) = (g.get(i, e), cpu.get(i, e));
                let err = (a - b).abs() / b.abs().max(1e-3);
                assert!(
                    err <= fit_tol,
                    "{precision:?} candidate {i} experiment {e}: {a} vs {b}"
                );
                worst = worst.max(err);
            }
        }
        let hist = histories_match(&mut gpu, &problem, &batch, &[0, 1, 4, 7], hist_tol);
        eprintln!(
            "{precision:?}: fitness within {worst:.2e} (relative), histories within {hist:.2e} of the largest |F|"
        );
    }
}

/// Each group's runs are the same bits as a job of that group alone.
#[test]
fn each_mode_scores_as_it_would_alone() {
    let Some(ctx) = common::gpu() else { return };
    let problem = problem();
    let batch = batch(24);
    let precision = precisions(&ctx).last().unwrap().0;
    let mixed = GpuByDrive::new(
        ctx.clone(),
        problem.clone(),
        precision,
        GpuOptions::default(),
    )
    .unwrap()
    .fitness(&batch)
    .unwrap();
    for group in [vec![0, 2], vec![1]] {
        let sub = Problem {
            model: problem.model.clone(),
            experiments: group
                .iter()
                .map(|&e| problem.experiments[e].clone())
                .collect(),
            substeps: problem.substeps,
        };
        let sub_batch = Batch {
            candidates: batch.candidates,
            params: group.iter().map(|&e| batch.params[e].clone()).collect(),
            offsets: group.iter().map(|&e| batch.offsets[e].clone()).collect(),
        };
        let alone = common::evaluator(&ctx, &sub, precision)
            .fitness(&sub_batch)
            .unwrap();
        for i in 0..batch.candidates {
            for (k, &e) in group.iter().enumerate() {
                assert_eq!(
                    mixed.get(i, e).to_bits(),
                    alone.get(i, k).to_bits(),
                    "candidate {i} experiment {e}"
                );
            }
        }
    }
    // One evaluator cannot take both modes; the backend selection opens the
    // composite one instead of falling back to the CPU.
    assert!(matches!(
        GpuEvaluator::new(ctx, problem.clone(), precision, GpuOptions::default()),
        Err(GpuError::MixedDrives(_))
    ));
    for backend in [Backend::Auto, Backend::Gpu] {
        let opened = open_evaluator(problem.clone(), backend, PrecisionChoice::F32).unwrap();
        assert_eq!(opened.note, None, "{backend:?}");
        assert_eq!(opened.evaluator.info().backend, "gpu", "{backend:?}");
    }
}

/// GPU histories of candidates `which` within `tol` of the largest force of
/// the CPU reference's; returns the largest difference so measured.
fn histories_match(
    gpu: &mut impl Evaluator,
    problem: &Problem,
    batch: &Batch,
    which: &[usize],
    tol: f64,
) -> f64 {
    let hist = gpu.histories(batch, which).unwrap();
    assert_eq!(hist.len(), which.len());
    let mut worst = 0.0_f64;
    for (h, &i) in hist.iter().zip(which) {
        assert_eq!(h.len(), problem.experiments.len());
        for (e, he) in h.iter().enumerate() {
            let c = simulate_history(problem, e, batch.params_of(e, i), batch.offsets[e][i]);
            assert_eq!(he.t.len(), c.t.len(), "candidate {i} experiment {e}");
            let scale = c.outputs[0]
                .iter()
                .fold(f64::MIN_POSITIVE, |m, f| m.max(f.abs()));
            for (k, (x, y)) in he.outputs[0].iter().zip(&c.outputs[0]).enumerate() {
                let d = (x - y).abs() / scale;
                assert!(
                    d <= tol,
                    "candidate {i} experiment {e} sample {k}: {x} vs {y}"
                );
                worst = worst.max(d);
            }
        }
    }
    worst
}

/// A campaign on the shipped tensile4 rig with a velocity, a force-table and
/// a velocity experiment, its records simulated from the reference rig.
fn write_campaign(dir: &Path) -> std::path::PathBuf {
    let problem = problem();
    for exp in &problem.experiments {
        let mut csv = String::from("t_s,force_N\n");
        for (k, f) in exp.measured.iter().enumerate() {
            csv += &format!("{:e},{:e}\n", exp.t_first + k as f64 * exp.dt, f);
        }
        std::fs::write(dir.join(format!("{}.csv", exp.name)), csv).unwrap();
    }
    let data = |name: &str| json!({"file": format!("{name}.csv"), "time_column": "t_s", "force_column": "force_N"});
    let t = table();
    // Every parameter fixed at the reference but two stiffness/damping genes;
    // the velocity is each experiment's own (unused by the force drive).
    let mut params = serde_json::Map::new();
    for (info, value) in rig().params().iter().zip(REFERENCE) {
        if info.name != "velocity" {
            params.insert(info.name.clone(), json!(value));
        }
    }
    params.insert(
        "k1".into(),
        json!({"min": 4e9, "max": 2e10, "scale": "log"}),
    );
    params.insert("c1".into(), json!({"min": 2e5, "max": 1e6, "scale": "log"}));
    let c: Value = json!({
        "name": "tensile4-mixed-drives",
        "rig": "tensile4",
        "params": params,
        "experiments": [
            {"name": "fast", "data": data("fast"), "params": {"velocity": 2.0}},
            {"name": "force", "data": data("force"), "params": {"velocity": 2.0},
             "drive": {"force": {"t": t.t, "value": t.value}}},
            {"name": "slow", "data": data("slow"), "params": {"velocity": 0.5}}
        ],
        "solver": {"substeps": 2, "backend": "gpu", "precision": "f32"},
        "search": {"population": 32, "generations": 2, "seed": 3,
                   "polish": {"starts": 1, "max_iterations": 1}}
    });
    let path = dir.join("campaign.json");
    std::fs::write(&path, serde_json::to_string_pretty(&c).unwrap()).unwrap();
    path
}

#[test]
fn rigfit_run_with_backend_gpu_takes_mixed_drive_modes() {
    if common::gpu().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let campaign = write_campaign(dir.path());
    let out = dir.path().join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .arg("run")
        .arg(&campaign)
        .arg("--out")
        .arg(&out)
        .args(["--backend", "gpu"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "rigfit run failed: {err}");
    assert!(err.contains("on gpu"), "{err}");
    assert!(!err.contains("using the CPU"), "{err}");
    let r: Value =
        serde_json::from_slice(&std::fs::read(out.join("result.json")).unwrap()).unwrap();
    assert_eq!(r["backend"], json!("gpu"));
    for name in ["fast", "force", "slow"] {
        assert!(out.join(format!("{name}.csv")).is_file(), "no {name}.csv");
    }
    // `check` estimates the GPU path's memory for it too.
    let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(["--json", "check"])
        .arg(&campaign)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let check: Value = serde_json::from_slice(&o.stdout).unwrap();
    let (gpu, cpu) = (&check["memory"]["gpu"], &check["memory"]["cpu"]);
    assert!(
        gpu["total"].as_f64().unwrap() > cpu["total"].as_f64().unwrap(),
        "{check}"
    );
}

/// The polish's residuals of the mixed campaign through the composite
/// evaluator agree with the CPU reference's.
#[test]
fn polish_residuals_of_a_mixed_campaign_match_the_cpu() {
    let Some(ctx) = common::gpu() else { return };
    let dir = tempfile::tempdir().unwrap();
    let c = rigfit::campaign::Campaign::load(&write_campaign(dir.path())).unwrap();
    let genomes = vec![vec![8.4e9, 5.51e5], vec![8.4e9 * 1.05, 5.51e5 * 0.9]];
    let residuals = |ev: Box<dyn Evaluator>| -> Vec<Vec<f64>> {
        rigfit::job::CampaignCost::new(&c, ev, true, 0)
            .residuals(&genomes)
            .unwrap()
            .into_iter()
            .map(Option::unwrap)
            .collect()
    };
    let cpu = residuals(Box::new(CpuEvaluator::new(c.problem.clone(), 0)));
    // A force error of ε·F_max is a residual error of at most ε·F_max/√SS_tot.
    let scale = c
        .problem
        .experiments
        .iter()
        .map(|x| x.measured.iter().fold(0.0_f64, |m, f| m.max(f.abs())) / x.ss_tot().sqrt())
        .fold(0.0_f64, f64::max);
    for (precision, _, tol) in precisions(&ctx) {
        let gpu = residuals(Box::new(
            GpuByDrive::new(
                ctx.clone(),
                c.problem.clone(),
                precision,
                GpuOptions::default(),
            )
            .unwrap(),
        ));
        let mut worst = 0.0_f64;
        for (a, b) in cpu.iter().zip(&gpu) {
            assert!(!a.is_empty());
            assert_eq!(a.len(), b.len());
            for (x, y) in a.iter().zip(b) {
                worst = worst.max((x - y).abs() / scale);
            }
        }
        eprintln!("{precision:?}: residuals within {worst:.2e} of F_max");
        assert!(worst <= tol, "{precision:?}: {worst:e} of F_max");
    }
}
