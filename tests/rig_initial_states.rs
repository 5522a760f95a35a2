//! Per-experiment initial states (`experiments[].initial`): fixed, free and
//! from the data; the regimes a run starts in; the CPU reference, the lane
//! ensemble and the GPU kernels alike; bad input refused with exit 2.
mod oracle;
mod tensile_common;

mod gpu_common;

use std::ops::ControlFlow;
use std::path::Path;
use std::process::Command;

use rigfit::base::Report;
use rigfit::campaign::Campaign;
use rigfit::eval::{Batch, CpuEvaluator, Evaluator, Precision, simulate_history};
use rigfit::gpu::{F32_HISTORY_TOLERANCE, F64_HISTORY_TOLERANCE};
use rigfit::job::{self, JobOptions};
use rigfit::model::param_index;
use serde_json::{Value, json};

const M: f64 = 1.0;
const K: f64 = 4e4;
const C: f64 = 20.0;
const DT: f64 = 1e-4;

/// A mass on a spring and a damper to ground, a stop (spring `k_c` behind a
/// tension gap of 1 mm), no drive; output 0 the spring-damper force, then the
/// stop's force.
fn rig() -> Value {
    json!({
        "id": "msd",
        "params": [
            {"name": "m", "unit": "kg", "default": M},
            {"name": "k", "unit": "N/m", "default": K},
            {"name": "c", "unit": "N·s/m", "default": C},
            {"name": "k_c", "unit": "N/m", "default": 0.0}
        ],
        "nodes": [{"name": "mass", "mass": "m"}],
        "elements": [
            {"name": "spring", "between": ["ground", "mass"],
             "spring": {"law": "linear", "k": "k"}, "damper": {"law": "viscous", "c": "c"}},
            {"name": "stop", "between": ["ground", "mass"],
             "spring": {"law": "linear", "k": "k_c"}, "gap": {"kind": "tension", "size": 0.001}}
        ],
        "outputs": [
            {"name": "force", "unit": "N", "sum": [{"force": "spring"}]},
            {"name": "stop_force", "unit": "N", "sum": [{"force": "stop"}]}
        ]
    })
}

/// Record text: `t_s`, `force_N` (a placeholder that varies) and `pos_m`
/// (`pos(t)`), `n` samples of `DT`.
fn record(n: usize, force: &dyn Fn(f64) -> f64, pos: &dyn Fn(f64) -> f64) -> String {
    let mut s = String::from("t_s,force_N,pos_m\n");
    for k in 0..n {
        let t = k as f64 * DT;
        s += &format!("{t:e},{:e},{:e}\n", force(t), pos(t));
    }
    s
}

fn placeholder(n: usize) -> String {
    record(n, &|t| (t * 300.0).sin(), &|t| {
        0.002 + 0.3 * t + 5.0 * t * t
    })
}

/// A campaign over the rig with one experiment `e1` whose `initial` is
/// `initial`, reading `record`.
fn campaign(dir: &Path, initial: Value, params: Value, record: &str) -> Result<Campaign, String> {
    let v = json!({
        "name": "initial-states",
        "rig": rig(),
        "params": params,
        "experiments": [{
            "name": "e1",
            "data": {"file": "e1.csv", "time_column": "t_s", "force_column": "force_N"},
            "initial": initial
        }],
        "solver": {"substeps": 4, "backend": "cpu"},
        "search": {"population": 48, "generations": 12, "seed": 3,
                   "polish": {"enabled": true, "starts": 2, "max_iterations": 20}}
    });
    std::fs::write(dir.join("e1.csv"), record).unwrap();
    let path = dir.join("campaign.json");
    std::fs::write(&path, v.to_string()).unwrap();
    Campaign::load(&path).map_err(|e| e.to_string())
}

/// The closed-form free response of `m ẍ + c ẋ + k x = 0` from `(x0, v0)`.
fn free_response(x0: f64, v0: f64, t: f64) -> (f64, f64) {
    let w = (K / M).sqrt();
    let z = C / (2.0 * M * w);
    let wd = w * (1.0 - z * z).sqrt();
    let (a, b) = (x0, (v0 + z * w * x0) / wd);
    let e = (-z * w * t).exp();
    let (s, c) = (wd * t).sin_cos();
    let x = e * (a * c + b * s);
    let v = e * (-z * w * (a * c + b * s) + (-a * wd * s + b * wd * c));
    (x, v)
}

