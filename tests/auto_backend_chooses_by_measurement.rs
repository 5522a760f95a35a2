//! `--backend auto` scores a trial batch on the GPU and on the CPU and runs
//! the job on the faster path (src/job/backend/): result.json's
//! `backend_trial` gives both measured rates and the choice, the job ran on
//! the path with the higher rate, and a second run of the same job reads the
//! choice back from the cache instead of measuring again. The trial scores
//! the search's first generation, and the path kept does not score it again:
//! the job takes those scores from memory and ends bit for bit where the
//! cached run, which scores it, ends. A forced backend
//! measures nothing, and `rigfit check` estimates the job's time from the
//! rates measured for it; where none were, `check` races the paths itself
//! and caches the choice, which the run then takes without a trial, short
//! job or not. A job too short for a trial to pay back runs on
//! the CPU unmeasured and says so, unless `RIGFIT_AUTO_TRIAL=always` (or
//! `RIGFIT_REQUIRE_GPU=1`, which opens the GPU to fail without one).

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

fn run(campaign: &Path, out: &Path, cache: &Path, backend: &str) -> Value {
    run_trial(campaign, out, cache, backend, "always").0
}

/// `rigfit run` with `RIGFIT_AUTO_TRIAL` set to `trial`: its result and
/// what it said.
fn run_trial(
    campaign: &Path,
    out: &Path,
    cache: &Path,
    backend: &str,
    trial: &str,
) -> (Value, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .arg("run")
        .arg(campaign)
        .arg("--out")
        .arg(out)
        .args(["--backend", backend])
        .env("RIGFIT_CACHE_DIR", cache)
        .env("RIGFIT_AUTO_TRIAL", trial)
        .env("RUST_LOG", "rigfit=info")
        .env_remove("RIGFIT_REQUIRE_GPU")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(o.status.success(), "rigfit run failed: {err}");
    if backend == "auto" {
        assert!(
            err.contains("backend auto chose the"),
            "no choice said: {err}"
        );
    }
    let result =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    (result, err)
}

#[test]
fn a_job_too_short_for_a_trial_runs_on_the_cpu_unmeasured() {
    let dir = tempfile::tempdir().unwrap();
    let campaign = small_campaign(dir.path());
    let cache = dir.path().join("cache");
    let (r, said) = run_trial(&campaign, &dir.path().join("a"), &cache, "auto", "");
    assert_eq!(r["backend"], "cpu");
    assert!(r.get("backend_trial").is_none(), "nothing measured");
    assert!(
        said.contains("without a trial: the job is estimated at") && said.contains("under 4 s"),
        "{said}"
    );
    assert!(
        !cache.join("backend-trials.json").exists(),
        "nothing cached"
    );
}

#[test]
fn auto_runs_on_the_path_it_measured_faster_and_remembers_it() {
    let dir = tempfile::tempdir().unwrap();
    let campaign = small_campaign(dir.path());
    let cache = dir.path().join("cache");
    let (first, said) = run_trial(&campaign, &dir.path().join("a"), &cache, "auto", "always");
    assert!(
        said.contains("64 candidates answered from memory"),
        "the first generation scored again: {said}"
    );
    let t = &first["backend_trial"];
    let (gpu, cpu) = (
        t["gpu_rate"].as_f64().unwrap(),
        t["cpu_rate"].as_f64().unwrap(),
    );
    assert!(gpu > 0.0 && cpu > 0.0, "{t}");
    // Each GPU kernel variant timed; the GPU's rate is the fastest one's.
    let kernels = t["gpu_kernel_rates"].as_object().unwrap();
    assert_eq!(kernels.len(), 2, "{t}");
    let (fastest, best) = kernels
        .iter()
        .map(|(k, r)| (k.as_str(), r.as_f64().unwrap()))
        .fold(("", 0.0), |m, x| if x.1 > m.1 { x } else { m });
    assert_eq!(t["gpu_kernel"], fastest, "{t}");
    assert_eq!(gpu, best, "{t}");
    let faster = if gpu >= cpu { "gpu" } else { "cpu" };
    assert_eq!(t["chosen"], faster, "{t}");
    assert_eq!(first["backend"], faster, "the job ran where the trial said");
    assert_eq!(t["cached"], false);
    assert!(t["trial_s"].as_f64().unwrap() > 0.0);
    assert!(cache.join("backend-trials.json").is_file());
    // `rigfit devices` lists the choice kept, with its rates and campaign.
    let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(["devices", "--json"])
        .env("RIGFIT_CACHE_DIR", &cache)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let devices: Value = serde_json::from_slice(&o.stdout).unwrap();
    let kept = devices["auto_choices"].as_array().unwrap();
    assert_eq!(kept.len(), 1, "{devices}");
    assert_eq!(kept[0]["population"], 64, "{devices}");
    assert_eq!(kept[0]["trial"]["chosen"], t["chosen"], "{devices}");
    assert_eq!(kept[0]["trial"]["gpu_rate"], t["gpu_rate"], "{devices}");
    assert_eq!(kept[0]["trial"]["cpu_rate"], t["cpu_rate"], "{devices}");
    let named = kept[0]["trial"]["campaign"].as_str().unwrap_or_default();
    assert!(named.contains("small.json"), "{devices}");

    let (second, said) = run_trial(&campaign, &dir.path().join("b"), &cache, "auto", "always");
    assert!(!said.contains("answered from memory"), "{said}");
    // The same search, its first generation from the trial's memory in the
    // first run and scored in the second.
    assert_eq!(second["fitness"], first["fitness"]);
    assert_eq!(second["evaluations"], first["evaluations"]);
    assert_eq!(second["parameters"], first["parameters"]);
    let t2 = &second["backend_trial"];
    assert_eq!(t2["cached"], true, "{t2}");
    assert_eq!(t2["chosen"], faster);
    assert_eq!(t2["gpu_rate"], t["gpu_rate"]);
    assert_eq!(t2["gpu_kernel"], t["gpu_kernel"]);
    assert_eq!(second["backend"], faster);

    let forced = run(&campaign, &dir.path().join("c"), &cache, "cpu");
    assert!(
        forced.get("backend_trial").is_none(),
        "a forced path measures nothing"
    );

    let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(["--json", "check"])
        .arg(&campaign)
        .env("RIGFIT_CACHE_DIR", &cache)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let check: Value = serde_json::from_slice(&o.stdout).unwrap();
    let e = &check["search_estimate"];
    assert_eq!(e["measured"], true, "{e}");
    assert_eq!(e["gpu_steps_per_s_assumed"], t["gpu_rate"]);
    // The forced CPU run searched on every core: the rate its search ran at
    // (tests/check_estimates_search_time.rs) takes the trial's place.
    assert_eq!(e["cpu_rate_observed"], true, "{e}");
    assert_ne!(e["cpu_steps_per_s_assumed"], t["cpu_rate"], "{e}");
}

