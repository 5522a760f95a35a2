//! `rigfit check` estimates the whole job's wall time on the CPU and on the
//! GPU (the GA, then the polish), says what rates it assumes, and grows the
//! estimate with the steps a clock offset adds. Once a run of the job has
//! searched on every CPU core, `check` estimates the CPU from the rate that
//! search ran at; before that, it times the CPU lanes on a few of the job's
//! candidates, unless `--no-measure` asks for the assumed rate.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::{Value, json};

fn check(c: &Path, json: bool) -> String {
    // No measurement of an earlier run (src/job/backend/), none by
    // `check` itself: the assumed rates.
    let cache = tempfile::tempdir().unwrap();
    check_with(c, json, cache.path(), &["--no-measure"])
}

fn check_with(c: &Path, json: bool, cache: &Path, flags: &[&str]) -> String {
    check_in(
        Command::new(env!("CARGO_BIN_EXE_rigfit")),
        c,
        json,
        cache,
        flags,
    )
}

/// `check` where no GPU adapter can be found (a backend this platform does
/// not have), so that only the CPU is measured.
fn check_without_gpu(c: &Path, json: bool, cache: &Path) -> String {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_rigfit"));
    cmd.env("WGPU_BACKEND", "metal")
        .env_remove("RIGFIT_REQUIRE_GPU");
    check_in(cmd, c, json, cache, &[])
}

fn check_in(mut cmd: Command, c: &Path, json: bool, cache: &Path, flags: &[&str]) -> String {
    if json {
        cmd.arg("--json");
    }
    let o = cmd
        .arg("check")
        .args(flags)
        .arg(c)
        .env("RIGFIT_CACHE_DIR", cache)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8(o.stdout).unwrap() + &String::from_utf8_lossy(&o.stderr)
}

