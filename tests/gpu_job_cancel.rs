//! SIGTERM while the GPU evaluates a long generation: the evaluator stops
//! between two chunks of steps instead of finishing the generation, the
//! process exits with 130, and the checkpoint of the last finished generation
//! is kept as it was.
mod oracle;
mod tensile_common;

mod gpu_common;

use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

/// The shipped example on the GPU in f32 with a record that starts 20 ms
/// into the run (22 500 steps per candidate) and 4096 candidates: a
/// generation is hundreds of chunks' worth of work on lavapipe.
fn campaign(dir: &Path) -> PathBuf {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(repo.join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    let data = repo.join("campaigns/aa2024_t3_v2_synthetic.csv");
    c["experiments"][0]["data"]["file"] = json!(data.to_str().unwrap());
    c["experiments"][0]["offset"] = json!(0.02);
    c["search"] = json!({
        "population": 4096, "generations": 100, "seed": 11, "checkpoint_every": 1
    });
    c["solver"]["backend"] = json!("gpu");
    c["solver"]["precision"] = json!("f32");
    let path = dir.join("campaign.json");
    std::fs::write(&path, serde_json::to_string_pretty(&c).unwrap()).unwrap();
    path
}

/// The checkpoint's search state, without its clock.
fn state(out: &Path) -> Option<Value> {
    let text = std::fs::read_to_string(out.join("checkpoint.json")).ok()?;
    let mut v: Value = serde_json::from_str(&text).ok()?;
    let mut s = v["checkpoint"]["state"].take();
    s.as_object_mut()?.remove("elapsed_s");
    Some(s)
}

#[cfg(unix)]
#[test]
fn sigterm_cancels_the_gpu_generation_in_flight_and_keeps_the_checkpoint() {
    if gpu_common::gpu().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path());
    let out = dir.path().join("out");
    let mut child = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .arg("run")
        .arg(&c)
        .arg("--out")
        .arg(&out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stderr = BufReader::new(child.stderr.take().unwrap());
    let mut text = String::new();
    while !text.contains("steps per candidate") {
        assert!(stderr.read_line(&mut text).unwrap() > 0, "{text}");
    }
    assert!(text.contains("on gpu"), "{text}");
    // The first checkpoint marks the end of the first generation; the next
    // one is being evaluated when the signal arrives.
    let deadline = Instant::now() + Duration::from_secs(300);
    let before = loop {
        if let Some(s) = state(&out) {
            break s;
        }
        assert!(child.try_wait().unwrap().is_none(), "ended early: {text}");
        assert!(Instant::now() < deadline, "no checkpoint appeared: {text}");
        std::thread::sleep(Duration::from_millis(5));
    };
    let signalled = Instant::now();
    let status = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    stderr.read_to_string(&mut text).unwrap();
    let status = child.wait().unwrap();
    // Reported, not asserted: the time depends on the machine's load.
    eprintln!(
        "exited {:?} after {:.2} s",
        status.code(),
        signalled.elapsed().as_secs_f64()
    );
    assert_eq!(status.code(), Some(130), "{text}");
    assert!(text.contains("checkpoint kept"), "{text}");
    // Had the generation in flight been finished, the checkpoint would hold it.
    let after = state(&out).expect("the checkpoint is kept and reads back");
    assert_eq!(after["generation"], before["generation"], "{text}");
    assert_eq!(after, before, "the checkpoint changed");
}
