//! The native lane code's build: its scratch folder is private (mode 0700
//! under any umask) and named with a token no other process can guess, one
//! left behind by a killed process is removed by the next build, and a C
//! compiler that hangs is stopped after `RIGFIT_CC_TIMEOUT` seconds, the job
//! finishing on the interpreted lanes. A build is kept in the cache folder
//! for the next process, which loads it only where it is still a private
//! file of this user's.

use std::os::unix::fs::PermissionsExt as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A one-generation CPU job, no polish, on the shipped campaign with native
/// lanes from the first batch, its temporary folder `tmp`, run under
/// `umask 000`, with the extra environment `env`.
fn job(tmp: &Path, out: &Path, env: &[(&str, &str)]) -> Output {
    job_command(tmp, out, env).output().unwrap()
}

/// [`job`]'s command, not yet started.
fn job_command(tmp: &Path, out: &Path, env: &[(&str, &str)]) -> Command {
    let campaigns = repo().join("campaigns");
    let text = std::fs::read_to_string(campaigns.join("aa2024_t3_synthetic.json")).unwrap();
    let mut c: serde_json::Value = serde_json::from_str(&text).unwrap();
    c["search"]["polish"] = serde_json::json!({"enabled": false});
    let file = campaigns.join(c["experiments"][0]["data"]["file"].as_str().unwrap());
    c["experiments"][0]["data"]["file"] = serde_json::json!(file.to_str().unwrap());
    let path = out.with_extension("json");
    std::fs::write(&path, serde_json::to_string(&c).unwrap()).unwrap();
    let mut cmd = Command::new("sh");
    cmd.arg("-c")
        .arg("umask 000; exec \"$@\"")
        .arg("sh")
        .arg(env!("CARGO_BIN_EXE_rigfit"))
        .arg("run")
        .arg(&path)
        .arg("--out")
        .arg(out)
        .args([
            "--backend",
            "cpu",
            "--generations",
            "1",
            "--population",
            "16",
        ])
        .env("TMPDIR", tmp)
        .env("RIGFIT_NATIVE", "always");
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd
}

fn script(dir: &Path, name: &str, body: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, format!("#!/bin/sh\n{body}\n")).unwrap();
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    path
}

