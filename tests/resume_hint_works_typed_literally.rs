//! The command `run` prints when it is stopped (SIGTERM, as Ctrl-C) works
//! typed literally: with the output folder and the overrides the job was
//! started with, quoted for the shell, it resumes the job to its end.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

fn campaign(dir: &Path) -> PathBuf {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(repo.join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    let data = repo.join("campaigns/aa2024_t3_v2_synthetic.csv");
    c["experiments"][0]["data"]["file"] = json!(data.to_str().unwrap());
    c["search"] = json!({
        "population": 16, "generations": 10, "seed": 1, "checkpoint_every": 1,
        "polish": {"enabled": false}
    });
    c["solver"]["backend"] = json!("cpu");
    let path = dir.join("my campaign.json");
    std::fs::write(&path, c.to_string()).unwrap();
    path
}

#[test]
fn the_resume_hint_after_an_interrupt_runs_as_printed() {
    let dir = tempfile::tempdir().unwrap();
    campaign(dir.path());
    // A folder name with a space and overrides that the checkpoint records:
    // a hint without them would find nothing to resume.
    let out = "results here";
    let mut child = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .current_dir(dir.path())
        .args(["run", "my campaign.json", "--out", out])
        .args(["--population", "40", "--generations", "200", "--seed", "5"])
        .args(["--threads", "1"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let checkpoint = dir.path().join(out).join("checkpoint.json");
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
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    let hint = err
        .lines()
        .find_map(|l| l.split_once("continue with: ").map(|(_, c)| c.to_string()))
        .unwrap_or_else(|| panic!("no resume hint in:\n{err}"));
    assert!(hint.contains("'results here'"), "{hint}");
    assert!(hint.contains("--population 40"), "{hint}");
    assert!(hint.ends_with("--resume"), "{hint}");
    // Shorter from here: the hint's own command, run by a shell as typed.
    let o = Command::new("sh")
        .current_dir(dir.path())
        .args(["-c", &hint])
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "`{hint}` failed:\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let r: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join(out).join("result.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(r["seed"], json!(5), "{r}");
}
