//! Proves the modal analysis: a single mass at √(k/m)/2π, a two-mass chain at its
//! closed form with mass-orthogonal shapes, and the reference rig's load-cell mode.

use rigfit::model::{Drive, Linearised, RigModel, tensile};
use rigfit::modes::{ModeReport, ModesError};
use std::f64::consts::TAU;

#[test]
fn single_mass_rings_at_sqrt_k_over_m() {
    let (m, k) = (7.9, 8.4e9);
    let r = ModeReport::new(&Linearised {
        dofs: vec!["x"],
        mass: vec![m],
        stiffness: vec![k],
    })
    .unwrap();
    let f = (k / m).sqrt() / TAU;
    assert_eq!(r.modes.len(), 1);
    assert!(
        (r.modes[0].frequency_hz - f).abs() < 1e-9 * f,
        "{} vs {f}",
        r.modes[0].frequency_hz
    );
    assert_eq!(r.modes[0].shape, vec![1.0]);
    assert!((r.modes[0].modal_mass - m).abs() < 1e-12);
}

#[test]
fn two_mass_chain_matches_its_closed_form() {
    // ground –k1– m1 –k2– m2 (free).
    let (m1, m2, k1, k2) = (2.0, 0.5, 3.0e6, 1.0e6);
    let lin = Linearised {
        dofs: vec!["a", "b"],
        mass: vec![m1, m2],
        stiffness: vec![k1 + k2, -k2, -k2, k2],
    };
    let r = ModeReport::new(&lin).unwrap();
    // ω² are the roots of ω⁴ − (tr)ω² + det = 0 of M⁻¹K.
    let tr = (k1 + k2) / m1 + k2 / m2;
    let det = k1 * k2 / (m1 * m2);
    let disc = (tr * tr - 4.0 * det).sqrt();
    let exact = [
        ((tr - disc) / 2.0).sqrt() / TAU,
        ((tr + disc) / 2.0).sqrt() / TAU,
    ];
    for (mode, f) in r.modes.iter().zip(exact) {
        assert!(
            (mode.frequency_hz - f).abs() < 1e-10 * f,
            "{} vs {f}",
            mode.frequency_hz
        );
        // Shape from the second row: (k2 − m2ω²)·φ_b = k2·φ_a.
        let w2 = mode.omega * mode.omega;
        let ratio = k2 / (k2 - m2 * w2);
        assert!((mode.shape[1] / mode.shape[0] - ratio).abs() < 1e-9 * ratio.abs());
        let peak = mode.shape.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
        assert_eq!(peak, 1.0);
        assert!((mode.energy_share.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    }
    // Mass-normalised shapes are M-orthonormal.
    let (p, q) = (r.modes[0].mass_normalised(), r.modes[1].mass_normalised());
    let dot = |u: &[f64], v: &[f64]| u[0] * m1 * v[0] + u[1] * m2 * v[1];
    assert!((dot(&p, &p) - 1.0).abs() < 1e-12 && (dot(&q, &q) - 1.0).abs() < 1e-12);
    assert!(dot(&p, &q).abs() < 1e-12);
    assert!(r.modes[0].frequency_hz < r.modes[1].frequency_hz);
}

/// The linearised reference rig (velocity drive: load cell, specimen, sliding bar)
/// has modes at 2863.9 Hz (sliding bar, 80 % of the kinetic energy), 5216.9 Hz
/// (load cell, 99.7 %) and 10794.2 Hz (specimen, 80 %). The load-cell mode is
/// 0.5 % above the bare √(k1/m1)/2π = 5189.7 Hz because the specimen spring
/// (k_lin = 8.63e7 N/m) adds to k1 while the light specimen side barely moves:
/// it sits at √((k1 + k_lin)/m1)/2π = 5216.3 Hz to within 0.7 Hz. After fracture
/// that spring is gone and the ringing drops to 5189 Hz.
#[test]
fn reference_rig_has_a_load_cell_mode_near_5_2_khz() {
    let p = tensile::REFERENCE;
    let r = ModeReport::new(&tensile::TENSILE4.linearise(&p, &Drive::Velocity)).unwrap();
    println!("{r}");
    let freqs: Vec<f64> = r.modes.iter().map(|m| m.frequency_hz).collect();
    let cell = r.dominated_by("load cell").expect("a load-cell mode");
    let with_specimen =
        ((p[tensile::ix::K1] + p[tensile::ix::K_LIN]) / p[tensile::ix::M1]).sqrt() / TAU;
    assert!(
        (cell.frequency_hz - 5216.9).abs() < 0.5,
        "load-cell mode at {}",
        cell.frequency_hz
    );
    assert!((cell.frequency_hz - with_specimen).abs() < 1.0);
    assert!(cell.energy_share[0] > 0.99);
    assert!(
        (freqs[0] - 2863.9).abs() < 0.5 && (freqs[2] - 10794.2).abs() < 0.5,
        "{freqs:?}"
    );
    assert_eq!(r.dofs[r.modes[0].dominant], "sliding bar");
    assert_eq!(r.dofs[r.modes[2].dominant], "specimen");
    let table = r.to_string();
    assert!(
        table.contains("load cell") && table.contains("5216.90"),
        "{table}"
    );

    // Force drive adds the actuator mode at ≈ 173 Hz and leaves the others.
    let pl = rigfit::model::PiecewiseLinear {
        t: vec![0.0],
        value: vec![0.0],
    };
    let rf = ModeReport::new(&tensile::TENSILE4.linearise(&p, &Drive::Force(pl))).unwrap();
    assert_eq!(rf.dofs[rf.modes[0].dominant], "actuator");
    assert!(
        (rf.modes[0].frequency_hz - 173.4).abs() < 0.5,
        "{}",
        rf.modes[0].frequency_hz
    );
    assert!((rf.dominated_by("load cell").unwrap().frequency_hz - cell.frequency_hz).abs() < 0.1);

    // The report survives a JSON round trip (to serde_json's float parsing, which
    // may differ in the last bit without its `float_roundtrip` feature).
    let back: ModeReport = serde_json::from_str(&serde_json::to_string(&r).unwrap()).unwrap();
    assert_eq!(back.dofs, r.dofs);
    for (a, b) in back.modes.iter().zip(&r.modes) {
        assert_eq!(a.dominant, b.dominant);
        assert!((a.frequency_hz - b.frequency_hz).abs() < 1e-12 * b.frequency_hz);
    }
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let bad_mass = Linearised {
        dofs: vec!["x"],
        mass: vec![0.0],
        stiffness: vec![1.0],
    };
    assert!(matches!(
        ModeReport::new(&bad_mass),
        Err(ModesError::Mass { .. })
    ));
    let bad_size = Linearised {
        dofs: vec!["x", "y"],
        mass: vec![1.0, 1.0],
        stiffness: vec![1.0],
    };
    assert_eq!(
        ModeReport::new(&bad_size),
        Err(ModesError::Size {
            expected: 4,
            found: 1
        })
    );
}
