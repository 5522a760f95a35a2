//! The RK4 step rule: `"auto"` picks the fewest substeps with
//! `h·ω_bound ≤ 2` (where accuracy asks no more), an explicit count that breaks it is refused naming the
//! limiting parameter, and the chosen step keeps a stiff run from blowing up.
mod oracle;
mod tensile_common;

mod campaign_common;
use campaign_common as common;

use common::{csv, example, set, write};
use rigfit::campaign::{Campaign, STABILITY_LIMIT};
use rigfit::eval::score_one;
use serde_json::{Value, json};

/// The example with 100 kHz data (dt = 10 µs) and the load-cell damping free up
/// to 3e6 N·s/m, which dominates the frequency bound of the 7.9 kg load cell;
/// its integration-error tolerance is loose enough that stability alone sets
/// the step.
fn coarse() -> Value {
    let mut v = accurate();
    set(&mut v, "/solver/tolerance", json!(100.0));
    v
}

/// [`coarse`] with the default accuracy: the step is also chosen for the
/// integration error the record's noise allows.
fn accurate() -> Value {
    let mut v = example();
    set(&mut v, "/experiments/0/fit_window", json!({}));
    v
}

fn load(v: &Value) -> Result<Campaign, String> {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        &v.to_string(),
        &[("v2.csv", &csv(60, 1e-5, 0.0))],
    );
    Campaign::load(&path).map_err(|e| e.to_string())
}

/// `h·ω` bound of experiment 0 with `substeps`.
fn h_omega(c: &Campaign, substeps: usize) -> (f64, String) {
    let (lo, hi) = c.bounds(0);
    let x = &c.problem.experiments[0];
    let (omega, name) = c.model.omega_bound(&lo, &hi, &x.drive);
    (omega * x.dt / substeps as f64, name)
}

#[test]
fn auto_picks_the_fewest_stable_substeps_and_says_why() {
    let c = load(&coarse()).unwrap();
    let n = c.solver.substeps;
    let (hw, name) = h_omega(&c, n);
    assert!(n > 1, "10 µs needs more than one step, got {n}");
    assert!(hw <= STABILITY_LIMIT, "h·ω = {hw}");
    assert!(h_omega(&c, n - 1).0 > STABILITY_LIMIT, "{} would do", n - 1);
    assert!(c.solver.auto);
    assert_eq!(name, "c1");
    assert!(
        c.solver
            .note
            .contains(&format!("substeps = {n} chosen automatically")),
        "{}",
        c.solver.note
    );
    assert!(
        c.solver.note.contains("limited by 'c1'"),
        "{}",
        c.solver.note
    );
}

#[test]
fn the_step_chosen_for_accuracy_is_never_less_stable() {
    let stable = load(&coarse()).unwrap().solver.substeps;
    let c = load(&accurate()).unwrap();
    let n = c.solver.substeps;
    assert!(c.solver.auto);
    assert!(n >= stable, "{n} substeps, stability needs {stable}");
    assert!(h_omega(&c, n).0 <= STABILITY_LIMIT);
    if n > stable {
        assert!(
            c.solver
                .note
                .contains(&format!("stability alone needs {stable}")),
            "{}",
            c.solver.note
        );
    }
}

#[test]
fn explicit_unstable_substeps_are_refused_naming_the_limiting_parameter() {
    let auto = load(&coarse()).unwrap().solver.substeps;
    let mut v = coarse();
    set(&mut v, "/solver/substeps", json!(1));
    let err = load(&v).unwrap_err();
    assert!(
        err.contains("campaign.json: solver.substeps: expected a stable RK4 step"),
        "{err}"
    );
    assert!(err.contains("found substeps = 1"), "{err}");
    assert!(err.contains("limited by 'c1'"), "{err}");
    assert!(err.contains(&format!("use substeps ≥ {auto}")), "{err}");
    assert!(err.contains("a sample interval ≤"), "{err}");

    set(&mut v, "/solver/substeps", json!(auto));
    let c = load(&v).unwrap();
    assert_eq!((c.solver.substeps, c.solver.auto), (auto, false));
    set(&mut v, "/solver/substeps", json!(1_000_000));
    assert!(
        load(&v)
            .unwrap_err()
            .contains("expected at most 10000 substeps")
    );
}

#[test]
fn narrowing_the_limiting_range_lowers_the_substeps() {
    let wide = load(&coarse()).unwrap().solver.substeps;
    let mut v = coarse();
    set(&mut v, "/params/c1", json!({"min": 1e4, "max": 6e5}));
    let narrow = load(&v).unwrap().solver.substeps;
    assert!(narrow < wide, "{narrow} vs {wide}");
}

#[test]
fn auto_substeps_keep_the_stiffest_corner_from_blowing_up() {
    let c = load(&coarse()).unwrap();
    let (_, hi) = c.bounds(0);
    let (score, diverged) = score_one(&c.problem, 0, &hi, 0.0);
    assert!(
        !diverged,
        "stiffest corner diverged with {} substeps: {score}",
        c.solver.substeps
    );
    let mut one = c.problem.clone();
    one.substeps = 1;
    let (_, diverged) = score_one(&one, 0, &hi, 0.0);
    assert!(
        diverged,
        "one substep at h·ω = {:.1} should blow up",
        h_omega(&c, 1).0
    );
}

#[test]
fn param_file_rechecks_the_step() {
    let mut v = coarse();
    set(&mut v, "/params/c1", 5.5e5.into());
    set(&mut v, "/solver/substeps", json!(3));
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        &v.to_string(),
        &[("v2.csv", &csv(60, 1e-5, 0.0))],
    );
    let mut c = Campaign::load(&path).unwrap();
    let file = dir.path().join("p.json");
    std::fs::write(&file, r#"{"params": {"c1": 3e7}}"#).unwrap();
    let err = c.apply_param_file(&file).unwrap_err().to_string();
    assert!(
        err.contains("p.json: params: expected a stable RK4 step"),
        "{err}"
    );
    assert!(err.contains("limited by 'c1'"), "{err}");
    assert_eq!(
        c.base[0][tensile_common::ix::C1],
        5.5e5,
        "unchanged after refusal"
    );
}
