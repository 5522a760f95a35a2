//! Restoring-force surface and direct parameter estimation (the inertial fatigue rig paper ("A New Fatigue Testing Rig Based on Inertial Forces"),
//! §3.2–3.3) recover the laws of synthetic base-excited records made with
//! rigfit's integrator.

mod identify_common;

use identify_common::{BaseExcited, Multisine, simulate};
use rigfit::identify::dpe::{self, DpeOptions, GridOptions, Term, signed_power};
use rigfit::identify::rfs::{self, RfsOptions};

/// Simulates `m·ẍ + R(x, ẋ) = −m·a` under a 5–60 Hz multisine (the inertial fatigue rig paper's
/// band) and returns `(t, x, a)` at `fs`.
fn record(
    m: f64,
    restoring: impl Fn(f64, f64) -> f64,
    rms: f64,
    fs: f64,
    seconds: f64,
) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let base = Multisine::new(5.0, 60.0, 111, rms, 7);
    let mut sys = BaseExcited {
        m,
        restoring,
        base: base.clone(),
    };
    let (t, y) = simulate(&mut sys, fs, (seconds * fs) as usize, 8);
    let x = y.iter().map(|s| s[0]).collect();
    let a = t.iter().map(|&t| base.at(t)).collect();
    (t, x, a)
}

fn close(name: &str, got: f64, want: f64, rel: f64) {
    assert!(
        (got - want).abs() <= rel * want.abs(),
        "{name}: {got:e}, want {want:e} within {:.1} %",
        rel * 100.0
    );
}

#[test]
fn duffing_with_viscous_and_coulomb_damping_is_recovered() {
    let (m, kf1, kf2, cf1, fc) = (9.0, 4.0e5, 3.0e12, 114.0, 5.0);
    let law = move |x: f64, v: f64| kf1 * x + kf2 * x.powi(3) + cf1 * v + fc * v.signum();
    let (t, x, a) = record(m, law, 4.0, 4000.0, 4.0);
    let xmax = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    // The cubic term must matter for the test to mean anything.
    assert!(kf2 * xmax.powi(3) > 0.1 * kf1 * xmax, "x_max = {xmax:e}");
    let opts = RfsOptions {
        mass: m,
        cutoff_hz: None,
        filter_order: 4,
    };
    let surface = rfs::surface(&t, &x, &a, &opts).unwrap();
    let dpe_opts = DpeOptions {
        terms: vec![Term::Linear, Term::Cubic, Term::Viscous, Term::Coulomb],
        alpha: None,
        beta: None,
        grid: GridOptions::default(),
    };
    let r = dpe::estimate(&surface, &dpe_opts).unwrap();
    println!("{r:#?}");
    close("kf1", r.get(Term::Linear).unwrap(), kf1, 0.005);
    close("kf2", r.get(Term::Cubic).unwrap(), kf2, 0.02);
    close("cf1", r.get(Term::Viscous).unwrap(), cf1, 0.02);
    close("fc", r.get(Term::Coulomb).unwrap(), fc, 0.05);
    assert!(r.r2 > 0.9999, "{}", r.r2);
    assert!(r.search.is_empty());
    // The fragment carries every parameter of the family; unchosen terms are 0.
    let frag = r.to_campaign_fragment(false, &dpe_opts.grid);
    assert_eq!(frag["params"]["m"], 9.0);
    assert_eq!(frag["params"]["kf3"], 0.0);
    let kf1_entry = &frag["params"]["kf1"];
    assert!(kf1_entry["min"].as_f64().unwrap() < kf1 && kf1_entry["max"].as_f64().unwrap() > kf1);
}

/// The inertial fatigue rig paper, Table 1, 15 psi row: the laws with power-law damping and
/// stiffness. The mass is not given; §4.2 implies about 9 kg. The exponent grid
/// must find α = 0.64 and β = 1.81 and the least squares the six coefficients.
#[test]
fn table_1_at_15_psi_round_trips_with_its_exponents() {
    let m = 9.0;
    let (cf1, cf2, cf3, kf1, kf2, kf3, alpha, beta) = (
        352.38, -6.17e4, 365.17, 1.41e6, 8.66e12, -8.74e8, 0.64, 1.81,
    );
    let law = move |x: f64, v: f64| {
        cf1 * v
            + cf2 * v.powi(3)
            + cf3 * signed_power(v, alpha)
            + kf1 * x
            + kf2 * x.powi(3)
            + kf3 * signed_power(x, beta)
    };
    let (t, x, a) = record(m, law, 4.0, 4000.0, 4.0);
    let xmax = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(xmax < 3e-4, "beyond the document's range: {xmax:e} m");
    let surface = rfs::surface(
        &t,
        &x,
        &a,
        &RfsOptions {
            mass: m,
            cutoff_hz: None,
            filter_order: 4,
        },
    )
    .unwrap();
    let opts = DpeOptions {
        terms: Term::ALL
            .into_iter()
            .filter(|t| *t != Term::Coulomb)
            .collect(),
        alpha: None,
        beta: None,
        grid: GridOptions::default(),
    };
    let r = dpe::estimate(&surface, &opts).unwrap();
    println!("{r:#?}");
    let e = r.exponents;
    assert!((e.alpha.unwrap() - alpha).abs() < 0.02, "α = {:?}", e.alpha);
    assert!((e.beta.unwrap() - beta).abs() < 0.02, "β = {:?}", e.beta);
    // The stiffness and damping laws (not the nearly collinear coefficients one
    // by one) are what the surface pins down: compare them over the data.
    let vmax = surface.v.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for i in 1..=10 {
        let (xi, vi) = (xmax * i as f64 / 10.0, vmax * i as f64 / 10.0);
        let k_true = kf1 * xi + kf2 * xi.powi(3) + kf3 * signed_power(xi, beta);
        let c_true = cf1 * vi + cf2 * vi.powi(3) + cf3 * signed_power(vi, alpha);
        close("K(x)", r.stiffness(xi), k_true, 0.01);
        close("C(ẋ)", r.damping(vi), c_true, 0.03);
    }
    close("kf1", r.get(Term::Linear).unwrap(), kf1, 0.1);
}
