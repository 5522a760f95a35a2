//! Several jobs started together on one machine, each with its own output
//! folder: all finish, and each leaves exactly what it leaves when run alone,
//! on the CPU and on the GPU (four processes sharing one adapter).
mod oracle;
mod tensile_common;

mod gpu_common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::{Value, json};

const JOBS: usize = 4;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Campaign `i` of the test: the shipped example with a small population
/// (a fraction of a second of work each), seed `i + 1`, a checkpoint every
/// generation, on `backend` (the GPU in f32), writing to `out<i>`.
fn campaign(dir: &Path, i: usize, backend: &str) -> PathBuf {
    let text = std::fs::read_to_string(repo().join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    let record = repo().join("campaigns/aa2024_t3_v2_synthetic.csv");
    c["name"] = json!(format!("job{i}"));
    c["experiments"][0]["data"]["file"] = json!(record.to_str().unwrap());
    c["search"]["population"] = json!(48);
    c["search"]["generations"] = json!(15);
    c["search"]["seed"] = json!(i + 1);
    c["search"]["checkpoint_every"] = json!(1);
    c["search"]["polish"] = json!({"enabled": true, "starts": 1, "max_iterations": 2});
    c["solver"]["backend"] = json!(backend);
    c["solver"]["precision"] = json!("f32");
    c["output"] = json!(format!("out{i}"));
    let path = dir.join(format!("c{i}.json"));
    std::fs::write(&path, serde_json::to_string_pretty(&c).unwrap()).unwrap();
    path
}

fn job(c: &Path) -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_rigfit"));
    cmd.arg("run").arg(c).args(["--threads", "1", "--quiet"]);
    cmd
}

/// What a finished job leaves that does not depend on the clock: its files'
/// names, the result without times and memory, and the fitted history CSV.
fn outcome(folder: &Path) -> (Vec<String>, Value, Vec<u8>) {
    let mut names: Vec<String> = std::fs::read_dir(folder)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    let mut result: Value =
        serde_json::from_slice(&std::fs::read(folder.join("result.json")).unwrap()).unwrap();
    let r = result.as_object_mut().unwrap();
    for volatile in ["wall_time_s", "job_wall_time_s", "peak_memory_mib"] {
        r.remove(volatile);
    }
    for stage in ["polish", "profiles"] {
        if let Some(p) = r.get_mut(stage).and_then(Value::as_object_mut) {
            p.remove("wall_time_s");
        }
    }
    let fit = std::fs::read(folder.join("v2.csv")).unwrap();
    (names, result, fit)
}

#[test]
fn four_jobs_started_together_finish_as_they_do_alone() {
    together_as_alone("cpu");
}

#[test]
fn four_gpu_jobs_started_together_finish_as_they_do_alone() {
    if gpu_common::gpu().is_none() {
        return;
    }
    together_as_alone("gpu");
}

fn together_as_alone(backend: &str) {
    let dir = tempfile::tempdir().unwrap();
    let campaigns: Vec<PathBuf> = (0..JOBS)
        .map(|i| campaign(dir.path(), i, backend))
        .collect();

    let mut alone = BTreeMap::new();
    for (i, c) in campaigns.iter().enumerate() {
        let o = job(c).output().unwrap();
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        let folder = dir.path().join(format!("out{i}"));
        let done = outcome(&folder);
        assert_eq!(done.1["backend"], json!(backend), "job {i}");
        alone.insert(i, done);
        std::fs::rename(&folder, dir.path().join(format!("alone{i}"))).unwrap();
    }
    // Different seeds: the jobs really are different jobs.
    assert_ne!(alone[&0].1["params"], alone[&1].1["params"]);

    let children: Vec<_> = campaigns
        .iter()
        .map(|c| job(c).stderr(std::process::Stdio::piped()).spawn().unwrap())
        .collect();
    for (i, child) in children.into_iter().enumerate() {
        let o = child.wait_with_output().unwrap();
        assert_eq!(
            o.status.code(),
            Some(0),
            "job {i}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    for i in 0..JOBS {
        let together = outcome(&dir.path().join(format!("out{i}")));
        assert_eq!(together.0, alone[&i].0, "job {i}: files");
        assert_eq!(together.1, alone[&i].1, "job {i}: result.json");
        assert!(together.2 == alone[&i].2, "job {i}: v2.csv differs");
    }
}
