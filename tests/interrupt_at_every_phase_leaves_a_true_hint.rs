//! Ctrl-C (SIGINT) at each phase of `rigfit run` — `auto`'s backend trial,
//! the search, the polish, the writing of a finished search's outputs — stops
//! the job with exit 130, releases the output folder's lock and prints a hint
//! that holds: a `--resume` it prints resumes the job to its end, and where
//! nothing is kept it says to start again and the folder holds nothing to
//! resume. The times the stops take are printed, not asserted.

use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

fn rigfit(dir: &Path) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_rigfit"));
    // `auto`'s cache and the native builds of this test only.
    c.current_dir(dir)
        .env("RIGFIT_CACHE_DIR", dir.join("cache"));
    c
}

/// `rigfit run CAMPAIGN --out OUT` in `dir`, its stderr piped for
/// [`interrupt_when`].
fn run(dir: &Path, campaign: &Path, out: &Path) -> Command {
    let mut c = rigfit(dir);
    c.arg("run")
        .arg(campaign)
        .arg("--out")
        .arg(out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    c
}

/// A friction_sdof campaign over a record of `samples` samples at 0.1 ms
/// made by `rigfit simulate` from the shipped reference values, with
/// `search` as its search.
fn campaign(dir: &Path, samples: usize, search: Value, backend: &str) -> PathBuf {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let shipped = repo.join("campaigns/friction_sdof_synthetic.json");
    let mut c: Value = serde_json::from_str(&std::fs::read_to_string(&shipped).unwrap()).unwrap();
    let record = dir.join("record.csv");
    let o = rigfit(dir)
        .arg("simulate")
        .arg(&shipped)
        .arg("--params")
        .arg(repo.join("campaigns/friction_sdof_reference_params.json"))
        .args(["--dt", "1e-4", "--samples", &samples.to_string()])
        .args(["--noise", "0.2", "--seed", "3", "--out"])
        .arg(&record)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    c["experiments"][0]["data"]["file"] = json!(record.to_str().unwrap());
    c["solver"]["substeps"] = json!(1);
    c["solver"]["backend"] = json!(backend);
    c["search"] = search;
    let path = dir.join("c.json");
    std::fs::write(&path, c.to_string()).unwrap();
    path
}

/// Sends SIGINT to `child` once `ready` holds (checked every 5 ms, given
/// the stderr read so far), then reads the rest; returns the exit code, the
/// whole stderr and the seconds from the signal to the exit.
fn interrupt_when(
    mut child: Child,
    what: &str,
    mut ready: impl FnMut(&str) -> bool,
) -> (Option<i32>, String, f64) {
    let stderr = child.stderr.take().unwrap();
    let (tx, rx) = std::sync::mpsc::channel::<String>();
    let reader = std::thread::spawn(move || {
        let mut r = BufReader::new(stderr);
        let mut line = String::new();
        while r.read_line(&mut line).unwrap_or(0) > 0 {
            let _ = tx.send(std::mem::take(&mut line));
        }
        let mut rest = String::new();
        let _ = r.read_to_string(&mut rest);
        let _ = tx.send(rest);
    });
    let mut text = String::new();
    let deadline = Instant::now() + Duration::from_secs(300);
    loop {
        while let Ok(l) = rx.try_recv() {
            text.push_str(&l);
        }
        if ready(&text) {
            break;
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "the job ended before {what}:\n{text}"
        );
        assert!(Instant::now() < deadline, "never reached {what}:\n{text}");
        std::thread::sleep(Duration::from_millis(5));
    }
    let signalled = Instant::now();
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let code = child.wait().unwrap().code();
    let took = signalled.elapsed().as_secs_f64();
    reader.join().unwrap();
    while let Ok(l) = rx.try_recv() {
        text.push_str(&l);
    }
    // Reported, not asserted: the time depends on the machine's load.
    eprintln!("SIGINT during {what}: exited {code:?} after {took:.2} s");
    (code, text, took)
}

/// The command a hint ends with, after `marker`.
fn hinted(text: &str, marker: &str) -> Option<String> {
    text.lines()
        .find_map(|l| l.split_once(marker).map(|(_, c)| c.trim().to_string()))
}

/// Runs a hint's command as a shell would, typed in `dir`; it must succeed.
fn run_hint(dir: &Path, hint: &str) {
    let o = Command::new("sh")
        .current_dir(dir)
        .env("RIGFIT_CACHE_DIR", dir.join("cache"))
        .args(["-c", hint])
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "`{hint}` failed:\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// The interrupt's end as every phase must show it: 130, the lock gone.
fn assert_stopped(code: Option<i32>, text: &str, out: &Path) {
    assert_eq!(code, Some(130), "{text}");
    assert!(
        !out.join(".rigfit.lock").exists(),
        "the lock was left:\n{text}"
    );
}

/// A `--resume` hint after `marker` that resumes the job to its end.
fn assert_resume_hint_works(dir: &Path, out: &Path, text: &str, marker: &str) {
    let hint = hinted(text, marker).unwrap_or_else(|| panic!("no `{marker}` hint:\n{text}"));
    assert!(hint.ends_with("--resume"), "{hint}");
    assert!(
        out.join("checkpoint.json").exists(),
        "no checkpoint:\n{text}"
    );
    run_hint(dir, &hint);
    assert!(out.join("result.json").exists());
    assert!(
        !out.join("checkpoint.json").exists(),
        "the resumed job did not end"
    );
}

#[test]
fn sigint_during_the_backend_trial_writes_nothing_and_says_to_start_again() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(
        dir.path(),
        20_000,
        json!({"population": 2048, "generations": 2, "seed": 1, "polish": {"enabled": false}}),
        "auto",
    );
    let out = dir.path().join("out");
    let child = run(dir.path(), &c, &out)
        // A trial whatever the job's length: the GPU opened and raced.
        .env("RIGFIT_AUTO_TRIAL", "always")
        .spawn()
        .unwrap();
    // Without an adapter there is no trial: then the signal lands in the
    // first generation, which keeps nothing either.
    let (code, text, _) = interrupt_when(child, "the trial", |t| {
        t.contains("auto's trial") || t.contains("no GPU adapter")
    });
    assert_stopped(code, &text, &out);
    let hint = hinted(&text, "start it again with: ")
        .unwrap_or_else(|| panic!("no hint to start again:\n{text}"));
    assert!(!hint.contains("--resume"), "{hint}");
    assert!(!out.join("checkpoint.json").exists(), "{text}");
    assert!(!out.join("result.json").exists(), "{text}");
    // Nothing to resume, as it says; started again it runs.
    let o = rigfit(dir.path())
        .arg("run")
        .arg(&c)
        .arg("--out")
        .arg(&out)
        .arg("--resume")
        .output()
        .unwrap();
    assert!(!o.status.success());
    run_hint(dir.path(), &format!("{hint} --population 64"));
}

#[test]
fn sigint_during_the_search_keeps_the_checkpoint_and_resumes_as_hinted() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(
        dir.path(),
        20_000,
        json!({"population": 64, "generations": 40, "seed": 1, "checkpoint_every": 1,
               "polish": {"enabled": false}}),
        "cpu",
    );
    let out = dir.path().join("out");
    let child = run(dir.path(), &c, &out).spawn().unwrap();
    let checkpoint = out.join("checkpoint.json");
    let (code, text, _) = interrupt_when(child, "the search", |_| checkpoint.exists());
    assert_stopped(code, &text, &out);
    // The interim result of the generations done.
    assert!(out.join("result.json").exists(), "{text}");
    assert_resume_hint_works(dir.path(), &out, &text, "continue with: ");
}

