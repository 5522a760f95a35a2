//! Jobs that could not finish, or would fail only at their end, are refused by
//! `rigfit check` and `rigfit run` before any work: exit 2, one message naming
//! the file and the JSON path (or the flag), and no output folder.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::{Value, json};

fn rigfit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
}

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The shipped campaign, with its record's absolute path, spoilt by `spoil`,
/// written to `dir/c.json` with `output` = `out`.
fn campaign(dir: &Path, spoil: impl FnOnce(&mut Value)) -> PathBuf {
    let text = std::fs::read_to_string(repo().join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    let record = repo().join("campaigns/aa2024_t3_v2_synthetic.csv");
    c["experiments"][0]["data"]["file"] = json!(record.to_str().unwrap());
    c["search"]["population"] = json!(8);
    c["search"]["generations"] = json!(1);
    // The polish after the GA is not what these tests are about.
    c["search"]["polish"] = json!({"enabled": false});
    c["solver"]["backend"] = json!("cpu");
    c["output"] = json!("out");
    spoil(&mut c);
    let path = dir.join("c.json");
    std::fs::write(&path, serde_json::to_string_pretty(&c).unwrap()).unwrap();
    path
}

/// Runs `check` and `run` on the campaign; both must refuse with exit 2 and
/// every fragment, and leave no output folder.
fn refused(dir: &Path, c: &Path, fragments: &[&str]) {
    for cmd in ["check", "run"] {
        let o = rigfit().arg(cmd).arg(c).output().unwrap();
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{cmd}: {err}");
        for f in fragments {
            assert!(err.contains(f), "{cmd}: expected {f:?} in {err}");
        }
        assert!(err.lines().count() <= 2, "{cmd}: {err}");
        assert!(!dir.join("out").exists(), "{cmd} created the output folder");
    }
}

#[test]
fn an_offset_of_a_million_seconds_is_refused_with_its_estimate() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), |c| c["experiments"][0]["offset"] = json!(1e6));
    refused(
        dir.path(),
        &c,
        &[
            "c.json: experiments[0]: expected at most 1e8 RK4 steps per candidate",
            "--max-steps",
            "9.3 h per candidate",
            "offset reaches 1e6 s",
        ],
    );
    // A free offset is estimated at its upper bound.
    let c = campaign(dir.path(), |c| {
        c["experiments"][0]["offset"] = json!({"min": 0.0, "max": 1e3})
    });
    refused(dir.path(), &c, &["experiments[0]: expected at most"]);
}

#[test]
fn a_record_in_epoch_seconds_is_refused_with_the_offset_that_fixes_it() {
    let dir = tempfile::tempdir().unwrap();
    let mut csv = String::from("t_s,force_N\n");
    for k in 0..500 {
        csv += &format!(
            "{:.6},{}\n",
            1.7e9 + k as f64 * 1e-6,
            (k as f64 * 0.1).sin()
        );
    }
    std::fs::write(dir.path().join("epoch.csv"), csv).unwrap();
    let c = campaign(dir.path(), |c| {
        c["experiments"][0]["data"]["file"] = json!("epoch.csv");
        c["experiments"][0]["fit_window"] = json!(null);
    });
    refused(
        dir.path(),
        &c,
        &[
            "RK4 steps per candidate",
            "needs experiments[0].offset (about -1.7e9 s here)",
        ],
    );
}

#[test]
fn the_limit_can_be_raised_and_check_prints_the_estimate() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), |c| c["experiments"][0]["offset"] = json!(1e-3));
    let o = rigfit().arg("check").arg(&c).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(text.contains("one candidate: 3.50"), "{text}");
    let o = rigfit().args(["--json", "check"]).arg(&c).output().unwrap();
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    // 1 ms of prologue at 1 µs steps, then the record's 2500 steps.
    let steps = v["run_length"]["steps_per_candidate"].as_f64().unwrap();
    assert!((3500.0..=3501.0).contains(&steps), "{steps}");
    let o = rigfit()
        .args(["check", "--max-steps", "3000"])
        .arg(&c)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("found 3.50"), "{}", stderr(&o));
}

#[test]
fn a_name_too_long_for_a_file_is_refused_by_check() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), |c| {
        c["experiments"][0]["name"] = json!("v".repeat(300))
    });
    refused(
        dir.path(),
        &c,
        &["experiments[0].name", "at most 100 characters"],
    );
}

#[test]
fn an_output_that_cannot_be_a_folder_is_refused_with_its_json_path() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("afile"), b"x").unwrap();
    for output in ["afile", "afile/sub", "a\u{0}b"] {
        let c = campaign(dir.path(), |c| c["output"] = json!(output));
        let o = rigfit().arg("run").arg(&c).output().unwrap();
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{output:?}: {err}");
        assert!(
            err.contains("c.json: output: output folder"),
            "{output:?}: {err}"
        );
        assert_eq!(std::fs::read(dir.path().join("afile")).unwrap(), b"x");
    }
    let c = campaign(dir.path(), |_| {});
    let o = rigfit()
        .arg("run")
        .arg(&c)
        .arg("--out")
        .arg(dir.path().join("afile"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("--out: output folder"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_campaign_without_a_search_section_simulates_but_does_not_run() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), |c| {
        c.as_object_mut().unwrap().remove("search");
    });
    let sim = dir.path().join("sim.csv");
    let o = rigfit()
        .args(["--quiet", "simulate"])
        .arg(&c)
        .arg("--out")
        .arg(&sim)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(sim.is_file());
    for cmd in ["check", "modes"] {
        let o = rigfit().arg(cmd).arg(&c).output().unwrap();
        assert!(o.status.success(), "{cmd}: {}", stderr(&o));
    }
    let o = rigfit().arg("run").arg(&c).output().unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("c.json: search: expected a search section"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.path().join("out").exists());
}

#[test]
fn a_campaigns_output_outside_its_folder_and_the_current_one_needs_out() {
    let dir = tempfile::tempdir().unwrap();
    let home = dir.path().join("campaigns");
    std::fs::create_dir(&home).unwrap();
    let elsewhere = tempfile::tempdir().unwrap();
    let target = elsewhere.path().join("victim");
    for output in [target.to_str().unwrap().to_string(), "../../up".to_string()] {
        let c = campaign(&home, |c| c["output"] = json!(output));
        let o = rigfit()
            .arg("run")
            .arg(&c)
            .current_dir(&home)
            .output()
            .unwrap();
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{output}: {err}");
        assert!(
            err.contains("c.json: output: expected a folder inside"),
            "{err}"
        );
        assert!(err.contains("--out"), "{err}");
    }
    assert!(!target.exists());
    // --out is the user's own choice.
    let c = campaign(&home, |c| c["output"] = json!("/etc/rigfit-never"));
    let o = rigfit()
        .args(["--quiet", "run"])
        .arg(&c)
        .arg("--out")
        .arg(&target)
        .current_dir(&home)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(target.join("result.json").is_file());
}
