//! Bendat's reverse-path nonlinear MISO analysis (the friction rig paper ("Non-linear signal analysis applied to surface wear condition monitoring in reciprocating sliding testing machines"), Eq. 1) splits a
//! force-driven Duffing oscillator simulated with rigfit's integrator into its
//! linear impedance and its cubic path, and recovers m, c, k and k3.

mod identify_common;

use identify_common::{Multisine, System, simulate};
use rigfit::identify::nimiso::{self, NimisoOptions, Nonlinearity};

/// `m·ẍ + c·ẋ + k·x + k3·x³ = F(t)`.
struct Duffing {
    m: f64,
    c: f64,
    k: f64,
    k3: f64,
    force: Multisine,
}

impl System for Duffing {
    fn dim(&self) -> usize {
        2
    }

    fn deriv(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] =
            (self.force.at(t) - self.c * y[1] - self.k * y[0] - self.k3 * y[0].powi(3)) / self.m;
    }
}

fn close(name: &str, got: f64, want: f64, rel: f64) {
    assert!(
        (got - want).abs() <= rel * want.abs(),
        "{name}: {got}, want {want} within {:.1} %",
        rel * 100.0
    );
}

#[test]
fn duffing_paths_give_impedance_and_cubic_coefficient() {
    let (m, c, k, k3) = (1.0, 6.0, 1.0e4, 1.0e8);
    let force = Multisine::new(2.0, 40.0, 381, 20.0, 5);
    let mut sys = Duffing {
        m,
        c,
        k,
        k3,
        force: force.clone(),
    };
    let fs = 200.0;
    let (t, y) = simulate(&mut sys, fs, 26_000, 2);
    let skip = 2000;
    let x: Vec<f64> = y[skip..].iter().map(|s| s[0]).collect();
    let f: Vec<f64> = t[skip..].iter().map(|&t| force.at(t)).collect();
    let xmax = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    assert!(k3 * xmax.powi(3) > 0.1 * k * xmax, "too weak: {xmax:e}");
    let opts = NimisoOptions {
        sample_rate_hz: fs,
        segment_len: Some(2048),
        nonlinearity: Nonlinearity::Cubic,
        f_min: 3.0,
        f_max: 38.0,
    };
    let (path, r) = nimiso::analyse(&x, &f, &opts).unwrap();
    println!("{r:#?}");
    close("k3", r.nonlinear_coefficient, k3, 0.03);
    close("k", r.stiffness, k, 0.02);
    close("m", r.mass, m, 0.02);
    close("c", r.damping, c, 0.05);
    // Together the two paths explain the force; the linear one alone does not
    // near the resonance, where the cubic term matters most.
    assert!(r.mean_coherence_linear + r.mean_coherence_nonlinear > 0.99);
    let res = path.freqs.iter().position(|&f| f >= 16.0).unwrap();
    assert!(path.coherence_nonlinear[res] > 0.0);
    // Ignoring the cubic input biases the linear stiffness.
    assert!((path.h_o[res].re - path.h[res].re).abs() > 0.0);

    // The command reads the same record from a CSV and writes the fragment.
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("duffing.csv");
    let mut text = String::from("t_s,x_m,force_N\n");
    for (i, (x, f)) in x.iter().zip(&f).enumerate() {
        text += &format!("{:.17e},{x:.17e},{f:.17e}\n", t[skip + i]);
    }
    std::fs::write(&csv, text).unwrap();
    let frag = dir.path().join("duffing.json");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(["identify", "nimiso"])
        .arg(&csv)
        .args([
            "--motion",
            "x_m",
            "--force",
            "force_N",
            "--nonlinear",
            "cubic",
        ])
        .args([
            "--segment",
            "2048",
            "--f-min",
            "3",
            "--f-max",
            "38",
            "--fixed",
        ])
        .arg("--out")
        .arg(&frag)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let fragment: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&frag).unwrap()).unwrap();
    close(
        "k3 from the command",
        fragment["params"]["k3"].as_f64().unwrap(),
        k3,
        0.03,
    );
}
