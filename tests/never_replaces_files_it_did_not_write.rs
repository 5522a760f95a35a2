//! `rigfit run` and `rigfit simulate` never replace a file rigfit did not write:
//! a user's own file in the output folder, the measured record and the campaign
//! survive byte for byte, refused before any work with exit 2.

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

/// The shipped campaign in `dir`, its record copied next to it as `record`,
/// experiment named `experiment`, a tiny CPU search and `output`.
fn campaign(dir: &Path, experiment: &str, record: &str, output: &str) -> PathBuf {
    let text = std::fs::read_to_string(repo().join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    std::fs::copy(
        repo().join("campaigns/aa2024_t3_v2_synthetic.csv"),
        dir.join(record),
    )
    .unwrap();
    c["experiments"][0]["name"] = json!(experiment);
    c["experiments"][0]["data"]["file"] = json!(record);
    c["search"]["population"] = json!(8);
    c["search"]["generations"] = json!(1);
    // The polish after the GA is not what these tests are about.
    c["search"]["polish"] = json!({"enabled": false});
    c["solver"]["backend"] = json!("cpu");
    c["output"] = json!(output);
    let path = dir.join("c.json");
    std::fs::write(&path, serde_json::to_string_pretty(&c).unwrap()).unwrap();
    path
}

fn run(campaign: &Path, extra: &[&str]) -> Output {
    rigfit()
        .arg("--quiet")
        .arg("run")
        .arg(campaign)
        .args(extra)
        .output()
        .unwrap()
}

#[test]
fn a_users_file_in_the_output_folder_survives_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), "v2", "v2_record.csv", "out");
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let mine = b"my own notes, not a rigfit result\n";
    for name in ["v2.csv", "history.csv", "fitness.svg", "fit_v2.svg"] {
        std::fs::write(out.join(name), mine).unwrap();
        for flags in [&[][..], &["--overwrite"][..]] {
            let o = run(&c, flags);
            assert_eq!(o.status.code(), Some(2), "{name} {flags:?}: {}", stderr(&o));
            let err = stderr(&o);
            assert!(err.contains(name) && err.contains("did not write"), "{err}");
            assert_eq!(std::fs::read(out.join(name)).unwrap(), mine);
            assert!(
                !out.join("result.json").exists(),
                "work done before refusing"
            );
        }
        std::fs::remove_file(out.join(name)).unwrap();
    }
    // With the folder clear, the job runs, and a second run may replace its
    // own files with --overwrite.
    let o = run(&c, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run(&c, &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--overwrite"), "{}", stderr(&o));
    // What a kill during an atomic write leaves behind goes with the next job;
    // a hidden file of the user's that only looks similar stays.
    for tmp in [
        ".checkpoint.json.tmp-4242",
        ".v2.csv.tmp-17",
        ".result.json.tmp-9",
    ] {
        std::fs::write(out.join(tmp), b"torn").unwrap();
    }
    std::fs::write(out.join(".notes.txt.tmp-1"), b"mine").unwrap();
    let o = run(&c, &["--overwrite"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut left: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp-"))
        .collect();
    left.sort();
    assert_eq!(left, [".notes.txt.tmp-1"]);
}

#[test]
fn the_measured_record_is_never_an_output() {
    let dir = tempfile::tempdir().unwrap();
    // An experiment called `data` whose record is `data.csv`, written to the
    // campaign's own folder: its result CSV would be the record itself.
    let c = campaign(dir.path(), "data", "data.csv", ".");
    let record = std::fs::read(dir.path().join("data.csv")).unwrap();
    let campaign_text = std::fs::read(&c).unwrap();
    for flags in [&[][..], &["--overwrite"][..]] {
        let o = run(&c, flags);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(stderr(&o).contains("data.csv"), "{}", stderr(&o));
    }
    assert_eq!(std::fs::read(dir.path().join("data.csv")).unwrap(), record);
    assert_eq!(std::fs::read(&c).unwrap(), campaign_text);
    assert!(!dir.path().join("result.json").exists());
}

#[test]
fn simulate_out_refuses_an_existing_file_and_never_writes_over_its_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), "v2", "v2.csv", "out");
    let campaign_text = std::fs::read(&c).unwrap();
    let record = std::fs::read(dir.path().join("v2.csv")).unwrap();
    let simulate = |out: &Path, overwrite: bool| {
        let mut cmd = rigfit();
        cmd.args(["--quiet", "simulate"])
            .arg(&c)
            .arg("--out")
            .arg(out);
        if overwrite {
            cmd.arg("--overwrite");
        }
        cmd.output().unwrap()
    };
    for input in [c.clone(), dir.path().join("v2.csv")] {
        for overwrite in [false, true] {
            let o = simulate(&input, overwrite);
            assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        }
    }
    assert_eq!(std::fs::read(&c).unwrap(), campaign_text);
    assert_eq!(std::fs::read(dir.path().join("v2.csv")).unwrap(), record);

    let sim = dir.path().join("sim.csv");
    std::fs::write(&sim, b"keep me").unwrap();
    let o = simulate(&sim, false);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--overwrite"), "{}", stderr(&o));
    assert_eq!(std::fs::read(&sim).unwrap(), b"keep me");
    let o = simulate(&sim, true);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read_to_string(&sim).unwrap().starts_with("t_s,"));
}

#[test]
fn colliding_output_names_are_refused_by_check_naming_both() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), "a/b", "v2.csv", "out");
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&c).unwrap()).unwrap();
    let mut second = v["experiments"][0].clone();
    second["name"] = json!("a_b");
    v["experiments"].as_array_mut().unwrap().push(second);
    std::fs::write(&c, v.to_string()).unwrap();
    let o = rigfit().arg("check").arg(&c).output().unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("\"a/b\"") && err.contains("\"a_b\""), "{err}");
    assert!(err.contains("experiments[1].name"), "{err}");
}

#[test]
fn a_folder_held_by_another_job_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), "v2", "v2_record.csv", "out");
    let out = dir.path().join("out");
    let held = rigfit::job::OutputFolder::open(
        &out,
        &["result.json".to_string()],
        &[],
        rigfit::job::FolderMode::New,
    )
    .unwrap();
    let o = run(&c, &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("in use by another rigfit job"),
        "{}",
        stderr(&o)
    );
    assert!(!out.join("result.json").exists());
    drop(held);
    let o = run(&c, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn a_rig_file_is_an_input_too() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), "v2", "v2.csv", "out");
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&c).unwrap()).unwrap();
    v["rig"] = json!("my_rig.json");
    std::fs::write(&c, v.to_string()).unwrap();
    std::fs::copy(
        repo().join("rigs/tensile4.json"),
        dir.path().join("my_rig.json"),
    )
    .unwrap();
    let rig = std::fs::read(dir.path().join("my_rig.json")).unwrap();
    let o = rigfit()
        .args(["--quiet", "simulate"])
        .arg(&c)
        .arg("--out")
        .arg(dir.path().join("my_rig.json"))
        .arg("--overwrite")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("never writes over its inputs"),
        "{}",
        stderr(&o)
    );
    assert_eq!(std::fs::read(dir.path().join("my_rig.json")).unwrap(), rig);
}
