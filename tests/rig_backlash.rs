//! Backlash with its own play state (`"backlash": {"half_width": b}` on an
//! element with a spring and a viscous damper), on a mass held to ground by
//! one such element (`tests/data/backlash_sdof.json`), against hand-derived
//! cases: under a constant force the play is taken up at the closed-form time
//! and the mass then rings as a damped oscillator about `F0/k + b`; under a
//! sine the element takes up and leaves its play on both sides every cycle,
//! the play relaxes as `e − p ∝ e^{−k·t/c}` in between, and the run is fourth
//! order in the step.

use std::ops::ControlFlow;

use rigfit::base::SampleGrid;
use rigfit::base::{Drive, Report};
use rigfit::model::compiled::CompiledRig;
use rigfit::rig::desc::{DriveLaw, TableDesc};
use rigfit::rig::{RigSource, parse};

const FILE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/backlash_sdof.json");
const M: f64 = 1.0;
const K: f64 = 1e4;
const C: f64 = 60.0;
const B: f64 = 1e-3;

fn desc() -> rigfit::rig::desc::RigDesc {
    let text = std::fs::read_to_string(FILE).unwrap();
    parse(&text, &RigSource::File(FILE.into())).unwrap()
}

fn rig() -> CompiledRig {
    CompiledRig::new(desc(), FILE).unwrap()
}

/// The rig pushed by a constant force `f0` from `t = 0`.
fn constant_force_rig(f0: f64) -> CompiledRig {
    let mut d = desc();
    d.drives[0].law = DriveLaw::ForceTable(TableDesc {
        t: Some(vec![0.0, 100.0]),
        value: Some(vec![f0, f0]),
        gain: None,
    });
    CompiledRig::new(d, FILE).unwrap()
}

/// `[m, k, c, b, f0, freq]`.
fn params(f0: f64, freq: f64) -> Vec<f64> {
    vec![M, K, C, B, f0, freq]
}

/// What a run did, step by step: (t, state, mode of the play) after each step.
struct Run {
    steps: Vec<(f64, Vec<f64>, u32)>,
    fired: Vec<(f64, String)>,
    chattered: bool,
}

fn run(r: &CompiledRig, p: &[f64], steps: usize, h: f64) -> Run {
    assert!(r.check(p).is_ok());
    let drive = Drive::Velocity;
    let mut st = r.stepper(p, &drive).unwrap();
    let mut y = vec![0.0; r.state_names().len()];
    let mut out = Vec::with_capacity(steps);
    for i in 0..steps {
        st.step(i as f64 * h, h, &mut y);
        out.push(((i + 1) as f64 * h, y.clone(), st.regimes[0]));
    }
    let prog = &r.lowered.programs[0];
    Run {
        steps: out,
        fired: st
            .fired
            .iter()
            .map(|f| (f.t, prog.transitions[f.transition].name.clone()))
            .collect(),
        chattered: st.chattered,
    }
}

#[test]
fn the_play_is_a_state_with_three_modes() {
    let r = rig();
    assert_eq!(r.state_names(), ["x_mass", "v_mass", "p_joint"]);
    let m = &r.lowered.regimes[0];
    assert_eq!(m.name, "joint.backlash");
    assert_eq!(m.values, ["play", "tension", "compression"]);
    assert_eq!(r.lowered.programs[0].transitions.len(), 4);
}

