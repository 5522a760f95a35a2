//! `rigfit simulate` integrates at least as finely as a fit of the record it
//! writes would (`check` and `run` apply the step rule to the record's
//! noise), a synthetic record at twice that at least with its integration
//! error a stated small fraction of the noise it adds, and `--substeps`
//! overrides the choice within the stability rule.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn rigfit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
}

fn bearing() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("campaigns/bearing_2dof_synthetic.json")
}

fn json(o: &Output) -> Value {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap()
}

/// `rigfit --json simulate` of the bearing campaign on the grid of 500
/// samples at 2.56e-4 s, with `extra` options, into `out`.
fn simulate(out: &Path, extra: &[&str]) -> Output {
    rigfit()
        .args(["--json", "simulate"])
        .arg(bearing())
        .args(["--dt", "2.56e-4", "--samples", "500", "--out"])
        .arg(out)
        .args(extra)
        .output()
        .unwrap()
}

fn check_substeps() -> u64 {
    let o = rigfit()
        .args(["--json", "check", "--no-measure"])
        .arg(bearing())
        .output()
        .unwrap();
    json(&o)["substeps"].as_u64().unwrap()
}

#[test]
fn simulate_steps_at_least_as_finely_as_check_on_the_bearing_campaign() {
    let fit = check_substeps();
    let dir = tempfile::tempdir().unwrap();
    let clean = json(&simulate(&dir.path().join("clean.csv"), &[]));
    let n = clean["substeps"].as_u64().unwrap();
    assert!(
        n >= fit,
        "simulate took {n} steps per sample, check {fit}: {clean}"
    );
    assert_eq!(clean["step"]["substeps"].as_u64(), Some(n), "{clean}");
}

#[test]
fn a_synthetic_record_is_finer_than_the_fit_and_states_its_integration_error() {
    let fit = check_substeps();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("noisy.csv");
    let noisy = json(&simulate(&path, &["--noise", "2e-8", "--seed", "4"]));
    let n = noisy["substeps"].as_u64().unwrap();
    assert!(
        n >= 2 * fit,
        "a synthetic record at {n} steps, check {fit}: {noisy}"
    );
    let ch = &noisy["step"]["channels"][0];
    let (err, frac, allowed) = (
        ch["integration_error"].as_f64().unwrap(),
        ch["fraction_of_noise"].as_f64().unwrap(),
        ch["allowed_fraction"].as_f64().unwrap(),
    );
    assert!(
        err > 0.0 && (frac - err / 2e-8).abs() <= 1e-9 * frac,
        "{noisy}"
    );
    assert!(frac <= allowed && allowed <= 0.01, "{noisy}");
    assert_eq!(noisy["step"]["warning"], Value::Null, "{noisy}");
    // The record says so in its first comment lines, before the header.
    let text = std::fs::read_to_string(&path).unwrap();
    let comments: Vec<&str> = text.lines().take_while(|l| l.starts_with('#')).collect();
    let said = format!("{n} RK4 steps per sample");
    assert!(
        comments
            .iter()
            .any(|l| l.contains(&said) && l.contains("% of σ")),
        "{comments:#?}"
    );
}

#[test]
fn substeps_overrides_the_choice_and_is_held_to_the_stability_rule() {
    let dir = tempfile::tempdir().unwrap();
    let got = json(&simulate(
        &dir.path().join("seven.csv"),
        &["--noise", "2e-8", "--substeps", "7"],
    ));
    assert_eq!(got["substeps"].as_u64(), Some(7), "{got}");
    assert_eq!(got["step"]["chosen_by"], "requested", "{got}");
    // The run length limit still holds a count given.
    let long = simulate(
        &dir.path().join("long.csv"),
        &["--substeps", "1000", "--max-steps", "1e5"],
    );
    let msg = String::from_utf8_lossy(&long.stderr);
    assert_eq!(long.status.code(), Some(2), "{msg}");
    assert!(msg.contains("--max-steps"), "{msg}");
    let zero = simulate(&dir.path().join("zero.csv"), &["--substeps", "0"]);
    assert_eq!(zero.status.code(), Some(2));
    let msg = String::from_utf8_lossy(&zero.stderr);
    assert!(msg.contains("--substeps 0"), "{msg}");
    // A step coarser than the stability rule's count is refused: at a
    // sample interval 40 times longer the rule needs more than one step.
    let coarse = rigfit()
        .args(["--json", "simulate"])
        .arg(bearing())
        .args([
            "--dt",
            "1e-2",
            "--samples",
            "50",
            "--substeps",
            "1",
            "--out",
        ])
        .arg(dir.path().join("coarse.csv"))
        .output()
        .unwrap();
    let msg = String::from_utf8_lossy(&coarse.stderr);
    assert_eq!(coarse.status.code(), Some(2), "{msg}");
    assert!(msg.contains("stability rule"), "{msg}");
}