#[test]
fn the_scratch_folder_is_private_and_unpredictable_under_umask_000() {
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let seen = dir.path().join("seen.txt");
    // A compiler wrapper that records the folder it is asked to build in.
    let cc = script(
        dir.path(),
        "cc-wrapper",
        &format!(
            "prev=; for a; do [ \"$prev\" = -o ] && stat -c '%a %n' \"$(dirname \"$a\")\" >> '{}'; prev=$a; done\nexec cc \"$@\"",
            seen.display()
        ),
    );
    let o = job(
        &tmp,
        &dir.path().join("out"),
        &[("RIGFIT_CC", cc.to_str().unwrap())],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(!err.contains("native lane code"), "the build failed: {err}");
    let seen = std::fs::read_to_string(&seen).expect("the compiler was run");
    for line in seen.lines() {
        let (mode, path) = line.split_once(' ').unwrap();
        assert_eq!(mode, "700", "{line}");
        let name = Path::new(path).file_name().unwrap().to_str().unwrap();
        let token = name.rsplit('-').next().unwrap();
        assert!(
            name.starts_with("rigfit-native-") && token.len() == 16,
            "a guessable name: {name}"
        );
    }
    assert_eq!(std::fs::read_dir(&tmp).unwrap().count(), 0);
}

#[test]
fn folders_left_by_killed_builds_are_swept_and_live_ones_kept() {
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    // No process has a pid this large (Linux's limit is 2^22).
    let dead = tmp.join("rigfit-native-999999999-0123456789abcdef");
    let dead_old = tmp.join("rigfit-native-999999998-0");
    let live = tmp.join(format!("rigfit-native-{}-0", std::process::id()));
    let unrelated = tmp.join("rigfit-native-notes");
    for d in [&dead, &dead_old, &live, &unrelated] {
        std::fs::create_dir(d).unwrap();
        std::fs::write(d.join("lanes.c"), b"int x;").unwrap();
    }
    let o = job(&tmp, &dir.path().join("out"), &[]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        !dead.exists() && !dead_old.exists(),
        "stale build folders stayed"
    );
    assert!(live.join("lanes.c").exists() && unrelated.join("lanes.c").exists());
}

#[test]
fn a_hung_compiler_is_stopped_and_the_job_interprets() {
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let pid_file = dir.path().join("sleeper.pid");
    let starts = dir.path().join("starts");
    // A compiler that never ends, through a process of its own (as cc runs
    // cc1), which must be stopped too; each start leaves a line.
    let cc = script(
        dir.path(),
        "hung-cc",
        &format!(
            "echo started >> '{}'\nsleep 1000 &\necho $! > '{}'\nwait",
            starts.display(),
            pid_file.display()
        ),
    );
    let out = dir.path().join("out");
    let started = Instant::now();
    let o = job(
        &tmp,
        &out,
        &[
            ("RIGFIT_CC", cc.to_str().unwrap()),
            ("RIGFIT_CC_TIMEOUT", "1"),
            (
                "RIGFIT_CACHE_DIR",
                dir.path().join("cache").to_str().unwrap(),
            ),
        ],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(started.elapsed() < Duration::from_secs(120), "{err}");
    assert!(
        err.contains("did not finish within 1 s") && err.contains("interprets instead"),
        "{err}"
    );
    // Stopped once: asked what it builds for (the kept build's key), it hung,
    // and no build was started to hang as long again.
    let runs = std::fs::read_to_string(&starts).unwrap();
    assert_eq!(
        runs.lines().count(),
        1,
        "the hung compiler was started {runs:?}"
    );
    assert!(out.join("result.json").exists());
    let pid = std::fs::read_to_string(&pid_file).unwrap();
    let proc_dir = Path::new("/proc").join(pid.trim());
    let gone = (0..100).any(|_| {
        let state = std::fs::read_to_string(proc_dir.join("stat")).unwrap_or_default();
        let stopped = state.is_empty() || state.contains(") Z");
        if !stopped {
            std::thread::sleep(Duration::from_millis(50));
        }
        stopped
    });
    assert!(gone, "the compiler's own process {} still runs", pid.trim());
    assert_eq!(std::fs::read_dir(&tmp).unwrap().count(), 0);
}

/// What `result.json` says of the fit, without the timings.
fn fitted(out: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(out.join("result.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert!(v["params"].is_object(), "result.json has no params: {text}");
    serde_json::json!([v["params"], v["fitness"]])
}

#[test]
fn a_kept_build_is_loaded_by_the_next_job_only_while_it_is_private() {
    use std::os::unix::fs::PermissionsExt as _;
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let cache = dir.path().join("cache");
    let builds = dir.path().join("builds.txt");
    // A compiler wrapper that counts the library builds (not its
    // questions: `-dM -E`).
    let cc = script(
        dir.path(),
        "counting-cc",
        &format!(
            "case \" $* \" in *' -shared '*) echo build >> '{}';; esac\nexec cc \"$@\"",
            builds.display()
        ),
    );
    let env = [
        ("RIGFIT_CC", cc.to_str().unwrap()),
        ("RIGFIT_CACHE_DIR", cache.to_str().unwrap()),
    ];
    let count = || {
        std::fs::read_to_string(&builds)
            .unwrap_or_default()
            .lines()
            .count()
    };
    let run = |name: &str| {
        let out = dir.path().join(name);
        let o = job(&tmp, &out, &env);
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        fitted(&out)
    };
    let first = run("first");
    let built = count();
    assert!(built >= 1, "the first job built nothing");
    let kept: Vec<PathBuf> = std::fs::read_dir(cache.join("native"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(kept.len(), built, "{kept:?}");
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode(&cache.join("native")), 0o700);
    assert!(kept.iter().all(|k| mode(k) == 0o600), "{kept:?}");
    // The next job loads what was kept and scores the same.
    assert_eq!(run("second"), first);
    assert_eq!(count(), built, "the second job built again");
    // A kept build others may write is not loaded: built again, and kept
    // private again.
    for k in &kept {
        std::fs::set_permissions(k, std::fs::Permissions::from_mode(0o666)).unwrap();
    }
    assert_eq!(run("third"), first);
    assert_eq!(
        count(),
        2 * built,
        "a kept build others may write was loaded"
    );
    assert!(kept.iter().all(|k| mode(k) == 0o600), "{kept:?}");
    // Nor is a link planted in its place.
    let elsewhere = dir.path().join("elsewhere.so");
    std::fs::rename(&kept[0], &elsewhere).unwrap();
    std::os::unix::fs::symlink(&elsewhere, &kept[0]).unwrap();
    assert_eq!(run("fourth"), first);
    assert_eq!(count(), 2 * built + 1, "a planted link was loaded");
    assert!(std::fs::symlink_metadata(&kept[0]).unwrap().is_file());
    assert_eq!(std::fs::read_dir(&tmp).unwrap().count(), 0);
}

/// Whether process `pid` has ended (gone, or a zombie), waiting up to 5 s.
fn ends(pid: &str) -> bool {
    let proc_dir = Path::new("/proc").join(pid.trim());
    (0..100).any(|_| {
        let state = std::fs::read_to_string(proc_dir.join("stat")).unwrap_or_default();
        let stopped = state.is_empty() || state.contains(") Z");
        if !stopped {
            std::thread::sleep(Duration::from_millis(50));
        }
        stopped
    })
}

#[test]
fn a_killed_job_takes_its_compiler_with_it() {
    // A compiler still at work (and its own process, as cc runs cc1) when
    // the job is killed outright (SIGKILL, a scheduler's time limit): both
    // end with it, rather than run on for minutes at gigabytes.
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let pids = dir.path().join("pids");
    let cc = script(
        dir.path(),
        "slow-cc",
        &format!(
            "echo $$ >> '{p}'\nsleep 1000 &\necho $! >> '{p}'\nwait",
            p = pids.display()
        ),
    );
    let out = dir.path().join("out");
    let mut job = job_command(
        &tmp,
        &out,
        &[
            ("RIGFIT_CC", cc.to_str().unwrap()),
            (
                "RIGFIT_CACHE_DIR",
                dir.path().join("cache").to_str().unwrap(),
            ),
        ],
    )
    .stdout(std::process::Stdio::null())
    .stderr(std::process::Stdio::null())
    .spawn()
    .unwrap();
    let started = Instant::now();
    let found = loop {
        let text = std::fs::read_to_string(&pids).unwrap_or_default();
        if text.lines().count() >= 2 || started.elapsed() > Duration::from_secs(120) {
            break text;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    job.kill().unwrap();
    job.wait().unwrap();
    let found: Vec<&str> = found.lines().collect();
    assert_eq!(found.len(), 2, "the compiler never started: {found:?}");
    for pid in found {
        assert!(
            ends(pid),
            "the compiler's process {pid} outlived the killed job"
        );
    }
}