#[test]
fn fixed_initial_displacement_and_velocity_match_the_free_response() {
    let dir = tempfile::tempdir().unwrap();
    let (x0, v0) = (0.0005, -0.3);
    let c = campaign(
        dir.path(),
        json!({"x_mass": x0, "v_mass": v0}),
        json!({}),
        &placeholder(2000),
    )
    .unwrap();
    let p = &c.base[0];
    let ix = |n: &str| param_index(&c.model, n).unwrap();
    assert_eq!((p[ix("initial_x_mass")], p[ix("initial_v_mass")]), (x0, v0));
    let h = simulate_history(&c.problem, 0, p, 0.0);
    let amp = x0.hypot(v0 / (K / M).sqrt());
    let (mut ex, mut ev) = (0.0_f64, 0.0_f64);
    for (k, &t) in h.t.iter().enumerate() {
        let (x, v) = free_response(x0, v0, t);
        ex = ex.max((h.states[0][k] - x).abs());
        ev = ev.max((h.states[1][k] - v).abs());
    }
    let w = (K / M).sqrt();
    println!(
        "largest error against the free response: x {:.2e} m, v {:.2e} m/s ({:.2e}, {:.2e} of the amplitude)",
        ex,
        ev,
        ex / amp,
        ev / (amp * w)
    );
    assert!(ex < 1e-8 * amp && ev < 1e-8 * amp * w, "{ex:e} {ev:e}");
    assert_eq!(h.states[0][0], x0);
    assert_eq!(h.states[1][0], v0);

    // The lane ensemble starts each lane from its own initial state, bit for
    // bit as the scalar reference does.
    let mut q = p.clone();
    q[ix("initial_v_mass")] = 0.7;
    let exp = &c.problem.experiments[0];
    let grid = exp.grid(0.0, c.problem.substeps);
    let runs: Vec<&[f64]> = vec![p, &q, p];
    let mut lanes = vec![vec![]; runs.len()];
    c.model
        .simulate_many(&runs, &exp.drive, &grid, Report::Full, &mut |l, s| {
            lanes[l].push(s.state[0]);
            ControlFlow::Continue(())
        });
    for (l, run) in runs.iter().enumerate() {
        let h = simulate_history(&c.problem, 0, run, 0.0);
        assert_eq!(lanes[l], h.states[0], "lane {l}");
    }
    assert_ne!(lanes[0], lanes[1]);
}

#[test]
fn a_gap_already_closed_starts_in_contact() {
    let dir = tempfile::tempdir().unwrap();
    let k_c = 1e5;
    let x0 = 0.0015;
    let c = campaign(
        dir.path(),
        json!({"x_mass": x0}),
        json!({"k_c": k_c}),
        &placeholder(400),
    )
    .unwrap();
    let exp = &c.problem.experiments[0];
    let h = simulate_history(&c.problem, 0, &c.base[0], 0.0);
    // The stop pushes back from the first sample: k_c·(x0 − gap), and its force
    // at the next sample continues from there (no jump from 0).
    let f0 = k_c * (x0 - 0.001);
    println!(
        "stop force at samples 0, 1, 2: {:.6} {:.6} {:.6} N (k_c·(x0 − gap) = {f0:.6} N)",
        h.outputs[1][0], h.outputs[1][1], h.outputs[1][2]
    );
    assert!((h.outputs[1][0] - f0).abs() < 1e-9 * f0);
    // Over one sample the mass moves by ≈ ½·a·dt², a = −(k·x0 + f0)/m.
    let a = -(K * x0 + f0) / M;
    let expect1 = k_c * 0.5 * a * exp.dt * exp.dt + f0;
    assert!(
        (h.outputs[1][1] - expect1).abs() < 1e-3 * f0,
        "{} vs {expect1}",
        h.outputs[1][1]
    );
    // The mode it starts in, from the stepper.
    let model = c.model;
    let compiled = rigfit::model::compiled::CompiledRig::new(
        {
            let mut d: rigfit::rig::desc::RigDesc = serde_json::from_value(rig()).unwrap();
            d.params.push(
                serde_json::from_value(
                    json!({"name": "initial_x_mass", "unit": "m", "default": 0.0}),
                )
                .unwrap(),
            );
            d
        },
        "inline",
    )
    .unwrap();
    let mut p = c.base[0].clone();
    let st = compiled.stepper(&p, &exp.drive).unwrap();
    assert_eq!(st.regimes, vec![1], "the stop starts closed");
    assert_eq!(st.y0, vec![x0, 0.0]);
    // Exactly at the gap the stop stays open (no switch is past), and below it.
    for x in [0.001, 0.0005] {
        p[param_index(&model, "initial_x_mass").unwrap()] = x;
        assert_eq!(compiled.stepper(&p, &exp.drive).unwrap().regimes, vec![0]);
    }
}

