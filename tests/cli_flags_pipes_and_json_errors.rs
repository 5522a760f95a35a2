//! The binary's own edges: errors of flags name the flag, `--json` reports an
//! error as a JSON document, a closed stdout is no panic, a cause is printed
//! once, and `--help` lists every exit code.

use std::io::Read;
use std::path::PathBuf;
use std::process::{Command, Output, Stdio};

use serde_json::Value;

fn rigfit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
}

fn shipped() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("campaigns/aa2024_t3_synthetic.json")
}

/// The shipped campaign without the polish after the GA (not what these
/// tests are about), written into `dir`.
fn quick(dir: &std::path::Path) -> PathBuf {
    let mut c: Value = serde_json::from_str(&std::fs::read_to_string(shipped()).unwrap()).unwrap();
    let data = shipped().with_file_name("aa2024_t3_v2_synthetic.csv");
    c["experiments"][0]["data"]["file"] = Value::from(data.to_str().unwrap());
    c["search"]["polish"] = serde_json::json!({"enabled": false});
    let path = dir.join("quick.json");
    std::fs::write(&path, c.to_string()).unwrap();
    path
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn a_bad_flag_value_is_blamed_on_the_flag_not_the_campaign() {
    let dir = tempfile::tempdir().unwrap();
    for (flag, value, expect) in [
        ("--generations", "0", "--generations 0: expected at least 1"),
        ("--population", "2", "--population 2: expected at least 4"),
    ] {
        let o = rigfit()
            .arg("run")
            .arg(shipped())
            .args([flag, value, "--backend", "cpu", "--out"])
            .arg(dir.path().join("out"))
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        let err = stderr(&o);
        assert!(err.contains(expect), "{err}");
        assert!(!err.contains("aa2024_t3_synthetic.json"), "{err}");
    }
    assert!(!dir.path().join("out").exists());
}

#[test]
fn json_errors_are_a_json_document_on_stdout() {
    let o = rigfit()
        .args(["--json", "check", "no/such/campaign.json"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let v: Value = serde_json::from_slice(&o.stdout).expect("a JSON document on stdout");
    assert_eq!(v["exit_code"], 2);
    assert!(
        v["error"].as_str().unwrap().contains("campaign.json"),
        "{v}"
    );
}

#[test]
fn a_closed_stdout_ends_the_job_quietly() {
    let dir = tempfile::tempdir().unwrap();
    let mut child = rigfit()
        .args(["--json", "run"])
        .arg(quick(dir.path()))
        .args([
            "--backend",
            "cpu",
            "--population",
            "8",
            "--generations",
            "1",
            "--out",
        ])
        .arg(dir.path().join("out"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The reader goes away before the summary is written (`| head -c 0`).
    drop(child.stdout.take());
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    let status = child.wait().unwrap();
    assert!(!err.contains("panicked"), "{err}");
    assert!(status.success(), "{status:?}: {err}");
    assert!(dir.path().join("out/result.json").is_file());
}

#[test]
fn a_data_error_is_printed_once() {
    let dir = tempfile::tempdir().unwrap();
    let mut c: Value = serde_json::from_str(&std::fs::read_to_string(shipped()).unwrap()).unwrap();
    std::fs::write(dir.path().join("bad.csv"), "t_s,force_N\n0,1\n1e-6,x\n").unwrap();
    c["experiments"][0]["data"]["file"] = Value::from("bad.csv");
    let path = dir.path().join("c.json");
    std::fs::write(&path, c.to_string()).unwrap();
    let o = rigfit().arg("check").arg(&path).output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("bad.csv:3:"), "{err}");
}

#[test]
fn help_lists_every_exit_code_and_many_threads_draw_a_warning() {
    let o = rigfit().arg("--help").output().unwrap();
    let help = String::from_utf8_lossy(&o.stdout);
    assert!(help.contains("130"), "{help}");

    let dir = tempfile::tempdir().unwrap();
    let c = quick(dir.path());
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    let o = rigfit()
        .args(["--quiet", "run"])
        .arg(&c)
        .args([
            "--backend",
            "cpu",
            "--population",
            "8",
            "--generations",
            "1",
        ])
        .args(["--threads", &(4 * cores + 1).to_string(), "--out"])
        .arg(dir.path().join("out"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let o = rigfit()
        .args(["run"])
        .arg(&c)
        .args([
            "--backend",
            "cpu",
            "--population",
            "8",
            "--generations",
            "1",
        ])
        .args([
            "--threads",
            &(4 * cores + 1).to_string(),
            "--overwrite",
            "--out",
        ])
        .arg(dir.path().join("out"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("far above"), "{}", stderr(&o));
}

#[test]
fn the_vulkan_drivers_xdg_runtime_dir_lines_stay_out_of_rigfits_output() {
    // Mesa prints "XDG_RUNTIME_DIR is invalid or not set" twice on headless
    // machines; without an adapter the test shows only that nothing else broke.
    let o = rigfit()
        .arg("devices")
        .env_remove("XDG_RUNTIME_DIR")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("XDG_RUNTIME_DIR"), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("GPU adapters"));
}

#[test]
fn devices_says_whether_the_cpu_lanes_run_native_code() {
    let o = rigfit().args(["devices", "--json"]).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    // No C compiler here is a failure, not a skip.
    assert_eq!(v["cpu"]["native_lanes"], Value::Bool(true), "{v}");
    let o = rigfit()
        .arg("devices")
        .env("RIGFIT_CC", "/nonexistent/cc")
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("lanes interpret their code") && text.contains("/nonexistent/cc"),
        "{text}"
    );
}