#[test]
fn check_races_the_paths_and_the_run_takes_its_choice() {
    let dir = tempfile::tempdir().unwrap();
    let campaign = small_campaign(dir.path());
    let cache = dir.path().join("cache");
    let check = |flags: &[&str]| -> Value {
        let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
            .args(["--json", "check"])
            .args(flags)
            .arg(&campaign)
            .env("RIGFIT_CACHE_DIR", &cache)
            .env_remove("RIGFIT_REQUIRE_GPU")
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v: Value = serde_json::from_slice(&o.stdout).unwrap();
        v["search_estimate"].clone()
    };
    // --no-measure: nothing timed, nothing cached.
    let e = check(&["--no-measure"]);
    assert_eq!(e["measured"], false, "{e}");
    assert!(
        e.get("trial").is_none() && e.get("cpu_trial").is_none(),
        "{e}"
    );
    assert!(!cache.join("backend-trials.json").exists());

    let e = check(&[]);
    assert_eq!(e["measured"], true, "{e}");
    let t = &e["trial"];
    let (gpu, cpu) = (
        t["gpu_rate"]
            .as_f64()
            .unwrap_or_else(|| panic!("a race in {e}")),
        t["cpu_rate"].as_f64().unwrap(),
    );
    assert!(gpu > 0.0 && cpu > 0.0, "{t}");
    assert_eq!(t["chosen"], if gpu >= cpu { "gpu" } else { "cpu" }, "{t}");
    assert_eq!(e["gpu_steps_per_s_assumed"].as_f64(), Some(gpu), "{e}");
    assert_eq!(e["cpu_steps_per_s_assumed"].as_f64(), Some(cpu), "{e}");
    // The GPU's start-up as the race timed it, on top of the CPU's.
    let opened = t["gpu_startup_s"]
        .as_f64()
        .unwrap_or_else(|| panic!("the GPU's start-up in {t}"));
    assert!(opened > 0.0 && opened.is_finite(), "{t}");
    // serde_json's default float parsing may land an ulp off the value
    // printed (as may the cache's read-back below), so the sum is held to
    // within rounding, not to the bit.
    let startup = e["cpu_startup_seconds"].as_f64().unwrap() + opened;
    let near = |v: &Value| v.as_f64().is_some_and(|x| (x - startup).abs() <= 1e-12);
    assert!(near(&e["startup_seconds"]), "{startup} in {e}");
    assert!(cache.join("backend-trials.json").is_file());

    // The run, a job too short for a trial of its own, takes the cached
    // choice.
    let (r, said) = run_trial(&campaign, &dir.path().join("a"), &cache, "auto", "");
    assert!(
        said.contains("as measured before on this machine"),
        "{said}"
    );
    let rt = &r["backend_trial"];
    assert_eq!(rt["cached"], true, "{rt} {said}");
    assert_eq!(rt["chosen"], t["chosen"], "{rt}");
    assert_eq!(rt["gpu_rate"], t["gpu_rate"], "{rt}");
    assert_eq!(r["backend"], t["chosen"]);

    // A second check reads it back, measuring nothing.
    let e2 = check(&[]);
    assert!(e2.get("trial").is_none(), "{e2}");
    assert_eq!(e2["gpu_steps_per_s_assumed"].as_f64(), Some(gpu), "{e2}");
    assert!(near(&e2["startup_seconds"]), "{startup} in {e2}");
}

/// The shipped friction rig's campaign with a small search (population 64,
/// 2 generations) written into the campaign itself, so `check` reads the
/// population `run` ran.
fn small_campaign(dir: &Path) -> PathBuf {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("campaigns");
    let text = std::fs::read_to_string(repo.join("friction_sdof_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    for x in c["experiments"].as_array_mut().unwrap() {
        let file = repo.join(x["data"]["file"].as_str().unwrap());
        x["data"]["file"] = Value::from(file.to_str().unwrap());
    }
    c["search"]["population"] = Value::from(64);
    c["search"]["generations"] = Value::from(2);
    c["search"]["seed"] = Value::from(3);
    let path = dir.join("small.json");
    std::fs::write(&path, c.to_string()).unwrap();
    path
}
