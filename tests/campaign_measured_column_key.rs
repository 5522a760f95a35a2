//! A record's measured column is named by the neutral key `column` (and its
//! multiplier by `scale`), for records of any quantity; `force_column` and
//! `force_scale` remain the same keys, and giving a key under both names is
//! refused.

use std::path::{Path, PathBuf};

use rigfit::campaign::Campaign;
use serde_json::{Value, json};

fn campaign(dir: &Path, name: &str, data: Value) -> PathBuf {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(repo.join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    let record = repo.join("campaigns/aa2024_t3_v2_synthetic.csv");
    let mut d = data;
    d["file"] = json!(record.to_str().unwrap());
    c["experiments"][0]["data"] = d;
    let path = dir.join(name);
    std::fs::write(&path, c.to_string()).unwrap();
    path
}

#[test]
fn column_and_scale_read_the_record_as_force_column_and_force_scale_do() {
    let dir = tempfile::tempdir().unwrap();
    let old = Campaign::load(&campaign(
        dir.path(),
        "old.json",
        json!({"time_column": "t_s", "force_column": "force_N", "force_scale": 2.0}),
    ))
    .unwrap();
    let new = Campaign::load(&campaign(
        dir.path(),
        "new.json",
        json!({"time_column": "t_s", "column": "force_N", "scale": 2.0}),
    ))
    .unwrap();
    let (a, b) = (&old.problem.experiments[0], &new.problem.experiments[0]);
    assert!(!a.measured.is_empty());
    assert_eq!(a.measured, b.measured);
    // The scale applies: not the record's values as they are.
    let unscaled = Campaign::load(&campaign(
        dir.path(),
        "plain.json",
        json!({"time_column": "t_s", "column": "force_N"}),
    ))
    .unwrap();
    assert_eq!(
        unscaled.problem.experiments[0].measured[10] * 2.0,
        b.measured[10]
    );

    // A column that is not there is refused under the neutral key too.
    let e = Campaign::load(&campaign(
        dir.path(),
        "missing.json",
        json!({"time_column": "t_s", "column": "x_m"}),
    ))
    .unwrap_err()
    .to_string();
    assert!(e.contains("x_m"), "{e}");
}

#[test]
fn a_column_given_under_both_names_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let e = Campaign::load(&campaign(
        dir.path(),
        "both.json",
        json!({"time_column": "t_s", "column": "force_N", "force_column": "force_N"}),
    ))
    .unwrap_err()
    .to_string();
    assert!(e.contains("duplicate field"), "{e}");
}
