//! A modal fit over a band that does not hold the resonance still places a
//! pole (the band's response above a resonance is its mass line): the mode it
//! reports lies outside the band, where no line tests it, and `identify frf`
//! says so in its text and its JSON, while a fit over the resonance says
//! nothing.

mod identify_common;

use std::f64::consts::PI;

use identify_common::{ForcedChain, Multisine, simulate};
use rigfit::identify::frf;
use rigfit::identify::modal::{self, ModalOptions, Response};

/// An SDOF of 2 kg on 8000 N/m (10.07 Hz), ζ = 0.05, under a 2–30 Hz
/// multisine at 100 Hz: force and displacement after the first 10 s.
fn record() -> (Vec<f64>, Vec<f64>) {
    let (m, k, zeta): (f64, f64, f64) = (2.0, 8000.0, 0.05);
    let force = Multisine::new(2.0, 30.0, 281, 10.0, 11);
    let mut sys = ForcedChain {
        m: vec![m],
        k: vec![k],
        c: vec![2.0 * zeta * (k * m).sqrt()],
        driven: 0,
        force: force.clone(),
    };
    let (t, y) = simulate(&mut sys, 100.0, 13_000, 2);
    let skip = 1000;
    (
        t[skip..].iter().map(|&t| force.at(t)).collect(),
        y[skip..].iter().map(|s| s[0]).collect(),
    )
}

fn options(f_min: f64, f_max: f64) -> ModalOptions {
    ModalOptions {
        modes: 1,
        f_min,
        f_max,
        response: Response::Displacement,
        min_coherence: 0.9,
        iterations: 10,
    }
}

#[test]
fn a_mode_outside_the_fitted_band_is_flagged_and_one_inside_is_not() {
    let f_n = (8000.0_f64 / 2.0).sqrt() / (2.0 * PI);
    let (u, y) = record();
    let est = frf::estimate(&u, &y, 100.0, Some(1024)).unwrap();
    let over = modal::fit(&est.freqs, &est.h1, &est.coherence, &options(3.0, 28.0)).unwrap();
    assert!(over.modes[0].in_band, "{over:#?}");
    assert!(over.warnings.is_empty(), "{:?}", over.warnings);
    let above = modal::fit(&est.freqs, &est.h1, &est.coherence, &options(16.0, 28.0)).unwrap();
    println!("true f_n {f_n:.3} Hz; band 16–28 Hz: {above:#?}");
    let mode = &above.modes[0];
    assert!(
        !(16.0..=28.0).contains(&mode.natural_frequency_hz),
        "the fit over 16–28 Hz was meant to place its pole outside the band: {mode:?}"
    );
    assert!(!mode.in_band, "{mode:?}");
    assert_eq!(above.warnings.len(), 1, "{:?}", above.warnings);
    assert!(
        above.warnings[0].contains("outside") || above.warnings[0].contains("below"),
        "{}",
        above.warnings[0]
    );
}

#[test]
fn identify_frf_warns_in_text_and_json_of_a_mode_outside_the_band() {
    let (u, y) = record();
    let dir = tempfile::tempdir().unwrap();
    let mut csv = String::from("t_s,u,x_m\n");
    for (i, (u, y)) in u.iter().zip(&y).enumerate() {
        csv += &format!("{},{u},{y}\n", i as f64 / 100.0);
    }
    let data = dir.path().join("rec.csv");
    std::fs::write(&data, csv).unwrap();
    let run = |json: bool, band: [&str; 2]| {
        let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_rigfit"));
        if json {
            cmd.arg("--json");
        }
        let out = cmd
            .args(["identify", "frf"])
            .arg(&data)
            .args(["--f-min", band[0], "--f-max", band[1]])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).to_string()
    };
    let text = run(false, ["16", "28"]);
    assert!(
        text.contains("warning: mode 1") && text.contains("the fitted band 16 … 28 Hz"),
        "{text}"
    );
    let report: serde_json::Value = serde_json::from_str(&run(true, ["16", "28"])).unwrap();
    assert_eq!(
        report["warnings"].as_array().map(Vec::len),
        Some(1),
        "{report}"
    );
    assert_eq!(report["modal"]["modes"][0]["in_band"], false, "{report}");
    let report: serde_json::Value = serde_json::from_str(&run(true, ["3", "28"])).unwrap();
    assert_eq!(
        report["warnings"].as_array().map(Vec::len),
        Some(0),
        "{report}"
    );
    assert_eq!(report["modal"]["modes"][0]["in_band"], true, "{report}");
}
