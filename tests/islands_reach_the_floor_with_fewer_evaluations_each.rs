//! Four islands reach the noise floor of the three-rate tensile example with
//! fewer evaluations each than one search alone needs: at a population of 64,
//! one search of 5 generations (312 evaluations) stops short of the floor,
//! one of 10 generations (622) reaches it, and 4 islands of 5 generations
//! (312 each, exchanging every 2) reach it too.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

fn campaign(dir: &Path, islands: bool) -> PathBuf {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let campaigns = repo.join("campaigns");
    let text =
        std::fs::read_to_string(campaigns.join("tensile4_three_rates_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    for e in c["experiments"].as_array_mut().unwrap() {
        let file = campaigns.join(e["data"]["file"].as_str().unwrap());
        e["data"]["file"] = Value::from(file.to_str().unwrap());
    }
    c["solver"]["backend"] = Value::from("cpu");
    c["search"]["population"] = Value::from(64);
    if islands {
        c["search"]["islands"] =
            serde_json::json!({"count": 4, "every": 2, "migrants": 2, "wait_s": 60});
    }
    let path = dir.join(if islands { "islands.json" } else { "one.json" });
    std::fs::write(&path, serde_json::to_string_pretty(&c).unwrap()).unwrap();
    path
}

/// result.json of a run of `campaign` for `generations`.
fn run(campaign: &Path, out: &Path, generations: usize) -> Value {
    let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .arg("--quiet")
        .arg("run")
        .arg(campaign)
        .arg("--out")
        .arg(out)
        .args(["--generations", &generations.to_string(), "--seed", "1"])
        .env("RIGFIT_CACHE_DIR", out.with_extension("cache"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap()
}

/// The largest residual over the record's noise among the experiments.
fn over_floor(r: &Value) -> f64 {
    r["experiments"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["cost_over_noise_floor"].as_f64().unwrap())
        .fold(0.0, f64::max)
}

#[test]
fn four_islands_reach_the_floor_with_fewer_evaluations_each_than_one_search() {
    let dir = tempfile::tempdir().unwrap();
    let (one, islands) = (campaign(dir.path(), false), campaign(dir.path(), true));

    let short = run(&one, &dir.path().join("short"), 5);
    assert!(over_floor(&short) > 1.5, "{}", over_floor(&short));
    let long = run(&one, &dir.path().join("long"), 10);
    assert!(over_floor(&long) < 1.1, "{}", over_floor(&long));

    let ring = run(&islands, &dir.path().join("ring"), 5);
    assert!(over_floor(&ring) < 1.1, "{}", over_floor(&ring));
    let rows = ring["islands"]["islands"].as_array().unwrap();
    assert_eq!(rows.len(), 4);
    let alone = long["evaluations"].as_u64().unwrap();
    for row in rows {
        let each = row["evaluations"].as_u64().unwrap();
        assert!(
            each < alone,
            "island {each} evaluations, one search {alone}"
        );
        assert_eq!(row["exchanges_made"], 2, "{row}");
    }
}