#[test]
fn a_free_initial_velocity_is_recovered_within_its_interval() {
    let dir = tempfile::tempdir().unwrap();
    let (x0, v0) = (0.0002, 0.25);
    // The record: the reference run from the true initial state.
    let truth = campaign(
        dir.path(),
        json!({"x_mass": x0, "v_mass": v0}),
        json!({}),
        &placeholder(600),
    )
    .unwrap();
    let h = simulate_history(&truth.problem, 0, &truth.base[0], 0.0);
    let f = h.outputs[0].clone();
    let text = record(
        600,
        &|t| {
            let k = (t / DT).round() as usize;
            f[k] * (1.0 + 0.002 * ((k as f64) * 0.77).sin())
        },
        &|_| 0.0,
    );
    let c = campaign(
        dir.path(),
        json!({"x_mass": x0, "v_mass": {"min": -1.0, "max": 1.0}}),
        json!({"k": {"min": 2e4, "max": 8e4, "scale": "log"}}),
        &text,
    )
    .unwrap();
    let names: Vec<&str> = c.genes.iter().map(|g| g.name.as_str()).collect();
    assert_eq!(names, ["k", "e1.initial_v_mass"]);
    let out = tempfile::tempdir().unwrap();
    let opts = JobOptions::quiet(out.path());
    let started = std::time::Instant::now();
    let s = job::run(&c, Box::new(CpuEvaluator::new(c.problem.clone(), 0)), &opts).unwrap();
    let p = s
        .parameters
        .iter()
        .find(|p| p.name == "e1.initial_v_mass")
        .unwrap();
    let iv = p.interval_95.expect("an interval");
    println!(
        "e1.initial_v_mass = {:.6} m/s, 95 % interval [{:.6}, {:.6}] (true {v0}); {:.2} s",
        p.value,
        iv[0],
        iv[1],
        started.elapsed().as_secs_f64()
    );
    assert_eq!(p.unit, "m/s");
    assert!(iv[0] <= v0 && v0 <= iv[1], "{iv:?}");
    assert!((p.value - v0).abs() < 0.01 * v0);
}

#[test]
fn values_from_the_data_are_read_from_the_column() {
    let dir = tempfile::tempdir().unwrap();
    // pos = 2 mm + 0.3 m/s·t + 5 m/s²·t²: the first sample, and the one-sided
    // second-order difference, exact for a quadratic.
    let c = campaign(
        dir.path(),
        json!({"x_mass": {"column": "pos_m"}, "v_mass": {"column": "pos_m"}}),
        json!({}),
        &placeholder(50),
    )
    .unwrap();
    let p = &c.base[0];
    let x = p[param_index(&c.model, "initial_x_mass").unwrap()];
    let v = p[param_index(&c.model, "initial_v_mass").unwrap()];
    println!("from the column: x0 = {x:e} m, v0 = {v:e} m/s");
    assert!((x - 0.002).abs() < 1e-15, "{x}");
    assert!((v - 0.3).abs() < 1e-9, "{v}");
    // Millimetres, by index, a value over five samples, a slope over two.
    let c = campaign(
        dir.path(),
        json!({
            "x_mass": {"column": 2, "scale": 1e-3, "samples": 5},
            "v_mass": {"column": "pos_m", "samples": 2}
        }),
        json!({}),
        &placeholder(50),
    )
    .unwrap();
    let p = &c.base[0];
    let x = p[param_index(&c.model, "initial_x_mass").unwrap()];
    let v = p[param_index(&c.model, "initial_v_mass").unwrap()];
    assert!((x - 0.002e-3).abs() < 1e-15, "{x}");
    assert!((v - (0.3 + 5.0 * DT)).abs() < 1e-9, "{v}");
}

