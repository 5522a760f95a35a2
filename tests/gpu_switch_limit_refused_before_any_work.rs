//! A rig with more located switches than the GPU kernels hold is refused by
//! `run --backend gpu` before any work (exit 2, no output folder), naming the
//! count and the limit; `check` says so too, and refuses it where the campaign
//! asks for the GPU. A GPU required and missing leaves no output folder either.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::{Value, json};

/// The friction rig with `n` stick-slip dampers side by side: each damper's
/// transitions are located switches of their own.
fn rig(n: usize) -> Value {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut r: Value = serde_json::from_str(
        &std::fs::read_to_string(repo.join("rigs/friction_sdof.json")).unwrap(),
    )
    .unwrap();
    r["id"] = json!("many_dampers");
    let suspension = r["elements"][0].clone();
    let mut elements = vec![suspension];
    let mut sum = Vec::new();
    for i in 0..n {
        elements.push(json!({
            "name": format!("damper{i}"),
            "between": ["ground", "plate"],
            "friction": {"law": "stick_slip", "f_c": "f_c", "k_t": "k_c"}
        }));
        sum.push(json!({"force": format!("damper{i}")}));
    }
    r["elements"] = json!(elements);
    r["outputs"] = json!([{"name": "load_cell", "unit": "N", "sum": sum}]);
    r
}

fn campaign(dir: &Path, dampers: usize, backend: &str) -> PathBuf {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let text =
        std::fs::read_to_string(repo.join("campaigns/friction_sdof_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    c["rig"] = rig(dampers);
    let data = repo.join("campaigns/friction_sdof_synthetic.csv");
    c["experiments"][0]["data"]["file"] = json!(data.to_str().unwrap());
    c["solver"]["backend"] = json!(backend);
    c["search"] = json!({"population": 8, "generations": 1, "seed": 1});
    let path = dir.join(format!("c{dampers}_{backend}.json"));
    std::fs::write(&path, c.to_string()).unwrap();
    path
}

fn rigfit(args: &[&str], c: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(args)
        .arg(c)
        .env_remove("RIGFIT_REQUIRE_GPU")
        .output()
        .unwrap()
}

/// The count the message names, checked against the limit.
fn switches_named(text: &str) -> usize {
    let at = text
        .find(" located switches")
        .unwrap_or_else(|| panic!("{text}"));
    let count: usize = text[..at]
        .rsplit(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap_or_else(|_| panic!("{text}"));
    assert!(text.contains("the GPU kernels hold at most 32"), "{text}");
    count
}

#[test]
fn run_on_the_gpu_refuses_before_the_output_folder() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), 20, "auto");
    let out = dir.path().join("out");
    let o = rigfit(
        &["run", "--backend", "gpu", "--out", out.to_str().unwrap()],
        &c,
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("--backend gpu: rig `many_dampers`"), "{err}");
    assert!(switches_named(&err) > 32, "{err}");
    assert!(!err.contains("no GPU implementation"), "{err}");
    assert!(err.contains("run it on the CPU (--backend cpu)"), "{err}");
    assert!(!out.exists(), "the refused job left {}", out.display());

    // A rig within the limit is not refused for it.
    let small = campaign(dir.path(), 2, "auto");
    let o = rigfit(&["check"], &small);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(!err.contains("located switches"), "{err}");
}

#[test]
fn check_says_the_limit_and_refuses_it_for_the_gpu() {
    let dir = tempfile::tempdir().unwrap();
    let o = rigfit(&["check"], &campaign(dir.path(), 20, "auto"));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("warning: rig `many_dampers`"), "{err}");
    assert!(switches_named(&err) > 32, "{err}");

    let o = rigfit(&["check"], &campaign(dir.path(), 20, "gpu"));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("solver.backend \"gpu\""), "{err}");
    assert!(switches_named(&err) > 32, "{err}");
}

#[test]
fn a_required_gpu_that_is_missing_leaves_no_output_folder() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), 1, "auto");
    let out = dir.path().join("out");
    // No adapter: a backend this platform does not have.
    let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(["run", "--out", out.to_str().unwrap()])
        .arg(&c)
        .env("RIGFIT_REQUIRE_GPU", "1")
        .env("WGPU_BACKEND", "metal")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{err}");
    assert!(err.contains("no GPU adapter"), "{err}");
    assert!(!out.exists(), "the failed job left {}", out.display());
}
