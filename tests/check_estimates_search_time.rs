//! `rigfit check` estimates the whole search's wall time on the CPU and on
//! the GPU, says what rates it assumes, and grows the estimate with the steps
//! a clock offset adds.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::{Value, json};

fn check(c: &Path, json: bool) -> String {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_rigfit"));
    if json {
        cmd.arg("--json");
    }
    let o = cmd.arg("check").arg(c).output().unwrap();
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
        let gpu = e["gpu_seconds"].as_f64().unwrap();
        assert_eq!(gpu, steps / e["gpu_steps_per_s_assumed"].as_f64().unwrap());
        let cpu = e["cpu_seconds"].as_f64().unwrap();
        assert_eq!(cpu, steps / e["cpu_steps_per_s_assumed"].as_f64().unwrap());
        gpu_seconds.push(gpu);
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
    // 10 ms at 1 µs steps before the record: 10 000 more steps per candidate.
    assert!(gpu_seconds[1] > 4.0 * gpu_seconds[0], "{gpu_seconds:?}");
}