#[test]
fn gpu_runs_start_from_the_same_initial_state() {
    let Some(ctx) = gpu_common::gpu() else { return };
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(
        dir.path(),
        json!({"x_mass": 0.0012, "v_mass": {"min": -0.6, "max": 0.6}}),
        json!({"k_c": 2e5}),
        &placeholder(800),
    )
    .unwrap();
    // Candidates from rebounding off the stop to starting into it; 72 runs,
    // so the specialised kernel (the shared initial displacement and regimes
    // folded to literals) runs as well as the generic one (histories).
    let genomes: Vec<Vec<f64>> = (0..72)
        .map(|i| vec![-0.6 + 1.2 * i as f64 / 71.0])
        .collect();
    let batch: Batch = c.batch(&genomes);
    let which: Vec<usize> = (0..genomes.len()).collect();
    for precision in [Precision::F64, Precision::F32] {
        let mut gpu = gpu_common::evaluator(&ctx, &c.problem, precision);
        let hist = gpu.histories(&batch, &which).unwrap();
        let scores = gpu.fitness(&batch).unwrap();
        let baked = gpu.specialised_constants();
        assert!(baked.is_some(), "the specialised kernel scored the batch");
        let mut cpu = CpuEvaluator::new(c.problem.clone(), 1);
        let cpu_scores = cpu.fitness(&batch).unwrap();
        let tol = match precision {
            Precision::F64 => F64_HISTORY_TOLERANCE,
            Precision::F32 => F32_HISTORY_TOLERANCE,
        };
        let mut worst = 0.0_f64;
        for (i, h) in hist.iter().enumerate() {
            let r = simulate_history(&c.problem, 0, batch.params_of(0, i), 0.0);
            assert_eq!(r.states[1][0], genomes[i][0]);
            for (a, b) in r
                .outputs
                .iter()
                .zip(&h[0].outputs)
                .chain(r.states.iter().zip(&h[0].states))
            {
                let scale = a.iter().fold(f64::MIN_POSITIVE, |m, v| m.max(v.abs()));
                for (x, y) in a.iter().zip(b) {
                    worst = worst.max((x - y).abs() / scale);
                }
            }
            let (g, r) = (scores.get(i, 0), cpu_scores.get(i, 0));
            assert!((g - r).abs() <= 1e3 * tol * r.max(1e-3), "{g} vs {r}");
        }
        println!(
            "{precision:?}: largest history difference {worst:.2e} of each series' largest; \
             fitness by the specialised kernel ({baked:?} values baked in)"
        );
        assert!(worst <= tol, "{precision:?}: {worst:e}");
    }
}

fn check_refuses(initial: Value, params: Value, drive: Option<Value>, expect: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let mut r = rig();
    r["drives"] = json!([{"mode": "velocity", "node": "mass",
        "law": {"type": "sine", "quantity": "displacement", "amplitude": 0.001, "frequency": 5.0}}]);
    let mut v = json!({
        "name": "bad-initial",
        "rig": if drive.is_some() { r } else { rig() },
        "params": params,
        "experiments": [{
            "name": "e1",
            "data": {"file": "e1.csv", "time_column": "t_s", "force_column": "force_N"},
            "initial": initial
        }]
    });
    if let Some(m) = drive.and_then(|d| d.get("model").cloned()) {
        let o = v.as_object_mut().unwrap();
        o.remove("rig");
        o.insert("model".into(), m);
    }
    std::fs::write(dir.path().join("e1.csv"), placeholder(100)).unwrap();
    let path = dir.path().join("campaign.json");
    std::fs::write(&path, v.to_string()).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .arg("check")
        .arg(&path)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    println!("{err}");
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("campaign.json"), "{err}");
    for e in expect {
        assert!(err.contains(e), "{e:?} not in {err}");
    }
}

