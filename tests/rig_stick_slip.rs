//! `rigs/stick_slip.json` — a rig that exists as a file only — against
//! hand-derived cases: a block held by a tangential spring sticks until the
//! spring force reaches the slip force, then slips under a constant net force.

use rigfit::base::Drive;
use rigfit::model::compiled::CompiledRig;
use rigfit::rig::desc::{DriveLaw, TableDesc};

const M: f64 = 1.0;
const FC: f64 = 10.0;
const KT: f64 = 1e4;

fn rig(t: Vec<f64>, f: Vec<f64>) -> CompiledRig {
    let mut desc = rigfit::rig::shipped("stick_slip").unwrap();
    desc.drives[0].law = DriveLaw::ForceTable(TableDesc {
        t: Some(t),
        value: Some(f),
        gain: None,
    });
    CompiledRig::new(desc, "rigs/stick_slip.json").unwrap()
}

/// Runs `steps` steps of `h`; returns the final state and the fired events.
fn run(r: &CompiledRig, steps: usize, h: f64) -> (Vec<f64>, Vec<(f64, String)>, bool) {
    let drive = Drive::Velocity;
    let p = [M, FC, KT, 0.0];
    assert!(r.check(&p).is_ok());
    let mut st = r.stepper(&p, &drive).unwrap();
    let mut y = vec![0.0; 3];
    for i in 0..steps {
        st.step(i as f64 * h, h, &mut y);
    }
    let prog = &r.lowered.programs[0];
    let fired = st
        .fired
        .iter()
        .map(|f| (f.t, prog.transitions[f.transition].name.clone()))
        .collect();
    (y, fired, st.chattered)
}

fn bisect(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) < 0.0 { lo = mid } else { hi = mid }
    }
    0.5 * (lo + hi)
}

#[test]
fn a_ramped_force_slips_the_block_when_the_spring_force_reaches_the_slip_force() {
    // Stuck: m·ẍ + k_t·x = β·t, so x = (β/k_t)(t − sin(ωt)/ω).
    let beta = 20.0;
    let w = (KT / M).sqrt();
    let x = |t: f64| beta / KT * (t - (w * t).sin() / w);
    let t_slip = bisect(|t| KT * x(t) - FC, 0.3, 0.7);
    let r = rig(vec![0.0, 1.0], vec![0.0, beta]);
    let (_, fired, chattered) = run(&r, 6000, 1e-4);
    println!("{fired:?}; expected slip at {t_slip}");
    assert!(!chattered);
    let (t, name) = &fired[0];
    assert_eq!(name, "contact slips backward");
    assert!((t - t_slip).abs() < 1e-9, "slip at {t}, expected {t_slip}");
}

#[test]
fn under_a_constant_net_force_the_slip_velocity_grows_linearly() {
    let f0 = 15.0;
    let w = (KT / M).sqrt();
    // Stuck: x = (F0/k_t)(1 − cos ωt) until k_t·x = f_c.
    let ts = ((1.0 - FC / f0).acos()) / w;
    let vs = f0 / KT * w * (w * ts).sin();
    let r = rig(vec![0.0, 10.0], vec![f0, f0]);
    let h = 1e-4;
    let steps = 2000;
    let (y, fired, chattered) = run(&r, steps, h);
    assert!(!chattered);
    assert_eq!(fired.len(), 1, "{fired:?}");
    assert!(
        (fired[0].0 - ts).abs() < 1e-9,
        "slip at {}, expected {ts}",
        fired[0].0
    );
    let t_end = steps as f64 * h;
    let v_exact = vs + (f0 - FC) / M * (t_end - ts);
    println!("v = {} m/s, closed form {v_exact}", y[1]);
    assert!(
        (y[1] - v_exact).abs() < 1e-9 * v_exact,
        "{} vs {v_exact}",
        y[1]
    );
    // The tangential spring stays at the slip force while slipping.
    let spring = KT * y[2];
    assert!((spring.abs() - FC).abs() < 1e-9 * FC, "{spring}");
}

#[test]
fn a_slow_sine_sticks_and_slips_every_half_cycle_without_chattering() {
    let n = 400;
    let (t, f): (Vec<f64>, Vec<f64>) = (0..=n)
        .map(|i| {
            let t = i as f64 * 0.005;
            (t, 20.0 * (2.0 * std::f64::consts::PI * t).sin())
        })
        .unzip();
    let r = rig(t, f);
    let (_, fired, chattered) = run(&r, 20_000, 1e-4);
    assert!(!chattered);
    println!(
        "{} events, first {:?}",
        fired.len(),
        &fired[..6.min(fired.len())]
    );
    // Two slips and two sticks per cycle, two cycles.
    assert!(fired.len() >= 7, "{fired:?}");
    for w in fired.windows(2) {
        assert!(w[1].0 >= w[0].0, "events out of time order");
        let slip = |s: &str| s.contains("slips");
        assert_ne!(
            slip(&w[0].1),
            slip(&w[1].1),
            "a slip follows a stick: {w:?}"
        );
    }
}
