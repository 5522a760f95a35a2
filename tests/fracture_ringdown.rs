//! Proves the post-fracture history of the tensile rig: once the specimen breaks,
//! the load cell rings alone on `k1` and `c1_post` exactly as the closed-form
//! damped oscillator started from the state at fracture, on the compiled rig and
//! on the hand-written oracle (tests/oracle); and, of the classic RK4 the oracle
//! runs on, that the fracture time and the post-fracture history converge at
//! (nearly) fourth order because the switch is located inside the step, and
//! that detecting the fracture only at step boundaries would make the
//! post-fracture history orders of magnitude worse.

mod oracle;
mod tensile_common;

use oracle::rk4::{Integrator, System, rk4_step};
use oracle::systems::DampedOscillator;
use oracle::tensile::{REFERENCE, TensileSystem, ix};
use rigfit::base::Drive;
use tensile_common::tensile4;

/// What one fixed-step run records.
struct Run {
    /// State at `t_end`.
    y: Vec<f64>,
    /// Located fracture time (s).
    tf: f64,
    /// `(y1, v1)` at the fracture time.
    at_fracture: (f64, f64),
    /// `(t, y1)` after every step past fracture.
    after: Vec<(f64, f64)>,
}

/// The tensile system seen through boundary detection: the switch is reported
/// only once `g ≥ 0` at a step's start, so the integrator fires it there — up to
/// one step late, with no location inside the step.
struct BoundaryDetect<'a>(TensileSystem<'a>);

impl System for BoundaryDetect<'_> {
    fn dim(&self) -> usize {
        8
    }
    fn deriv(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        self.0.deriv(t, y, dy);
    }
    fn pending_switch(&self, t: f64, y: &[f64]) -> Option<(f64, f64)> {
        self.0.pending_switch(t, y).filter(|&(g, _)| g >= 0.0)
    }
    fn fire_switch(&mut self, t: f64) {
        self.0.fire_switch(t);
    }
}

/// Integrates the oracle from rest to `t_end` with steps `h`; `naive` selects
/// boundary detection instead of the located switch.
fn run(params: &[f64], h: f64, t_end: f64, naive: bool) -> Run {
    let drive = Drive::Velocity;
    let mut sys = BoundaryDetect(TensileSystem::new(params, &drive));
    let mut integ = Integrator::new(8);
    let mut scratch: [Vec<f64>; 5] = std::array::from_fn(|_| vec![0.0; 8]);
    let mut y = vec![0.0; 8];
    let (mut tf, mut at_fracture, mut after) = (f64::NAN, (0.0, 0.0), Vec::new());
    for i in 0..(t_end / h).round() as usize {
        let t = i as f64 * h;
        let (before, y_before) = (sys.0.clone(), y.clone());
        if naive {
            integ.step(&mut sys, t, h, &mut y);
        } else {
            integ.step(&mut sys.0, t, h, &mut y);
        }
        if sys.0.broken && !before.broken {
            tf = sys.0.fracture_time.expect("fracture time");
            // Replay the unbroken part of the step to get the state at fracture.
            let mut yf = y_before;
            let [a, b, c, d, e] = &mut scratch;
            rk4_step(&before, t, tf - t, &mut yf, [a, b, c, d, e]);
            at_fracture = (yf[0], yf[4]);
        }
        if sys.0.broken {
            after.push((t + h, y[0]));
        }
    }
    Run {
        y,
        tf,
        at_fracture,
        after,
    }
}

/// The reference rig with `gap = 0` and a linear specimen breaking at 60 µm
/// (≈ 5.2 kN): nothing but the fracture switches, so the convergence orders are
/// those of the method. In the reference run itself the slack engagement switches
/// the damper force `c4·(v4 − v3)` (≈ 30 kN) on at `d = 0` without location, and
/// that unlocated jump makes its fracture-time error erratic in `h`
/// (6.7e-10, 1.5e-9, 2.2e-10, 6.1e-12, 1.0e-10 s for h = 1 µs … 62.5 ns).
fn smooth_case() -> [f64; 27] {
    let mut p = REFERENCE;
    p[ix::GAP] = 0.0;
    p[ix::E_YIELD] = 1.0;
    p[ix::E_FRACTURE] = 6e-5;
    p
}

