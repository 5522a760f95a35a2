//! The ring-down analysis recovers the load cell's frequency, damping ratio and
//! `c1_post` from noisy generated fractures, and refuses unusable histories; on
//! a hammer impact of the shipped bearing rig (no fracture) its three damping
//! estimates agree, and its words are a ringdown's, not a fracture's.

mod paper_rigs_common;

use std::f64::consts::PI;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rigfit::identify::IdentifyError;
use rigfit::identify::csv_input::{parse_two_columns, read_two_columns};
use rigfit::identify::ringdown::{RingdownOptions, analyse};

const M1: f64 = 7.9;
const K1: f64 = 8.4e9;
const C1: f64 = 9.22e3;

fn gauss(rng: &mut ChaCha8Rng) -> f64 {
    let u: f64 = rng.random_range(f64::EPSILON..1.0);
    let v: f64 = rng.random();
    (-2.0 * u.ln()).sqrt() * (2.0 * PI * v).cos()
}

fn truth(c1: f64) -> (f64, f64) {
    let wn = (K1 / M1).sqrt();
    (wn / (2.0 * PI), c1 / (2.0 * (K1 * M1).sqrt()))
}

/// Ramp to `f0` until `t_frac`, then the free load cell `m1ÿ + c1ẏ + k1y = 0`
/// measured as `F1 = k1·y + c1·ẏ`, sampled at 1 MHz with Gaussian noise.
fn history(c1: f64, t_frac: f64, duration: f64, sigma: f64, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (f0, fs) = (5000.0, 1e6);
    let wn = (K1 / M1).sqrt();
    let zeta = c1 / (2.0 * (K1 * M1).sqrt());
    let (s, wd) = (zeta * wn, wn * (1.0 - zeta * zeta).sqrt());
    let y0 = f0 / K1;
    let n = (duration * fs) as usize + 1;
    let t: Vec<f64> = (0..n).map(|i| i as f64 / fs).collect();
    let f = t
        .iter()
        .map(|&t| {
            let clean = if t <= t_frac {
                f0 * t / t_frac
            } else {
                let tau = t - t_frac;
                let (sin, cos) = (wd * tau).sin_cos();
                let e = (-s * tau).exp();
                let y = e * y0 * (cos + s / wd * sin);
                let v = -e * y0 * (s * s + wd * wd) / wd * sin;
                K1 * y + c1 * v
            };
            clean + sigma * gauss(&mut rng)
        })
        .collect();
    (t, f)
}

fn with_masses(m1: Option<f64>, k1: Option<f64>) -> RingdownOptions {
    RingdownOptions {
        m1,
        k1,
        ..RingdownOptions::default()
    }
}

#[test]
fn reference_load_cell_is_recovered_with_m1_and_k1_given() {
    let (t, f) = history(C1, 2e-3, 20e-3, 10.0, 42);
    let r = analyse(&t, &f, &with_masses(Some(M1), Some(K1))).unwrap();
    let (fn_true, zeta_true) = truth(C1);
    assert!((r.start.time - 2e-3).abs() <= 2e-6, "{:?}", r.start);
    assert!(
        (r.psd.peak_hz - fn_true).abs() <= r.psd.resolution_hz,
        "{:?}",
        r.psd
    );
    assert!((r.natural_frequency_hz - fn_true).abs() < 1e-3 * fn_true);
    let zd = r.decrement.zeta_mean;
    assert!(
        (zd / zeta_true - 1.0).abs() < 0.05,
        "decrement ζ {zd} vs {zeta_true}: {:?}",
        r.decrement
    );
    assert!(
        (r.fit.zeta / zeta_true - 1.0).abs() < 0.02,
        "fit ζ {}",
        r.fit.zeta
    );
    assert!(
        (r.load_cell.c1_post.unwrap() / C1 - 1.0).abs() < 0.03,
        "c1 {:?}",
        r.load_cell.c1_post
    );
    assert!((r.load_cell.c1_post_decrement.unwrap() / C1 - 1.0).abs() < 0.03);
    assert!(r.fit.r2 > 0.99 && r.fit.converged, "{:?}", r.fit);
    assert!(!r.load_cell.k1_from_frequency && r.load_cell.model_frequency_hz.is_some());
    let fragment = r.to_campaign_fragment();
    assert_eq!(fragment["params"]["c1_post"].as_f64(), r.load_cell.c1_post);
    assert!(fragment["params"].get("k1").is_none());
}

