//! The bearing rig thesis chapter ("Experimental Investigations of Lubricated Bearing Stiffness")'s impedance method on the shipped `bearing_2dof` rig: two
//! hammer impacts simulated by rigfit (one in x, one in y, as the document's
//! two linearly independent tests) give the 2 × 2 impedance and receptance
//! matrices, and their curve fits return the rig's mass, direct and cross
//! stiffness and damping; the command writes a fragment the shipped campaign
//! takes.

mod paper_rigs_common;

use std::f64::consts::PI;

use paper_rigs_common::{outputs, params, rig, shipped, truth};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rigfit::identify::impedance::{self, ImpactRecord};

const FS: f64 = 3906.25;
/// Samples per record (0.13 s): the ringing has died out well before, and a
/// longer record adds only noise to the DFTs.
const SAMPLES: usize = 512;
/// Hammer pulse length (s). The shipped records' 1 ms pulse spans four samples
/// at the document's rate, and the DFT of the sampled pulse then misses the
/// continuous force's enough to put the mass 2.9 % low; a 4 ms pulse (a softer
/// hammer tip) spans sixteen.
const TAU: f64 = 0.004;

/// Sensor noise (m), the shipped records' level.
const NOISE: f64 = 2e-8;

/// `(force, x, y)` of the impact named `exp` (`"hx"` or `"hy"`), with seeded
/// noise of [`NOISE`] on the displacements.
fn impact(exp: &str, seed: u64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let rig = rig("bearing_2dof");
    let mut v = truth("bearing_2dof_reference_params.json");
    let other = if exp == "hx" { "hy." } else { "hx." };
    v.retain(|k, _| !k.starts_with(other));
    v.insert(format!("{exp}.tau"), TAU.into());
    let h = outputs(&rig, &params(&rig, &v), 1.0 / FS, SAMPLES, 8);
    let amp = v[&format!("{exp}.{}", if exp == "hx" { "f_x" } else { "f_y" })]
        .as_f64()
        .unwrap();
    let t0 = v[&format!("{exp}.t_impact")].as_f64().unwrap();
    let force = (0..SAMPLES)
        .map(|i| {
            let t = i as f64 / FS;
            if t >= t0 && t <= t0 + TAU {
                amp * (PI * (t - t0) / TAU).sin()
            } else {
                0.0
            }
        })
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut noisy = |x: &Vec<f64>| -> Vec<f64> {
        x.iter()
            .map(|v| {
                let (u1, u2): (f64, f64) = (rng.random(), rng.random());
                v + NOISE * (-2.0 * (1.0 - u1).ln()).sqrt() * (2.0 * PI * u2).cos()
            })
            .collect()
    };
    (force, noisy(&h[0]), noisy(&h[1]))
}

#[test]
fn two_impacts_give_the_bearing_matrices_and_the_rig_parameters() {
    let truth = truth("bearing_2dof_reference_params.json");
    let (f1, x1, y1) = impact("hx", 1);
    let (f2, x2, y2) = impact("hy", 2);
    let m = impedance::matrices(
        ImpactRecord {
            force: &f1,
            x: &x1,
            y: &y1,
        },
        ImpactRecord {
            force: &f2,
            x: &x2,
            y: &y2,
        },
        FS,
    )
    .unwrap();
    // The receptance is the impedance's inverse at every line.
    let k = m.freqs.iter().position(|&f| f > 150.0).unwrap();
    let id = m.impedance[k] * m.receptance[k];
    assert!((id[(0, 0)].re - 1.0).abs() < 1e-9 && id[(0, 1)].norm() < 1e-9);

    let fit = impedance::fit(&m, (20.0, 300.0), None).unwrap();
    println!("{fit:#?}");
    for (name, got) in fit.bearing_params() {
        let want = truth[name].as_f64().unwrap();
        let rel = (got / want - 1.0).abs();
        println!(
            "{name}: {got:.6e} (rig {want:.6e}, {:+.3} %)",
            100.0 * (got / want - 1.0)
        );
        // The cross damping is the weakest term (ω·c_xy is a tenth of the
        // direct damping's and under half of k_xy at the mode): the sensor
        // noise moves it by a few per cent (0.06 % without noise).
        let tol = match name {
            "m" | "k_x" | "k_y" | "c_x" | "c_y" => 0.01,
            "k_xy" => 0.02,
            _ => 0.06,
        };
        assert!(rel < tol, "{name}: {got} vs {want}");
    }
    assert!(fit.r2_real[0][0] > 0.999 && fit.r2_real[1][1] > 0.999);
    assert!(fit.r2_imag[0][0] > 0.99 && fit.r2_imag[1][1] > 0.99);
    // A given mass is kept and the rest follows.
    let given = impedance::fit(&m, (20.0, 300.0), Some(3.0)).unwrap();
    assert_eq!(given.mass, 3.0);
    assert!((given.bearing_params()[1].1 / 2.4e6 - 1.0).abs() < 0.01);
}

#[test]
fn the_impedance_command_writes_a_fragment_the_bearing_campaign_takes() {
    let dir = tempfile::tempdir().unwrap();
    let mut files = vec![];
    for (exp, seed) in [("hx", 1), ("hy", 2)] {
        let (f, x, y) = impact(exp, seed);
        let mut text = String::from("t_s,force_N,x_m,y_m\n");
        for i in 0..f.len() {
            text += &format!(
                "{:.10e},{:.10e},{:.10e},{:.10e}\n",
                i as f64 / FS,
                f[i],
                x[i],
                y[i]
            );
        }
        let p = dir.path().join(format!("{exp}.csv"));
        std::fs::write(&p, text).unwrap();
        files.push(p);
    }
    let (frag, svg) = (dir.path().join("b.json"), dir.path().join("b.svg"));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(["identify", "impedance"])
        .args(&files)
        .args([
            "--force", "force_N", "--x", "x_m", "--y", "y_m", "--mass", "3",
        ])
        .args(["--f-min", "20", "--f-max", "300", "--out"])
        .arg(&frag)
        .arg("--svg")
        .arg(&svg)
        .output()
        .unwrap();
    println!("{}", String::from_utf8_lossy(&out.stdout));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));
    let fragment: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&frag).unwrap()).unwrap();
    assert_eq!(fragment["params"]["m"], 3.0);
    let path = shipped("bearing_2dof_synthetic.json");
    let mut c: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    for (name, entry) in fragment["params"].as_object().unwrap() {
        c["params"][name] = entry.clone();
    }
    let campaign = rigfit::campaign::Campaign::from_str(
        &c.to_string(),
        path.parent().unwrap(),
        "bearing_2dof_synthetic.json",
    )
    .unwrap_or_else(|e| panic!("{e}\n{fragment:#}"));
    for name in ["k_x", "k_y", "c_x", "c_y", "k_xy", "c_xy"] {
        let g = campaign.genes.iter().find(|g| g.name == name).unwrap();
        assert_eq!(g.init, fragment["params"][name]["init"].as_f64(), "{name}");
    }
}
