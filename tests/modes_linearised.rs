//! Proves the modal analysis: a single mass at √(k/m)/2π, a two-mass chain at its
//! closed form with mass-orthogonal shapes, and the compiled reference rig's
//! modes, its linearisation checked against the hand-written oracle
//! (tests/oracle).

mod oracle;
mod tensile_common;

use oracle::tensile::{REFERENCE, ix};
use rigfit::base::Drive;
use rigfit::model::Linearised;
use rigfit::model::modes::{ModeReport, ModesError};
use std::f64::consts::TAU;
use tensile_common::tensile4;

#[test]
fn single_mass_rings_at_sqrt_k_over_m() {
    let (m, k) = (7.9, 8.4e9);
    let r = ModeReport::new(&Linearised {
        dofs: vec!["x".into()],
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
        dofs: vec!["a".into(), "b".into()],
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

/// The oracle's linearisation (tests/oracle) with the slack adapter's spring
/// at its tangent where the compiled rig linearises it: about rest with the
/// contact closed, the exponential law's `a·e^{b·d} + c` at `d = −gap`. (The
/// oracle takes `k4_lin`, the adapter engaged beyond its knee.)
fn oracle_at_rest(p: &[f64], drive: &Drive) -> Linearised {
    let mut q = p.to_vec();
    q[ix::K4_LIN] = p[ix::SLACK_A] * (-p[ix::SLACK_B] * p[ix::GAP]).exp() + p[ix::SLACK_C];
    let o = oracle::tensile::linearise(&q, drive);
    Linearised {
        dofs: o.dofs.iter().map(|d| d.to_string()).collect(),
        mass: o.mass,
        stiffness: o.stiffness,
    }
}

/// The compiled rig's linearisation is the oracle's, dof by dof, to rounding.
fn assert_matches_the_oracle(lin: &Linearised, p: &[f64], drive: &Drive) {
    let o = oracle_at_rest(p, drive);
    // The oracle's dof names are words; the rig's nodes are identifiers.
    let names: Vec<String> = o
        .dofs
        .iter()
        .map(|d| d.replace("sliding bar", "bar").replace(' ', "_"))
        .collect();
    assert_eq!(lin.dofs, names, "{drive:?}");
    assert_eq!(lin.mass, o.mass, "{drive:?}");
    let scale = o.stiffness.iter().fold(0.0_f64, |m, k| m.max(k.abs()));
    for (i, (a, b)) in lin.stiffness.iter().zip(&o.stiffness).enumerate() {
        assert!(
            (a - b).abs() <= 1e-12 * scale,
            "{drive:?}: K[{i}] = {a} vs the oracle's {b}"
        );
    }
}

/// The compiled reference rig linearised about rest (velocity drive: load cell,
/// specimen, bar) has modes at 1987.4 Hz (bar, 82 % of the kinetic energy),
/// 5215.7 Hz (load cell, 99.8 %) and 10748.2 Hz (specimen, 82 %). The load-cell
/// mode is 0.5 % above the bare √(k1/m1)/2π = 5189.7 Hz because the specimen
/// spring (k_lin = 8.63e7 N/m) adds to k1 while the light specimen side barely
/// moves: it sits at √((k1 + k_lin)/m1)/2π = 5216.3 Hz to within 1 Hz. After
/// fracture that spring is gone and the ringing drops to 5189 Hz. The slack
/// adapter enters at its stiffness on first contact (≈ a + c = 1.94e7 N/m, see
/// [`oracle_at_rest`]), which sets the bar and actuator modes.
#[test]
fn reference_rig_has_a_load_cell_mode_near_5_2_khz() {
    let p = REFERENCE;
    let rig = tensile4();
    let lin = rig.linearise(&p, &Drive::Velocity);
    assert_matches_the_oracle(&lin, &p, &Drive::Velocity);
    let r = ModeReport::new(&lin).unwrap();
    println!("{}\n{r}", rig.linearisation_point());
    let freqs: Vec<f64> = r.modes.iter().map(|m| m.frequency_hz).collect();
    let cell = r.dominated_by("load_cell").expect("a load-cell mode");
    let with_specimen = ((p[ix::K1] + p[ix::K_LIN]) / p[ix::M1]).sqrt() / TAU;
    assert!(
        (cell.frequency_hz - 5215.74).abs() < 0.5,
        "load-cell mode at {}",
        cell.frequency_hz
    );
    assert!((cell.frequency_hz - with_specimen).abs() < 1.0);
    assert!(cell.energy_share[0] > 0.99);
    assert!(
        (freqs[0] - 1987.42).abs() < 0.5 && (freqs[2] - 10748.18).abs() < 0.5,
        "{freqs:?}"
    );
    assert_eq!(r.dofs[r.modes[0].dominant], "bar");
    assert_eq!(r.dofs[r.modes[2].dominant], "specimen");
    let table = r.to_string();
    assert!(
        table.contains("load_cell") && table.contains("5215.74"),
        "{table}"
    );

    // Force drive adds the actuator mode at ≈ 102 Hz and leaves the others.
    let pl = rigfit::base::PiecewiseLinear {
        t: vec![0.0],
        value: vec![0.0],
    };
    let force = Drive::Force(pl);
    let lin_f = rig.linearise(&p, &force);
    assert_matches_the_oracle(&lin_f, &p, &force);
    let rf = ModeReport::new(&lin_f).unwrap();
    assert_eq!(rf.dofs[rf.modes[0].dominant], "actuator");
    assert!(
        (rf.modes[0].frequency_hz - 101.63).abs() < 0.5,
        "{}",
        rf.modes[0].frequency_hz
    );
    assert!((rf.dominated_by("load_cell").unwrap().frequency_hz - cell.frequency_hz).abs() < 0.1);

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
        dofs: vec!["x".into()],
        mass: vec![0.0],
        stiffness: vec![1.0],
    };
    assert!(matches!(
        ModeReport::new(&bad_mass),
        Err(ModesError::Mass { .. })
    ));
    let bad_size = Linearised {
        dofs: vec!["x".into(), "y".into()],
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