/// The compiled rig from rest to `t_end` with steps `h`: its located fracture
/// time, `(y1, v1)` at the end of the step that holds it, and `(t, y1)` after
/// every step past fracture.
fn compiled_run(params: &[f64], h: f64, t_end: f64) -> (f64, (f64, f64), Vec<(f64, f64)>) {
    let rig = tensile4();
    let drive = Drive::Velocity;
    let mut st = rig.stepper(params, &drive).expect("a velocity drive");
    let prog = &rig.lowered.programs[rig.program_for(&drive).expect("velocity")];
    let mut y = st.y0.clone();
    let mut broke: Option<(f64, (f64, f64))> = None;
    let mut after = Vec::new();
    for i in 0..(t_end / h).round() as usize {
        let t = i as f64 * h;
        st.step(t, h, &mut y);
        if broke.is_none()
            && let Some(f) = st
                .fired
                .iter()
                .find(|f| prog.transitions[f.transition].name == "specimen breaks")
        {
            broke = Some((f.t, (y[0], y[4])));
        }
        if broke.is_some() {
            after.push((t + h, y[0]));
        }
    }
    assert!(!st.chattered);
    let (tf, at) = broke.expect("the specimen breaks");
    (tf, at, after)
}

/// Holds a post-fracture load-cell history `after` to the closed-form
/// oscillator `osc`: displacement, ringing frequency and decay.
fn assert_rings_as(what: &str, osc: &DampedOscillator, after: &[(f64, f64)]) {
    let scale = osc.x0.hypot(osc.v0 / osc.omega0());
    let worst = after
        .iter()
        .map(|&(t, y1)| (y1 - osc.exact(t).0).abs() / scale)
        .fold(0.0, f64::max);
    println!("{what}: max |y1 − closed form| / amplitude = {worst:.3e}");
    // RK4 phase error ≈ (ω₀h)⁵/120 per step ≈ 1e-11 × ~4900 steps ≈ 5e-8.
    assert!(
        worst < 1e-7,
        "{what}: post-fracture y1 differs from the closed form by {worst:e}"
    );

    // Frequency from the zero crossings, decay from the successive maxima.
    let a = after;
    let zeros: Vec<f64> = a
        .windows(2)
        .filter(|w| w[0].1 < 0.0 && w[1].1 >= 0.0)
        .map(|w| w[0].0 + (w[1].0 - w[0].0) * w[0].1 / (w[0].1 - w[1].1))
        .collect();
    let f = (zeros.len() - 1) as f64 / (zeros[zeros.len() - 1] - zeros[0]);
    let fd = osc.omega_d() / std::f64::consts::TAU;
    let peaks: Vec<(f64, f64)> = a
        .windows(3)
        .filter(|w| w[1].1 > w[0].1 && w[1].1 >= w[2].1 && w[1].1 > 0.0)
        .map(|w| (w[1].0, w[1].1.ln()))
        .collect();
    let n = peaks.len() as f64;
    let (mt, ml) = peaks
        .iter()
        .fold((0.0, 0.0), |s, p| (s.0 + p.0 / n, s.1 + p.1 / n));
    let slope = peaks.iter().map(|p| (p.0 - mt) * (p.1 - ml)).sum::<f64>()
        / peaks.iter().map(|p| (p.0 - mt).powi(2)).sum::<f64>();
    println!(
        "{what}: ringing {f:.2} Hz (closed form {fd:.2} Hz), decay {:.2} 1/s (closed form {:.2} 1/s)",
        -slope,
        osc.decay_rate()
    );
    assert!(
        (f - fd).abs() / fd < 1e-4,
        "{what}: ringing frequency {f} vs {fd}"
    );
    assert!(
        (-slope - osc.decay_rate()).abs() / osc.decay_rate() < 5e-3,
        "{what}: decay {}",
        -slope
    );
}