#[test]
fn lightly_damped_load_cell_and_k1_from_frequency() {
    // ζ ≈ 1.8e-3: about a hundred cycles before the ringing fades.
    let c1 = C1 / 10.0;
    let (t, f) = history(c1, 1e-3, 30e-3, 10.0, 7);
    let r = analyse(&t, &f, &with_masses(Some(M1), None)).unwrap();
    let (fn_true, zeta_true) = truth(c1);
    assert!(
        (r.psd.peak_hz - fn_true).abs() <= r.psd.resolution_hz,
        "{:?}",
        r.psd
    );
    assert!(r.decrement.n_peaks > 50, "{:?}", r.decrement);
    assert!(
        (r.decrement.zeta_mean / zeta_true - 1.0).abs() < 0.05,
        "{:?}",
        r.decrement
    );
    assert!((r.fit.zeta / zeta_true - 1.0).abs() < 0.02, "{:?}", r.fit);
    assert!(r.load_cell.k1_from_frequency);
    assert!(
        (r.load_cell.k1.unwrap() / K1 - 1.0).abs() < 0.002,
        "k1 {:?}",
        r.load_cell.k1
    );
    assert!(
        (r.load_cell.c1_post.unwrap() / c1 - 1.0).abs() < 0.03,
        "c1 {:?}",
        r.load_cell.c1_post
    );
    let fragment = r.to_campaign_fragment();
    assert_eq!(fragment["params"]["k1"].as_f64(), r.load_cell.k1);
}

#[test]
fn explicit_start_skips_detection() {
    let (t, f) = history(C1, 2e-3, 12e-3, 10.0, 3);
    let opts = RingdownOptions {
        start: Some(2e-3),
        k1: Some(K1),
        ..RingdownOptions::default()
    };
    let r = analyse(&t, &f, &opts).unwrap();
    assert!(r.start.drop.is_none());
    assert_eq!(r.start.index, 2000);
    assert!(
        (r.load_cell.c1_post.unwrap() / C1 - 1.0).abs() < 0.03,
        "{:?}",
        r.load_cell.c1_post
    );
}

#[test]
fn shipped_example_file_gives_the_reference_load_cell() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/campaigns/ringdown_synthetic.csv"
    );
    let data = read_two_columns(path.as_ref()).unwrap();
    let r = analyse(&data.x, &data.y, &with_masses(Some(M1), None)).unwrap();
    let (fn_true, _) = truth(C1);
    assert!(
        (r.psd.peak_hz - fn_true).abs() <= r.psd.resolution_hz,
        "{:?}",
        r.psd
    );
    assert!(
        (r.load_cell.c1_post.unwrap() / C1 - 1.0).abs() < 0.03,
        "{r:?}"
    );
    assert!((r.load_cell.k1.unwrap() / K1 - 1.0).abs() < 0.002, "{r:?}");
}

#[test]
fn ramp_without_fracture_is_refused() {
    let (t, f) = history(C1, 50e-3, 10e-3, 10.0, 1);
    let err = analyse(&t, &f, &RingdownOptions::default()).unwrap_err();
    assert!(matches!(err, IdentifyError::NoRingStart { .. }), "{err}");
}

#[test]
fn fracture_at_the_end_is_too_short() {
    let (t, f) = history(C1, 9.9e-3, 10e-3, 10.0, 1);
    let err = analyse(&t, &f, &RingdownOptions::default()).unwrap_err();
    assert!(
        matches!(err, IdentifyError::TooShortRingdown { needed: 256, .. }),
        "{err}"
    );
    // Enough samples but fewer than six cycles above the noise.
    let (t, f) = history(C1, 9.3e-3, 10e-3, 10.0, 1);
    let err = analyse(&t, &f, &RingdownOptions::default()).unwrap_err();
    assert!(
        matches!(
            err,
            IdentifyError::TooShortRingdown {
                what: "positive peaks",
                ..
            }
        ),
        "{err}"
    );
    let err = analyse(&t[..100], &f[..100], &RingdownOptions::default()).unwrap_err();
    assert!(
        matches!(err, IdentifyError::TooShortRingdown { found: 100, .. }),
        "{err}"
    );
}

#[test]
fn uneven_time_steps_and_bad_options_are_refused() {
    let (mut t, f) = history(C1, 2e-3, 5e-3, 10.0, 1);
    t[1000] += 0.5e-6;
    let err = analyse(&t, &f, &RingdownOptions::default()).unwrap_err();
    assert!(
        matches!(err, IdentifyError::NonUniformTime { index: 1000, .. }),
        "{err}"
    );
    let (t, f) = history(C1, 2e-3, 5e-3, 10.0, 1);
    let err = analyse(&t, &f, &with_masses(Some(-7.9), None)).unwrap_err();
    assert!(
        matches!(err, IdentifyError::InvalidOption { name: "m1", .. }),
        "{err}"
    );
}

