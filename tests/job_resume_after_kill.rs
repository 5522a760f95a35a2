//! A calibration job killed at any moment (SIGKILL or SIGTERM) and resumed with
//! `--resume` ends with exactly the result of a job that was never interrupted.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

fn rigfit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
}

/// The shipped campaign with a search long enough to be interrupted.
fn campaign(dir: &Path) -> PathBuf {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(repo.join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    let data = repo.join("campaigns/aa2024_t3_v2_synthetic.csv");
    c["experiments"][0]["data"]["file"] = Value::from(data.to_str().unwrap());
    c["search"] = serde_json::json!({
        "population": 48, "generations": 60, "seed": 11, "checkpoint_every": 1
    });
    c["solver"]["backend"] = Value::from("cpu");
    let path = dir.join("campaign.json");
    std::fs::write(&path, serde_json::to_string_pretty(&c).unwrap()).unwrap();
    path
}

fn start(campaign: &Path, out: &Path, resume: bool) -> Child {
    let mut cmd = rigfit();
    cmd.arg("--quiet")
        .arg("run")
        .arg(campaign)
        .arg("--out")
        .arg(out)
        .args(["--threads", "1"])
        // A cache folder of each output's own: a job does not load the
        // native builds another kept, so each takes as long as the kills'
        // timings assume (the polish's histories interpret until their
        // build is done).
        .env("RIGFIT_CACHE_DIR", out.with_extension("cache"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    if resume {
        cmd.arg("--resume");
    }
    cmd.spawn().unwrap()
}

fn finish(child: Child) {
    let o = child.wait_with_output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// Waits until the checkpoint in `out` has reached generation `g`.
fn wait_for_generation(child: &mut Child, out: &Path, g: u64) {
    let deadline = Instant::now() + Duration::from_secs(120);
    loop {
        let text = std::fs::read_to_string(out.join("checkpoint.json")).unwrap_or_default();
        let at = serde_json::from_str::<Value>(&text)
            .ok()
            .and_then(|v| v["checkpoint"]["state"]["generation"].as_u64());
        if at.is_some_and(|at| at >= g) {
            return;
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "the job ended before it could be interrupted"
        );
        assert!(Instant::now() < deadline, "no checkpoint appeared");
        std::thread::sleep(Duration::from_millis(5));
    }
}

fn result(out: &Path) -> (Value, Value) {
    let r: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    (r["params"].clone(), r["fitness"].clone())
}

#[test]
fn killed_and_resumed_job_ends_bit_identical() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path());
    let straight = dir.path().join("straight");
    finish(start(&c, &straight, false));

    let killed = dir.path().join("killed");
    let mut child = start(&c, &killed, false);
    wait_for_generation(&mut child, &killed, 5);
    child.kill().unwrap(); // SIGKILL: no handler runs
    let _ = child.wait();
    assert!(!killed.join("result.json").exists());
    finish(start(&c, &killed, true));

    assert_eq!(result(&straight), result(&killed));
    assert!(!killed.join("checkpoint.json").exists());
}

#[cfg(unix)]
#[test]
fn sigterm_writes_a_checkpoint_and_resume_ends_bit_identical() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path());
    let straight = dir.path().join("straight");
    finish(start(&c, &straight, false));

    let stopped = dir.path().join("stopped");
    let mut child = start(&c, &stopped, false);
    wait_for_generation(&mut child, &stopped, 3);
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
    assert!(stopped.join("checkpoint.json").is_file());
    finish(start(&c, &stopped, true));

    assert_eq!(result(&straight), result(&stopped));
}

#[test]
fn resume_refuses_a_changed_campaign_and_names_the_change() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path());
    let out = dir.path().join("out");
    let mut child = start(&c, &out, false);
    wait_for_generation(&mut child, &out, 2);
    child.kill().unwrap();
    let _ = child.wait();

    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&c).unwrap()).unwrap();
    v["params"]["k1"]["max"] = Value::from(5e10);
    std::fs::write(&c, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    let o = start(&c, &out, true).wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("gene k1"), "{err}");
}

#[cfg(unix)]
#[test]
fn sigterm_cancels_the_generation_in_flight() {
    use std::io::{BufRead, BufReader};
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path());
    // One generation of 4096 candidates of 22 500 steps on one thread: several
    // seconds, so the signal arrives while the first generation is evaluated.
    let out = dir.path().join("out");
    let text = std::fs::read_to_string(&c).unwrap();
    let mut v: Value = serde_json::from_str(&text).unwrap();
    v["experiments"][0]["offset"] = Value::from(0.02);
    std::fs::write(&c, v.to_string()).unwrap();
    let mut child = rigfit()
        .arg("run")
        .arg(&c)
        .arg("--out")
        .arg(&out)
        .args(["--threads", "1", "--population", "4096"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stderr = BufReader::new(child.stderr.take().unwrap());
    let mut text = String::new();
    while !text.contains("steps per candidate") {
        assert!(stderr.read_line(&mut text).unwrap() > 0, "{text}");
    }
    // The signal handler is installed right after that line.
    std::thread::sleep(Duration::from_millis(300));
    let status = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    std::io::Read::read_to_string(&mut stderr, &mut text).unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "{text}");
    // Had the generation been finished first, it would have been checkpointed.
    assert!(
        text.contains("before the first generation was complete"),
        "{text}"
    );
    assert!(!out.join("checkpoint.json").exists());
    assert!(!out.join("result.json").exists());
}

#[test]
fn killed_during_the_polish_and_resumed_ends_bit_identical() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path());
    // A short GA and a long polish: the kill lands after the GA's last
    // checkpoint, while the polish runs.
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&c).unwrap()).unwrap();
    v["search"] = serde_json::json!({
        "population": 32, "generations": 4, "seed": 11, "checkpoint_every": 1,
        "polish": {"starts": 8, "max_iterations": 30}
    });
    std::fs::write(&c, v.to_string()).unwrap();
    let straight = dir.path().join("straight");
    finish(start(&c, &straight, false));
    let (_, fitness) = result(&straight);
    let r: Value =
        serde_json::from_str(&std::fs::read_to_string(straight.join("result.json")).unwrap())
            .unwrap();
    assert!(
        r["polish"]["iterations"].as_u64().unwrap() > 1,
        "{}",
        r["polish"]
    );

    let killed = dir.path().join("killed");
    let mut child = start(&c, &killed, false);
    wait_for_generation(&mut child, &killed, 3);
    // The last generation takes about 0.2 s on one thread, the polish about 4 s
    // (30 iterations of 8 starts): the kill falls in the polish.
    std::thread::sleep(Duration::from_millis(1000));
    child.kill().unwrap();
    let _ = child.wait();
    let ck: Value =
        serde_json::from_str(&std::fs::read_to_string(killed.join("checkpoint.json")).unwrap())
            .unwrap();
    // The GA's last generation was not finished or not checkpointed: resume
    // runs it again, then the whole polish.
    assert_eq!(ck["checkpoint"]["state"]["generation"], 3);
    assert!(!killed.join("result.json").exists());
    finish(start(&c, &killed, true));

    assert_eq!(result(&straight), result(&killed));
    assert_eq!(result(&killed).1, fitness);
    let k: Value =
        serde_json::from_str(&std::fs::read_to_string(killed.join("result.json")).unwrap())
            .unwrap();
    assert_eq!(k["parameters"], r["parameters"]);
    assert!(r["parameters"].as_array().is_some_and(|p| !p.is_empty()));
    assert_eq!(k["polish"]["correlation"], r["polish"]["correlation"]);
}
