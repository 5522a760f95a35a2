//! Columns are chosen by header name everywhere; by position a campaign
//! counts from 0 and the command line (`identify`) from 1, as documented,
//! and every message about a position says which it counts from.

use std::path::PathBuf;
use std::process::Command;

use serde_json::{Value, json};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn a_campaign_position_past_the_last_column_says_it_counts_from_0() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo().join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    let record = repo().join("campaigns/aa2024_t3_v2_synthetic.csv");
    c["experiments"][0]["data"]["file"] = json!(record.to_str().unwrap());
    c["experiments"][0]["data"]["time_column"] = json!(0);
    c["experiments"][0]["data"]["force_column"] = json!(2);
    let path = dir.path().join("c.json");
    std::fs::write(&path, c.to_string()).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .arg("check")
        .arg(&path)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("no column #2 (0-based: #0 is the first column)"),
        "{err}"
    );
    // Position 1 from 0 is the second column, the force: accepted.
    c["experiments"][0]["data"]["force_column"] = json!(1);
    std::fs::write(&path, c.to_string()).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .arg("check")
        .arg(&path)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn an_identify_position_of_0_says_positions_count_from_1() {
    let dir = tempfile::tempdir().unwrap();
    let record = dir.path().join("r.csv");
    let mut s = String::from("t_s,x_m,force_N\n");
    for k in 0..2000 {
        let t = k as f64 * 1e-3;
        s += &format!("{t},{},{}\n", (7.0 * t).sin(), (3.0 * t).cos());
    }
    std::fs::write(&record, s).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(["identify", "idim"])
        .arg(&record)
        .args(["--position", "0", "--force", "3", "--sample-rate", "1000"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("no column \"0\"") && err.contains("counts from 1"),
        "{err}"
    );
    assert!(err.contains("positions 1..=3"), "{err}");
}