#[test]
fn non_numeric_and_nan_csv_lines_are_reported_with_line_numbers() {
    let err = parse_two_columns("time_s,force_N\n0,1\n1e-6,1..2\n").unwrap_err();
    assert!(
        matches!(
            err,
            IdentifyError::NotNumeric {
                line: 3,
                column: 2,
                ..
            }
        ),
        "{err}"
    );
    let err = parse_two_columns("# x\n0,1\nnan,2\n").unwrap_err();
    assert!(
        matches!(
            err,
            IdentifyError::NotFinite {
                line: 3,
                column: 1,
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn coarse_psd_resolution_still_gives_the_decay() {
    // Δf ≈ 2 kHz: the PSD only locates the mode; peak timing and the fit refine it.
    let c1 = C1 / 10.0;
    let (t, f) = history(c1, 1e-3, 30e-3, 10.0, 9);
    let opts = RingdownOptions {
        segment_len: Some(512),
        m1: Some(M1),
        k1: Some(K1),
        ..RingdownOptions::default()
    };
    let r = analyse(&t, &f, &opts).unwrap();
    let (fn_true, zeta_true) = truth(c1);
    assert_eq!(r.psd.segment_len, 512);
    assert!(
        (r.psd.peak_hz - fn_true).abs() <= r.psd.resolution_hz,
        "{:?}",
        r.psd
    );
    assert!((r.natural_frequency_hz / fn_true - 1.0).abs() < 1e-3);
    assert!((r.fit.zeta / zeta_true - 1.0).abs() < 0.02, "{:?}", r.fit);
    assert!(
        (r.decrement.zeta_mean / zeta_true - 1.0).abs() < 0.03,
        "{:?}",
        r.decrement
    );
}

/// A hammer-like free decay at 212 Hz sampled at only 1280 Hz (six samples per
/// cycle) with very light damping: the envelope recovers ζ, and the report
/// compares the three estimates and says so when they disagree.
#[test]
fn six_samples_per_cycle_envelope_recovers_light_damping_and_agreement_is_reported() {
    let (fs, f0, zeta) = (1280.0, 212.0, 0.0009);
    let w0 = 2.0 * PI * f0;
    let t: Vec<f64> = (0..12_800).map(|i| i as f64 / fs).collect();
    let f: Vec<f64> = t
        .iter()
        .map(|&t| 100.0 * (-zeta * w0 * t).exp() * (w0 * (1.0 - zeta * zeta).sqrt() * t).cos())
        .collect();
    let opts = RingdownOptions {
        start: Some(0.0),
        ..RingdownOptions::default()
    };
    let r = analyse(&t, &f, &opts).unwrap();
    let env = r.envelope.as_ref().expect("an envelope");
    assert!((env.zeta / zeta - 1.0).abs() < 0.03, "{env:?}");
    assert!((r.fit.zeta / zeta - 1.0).abs() < 0.03, "{:?}", r.fit);
    let g = &r.agreement;
    assert!((g.samples_per_cycle - fs / f0).abs() < 0.01);
    assert_eq!(g.zeta_envelope, Some(env.zeta));
    // The flag follows the spread, and a disagreement always carries a warning.
    assert_eq!(g.agree, g.relative_spread <= 0.1);
    assert_eq!(g.agree, g.warnings.is_empty());
}

/// The damping ratio of both directions of [`bearing_hammer`].
const BEARING_ZETA: f64 = 0.01;

/// A hammer impact on the shipped `bearing_2dof` rig: times (s), and the
/// displacements in x and y (m), sampled at 3906.25 Hz.
struct Hammer {
    t: Vec<f64>,
    x: Vec<f64>,
    y: Vec<f64>,
    /// The rig's shaft mass `m` (kg).
    m: f64,
}

/// The bearing rig at its reference values, damped to [`BEARING_ZETA`] in x
/// and y without cross damping, struck in x.
fn bearing_hammer() -> Hammer {
    use paper_rigs_common::{outputs, params, rig, truth};
    let rig = rig("bearing_2dof");
    let mut v = truth("bearing_2dof_reference_params.json");
    let (m, kx) = (v["m"].as_f64().unwrap(), v["k_x"].as_f64().unwrap());
    let c = 2.0 * BEARING_ZETA * (kx * m).sqrt();
    v.insert("c_x".into(), c.into());
    v.insert("c_y".into(), c.into());
    v.insert("c_xy".into(), 0.0.into());
    v.retain(|key, _| !key.starts_with("hy."));
    let fs = 3906.25;
    let mut h = outputs(&rig, &params(&rig, &v), 1.0 / fs, 8000, 8);
    let (y, x) = (h.pop().unwrap(), h.pop().unwrap());
    let t = (0..x.len()).map(|i| i as f64 / fs).collect();
    Hammer { t, x, y, m }
}

/// `ringdown` speaks the rig it is given: `--time` and `--signal` choose the
/// columns of a wider record by name, `--mass` is the rig's, and the fragment
/// and the report carry the names `--names` asks for, with the very values a
/// two-column record of the same signal gives under the load cell's names.
#[test]
fn ringdown_takes_the_rigs_columns_and_names() {
    let hammer = bearing_hammer();
    let dir = tempfile::tempdir().unwrap();
    let (wide, two) = (dir.path().join("wide.csv"), dir.path().join("two.csv"));
    let (mut w, mut t) = (String::from("y_m,t_s,x_m\n"), String::new());
    for ((time, x), y) in hammer.t.iter().zip(&hammer.x).zip(&hammer.y) {
        w += &format!("{y:.10e},{time:.10e},{x:.10e}\n");
        t += &format!("{time:.10e},{x:.10e}\n");
    }
    std::fs::write(&wide, w).unwrap();
    std::fs::write(&two, t).unwrap();
    let m = hammer.m.to_string();
    let run = |args: &[&str]| {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_rigfit"))
            .args(args)
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        stdout
    };
    let wide = wide.to_str().unwrap();
    let named = ["ringdown", wide, "--time", "t_s", "--signal", "x_m"];
    let named = [&named[..], &["--mass", &m, "--names", "k_x,c_x"]].concat();
    let text = run(&named);
    assert!(
        text.contains("  c_x = ") && text.contains("  k_x from"),
        "{text}"
    );
    assert!(
        !text.contains("c1_post =") && !text.contains("k1 from"),
        "{text}"
    );
    let json = |stdout: String| -> serde_json::Value { serde_json::from_str(&stdout).unwrap() };
    let named = json(run(&[&["--json"], &named[..]].concat()));
    let plain = json(run(&[
        "--json",
        "ringdown",
        two.to_str().unwrap(),
        "--m1",
        &m,
    ]));
    let (named, plain) = (&named["fragment"]["params"], &plain["fragment"]["params"]);
    assert_eq!(named.as_object().unwrap().len(), 2, "{named}");
    assert_eq!(named["k_x"], plain["k1"], "{named} {plain}");
    assert_eq!(named["c_x"], plain["c1_post"], "{named} {plain}");
    // The damping of the x mode, within the estimators' agreement.
    let (k, c) = (
        named["k_x"].as_f64().unwrap(),
        named["c_x"].as_f64().unwrap(),
    );
    let zeta = c / (2.0 * (k * hammer.m).sqrt());
    assert!((zeta / BEARING_ZETA - 1.0).abs() < 0.1, "ζ {zeta}");
}

/// A hammer impact on the shipped `bearing_2dof` rig, lightly damped and with
/// its cross coupling (so the x sensor sees both modes), read by the command:
/// the start is found without a fracture, the envelope's band keeps the
/// chosen mode, the estimators agree with the rig's ζ and the words suit any
/// ringdown.
#[test]
fn a_hammer_ringdown_of_the_bearing_rig_is_reported_in_a_ringdowns_words() {
    let zeta = BEARING_ZETA;
    let hammer = bearing_hammer();
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("hammer.csv");
    let mut text = String::from("t_s,x_m\n");
    for (t, x) in hammer.t.iter().zip(&hammer.x) {
        text += &format!("{t:.10e},{x:.10e}\n");
    }
    std::fs::write(&csv, text).unwrap();
    let svg = dir.path().join("hammer.svg");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .arg("ringdown")
        .arg(&csv)
        .arg("--svg")
        .arg(&svg)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    println!("{stdout}");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(!stdout.to_lowercase().contains("fractur"), "{stdout}");
    assert!(stdout.contains("free ringing from"), "{stdout}");
    // The figure: the decay envelope, and the estimators' decay lines.
    let figure = std::fs::read_to_string(&svg).unwrap();
    assert!(
        figure.contains("<svg") && figure.contains("envelope"),
        "{figure}"
    );
    assert!(!figure.to_lowercase().contains("fractur"));
    let data = read_two_columns(&csv).unwrap();
    let r = analyse(&data.x, &data.y, &RingdownOptions::default()).unwrap();
    // The x mode: k_x + k_xy against the mass, with the y mode beside it.
    let g = &r.agreement;
    println!("{g:?}; f_n = {:.2} Hz", r.natural_frequency_hz);
    assert!(g.agree, "{g:?}");
    let env = r.envelope.as_ref().unwrap().zeta;
    assert!((env / zeta - 1.0).abs() < 0.1, "{env}");
}
