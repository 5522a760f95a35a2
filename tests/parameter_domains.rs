//! A campaign's value, bound or `init` outside a parameter's physical domain
//! (a negative stiffness, a negative damping, a negative fracture elongation
//! or ramp) is refused before any work, naming the campaign file, the JSON
//! path and the rig's declaration; so are a parameter file's values, and a
//! rig whose own default lies outside its domain. Signed parameters (a
//! polynomial coefficient, a velocity, an initial state) keep any sign.

mod campaign_common;

use campaign_common::{csv, example, set, write};
use rigfit::campaign::Campaign;
use serde_json::{Value, json};

/// Loads `c` (with its record) from a fresh folder.
fn load(c: &Value) -> Result<Campaign, String> {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        &c.to_string(),
        &[("v2.csv", &csv(400, 1e-6, 0.0))],
    );
    Campaign::load(&path).map_err(|e| e.to_string())
}

/// The refusal of `c`, which must be refused.
fn refusal(c: &Value) -> String {
    match load(c) {
        Ok(_) => panic!("accepted: {c}"),
        Err(e) => e,
    }
}

#[test]
fn a_negative_stiffness_bound_is_refused_at_its_path() {
    let mut c = example();
    set(
        &mut c,
        "/experiments/0/params/k_lin",
        json!({"min": -3e7, "max": 3e8, "scale": "linear"}),
    );
    let e = refusal(&c);
    assert!(e.contains("campaign.json"), "{e}");
    assert!(e.contains("experiments[0].params.k_lin.min"), "{e}");
    assert!(e.contains("rig 'tensile4' declares k_lin (N/m)"), "{e}");
    assert!(e.contains("found -30000000"), "{e}");
}

#[test]
fn a_log_scale_stiffness_below_zero_names_its_domain_not_a_linear_scale() {
    let mut c = example();
    set(&mut c, "/params/k1", json!({"min": -2e9, "max": 3e10}));
    let e = refusal(&c);
    assert!(e.contains("params.k1.min"), "{e}");
    assert!(e.contains("declares k1 (N/m) positive"), "{e}");
    assert!(
        !e.contains("\"linear\""),
        "no advice to search through 0: {e}"
    );
}

#[test]
fn fixed_negative_stiffness_and_damping_are_refused() {
    for (pointer, path) in [
        ("/params/k3", "params.k3"),
        ("/params/c4", "params.c4"),
        ("/params/c1", "params.c1"),
    ] {
        let mut c = example();
        set(&mut c, pointer, json!(-10.0));
        let e = refusal(&c);
        assert!(e.contains(&format!("{path}: expected a value")), "{e}");
        assert!(e.contains("found -10"), "{e}");
    }
}

#[test]
fn a_negative_fracture_elongation_ramp_or_gap_is_refused() {
    for (pointer, value, path) in [
        ("/params/e_fracture", json!(-1e-3), "params.e_fracture"),
        (
            "/experiments/0/params/ramp",
            json!(-1e-6),
            "experiments[0].params.ramp",
        ),
        (
            "/params/gap",
            json!({"min": -1e-5, "max": 5e-5}),
            "params.gap.min",
        ),
    ] {
        let mut c = example();
        set(&mut c, pointer, value);
        let e = refusal(&c);
        assert!(e.contains(path), "{e}");
        assert!(e.contains("nonnegative"), "{e}");
    }
}

#[test]
fn an_init_outside_the_domain_is_refused_at_init() {
    let mut c = example();
    set(
        &mut c,
        "/params/c4",
        json!({"min": 0.0, "max": 1e5, "init": -5.0}),
    );
    let e = refusal(&c);
    assert!(e.contains("params.c4.init"), "{e}");
}

#[test]
fn signed_parameters_keep_either_sign() {
    let mut c = example();
    set(&mut c, "/params/a1", json!(-1.97e6));
    set(&mut c, "/params/slack_c", json!(-1e3));
    set(&mut c, "/params/c4", json!(0.0));
    set(&mut c, "/experiments/0/params/velocity", json!(-2.0));
    load(&c).unwrap();
}

#[test]
fn a_parameter_file_value_outside_the_domain_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        &example().to_string(),
        &[("v2.csv", &csv(400, 1e-6, 0.0))],
    );
    let mut c = Campaign::load(&path).unwrap();
    let file = dir.path().join("values.json");
    std::fs::write(&file, r#"{"params": {"k3": -4.4e8}}"#).unwrap();
    let e = c.apply_param_file(&file).unwrap_err().to_string();
    assert!(e.contains("values.json"), "{e}");
    assert!(e.contains("params.k3"), "{e}");
    assert!(e.contains("declares k3 (N/m)"), "{e}");
    std::fs::write(&file, r#"{"v2.e_fracture": -1e-4}"#).unwrap();
    let e = c.apply_param_file(&file).unwrap_err().to_string();
    assert!(
        e.contains("v2.e_fracture") && e.contains("nonnegative"),
        "{e}"
    );
    std::fs::write(&file, r#"{"k3": 4.0e8, "a2": -1e9}"#).unwrap();
    c.apply_param_file(&file).unwrap();
}

#[test]
fn an_inline_rig_declares_a_domain_and_its_default_is_held_to_it() {
    let mut rig: Value =
        serde_json::from_str(&rigfit::rig::SHIPPED[0].1.replace("\"tensile4\"", "\"t4\"")).unwrap();
    // A signed gap (a preload) declared by the rig file: taken.
    let gap = rig["params"]
        .as_array()
        .unwrap()
        .iter()
        .position(|p| p["name"] == "gap")
        .unwrap();
    rig["params"][gap]["domain"] = json!("positive");
    let mut c = example();
    set(&mut c, "/rig", rig.clone());
    set(&mut c, "/params/gap", json!(0.0));
    let e = refusal(&c);
    assert!(
        e.contains("params.gap") && e.contains("rig 't4' declares gap (m) positive"),
        "{e}"
    );
    assert!(e.contains("\"domain\" key"), "{e}");
    rig["params"][gap]["domain"] = json!("negative");
    set(&mut c, "/rig", rig.clone());
    let e = refusal(&c);
    assert!(e.contains("params[") && e.contains("domain"), "{e}");
    rig["params"][gap]["domain"] = json!("positive");
    rig["params"][gap]["default"] = json!(-1.0);
    set(&mut c, "/rig", rig);
    let e = refusal(&c);
    assert!(e.contains(&format!("params[{gap}].default")), "{e}");
}

#[test]
fn every_shipped_campaign_and_its_reference_values_lie_in_their_domains() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns");
    let mut loaded = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if !name.ends_with(".json") || name.ends_with("_reference_params.json") {
            continue;
        }
        let mut c = Campaign::load(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        loaded += 1;
        let stem = name
            .trim_end_matches(".json")
            .trim_end_matches("_synthetic")
            .trim_end_matches("_channels");
        let reference = dir.join(format!("{stem}_reference_params.json"));
        if reference.exists() {
            c.apply_param_file(&reference)
                .unwrap_or_else(|e| panic!("{name} with {}: {e}", reference.display()));
        }
    }
    assert!(loaded >= 10, "{loaded} campaigns");
}
