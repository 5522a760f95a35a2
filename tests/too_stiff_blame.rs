//! A campaign whose step is too coarse for the rig's highest frequency over
//! the free bounds is refused with the free bound that sets that frequency:
//! a grip mass `m2` searched down to 1e-7 kg makes the specimen node ring at
//! ~1e8 rad/s, and the refusal names m2's lower bound (where it is set and
//! which way to move it), not only the fixed stiffness `k3` that the bound's
//! law names, whose "range" cannot be narrowed.

mod campaign_common;

use campaign_common::{csv, example, set, write};
use rigfit::campaign::Campaign;
use serde_json::{Value, json};

fn refusal(c: &Value) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        &c.to_string(),
        &[("v2.csv", &csv(400, 1e-6, 0.0))],
    );
    match Campaign::load(&path) {
        Ok(_) => panic!("accepted: {c}"),
        Err(e) => e.to_string(),
    }
}

/// The shipped example with `m2` free over `[lo, 0.5]` kg, every other
/// parameter fixed, and `substeps` RK4 steps per sample.
fn light_grip(lo: f64, substeps: Value) -> Value {
    let mut c = example();
    set(&mut c, "/params/m2", json!({"min": lo, "max": 0.5}));
    set(&mut c, "/params/k1", json!(8e9));
    set(&mut c, "/params/c1", json!(1e5));
    set(&mut c, "/experiments/0/params/k_lin", json!(8.63e7));
    set(&mut c, "/solver/substeps", substeps);
    c
}

#[test]
fn a_light_free_mass_is_named_where_a_fixed_stiffness_limits_the_bound() {
    let e = refusal(&light_grip(1e-7, json!(1)));
    assert!(e.contains("solver.substeps"), "{e}");
    assert!(e.contains("raise m2's lower bound"), "{e}");
    assert!(e.contains("params.m2.min = 1e-7 kg"), "{e}");
    // The law's parameter is fixed: no advice to narrow its range.
    let limiter = e
        .split("limited by '")
        .nth(1)
        .and_then(|r| r.split('\'').next())
        .expect("the bound's law is named");
    assert_ne!(limiter, "m2", "{e}");
    assert!(
        !e.contains(&format!("narrow the range of '{limiter}'")),
        "{e}"
    );
    assert!(e.contains(&format!("'{limiter}' is fixed")), "{e}");
}

#[test]
fn a_free_limiting_stiffness_keeps_its_own_advice() {
    let mut c = example();
    set(&mut c, "/params/k1", json!(8e9));
    set(&mut c, "/params/c1", json!(1e5));
    set(&mut c, "/params/k3", json!({"min": 1e8, "max": 1e14}));
    set(&mut c, "/experiments/0/params/k_lin", json!(8.63e7));
    set(&mut c, "/solver/substeps", json!(1));
    let e = refusal(&c);
    assert!(e.contains("narrow the range of 'k3'"), "{e}");
}

#[test]
fn a_bound_no_free_range_sets_asks_only_for_a_finer_step() {
    // Every parameter fixed: only the step can change.
    let mut c = light_grip(1e-7, json!(1));
    set(&mut c, "/params/m2", json!(1e-7));
    set(&mut c, "/params/c1", json!({"min": 1e4, "max": 1e5}));
    let e = refusal(&c);
    assert!(e.contains("use substeps ≥"), "{e}");
    assert!(!e.contains("narrow the range"), "{e}");
    assert!(!e.contains("raise"), "{e}");
}