fn campaign(dir: &Path, offset: f64) -> PathBuf {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(repo.join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    let data = repo.join("campaigns/aa2024_t3_v2_synthetic.csv");
    c["experiments"][0]["data"]["file"] = json!(data.to_str().unwrap());
    c["experiments"][0]["offset"] = json!(offset);
    c["search"]["population"] = json!(1000);
    c["search"]["generations"] = json!(50);
    let path = dir.join(format!("c{offset}.json"));
    std::fs::write(&path, c.to_string()).unwrap();
    path
}

#[test]
fn check_estimates_the_search_on_cpu_and_gpu_with_its_assumptions() {
    let dir = tempfile::tempdir().unwrap();
    let mut gpu_seconds = Vec::new();
    for offset in [0.0, 0.01] {
        let c = campaign(dir.path(), offset);
        let v: Value = serde_json::from_str(&check(&c, true)).unwrap();
        let e = &v["search_estimate"];
        let per_candidate = v["run_length"]["steps_per_candidate"].as_f64().unwrap();
        assert_eq!(e["candidates"].as_f64(), Some(50_000.0), "{e}");
        let steps = e["steps"].as_f64().unwrap();
        assert_eq!(steps, 50_000.0 * per_candidate, "{e}");
        // Start-up, the GA's steps at each path's rate, then the polish's.
        let f = |k: &str| e[k].as_f64().unwrap_or_else(|| panic!("{k} in {e}"));
        let gpu = f("gpu_seconds");
        assert_eq!(
            gpu,
            f("startup_seconds") + steps / f("gpu_steps_per_s_assumed") + f("gpu_polish_seconds")
        );
        let cpu = f("cpu_seconds");
        assert_eq!(
            cpu,
            f("cpu_startup_seconds")
                + steps / f("cpu_steps_per_s_assumed")
                + f("cpu_polish_seconds")
        );
        assert!(f("cpu_startup_seconds") < f("startup_seconds"), "{e}");
        gpu_seconds.push(gpu - f("startup_seconds"));
        let text = check(&c, false);
        assert!(
            text.contains("on the GPU (at an assumed 1e8 candidate-steps/s"),
            "{text}"
        );
        assert!(
            text.contains("at most 5.000e4 candidates (1000 × 50 generations)"),
            "{text}"
        );
    }
    // 10 ms at 1 µs steps before the record: 10 000 more steps per candidate
    // (the start-up the same).
    assert!(gpu_seconds[1] > 4.0 * gpu_seconds[0], "{gpu_seconds:?}");
}

/// The estimate counts the polish after the GA: its candidates at the
/// iteration limit bound the evaluations a run's polish takes, its expected
/// candidates (fewer rounds) at a share of each path's rate are in both
/// totals, and a campaign without the polish estimates none.
#[test]
fn check_estimates_the_polish_after_the_search() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), 0.0);
    let v: Value = serde_json::from_str(&check(&c, true)).unwrap();
    let e = &v["search_estimate"];
    let f = |k: &str| e[k].as_f64().unwrap_or_else(|| panic!("{k} in {e}"));
    let genes = v["genes"].as_array().unwrap().len() as f64;
    // The default polish: 8 starts, 30 iterations and the first linearisation.
    assert_eq!(
        f("polish_candidates"),
        8.0 * (2.0 * genes + 1.0) * 31.0,
        "{e}"
    );
    let per_candidate = v["run_length"]["steps_per_candidate"].as_f64().unwrap();
    assert_eq!(f("polish_steps"), f("polish_candidates") * per_candidate);
    // Expected: the first linearisation and six iterations.
    assert_eq!(
        f("polish_candidates_expected"),
        8.0 * (2.0 * genes + 1.0) * 7.0,
        "{e}"
    );
    let steps = f("polish_steps_expected");
    assert_eq!(steps, f("polish_candidates_expected") * per_candidate);
    for path in ["cpu", "gpu"] {
        let g = |k: &str| f(&format!("{path}_{k}"));
        // The polish at a share of the path's GA rate.
        let rate = g("polish_steps_per_s");
        assert!(rate > 0.0 && rate < g("steps_per_s_assumed"), "{e}");
        let polish = steps / rate;
        assert_eq!(g("polish_seconds"), polish, "{e}");
        let startup = if path == "cpu" {
            f("cpu_startup_seconds")
        } else {
            f("startup_seconds")
        };
        assert_eq!(
            g("seconds"),
            startup + f("steps") / g("steps_per_s_assumed") + polish
        );
    }
    let text = check(&c, false);
    assert!(text.contains("the polish after it: about"), "{text}");

    // A run's polish takes no more evaluations than the estimate counts.
    let mut small: Value = serde_json::from_str(&std::fs::read_to_string(&c).unwrap()).unwrap();
    small["search"]["population"] = json!(16);
    small["search"]["generations"] = json!(2);
    small["search"]["polish"] = json!({"starts": 2, "max_iterations": 4});
    let small_path = dir.path().join("small.json");
    std::fs::write(&small_path, small.to_string()).unwrap();
    let est: Value = serde_json::from_str(&check(&small_path, true)).unwrap();
    let bound = est["search_estimate"]["polish_candidates"]
        .as_f64()
        .unwrap();
    assert_eq!(bound, 2.0 * (2.0 * genes + 1.0) * 5.0);
    let out = dir.path().join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(["--json", "run", "--backend", "cpu", "--out"])
        .arg(&out)
        .arg(&small_path)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    let evaluations = r["polish"]["evaluations"].as_f64().unwrap();
    assert!(
        evaluations > 0.0 && evaluations <= bound,
        "{evaluations} evaluations against the estimate's {bound}"
    );

    small["search"]["polish"] = json!({"enabled": false});
    std::fs::write(&small_path, small.to_string()).unwrap();
    let none: Value = serde_json::from_str(&check(&small_path, true)).unwrap();
    let e = &none["search_estimate"];
    assert_eq!(e["polish_candidates"].as_f64(), Some(0.0), "{e}");
    let (cpu, sum) = (
        e["cpu_seconds"].as_f64().unwrap(),
        e["cpu_startup_seconds"].as_f64().unwrap()
            + e["steps"].as_f64().unwrap() / e["cpu_steps_per_s_assumed"].as_f64().unwrap(),
    );
    assert!((cpu / sum - 1.0).abs() < 1e-12, "{cpu} against {sum}");
    assert!(!check(&small_path, false).contains("the polish after it"));
}