#[test]
fn load_cell_rings_as_the_closed_form_oscillator_after_fracture() {
    let p = REFERENCE;
    let (h, t_end) = (0.5e-6, 3e-3);
    let ringing = |x0: f64, v0: f64, t0: f64| DampedOscillator {
        m: p[ix::M1],
        k: p[ix::K1],
        c: p[ix::C1_POST],
        x0,
        v0,
        t0,
    };

    // The compiled rig, from the state at the end of the step that breaks.
    let (tf, (x0, v0), after) = compiled_run(&p, h, t_end);
    println!("compiled rig: fracture at {:.6} ms", tf * 1e3);
    let t0 = after[0].0;
    assert!(t0 - h < tf && tf <= t0, "fracture {tf} outside its step");
    assert_rings_as("compiled rig", &ringing(x0, v0, t0), &after[1..]);

    // The oracle, from the state at the located fracture itself.
    let r = run(&p, h, t_end, false);
    println!("oracle: fracture at {:.6} ms", r.tf * 1e3);
    assert_rings_as(
        "oracle",
        &ringing(r.at_fracture.0, r.at_fracture.1, r.tf),
        &r.after,
    );
}

#[test]
fn fracture_time_and_post_fracture_history_converge_faster_than_third_order() {
    let p = smooth_case();
    let t_end = 1e-3;
    let fine = run(&p, 1e-6 / 256.0, t_end, false);
    let errs: Vec<(f64, f64)> = [1e-6, 0.5e-6, 0.25e-6]
        .iter()
        .map(|&h| {
            let r = run(&p, h, t_end, false);
            let hist = ((r.y[0] - fine.y[0]) / fine.y[0])
                .abs()
                .max(((r.y[4] - fine.y[4]) / fine.y[4]).abs());
            ((r.tf - fine.tf).abs(), hist)
        })
        .collect();
    for w in errs.windows(2) {
        let (otf, ohist) = ((w[0].0 / w[1].0).log2(), (w[0].1 / w[1].1).log2());
        println!(
            "errors {:?} → {:?}: order of t_f {otf:.3}, of y1/v1 at 1 ms {ohist:.3}",
            w[0], w[1]
        );
        assert!(otf >= 3.5, "fracture-time order {otf}");
        assert!(ohist >= 3.5, "post-fracture history order {ohist}");
    }
}

/// Boundary detection fires up to one step late, by `(1 − θ)·h` where `θ` is where
/// the crossing falls in the step, so its error depends on that phase. Eight
/// fracture strains spread the crossing over the step; the mean boundary-detection
/// error is compared with the worst located error.
#[test]
fn located_switch_beats_boundary_detection_by_orders_of_magnitude() {
    let (h, t_end) = (0.5e-6, 1e-3);
    let (mut worst_located, mut mean_naive) = (0.0_f64, 0.0);
    for k in 0..8 {
        let mut p = smooth_case();
        p[ix::E_FRACTURE] = 6e-5 * (1.0 + 0.0013 * k as f64);
        let fine = run(&p, h / 64.0, t_end, false);
        let err = |r: &Run| ((r.y[0] - fine.y[0]) / fine.y[0]).abs();
        let (located, naive) = (run(&p, h, t_end, false), run(&p, h, t_end, true));
        let theta = (fine.tf / h).fract();
        println!(
            "θ = {theta:.2}: y1(1 ms) rel error located {:.2e}, boundary {:.2e}",
            err(&located),
            err(&naive)
        );
        worst_located = worst_located.max(err(&located));
        mean_naive += err(&naive) / 8.0;
    }
    let ratio = mean_naive / worst_located;
    println!("mean boundary-detection error / worst located error = {ratio:.0}");
    assert!(ratio > 100.0, "boundary detection only {ratio:.1}× worse");
}