#[test]
fn a_constant_force_takes_up_the_play_then_rings_about_the_static_deflection() {
    let f0 = 10.0;
    let a = f0 / M;
    // In play F = 0: x = a·t²/2, and e − p decays as e^{−k·t/c} from 0, so
    // p = e: the play is taken up when a·t²/2 = b.
    let t1 = (2.0 * B / a).sqrt();
    let v1 = a * t1;
    // Then m·ÿ + c·ẏ + k·y = 0 for y = x − (b + F0/k), from y = −F0/k, ẏ = v1.
    let w0 = (K / M).sqrt();
    let z = C / (2.0 * (K * M).sqrt());
    let wd = w0 * (1.0 - z * z).sqrt();
    let y0 = -f0 / K;
    let bb = (v1 + z * w0 * y0) / wd;
    let x_exact = |t: f64| {
        let tau = t - t1;
        let y = (-z * w0 * tau).exp() * (y0 * (wd * tau).cos() + bb * (wd * tau).sin());
        B + f0 / K + y
    };
    let r = constant_force_rig(f0);
    let h = 1e-5;
    let run = run(&r, &params(f0, 5.0), 20_000, h);
    println!("{:?}; expected contact at {t1}", run.fired);
    assert!(!run.chattered);
    // The closed form keeps the element in contact (its force stays above
    // 6 N), so exactly one event.
    assert_eq!(run.fired.len(), 1, "{:?}", run.fired);
    assert_eq!(run.fired[0].1, "joint takes up its play in tension");
    assert!(
        (run.fired[0].0 - t1).abs() < 1e-9 * t1,
        "contact at {}, expected {t1}",
        run.fired[0].0
    );
    let scale = f0 / K;
    let mut worst = 0.0_f64;
    for (t, y, mode) in &run.steps {
        let (x, p) = (y[0], y[2]);
        if *t < t1 {
            assert_eq!(*mode, 0);
            let e = a * t * t / 2.0;
            worst = worst.max((x - e).abs() / scale).max((p - e).abs() / scale);
        } else {
            assert_eq!(*mode, 1);
            assert!((p - B).abs() < 1e-9 * B, "p = {p} in contact");
            worst = worst.max((x - x_exact(*t)).abs() / scale);
        }
    }
    let (_, y, _) = run.steps.last().unwrap();
    println!(
        "largest error {worst:.2e} of F0/k; x at 0.2 s {} (static {})",
        y[0],
        B + f0 / K
    );
    assert!(worst < 1e-8, "{worst:e}");
    // By 0.2 s the ringing has died to F0/k·e^{−ζ·ω0·0.19} ≈ 3e-3 of it.
    assert!((y[0] - (B + f0 / K)).abs() < 1e-2 * scale);
}

#[test]
fn under_a_sine_the_play_is_taken_up_and_left_on_both_sides_every_cycle() {
    let r = rig();
    let h = 1e-4;
    let run = run(&r, &params(20.0, 5.0), 10_000, h);
    assert!(!run.chattered);
    let names: Vec<&str> = run.fired.iter().map(|f| f.1.as_str()).collect();
    println!("{} events: {:?}", names.len(), &names[..8.min(names.len())]);
    // Five cycles, four events each (tension taken up and left, compression
    // taken up and left); the first quarter-cycle reaches tension only.
    assert!(names.len() >= 18, "{names:?}");
    let count = |s: &str| names.iter().filter(|n| n.contains(s)).count();
    assert!(count("in tension") >= 4 && count("in compression") >= 4);
    for w in run.fired.windows(2) {
        assert!(w[1].0 > w[0].0, "events out of time order: {w:?}");
        let takes = |s: &str| s.contains("takes up");
        assert_ne!(
            takes(&w[0].1),
            takes(&w[1].1),
            "take-up and release alternate: {w:?}"
        );
        if takes(&w[0].1) {
            let side = |s: &str| s.contains("tension");
            assert_eq!(side(&w[0].1), side(&w[1].1), "left where taken up: {w:?}");
        }
    }
    // Events at least a few steps apart: no chatter at the stops.
    let gap = run
        .fired
        .windows(2)
        .map(|w| w[1].0 - w[0].0)
        .fold(f64::INFINITY, f64::min);
    println!("closest events {gap:.3e} s apart");
    assert!(gap > 10.0 * h);

    // Between steps that stay in play, e − p decays as e^{−k·h/c} exactly as
    // the play law says (whatever the mass does); in contact p stays at ±b
    // and the element's force is k·(e ∓ b) + c·ė; in play it is 0.
    let decay = (-K / C * h).exp();
    let mut checked = 0;
    let fired_between = |t0: f64, t1: f64| run.fired.iter().any(|f| f.0 > t0 && f.0 <= t1);
    for w in run.steps.windows(2) {
        let ((t0, y0, m0), (t1, y1, m1)) = (&w[0], &w[1]);
        assert!(y1[2].abs() <= B * (1.0 + 1e-9), "|p| = {} beyond b", y1[2]);
        if *m0 == 0 && *m1 == 0 && !fired_between(*t0, *t1) {
            let (u0, u1) = (y0[0] - y0[2], y1[0] - y1[2]);
            assert!(
                (u1 - u0 * decay).abs() <= 1e-9 * u0.abs() + 1e-15,
                "e − p: {u0:e} → {u1:e}, expected {:e}",
                u0 * decay
            );
            checked += 1;
        }
        if *m1 != 0 {
            let stop = if *m1 == 1 { B } else { -B };
            assert!((y1[2] - stop).abs() < 1e-9 * B, "p = {} in contact", y1[2]);
        }
    }
    println!("{checked} steps in play checked against e^(-k·h/c)");
    assert!(checked > 1000);
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-3,
        samples: 1000,
        substeps: 10,
    };
    let mut seen = (0, 0);
    r.simulate(&params(20.0, 5.0), &Drive::Velocity, &grid, &mut |s| {
        let (x, v, p) = (s.state[0], s.state[1], s.state[2]);
        let f = s.outputs[0];
        if (p.abs() - B).abs() < 1e-9 * B && f != 0.0 {
            let expected = K * (x - B.copysign(p)) + C * v;
            assert!(
                (f - expected).abs() <= 1e-9 * f.abs().max(1.0),
                "{f} vs {expected}"
            );
            seen.0 += 1;
        } else if f == 0.0 {
            seen.1 += 1;
        }
        ControlFlow::Continue(())
    });
    println!("samples in contact {}, in play {}", seen.0, seen.1);
    assert!(seen.0 > 100 && seen.1 > 100, "{seen:?}");
}