/// A run that searched on every CPU core leaves the rate it ran at, and
/// `check` estimates the CPU from it; a run on fewer threads leaves none.
#[test]
fn check_estimates_the_cpu_from_the_rate_its_last_search_ran_at() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let mut small: Value =
        serde_json::from_str(&std::fs::read_to_string(campaign(dir.path(), 0.0)).unwrap()).unwrap();
    small["search"]["population"] = json!(64);
    small["search"]["generations"] = json!(3);
    small["search"]["polish"] = json!({"enabled": false});
    let path = dir.path().join("small.json");
    std::fs::write(&path, small.to_string()).unwrap();
    let run = |threads: &str, out: &str| {
        let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
            .args(["run", "--backend", "cpu", "--threads", threads, "--out"])
            .arg(dir.path().join(out))
            .arg(&path)
            .env("RIGFIT_CACHE_DIR", &cache)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let r: Value = serde_json::from_str(
            &std::fs::read_to_string(dir.path().join(out).join("result.json")).unwrap(),
        )
        .unwrap();
        r
    };
    // Nothing measured for the estimate but what the runs left.
    let estimate = || -> Value {
        serde_json::from_str::<Value>(&check_with(&path, true, &cache, &["--no-measure"])).unwrap()
            ["search_estimate"]
            .clone()
    };
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    if cores > 1 {
        run("1", "one");
        assert_eq!(
            estimate()["cpu_rate_observed"],
            false,
            "one thread of {cores}"
        );
    }
    let r = run("0", "all");
    let e = estimate();
    assert_eq!(e["cpu_rate_observed"], true, "{e}");
    let steps = e["steps"].as_f64().unwrap() / e["candidates"].as_f64().unwrap();
    let rate = r["evaluations"].as_f64().unwrap() * steps / r["wall_time_s"].as_f64().unwrap();
    let kept = e["cpu_steps_per_s_assumed"].as_f64().unwrap();
    assert!((kept / rate - 1.0).abs() < 1e-9, "{kept} against {rate}");
    let text = check_with(&path, false, &cache, &["--no-measure"]);
    assert!(
        text.contains("the rate its last search on every core here ran at"),
        "{text}"
    );
}

