//! A checkpoint resumes after an edit that cannot change the search's path
//! (the campaign's `description`, a comment line in the record, a stopping
//! limit such as `stall_generations`), and one that can (a number of the
//! record) is refused with what changed and why it matters, not as a failed
//! search.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

/// The shipped tensile campaign with its record copied next to it, and a
/// search long enough to be interrupted.
fn campaign(dir: &Path) -> Value {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(repo.join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    std::fs::copy(
        repo.join("campaigns/aa2024_t3_v2_synthetic.csv"),
        dir.join("data.csv"),
    )
    .unwrap();
    c["experiments"][0]["data"]["file"] = json!("data.csv");
    c["description"] = json!("first words");
    c["search"] = json!({
        "population": 16, "generations": 100000, "seed": 3, "checkpoint_every": 1,
        "polish": {"enabled": false}
    });
    c["solver"]["backend"] = json!("cpu");
    write(dir, &c);
    c
}

fn write(dir: &Path, c: &Value) {
    std::fs::write(dir.join("c.json"), serde_json::to_string_pretty(c).unwrap()).unwrap();
}

/// Starts the job, stops it with SIGTERM once it has a checkpoint, and
/// returns the checkpoint's generation.
fn interrupted(dir: &Path) -> u64 {
    let mut child = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .current_dir(dir)
        .args(["--quiet", "run", "c.json", "--out", "out", "--threads", "1"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let checkpoint = dir.join("out/checkpoint.json");
    let deadline = Instant::now() + Duration::from_secs(120);
    while !checkpoint.exists() {
        assert!(child.try_wait().unwrap().is_none(), "the job ended early");
        assert!(Instant::now() < deadline, "no checkpoint appeared");
        std::thread::sleep(Duration::from_millis(5));
    }
    let status = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let o = child.wait_with_output().unwrap();
    assert_eq!(
        o.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let cp: Value = serde_json::from_str(&std::fs::read_to_string(&checkpoint).unwrap()).unwrap();
    cp["checkpoint"]["state"]["generation"].as_u64().unwrap()
}

/// Resumes the job for one generation past its checkpoint.
fn resume(dir: &Path, generation: u64) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .current_dir(dir)
        .args(["--quiet", "run", "c.json", "--out", "out", "--threads", "1"])
        .args(["--generations", &(generation + 1).to_string(), "--resume"])
        .output()
        .unwrap()
}

fn resumes(dir: &Path, generation: u64) {
    let o = resume(dir, generation);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // A finished job removes its checkpoint.
    assert!(!dir.join("out/checkpoint.json").exists());
}

#[test]
fn a_new_description_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let mut c = campaign(dir.path());
    let g = interrupted(dir.path());
    c["description"] = json!("other words, same problem");
    write(dir.path(), &c);
    resumes(dir.path(), g);
}

#[test]
fn a_comment_line_in_the_record_resumes() {
    let dir = tempfile::tempdir().unwrap();
    campaign(dir.path());
    let g = interrupted(dir.path());
    let data = dir.path().join("data.csv");
    let text = std::fs::read_to_string(&data).unwrap();
    std::fs::write(&data, format!("# checked by hand, no change\n{text}")).unwrap();
    resumes(dir.path(), g);
}

#[test]
fn a_stopping_limit_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let mut c = campaign(dir.path());
    let g = interrupted(dir.path());
    c["search"]["stall_generations"] = json!(500);
    c["search"]["max_time_s"] = json!(600.0);
    write(dir.path(), &c);
    resumes(dir.path(), g);
}

#[test]
fn a_changed_number_of_the_record_is_refused_saying_what_and_why() {
    let dir = tempfile::tempdir().unwrap();
    campaign(dir.path());
    let g = interrupted(dir.path());
    let data = dir.path().join("data.csv");
    let text = std::fs::read_to_string(&data).unwrap();
    // The last sample's force, doubled.
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let last = lines.pop().unwrap();
    let (t, f) = last.split_once(',').unwrap();
    let f: f64 = f.trim().parse().unwrap();
    lines.push(format!("{t},{}", 2.0 * f + 1.0));
    std::fs::write(&data, lines.join("\n") + "\n").unwrap();
    let o = resume(dir.path(), g);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(!err.contains("search failed"), "{err}");
    assert!(err.contains("cannot resume"), "{err}");
    assert!(err.contains("record of experiment v2"), "{err}");
    assert!(err.contains("undo the change"), "{err}");
    assert!(err.starts_with("rigfit: error: cannot resume"), "{err}");
    // Kept for a resume once the record is back.
    assert!(dir.path().join("out/checkpoint.json").exists());
    eprintln!("{err}");
}