fn history(r: &CompiledRig, substeps: usize) -> Vec<f64> {
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-3,
        samples: 1000,
        substeps,
    };
    let mut h = Vec::with_capacity(2 * grid.samples);
    r.simulate(&params(20.0, 5.0), &Drive::Velocity, &grid, &mut |s| {
        h.push(s.outputs[0]);
        h.push(s.state[2]);
        ControlFlow::Continue(())
    });
    h
}

fn rel_rms(a: &[f64], b: &[f64]) -> f64 {
    // Force and play position, each relative to its own RMS.
    let part = |k: usize| {
        let num: f64 = a
            .iter()
            .zip(b)
            .skip(k)
            .step_by(2)
            .map(|(x, y)| (x - y).powi(2))
            .sum();
        let den: f64 = b.iter().skip(k).step_by(2).map(|y| y * y).sum();
        (num / den).sqrt()
    };
    part(0).max(part(1))
}

#[test]
fn located_switches_keep_the_run_fourth_order() {
    let r = rig();
    let fine = history(&r, 256);
    let e: Vec<f64> = [1, 2, 4, 8]
        .iter()
        .map(|&s| rel_rms(&history(&r, s), &fine))
        .collect();
    let orders: Vec<f64> = e.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
    println!("errors {e:?}, orders {orders:.2?}");
    for o in &orders {
        assert!(*o >= 3.5, "order {o} (errors {e:?})");
    }
}

#[test]
fn a_damping_parameter_at_zero_is_refused_per_run() {
    let r = rig();
    let mut p = params(20.0, 5.0);
    p[2] = 0.0;
    let (name, expected) = r.check(&p).unwrap_err();
    assert_eq!(name, "c");
    assert!(expected.contains("damping > 0"), "{expected}");
}

#[test]
fn the_stability_bound_counts_the_plays_relaxation_rate() {
    // k/c = 1e4/6 at the box's stiffest, least damped corner, above the
    // mass's √(k/m) + c/m (100 + 60 at most here).
    let r = rig();
    let lo = [1.0, 1e4, 6.0, 1e-3, 20.0, 5.0];
    let hi = [1.0, 1e4, 60.0, 1e-3, 20.0, 5.0];
    let (w, name) = r.per_law_omega(&lo, &hi, &Drive::Velocity);
    println!("per-law bound {w} rad/s ({name})");
    assert!((w - 1e4 / 6.0).abs() < 1e-9 * w, "{w}");
    assert_eq!(name, "c");
    let (w, _) = r.omega_bound(&lo, &hi, &Drive::Velocity);
    println!("guard's bound {w} rad/s");
    assert!(w >= 1e4 / 6.0 * (1.0 - 1e-12), "{w}");
}

#[test]
fn modes_see_the_element_in_contact_and_the_interval_bound_its_play() {
    // `modes` linearises with every contact closed: the play taken up, the
    // mass on k alone rings at √(k/m).
    let r = rig();
    let lin = r.linearise(&params(20.0, 5.0), &Drive::Velocity);
    assert_eq!(lin.dofs, ["mass"]);
    assert!(
        (lin.stiffness[0] - K).abs() < 1e-9 * K,
        "{:?}",
        lin.stiffness
    );
    let report = rigfit::model::modes::ModeReport::new(&lin).unwrap();
    let w = report.modes[0].omega;
    println!("linearised: {w} rad/s");
    assert!((w - (K / M).sqrt()).abs() < 1e-9 * w);
    // The graph's interval bound encloses the play's rate k/c (its Jacobian
    // in play has the eigenvalue −k/c).
    let lo = [0.8, 0.8e4, 48.0, 0.8e-3, 16.0, 4.0];
    let hi = [1.25, 1.25e4, 75.0, 1.25e-3, 25.0, 6.25];
    let (wi, _) = r.interval_omega(&lo, &hi, &Drive::Velocity, 2.0).unwrap();
    let (wp, _) = r.per_law_omega(&lo, &hi, &Drive::Velocity);
    println!("interval bound {wi:.1} rad/s, per-law bound {wp:.1} rad/s");
    assert!(wi.is_finite() && wi >= 1.25e4 / 48.0, "{wi}");
    assert!(wp >= 1.25e4 / 48.0 * (1.0 - 1e-12), "{wp}");
}