#[test]
fn bad_initial_states_are_refused_with_exit_2_and_the_path() {
    check_refuses(
        json!({"x_mas": 0.001}),
        json!({}),
        None,
        &[
            "experiments[0].initial.x_mas",
            "a state of rig 'msd' (x_mass, v_mass)",
        ],
    );
    check_refuses(
        json!({"x_mass": {"column": "no_such_column"}}),
        json!({}),
        None,
        &["experiments[0].initial.x_mass.column", "no_such_column"],
    );
    check_refuses(
        json!({"x_mass": 0.001}),
        json!({}),
        Some(json!({})),
        &[
            "experiments[0].initial.x_mass",
            "prescribed by the rig's \"velocity\"-mode drive",
        ],
    );
    check_refuses(
        json!({"v_mass": {"min": 1.0, "max": -1.0}}),
        json!({}),
        None,
        &["experiments[0].initial.v_mass.max", "max > min"],
    );
    check_refuses(
        json!({"v_mass": {"column": "pos_m", "samples": 1}}),
        json!({}),
        None,
        &["experiments[0].initial.v_mass.samples", "at least 2"],
    );
    check_refuses(
        json!({"x_mass": "free"}),
        json!({}),
        None,
        &[
            "experiments[0].initial.x_mass",
            "an initial state is a number",
        ],
    );
    check_refuses(
        json!({"x1": 0.001}),
        json!({}),
        Some(json!({"model": "tensile4"})),
        &[
            "model",
            "the \"model\" key is gone, write \"rig\": \"tensile4\"",
        ],
    );
}

#[test]
fn a_friction_element_starts_stuck_or_slipping_as_its_stretch_implies() {
    // A mass on a spring and a Coulomb contact (f_c = 2 N, k_t = 1e4 N/m) to
    // ground, its tangential stretch and velocity given.
    let desc: rigfit::rig::desc::RigDesc = serde_json::from_value(json!({
        "id": "slider",
        "params": [
            {"name": "initial_s_contact", "unit": "m", "scope": "experiment", "default": 0.0},
            {"name": "initial_v_mass", "unit": "m/s", "scope": "experiment", "default": 0.0}
        ],
        "nodes": [{"name": "mass", "mass": 1.0}],
        "elements": [
            {"name": "spring", "between": ["ground", "mass"], "spring": {"law": "linear", "k": 100.0}},
            {"name": "contact", "between": ["ground", "mass"],
             "friction": {"law": "stick_slip", "f_c": 2.0, "k_t": 1e4}}
        ],
        "outputs": [{"name": "friction", "unit": "N", "sum": [{"force": "contact"}]}]
    }))
    .unwrap();
    let rig = rigfit::model::compiled::CompiledRig::new(desc, "inline").unwrap();
    let drive = rigfit::base::Drive::Velocity;
    let regimes = |s: f64, v: f64| rig.stepper(&[s, v], &drive).unwrap().regimes;
    // Inside ±f_c/k_t = ±0.2 mm: stuck, whatever the velocity; at the limit
    // exactly: still stuck; past it: slipping in the spring's direction.
    assert_eq!(regimes(0.0, 0.5), vec![0]);
    assert_eq!(regimes(1e-4, -0.5), vec![0]);
    assert_eq!(regimes(2e-4, 0.0), vec![0]);
    assert_eq!(regimes(3e-4, 0.1), vec![1]);
    assert_eq!(regimes(-3e-4, -0.1), vec![2]);
    // Past +f_c while the element shortens (past the stick switch as well):
    // each regime variable switches once, so it starts slipping forward.
    assert_eq!(regimes(3e-4, -0.1), vec![1]);
}
