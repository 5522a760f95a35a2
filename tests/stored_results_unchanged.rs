//! Every existing seed gives the same result.json: a job run here is compared
//! with the result.json the same command wrote before the search moved onto
//! the solver trait (`tests/data/stored_results/`, written by the code of
//! commit 1ac9908). Everything a search computes is compared to the bit
//! (genomes, costs, intervals, warnings, the polish, the history); only what
//! measures this machine's clock is left out (wall times, rates, the
//! fingerprint's record of the host).
//!
//! `RIGFIT_BLESS=1 cargo test --test stored_results_unchanged` writes the
//! stored files again; do that only for a change that is meant to change
//! results, and say so in its commit.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Keys whose values measure this machine (its clock, its memory, where the
/// clone lies), not the search.
const CLOCK_KEYS: &[&str] = &[
    "campaign_file",
    // `inputs[].path`: the campaign file as the test names it, under the clone.
    "path",
    "peak_memory_mib",
    "wall_time_s",
    "elapsed_s",
    "evals_per_s",
    "candidate_steps_per_s",
    "seconds",
    "started",
    "finished",
    "version",
    "duration_s",
    "time_s",
];

/// The value with every clock key's value replaced by null, at any depth.
fn without_clock(v: &Value) -> Value {
    match v {
        Value::Object(m) => Value::Object(
            m.iter()
                .map(|(k, x)| {
                    let keep = !CLOCK_KEYS.contains(&k.as_str()) && !k.ends_with("_time_s");
                    (k.clone(), if keep { without_clock(x) } else { Value::Null })
                })
                .collect(),
        ),
        Value::Array(a) => Value::Array(a.iter().map(without_clock).collect()),
        other => other.clone(),
    }
}

/// The paths (JSON pointers) where `a` and `b` differ, at most `max`.
fn differences(a: &Value, b: &Value, at: &str, out: &mut Vec<String>, max: usize) {
    if out.len() >= max {
        return;
    }
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            for k in x.keys().chain(y.keys().filter(|k| !x.contains_key(*k))) {
                let path = format!("{at}/{k}");
                match (x.get(k), y.get(k)) {
                    (Some(p), Some(q)) => differences(p, q, &path, out, max),
                    _ => out.push(format!("{path}: present on one side only")),
                }
            }
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => {
            for (i, (p, q)) in x.iter().zip(y).enumerate() {
                differences(p, q, &format!("{at}/{i}"), out, max);
            }
        }
        _ if a == b => {}
        _ => out.push(format!("{at}: stored {a} now {b}")),
    }
}

fn run_job(campaign: &str, args: &[&str], out: &Path) -> Value {
    let status = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .arg("run")
        .arg(repo().join("campaigns").join(campaign))
        .args([
            "--backend",
            "cpu",
            "--precision",
            "f64",
            "--threads",
            "1",
            "-q",
        ])
        .args(args)
        .arg("--out")
        .arg(out)
        .status()
        .expect("rigfit runs");
    assert!(status.success(), "rigfit run {campaign} failed");
    let text = std::fs::read_to_string(out.join("result.json")).expect("result.json");
    serde_json::from_str(&text).expect("result.json is JSON")
}

fn check(name: &str, campaign: &str, args: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let now = without_clock(&run_job(campaign, args, &dir.path().join("out")));
    let stored_path = repo()
        .join("tests/data/stored_results")
        .join(format!("{name}.result.json"));
    if std::env::var_os("RIGFIT_BLESS").is_some() {
        let text = serde_json::to_string_pretty(&now).unwrap() + "\n";
        std::fs::write(&stored_path, text).unwrap();
        return;
    }
    let stored: Value = serde_json::from_str(
        &std::fs::read_to_string(&stored_path)
            .unwrap_or_else(|e| panic!("{}: {e}", stored_path.display())),
    )
    .unwrap();
    let mut diff = Vec::new();
    differences(&stored, &now, "", &mut diff, 20);
    assert!(
        diff.is_empty(),
        "{name}: result.json differs from {}:\n{}",
        stored_path.display(),
        diff.join("\n")
    );
}

#[test]
fn friction_rig_seed_3_gives_the_stored_result() {
    check(
        "friction_sdof_seed3",
        "friction_sdof_synthetic.json",
        &["--population", "32", "--generations", "8", "--seed", "3"],
    );
}

#[test]
fn quarter_car_seed_11_gives_the_stored_result() {
    check(
        "quarter_car_seed11",
        "quarter_car_synthetic.json",
        &["--population", "24", "--generations", "6", "--seed", "11"],
    );
}
