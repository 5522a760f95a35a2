//! When no RK4 step can be chosen because of a node's mass (one that turns
//! negative once an element breaks, or a campaign bound that lets it reach
//! 1e-300 kg), the refusal names that mass, its value or bound and where it
//! is set, not the stiffness or damping the frequency bound happens to name.

use std::path::{Path, PathBuf};

use rigfit::campaign::Campaign;
use serde_json::{Value, json};

fn campaigns() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns")
}

/// The shipped friction campaign (one plate on a suspension and a
/// stick-slip damper), edited, loaded from `dir` with its record.
fn load(dir: &Path, edit: impl FnOnce(&mut Value)) -> Result<Campaign, String> {
    let text = std::fs::read_to_string(campaigns().join("friction_sdof_synthetic.json")).unwrap();
    let mut v: Value = serde_json::from_str(&text).unwrap();
    v["experiments"][0]["data"]["file"] = json!(
        campaigns()
            .join("friction_sdof_synthetic.csv")
            .display()
            .to_string()
    );
    edit(&mut v);
    let file = dir.join("campaign.json");
    std::fs::write(&file, v.to_string()).unwrap();
    Campaign::load(&file).map_err(|e| e.to_string())
}

#[test]
fn a_mass_bound_of_1e_300_is_named_with_its_json_path() {
    let dir = tempfile::tempdir().unwrap();
    let err = load(dir.path(), |v| {
        v["params"]["m"] = json!({"min": 1e-300, "max": 5.0, "scale": "log"});
    })
    .unwrap_err();
    assert!(err.contains("campaign.json: solver.substeps:"), "{err}");
    assert!(err.contains("node 'plate' has a mass 'm'"), "{err}");
    assert!(
        err.contains("lower bound 1e-300 kg (params.m.min)"),
        "{err}"
    );
    assert!(!err.contains("limited by"), "{err}");
    // The same bound is fine where the mass is not that light.
    load(dir.path(), |v| {
        v["params"]["m"] = json!({"min": 1.0, "max": 5.0, "scale": "log"});
    })
    .unwrap();
}

#[test]
fn a_mass_that_turns_negative_after_a_break_is_named_with_its_stage() {
    let dir = tempfile::tempdir().unwrap();
    let mut rig: Value = serde_json::from_str(
        &std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("rigs/friction_sdof.json"),
        )
        .unwrap(),
    )
    .unwrap();
    rig["elements"][1]["breaks_at"] = json!(0.001);
    rig["nodes"][0]["mass"] = json!({"before": "m", "after": -1.0, "broken": "damper"});
    let rig_file = dir.path().join("rig.json");
    std::fs::write(&rig_file, rig.to_string()).unwrap();
    let err = load(dir.path(), |v| v["rig"] = json!("rig.json")).unwrap_err();
    assert!(
        err.contains("node 'plate' has a mass of -1 kg after 'damper' breaks"),
        "{err}"
    );
    assert!(err.contains("nodes[0].mass.after"), "{err}");
    assert!(!err.contains("limited by 'k_c'"), "{err}");
}

#[test]
fn a_fixed_mass_too_light_to_step_is_shown_beside_the_limiting_parameter() {
    let dir = tempfile::tempdir().unwrap();
    let err = load(dir.path(), |v| v["params"]["m"] = json!(1e-300)).unwrap_err();
    assert!(
        err.contains("with the lightest node 'plate' at 1e-300 kg"),
        "{err}"
    );
    assert!(!err.contains("18446744073709551615"), "{err}");
}
