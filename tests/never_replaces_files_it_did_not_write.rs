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

#[test]
fn a_link_planted_as_the_lock_file_is_refused_and_its_target_kept() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), "v2", "v2_record.csv", "out");
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let record_path = dir.path().join("v2_record.csv");
    let record = std::fs::read(&record_path).unwrap();
    std::os::unix::fs::symlink("../v2_record.csv", out.join(".rigfit.lock")).unwrap();
    for flags in [&[][..], &["--overwrite"][..]] {
        let o = run(&c, flags);
        assert_eq!(o.status.code(), Some(2), "{flags:?}: {}", stderr(&o));
        let err = stderr(&o);
        assert!(
            err.contains(".rigfit.lock") && err.contains("link"),
            "{err}"
        );
        assert_eq!(std::fs::read(&record_path).unwrap(), record);
        assert!(
            !out.join("result.json").exists(),
            "work done before refusing"
        );
    }
}

#[test]
fn the_lock_file_goes_when_the_job_ends() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), "v2", "v2_record.csv", "out");
    let lock = dir.path().join("out").join(".rigfit.lock");
    let o = run(&c, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join("out/result.json").is_file());
    assert!(!lock.exists(), "the lock file stayed after the job");
    // Refused once the lock was taken (the folder holds a result): it goes too.
    let o = run(&c, &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(!lock.exists(), "the lock file stayed after a refusal");
    // A lock file left by a killed job is taken over and then removed.
    std::fs::write(&lock, b"pid 999999\n").unwrap();
    let o = run(&c, &["--overwrite"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!lock.exists(), "a stale lock file stayed");
}

/// The record of `identify`, `fit-specimen` and `ringdown` below: two
/// columns, a header, a ringing decay.
fn ringing_record(path: &Path) {
    let mut s = String::from("t_s,force_N\n");
    for k in 0..4000 {
        let t = k as f64 * 1e-4;
        let f = (-3.0 * t).exp() * (2.0 * std::f64::consts::PI * 50.0 * t).sin();
        s += &format!("{t:.6e},{f:.6e}\n");
    }
    std::fs::write(path, s).unwrap();
}

/// The pre-calibration and identification commands on `record`, each with
/// `outs` appended (flag, file) and `extra` flags.
fn precal_commands(record: &Path) -> Vec<Vec<String>> {
    let r = record.to_str().unwrap().to_string();
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    vec![
        s(&["fit-specimen", &r]),
        s(&["ringdown", &r, "--m1", "7.9"]),
        s(&[
            "identify",
            "idim",
            &r,
            "--position",
            "2",
            "--force",
            "2",
            "--sample-rate",
            "1000",
        ]),
        s(&[
            "identify", "frf", &r, "--input", "force_N", "--output", "force_N",
        ]),
    ]
}

#[test]
fn precalibration_and_identify_never_write_over_their_input_or_an_existing_file() {
    let dir = tempfile::tempdir().unwrap();
    let record = dir.path().join("rec.csv");
    ringing_record(&record);
    let original = std::fs::read(&record).unwrap();
    let other = dir.path().join("mine.json");
    std::fs::write(&other, b"my own file").unwrap();
    let same_through_dots = dir.path().join(".").join("rec.csv");
    for cmd in precal_commands(&record) {
        let figure = if cmd[0] == "fit-specimen" {
            "--out"
        } else {
            "--svg"
        };
        for flag in ["--out", figure] {
            for target in [&record, &same_through_dots] {
                for overwrite in [false, true] {
                    let mut c = rigfit();
                    c.arg("--quiet").args(&cmd).arg(flag).arg(target);
                    if overwrite {
                        c.arg("--overwrite");
                    }
                    let o = c.output().unwrap();
                    let err = stderr(&o);
                    assert_eq!(o.status.code(), Some(2), "{cmd:?} {flag}: {err}");
                    assert!(
                        err.contains("never writes over its inputs"),
                        "{cmd:?}: {err}"
                    );
                    assert_eq!(std::fs::read(&record).unwrap(), original, "{cmd:?} {flag}");
                }
            }
            // An existing file of the user's, without --overwrite.
            let o = rigfit()
                .arg("--quiet")
                .args(&cmd)
                .arg(flag)
                .arg(&other)
                .output()
                .unwrap();
            assert_eq!(o.status.code(), Some(2), "{cmd:?} {flag}: {}", stderr(&o));
            assert!(stderr(&o).contains("--overwrite"), "{}", stderr(&o));
            assert_eq!(std::fs::read(&other).unwrap(), b"my own file");
        }
    }
}

#[test]
fn out_and_svg_naming_one_file_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let record = dir.path().join("rec.csv");
    ringing_record(&record);
    let x = dir.path().join("x.json");
    let x_again = dir.path().join("sub").join("..").join("x.json");
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    for cmd in precal_commands(&record).into_iter().skip(1) {
        let o = rigfit()
            .args(&cmd)
            .arg("--out")
            .arg(&x)
            .arg("--svg")
            .arg(&x_again)
            .output()
            .unwrap();
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{cmd:?}: {err}");
        assert!(err.contains("names the same file"), "{cmd:?}: {err}");
        assert!(!x.exists(), "{cmd:?} wrote before refusing");
    }
    let csv = dir.path().join("frf.csv");
    let o = rigfit()
        .args(&precal_commands(&record)[3])
        .arg("--csv")
        .arg(&csv)
        .arg("--svg")
        .arg(&csv)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(!csv.exists());
}

#[test]
fn precalibration_replaces_its_own_earlier_output_with_overwrite() {
    let dir = tempfile::tempdir().unwrap();
    let record = dir.path().join("rec.csv");
    ringing_record(&record);
    let out = dir.path().join("ring.json");
    let svg = dir.path().join("ring.svg");
    let ringdown = |overwrite: bool| {
        let mut c = rigfit();
        c.args(["--quiet", "ringdown"])
            .arg(&record)
            .args(["--m1", "7.9", "--out"])
            .arg(&out)
            .arg("--svg")
            .arg(&svg);
        if overwrite {
            c.arg("--overwrite");
        }
        c.output().unwrap()
    };
    let o = ringdown(false);
    assert!(o.status.success(), "{}", stderr(&o));
    let first = std::fs::read(&out).unwrap();
    let o = ringdown(false);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let o = ringdown(true);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(&out).unwrap(), first);
}
