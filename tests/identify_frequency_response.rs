//! H1/H2 with coherence and the rational-fraction modal fit recover the natural
//! frequencies, damping ratios and modal masses of force-driven chains
//! simulated with rigfit's integrator (closed-form truth).

mod identify_common;

use std::f64::consts::PI;
use std::path::Path;

use identify_common::{ForcedChain, Multisine, simulate};
use rigfit::campaign::Campaign;
use rigfit::identify::frf;
use rigfit::identify::modal::{self, ModalOptions, Response};

/// Simulates the chain under a 2–30 Hz multisine (0.1 Hz line spacing) on mass
/// 1 at 100 Hz for 130 s and returns force and x1 after the first 10 s.
fn record(m: Vec<f64>, k: Vec<f64>, c: Vec<f64>) -> (Vec<f64>, Vec<f64>) {
    let force = Multisine::new(2.0, 30.0, 281, 10.0, 11);
    let mut sys = ForcedChain {
        m,
        k,
        c,
        driven: 0,
        force: force.clone(),
    };
    let fs = 100.0;
    let (t, y) = simulate(&mut sys, fs, 13_000, 2);
    let skip = 1000;
    (
        t[skip..].iter().map(|&t| force.at(t)).collect(),
        y[skip..].iter().map(|s| s[0]).collect(),
    )
}

fn close(name: &str, got: f64, want: f64, rel: f64) {
    assert!(
        (got - want).abs() <= rel * want.abs(),
        "{name}: {got}, want {want} within {:.1} %",
        rel * 100.0
    );
}

#[test]
fn sdof_frequency_damping_and_mass_are_recovered() {
    let (m, k, zeta): (f64, f64, f64) = (2.0, 8000.0, 0.05);
    let c = 2.0 * zeta * (k * m).sqrt();
    let (u, y) = record(vec![m], vec![k], vec![c]);
    let est = frf::estimate(&u, &y, 100.0, Some(1024)).unwrap();
    let opts = ModalOptions {
        modes: 1,
        f_min: 3.0,
        f_max: 28.0,
        response: Response::Displacement,
        min_coherence: 0.9,
        iterations: 10,
    };
    let fit = modal::fit(&est.freqs, &est.h1, &est.coherence, &opts).unwrap();
    println!("{fit:#?}");
    let mode = &fit.modes[0];
    close(
        "f_n",
        mode.natural_frequency_hz,
        (k / m).sqrt() / (2.0 * PI),
        0.002,
    );
    close("ζ", mode.damping_ratio, zeta, 0.05);
    close("m", mode.mass, m, 0.03);
    close("k", mode.stiffness, k, 0.03);
    // A noise-free linear record is fully coherent in the excited band.
    let band = est.freqs.iter().position(|&f| f > 3.0).unwrap();
    assert!(est.coherence[band..280].iter().all(|&g| g > 0.95));
    let names = ["m1".to_string(), "k1".to_string(), "c1".to_string()];
    let frag = fit.to_campaign_fragment(&names, true);
    assert!((frag["params"]["k1"].as_f64().unwrap() - mode.stiffness).abs() < 1e-9 * k);
    // The free form, pasted into the shipped tensile4 campaign, is a valid
    // campaign with the load cell's three values as genes.
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns");
    let mut campaign: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("aa2024_t3_synthetic.json")).unwrap(),
    )
    .unwrap();
    let free = fit.to_campaign_fragment(&names, false);
    for (name, value) in free["params"].as_object().unwrap() {
        campaign["params"][name] = value.clone();
    }
    let c = Campaign::from_str(&campaign.to_string(), &dir, "merged").unwrap();
    c.require_genes().unwrap();
}

#[test]
fn two_dof_chain_modes_match_the_closed_form() {
    // Stiffness-proportional damping C = βK keeps the modes real:
    // ζ_i = β·ω_i/2, and the modal mass at mass 1 is φᵀMφ with φ₁ = 1.
    let (m1, m2, k1, k2, beta) = (2.0, 1.0, 8000.0, 6000.0, 0.002);
    let (u, y) = record(vec![m1, m2], vec![k1, k2], vec![beta * k1, beta * k2]);
    // det(K − ω²M) = 0: m1m2·w² − (m1k2 + m2(k1 + k2))·w + k1k2 = 0, w = ω².
    let (a, b, c) = (m1 * m2, -(m1 * k2 + m2 * (k1 + k2)), k1 * k2);
    let disc = (b * b - 4.0 * a * c).sqrt();
    let truth: Vec<(f64, f64, f64)> = [(-b - disc) / (2.0 * a), (-b + disc) / (2.0 * a)]
        .iter()
        .map(|&w| {
            let phi2 = k2 / (k2 - m2 * w);
            (
                w.sqrt() / (2.0 * PI),
                beta * w.sqrt() / 2.0,
                m1 + m2 * phi2 * phi2,
            )
        })
        .collect();
    let est = frf::estimate(&u, &y, 100.0, Some(1024)).unwrap();
    let opts = ModalOptions {
        modes: 2,
        f_min: 3.0,
        f_max: 28.0,
        response: Response::Displacement,
        min_coherence: 0.9,
        iterations: 10,
    };
    let fit = modal::fit(&est.freqs, &est.h1, &est.coherence, &opts).unwrap();
    println!("{truth:?}\n{fit:#?}");
    for (mode, &(f, z, mm)) in fit.modes.iter().zip(&truth) {
        close("f_n", mode.natural_frequency_hz, f, 0.003);
        close("ζ", mode.damping_ratio, z, 0.06);
        close("modal mass", mode.mass, mm, 0.05);
    }
}

#[test]
fn identify_frf_says_its_mass_stiffness_and_damping_assume_a_force_input() {
    let (m, k, zeta): (f64, f64, f64) = (2.0, 8000.0, 0.05);
    let c = 2.0 * zeta * (k * m).sqrt();
    let (u, y) = record(vec![m], vec![k], vec![c]);
    let dir = tempfile::tempdir().unwrap();
    let mut csv = String::from("t_s,u,x_m\n");
    for (i, (u, y)) in u.iter().zip(&y).enumerate() {
        csv += &format!("{},{u},{y}\n", i as f64 / 100.0);
    }
    let data = dir.path().join("rec.csv");
    std::fs::write(&data, csv).unwrap();
    let run = |json: bool| {
        let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_rigfit"));
        if json {
            cmd.arg("--json");
        }
        let out = cmd
            .args(["identify", "frf"])
            .arg(&data)
            .args(["--f-min", "3", "--f-max", "28"])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).to_string()
    };
    let text = run(false);
    assert!(text.contains(frf::FORCE_INPUT), "{text}");
    let report: serde_json::Value = serde_json::from_str(&run(true)).unwrap();
    assert_eq!(
        report["assumes"].as_str(),
        Some(frf::FORCE_INPUT),
        "{report}"
    );
}