/// Where nothing has measured the job on this machine and there is no GPU
/// to race (tests/auto_backend_chooses_by_measurement.rs races one),
/// `check` times the CPU lanes on the search's first candidates and
/// estimates the CPU from that rate; `--no-measure` keeps the assumed one,
/// and a candidate too long to time before a job is not timed, with why.
#[test]
fn check_times_the_cpu_where_nothing_was_measured() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), 0.0);
    let cache = dir.path().join("cache");
    let v: Value = serde_json::from_str(&check_without_gpu(&c, true, &cache)).unwrap();
    let e = &v["search_estimate"];
    assert!(e["gpu_trial_skipped"].is_string(), "{e}");
    assert_eq!(e["measured"], false, "{e}");
    let t = &e["cpu_trial"];
    let rate = t["rate"]
        .as_f64()
        .unwrap_or_else(|| panic!("a trial in {e}"));
    assert!(rate > 1e4 && rate < 1e11, "{t}");
    assert_eq!(e["cpu_steps_per_s_assumed"].as_f64(), Some(rate), "{e}");
    // The population (1000) fits the trial's steps: the whole first
    // generation is timed, in f64 (the campaign's precision is `auto`).
    assert_eq!(t["candidates"].as_u64(), Some(1000), "{t}");
    assert_eq!(t["precision"], "f64", "{t}");
    assert!(t["trial_s"].as_f64().unwrap() > 0.0, "{t}");
    let steps = e["steps"].as_f64().unwrap();
    let polish = e["cpu_polish_seconds"].as_f64().unwrap();
    let cpu = e["cpu_seconds"].as_f64().unwrap();
    assert_eq!(
        cpu,
        e["cpu_startup_seconds"].as_f64().unwrap() + steps / rate + polish
    );
    let text = check_without_gpu(&c, false, &cache);
    assert!(text.contains("the GPU was not timed here:"), "{text}");
    assert!(
        text.contains("candidate-steps/s, measured here in"),
        "{text}"
    );
    assert!(text.contains("on 1000 of its candidates in f64"), "{text}");

    // --no-measure: the assumed rate on every core.
    let v: Value = serde_json::from_str(&check_with(&c, true, &cache, &["--no-measure"])).unwrap();
    let e = &v["search_estimate"];
    assert!(e.get("cpu_trial").is_none(), "{e}");
    let cores = e["cpu_cores"].as_f64().unwrap();
    assert_eq!(
        e["cpu_steps_per_s_assumed"].as_f64(),
        Some(3e7 * cores),
        "{e}"
    );

    // A campaign that asks for the CPU: no GPU opened, the CPU timed.
    let mut on_cpu: Value = serde_json::from_str(&std::fs::read_to_string(&c).unwrap()).unwrap();
    on_cpu["solver"]["backend"] = json!("cpu");
    let on_cpu_path = dir.path().join("on_cpu.json");
    std::fs::write(&on_cpu_path, on_cpu.to_string()).unwrap();
    let fresh = dir.path().join("fresh-cache");
    let v: Value = serde_json::from_str(&check_with(&on_cpu_path, true, &fresh, &[])).unwrap();
    let e = &v["search_estimate"];
    let why = e["gpu_trial_skipped"]
        .as_str()
        .unwrap_or_else(|| panic!("{e}"));
    assert!(why.contains("solver.backend is \"cpu\""), "{why}");
    assert!(e["cpu_trial"]["rate"].as_f64().is_some(), "{e}");
    assert!(!fresh.join("backend-trials.json").exists(), "nothing raced");
    // An adapter named for `run`, which takes it unmeasured: no race either.
    let mut named = Command::new(env!("CARGO_BIN_EXE_rigfit"));
    named.env("RIGFIT_ADAPTER", "no-such-adapter");
    let v: Value = serde_json::from_str(&check_in(named, &c, true, &fresh, &[])).unwrap();
    let e = &v["search_estimate"];
    let why = e["gpu_trial_skipped"]
        .as_str()
        .unwrap_or_else(|| panic!("{e}"));
    assert!(
        why.contains("RIGFIT_ADAPTER=no-such-adapter names the adapter"),
        "{why}"
    );
    assert!(e["cpu_trial"]["rate"].as_f64().is_some(), "{e}");
    assert!(!fresh.join("backend-trials.json").exists(), "nothing raced");

    // A candidate of 5·10⁵ steps (0.5 s before the record at 1 µs steps):
    // the smallest batch, 128 of them, is more than `check` times.
    let long = campaign(dir.path(), 0.5);
    let v: Value = serde_json::from_str(&check_without_gpu(&long, true, &cache)).unwrap();
    let e = &v["search_estimate"];
    assert!(e.get("cpu_trial").is_none(), "{e}");
    let why = e["cpu_trial_skipped"]
        .as_str()
        .unwrap_or_else(|| panic!("{e}"));
    assert!(why.contains("128 candidates of"), "{why}");
    assert_eq!(
        e["cpu_steps_per_s_assumed"].as_f64(),
        Some(3e7 * cores),
        "{e}"
    );
}
