//! Proves that `modes` linearises in the regime it says: a stuck slider's
//! tangential spring and a closed contact's spring stiffen the rig. The
//! shipped `friction_sdof` stuck rings at √((k + k_c)/m)/2π for any k_c, a
//! slider between two masses couples them, and a mass resting on a closed
//! contact rings at √((k + k_g)/m)/2π.

use rigfit::base::Drive;
use rigfit::model::CompiledRig;
use rigfit::model::modes::ModeReport;
use std::f64::consts::TAU;

fn compiled(json: &str) -> CompiledRig {
    let desc = serde_json::from_str(json).unwrap();
    CompiledRig::new(desc, "inline.json").unwrap()
}

fn vector(rig: &CompiledRig, values: &[(&str, f64)]) -> Vec<f64> {
    rig.params()
        .iter()
        .map(|p| {
            values
                .iter()
                .find(|(n, _)| *n == p.name)
                .map(|v| v.1)
                .or(p.default)
                .unwrap_or_else(|| panic!("no value for {}", p.name))
        })
        .collect()
}

fn frequencies(rig: &CompiledRig, p: &[f64]) -> Vec<f64> {
    let r = ModeReport::new(&rig.linearise(p, &Drive::Velocity)).unwrap();
    r.modes.iter().map(|m| m.frequency_hz).collect()
}

#[test]
fn friction_sdof_stuck_rings_with_its_contact_stiffness() {
    let rig = CompiledRig::new(
        rigfit::rig::shipped("friction_sdof").unwrap(),
        "rigs/friction_sdof.json",
    )
    .unwrap();
    assert!(
        rig.linearisation_point().contains("every slider stuck"),
        "{}",
        rig.linearisation_point()
    );
    let (m, k) = (5.0, 6.4e4);
    for k_c in [1.6e6, 1e8] {
        let p = vector(
            &rig,
            &[
                ("m", m),
                ("k", k),
                ("c", 3.0),
                ("f_c", 20.0),
                ("k_c", k_c),
                ("amplitude", 10.0),
                ("frequency", 20.0),
            ],
        );
        let f = frequencies(&rig, &p);
        let exact = ((k + k_c) / m).sqrt() / TAU;
        assert_eq!(f.len(), 1);
        assert!(
            (f[0] - exact).abs() < 1e-9 * exact,
            "k_c {k_c}: {} Hz vs the closed form {exact} Hz",
            f[0]
        );
    }
}

#[test]
fn a_stuck_slider_between_two_masses_couples_them() {
    let rig = compiled(
        r#"{
        "id": "two_plates",
        "params": [
            {"name": "m1", "unit": "kg"}, {"name": "m2", "unit": "kg"},
            {"name": "k1", "unit": "N/m"}, {"name": "k2", "unit": "N/m"},
            {"name": "k_t", "unit": "N/m"}, {"name": "f_c", "unit": "N"}
        ],
        "nodes": [{"name": "a", "mass": "m1"}, {"name": "b", "mass": "m2"}],
        "elements": [
            {"name": "sa", "between": ["ground", "a"], "spring": {"law": "linear", "k": "k1"}},
            {"name": "sb", "between": ["ground", "b"], "spring": {"law": "linear", "k": "k2"}},
            {"name": "joint", "between": ["a", "b"],
             "friction": {"law": "stick_slip", "f_c": "f_c", "k_t": "k_t"}}
        ],
        "outputs": [{"name": "x", "unit": "m", "sum": [{"displacement": "a"}]}]
    }"#,
    );
    let (m1, m2, k1, k2, kt) = (2.0, 0.5, 3.0e5, 1.0e5, 4.0e6);
    let p = vector(
        &rig,
        &[
            ("m1", m1),
            ("m2", m2),
            ("k1", k1),
            ("k2", k2),
            ("k_t", kt),
            ("f_c", 10.0),
        ],
    );
    // K = [[k1 + kt, −kt], [−kt, k2 + kt]]: ω² are the eigenvalues of M⁻¹K.
    let (a, b, c) = ((k1 + kt) / m1, (k2 + kt) / m2, kt * kt / (m1 * m2));
    let disc = ((a - b) * (a - b) + 4.0 * c).sqrt();
    let exact = [
        ((a + b - disc) / 2.0).sqrt() / TAU,
        ((a + b + disc) / 2.0).sqrt() / TAU,
    ];
    let f = frequencies(&rig, &p);
    for (got, want) in f.iter().zip(exact) {
        assert!((got - want).abs() < 1e-9 * want, "{f:?} vs {exact:?}");
    }
}

#[test]
fn a_closed_contact_adds_its_spring() {
    for kind in ["compression", "tension", "free_play"] {
        let rig = compiled(&format!(
            r#"{{
            "id": "stop",
            "params": [
                {{"name": "m", "unit": "kg"}}, {{"name": "k", "unit": "N/m"}},
                {{"name": "k_g", "unit": "N/m"}}, {{"name": "gap", "unit": "m"}}
            ],
            "nodes": [{{"name": "mass", "mass": "m"}}],
            "elements": [
                {{"name": "s", "between": ["ground", "mass"], "spring": {{"law": "linear", "k": "k"}}}},
                {{"name": "stop", "between": ["ground", "mass"], "spring": {{"law": "linear", "k": "k_g"}},
                 "gap": {{"kind": "{kind}", "size": "gap"}}}}
            ],
            "outputs": [{{"name": "x", "unit": "m", "sum": [{{"displacement": "mass"}}]}}]
        }}"#
        ));
        assert!(rig.linearisation_point().contains("every contact closed"));
        let (m, k, k_g) = (3.0, 2.0e4, 5.0e6);
        let p = vector(&rig, &[("m", m), ("k", k), ("k_g", k_g), ("gap", 1e-4)]);
        let f = frequencies(&rig, &p);
        let exact = ((k + k_g) / m).sqrt() / TAU;
        assert!(
            (f[0] - exact).abs() < 1e-9 * exact,
            "{kind}: {} Hz vs {exact} Hz",
            f[0]
        );
    }
}