/// A campaign naming the rig file, with `c` as given, in `dir` (a grid record).
fn campaign(dir: &std::path::Path, c: serde_json::Value) -> Result<(), String> {
    std::fs::write(dir.join("grid.csv"), "t_s,force_N\n0,0\n0.001,1\n").unwrap();
    let json = serde_json::json!({
        "name": "backlash",
        "rig": FILE,
        "params": {"m": 1.0, "k": 1e4, "c": c, "b": 1e-3, "f0": 20.0, "freq": 5.0},
        "experiments": [{"name": "s5", "data": {"file": "grid.csv", "time_column": "t_s", "force_column": "force_N"}}],
        "solver": {"substeps": "auto", "backend": "cpu"},
        "search": {"population": 16, "generations": 2, "seed": 1},
        "output": "out"
    });
    rigfit::campaign::Campaign::from_str(&json.to_string(), dir, "c.json")
        .map(|_| ())
        .map_err(|e| e.to_string())
}

#[test]
fn a_campaign_loads_the_rig_file_and_refuses_a_damping_range_through_zero() {
    let tmp = tempfile::tempdir().unwrap();
    campaign(tmp.path(), serde_json::json!(60.0)).unwrap();
    campaign(tmp.path(), serde_json::json!({"min": 20.0, "max": 200.0})).unwrap();
    for c in [
        serde_json::json!(0.0),
        serde_json::json!({"min": 0.0, "max": 200.0, "scale": "linear"}),
    ] {
        let err = campaign(tmp.path(), c).unwrap_err();
        println!("{err}");
        assert!(err.contains("params.c") && err.contains("> 0"), "{err}");
    }
}

#[test]
fn a_play_of_zero_width_is_the_plain_spring_and_damper() {
    let with = rig();
    let mut d = desc();
    d.elements[0].backlash = None;
    let plain = CompiledRig::new(d, FILE).unwrap();
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-3,
        samples: 1000,
        substeps: 4,
    };
    let mut p = params(20.0, 5.0);
    p[3] = 0.0;
    let force = |r: &CompiledRig| {
        let mut h = vec![];
        r.simulate(&p, &Drive::Velocity, &grid, &mut |s| {
            h.push(s.outputs[0]);
            ControlFlow::Continue(())
        });
        h
    };
    let (a, b) = (force(&with), force(&plain));
    let e = rel_rms(
        &a.iter().flat_map(|&x| [x, 1.0]).collect::<Vec<_>>(),
        &b.iter().flat_map(|&x| [x, 1.0]).collect::<Vec<_>>(),
    );
    let run = run(&with, &p, 4000, 2.5e-4);
    println!(
        "b = 0: {} events, force differs by {e:.2e} (relative RMS)",
        run.fired.len()
    );
    assert!(!run.chattered);
    assert!(e < 1e-8, "{e:e}");
}

#[test]
fn the_cpu_lane_ensemble_gives_the_reference_bits() {
    let r = rig();
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-3,
        samples: 600,
        substeps: 2,
    };
    // 20 candidates (a full group of lanes and a part one), b and c spread.
    let ps: Vec<Vec<f64>> = (0..20)
        .map(|i| {
            let mut p = params(20.0, 5.0);
            p[2] *= 1.0 + 0.05 * i as f64;
            p[3] *= 0.5 + 0.1 * i as f64;
            p
        })
        .collect();
    let refs: Vec<&[f64]> = ps.iter().map(|p| p.as_slice()).collect();
    let mut many = vec![vec![]; ps.len()];
    r.simulate_many(&refs, &Drive::Velocity, &grid, Report::Full, &mut |j, s| {
        many[j].extend_from_slice(s.outputs);
        many[j].extend_from_slice(s.state);
        ControlFlow::Continue(())
    });
    for (j, p) in ps.iter().enumerate() {
        let mut one = vec![];
        r.simulate(p, &Drive::Velocity, &grid, &mut |s| {
            one.extend_from_slice(s.outputs);
            one.extend_from_slice(s.state);
            ControlFlow::Continue(())
        });
        assert_eq!(one.len(), many[j].len());
        for (a, b) in one.iter().zip(&many[j]) {
            assert_eq!(a.to_bits(), b.to_bits(), "candidate {j}");
        }
    }
}