#[test]
fn sigint_during_the_polish_keeps_the_checkpoint_and_resumes_as_hinted() {
    let dir = tempfile::tempdir().unwrap();
    // 100 000 samples: a polish of several seconds.
    let c = campaign(
        dir.path(),
        100_000,
        json!({"population": 16, "generations": 2, "seed": 1, "checkpoint_every": 1,
               "polish": {"starts": 8, "max_iterations": 30}}),
        "cpu",
    );
    let out = dir.path().join("out");
    let child = run(dir.path(), &c, &out).spawn().unwrap();
    // The checkpoint of the search's end is written before the polish starts.
    let checkpoint = out.join("checkpoint.json");
    let ended = || -> Option<u64> {
        let v: Value = serde_json::from_str(&std::fs::read_to_string(&checkpoint).ok()?).ok()?;
        v["checkpoint"]["state"]["generation"].as_u64()
    };
    let (code, text, _) = interrupt_when(child, "the polish", |_| ended().is_some_and(|g| g >= 1));
    assert_stopped(code, &text, &out);
    assert_resume_hint_works(dir.path(), &out, &text, "continue with: ");
    let r: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    assert!(r["polish"]["iterations"].as_u64().is_some(), "{r}");
}

#[test]
fn sigint_while_the_outputs_are_written_keeps_the_checkpoint_and_resumes_as_hinted() {
    let dir = tempfile::tempdir().unwrap();
    // A long record: its CSV is written first, then its figure, then the
    // integration error's runs at two and four times the steps.
    let c = campaign(
        dir.path(),
        1_000_000,
        json!({"population": 4, "generations": 1, "seed": 1, "checkpoint_every": 1,
               "polish": {"enabled": false}}),
        "cpu",
    );
    let out = dir.path().join("out");
    let child = run(dir.path(), &c, &out).spawn().unwrap();
    let csv = out.join("f10.csv");
    let (code, text, _) = interrupt_when(child, "the outputs", |_| csv.exists());
    assert_stopped(code, &text, &out);
    assert!(
        text.contains("interrupted while writing the outputs"),
        "{text}"
    );
    assert!(
        text.contains("f10.csv"),
        "the files written are not named:\n{text}"
    );
    assert!(!out.join("result.json").exists(), "{text}");
    assert_resume_hint_works(dir.path(), &out, &text, "continue with: ");
}
