//! The native lane code in a whole job: built and loaded leaving no file
//! behind in the temporary folder, and, where the C compiler cannot be run,
//! the job still finishes (the lanes interpret) and says why once.

use std::path::PathBuf;
use std::process::{Command, Output};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A one-generation CPU job, no polish, on the three-rate campaign (a
/// compiled rig), with its own temporary folder `tmp` and the extra
/// environment `env`.
fn job(tmp: &std::path::Path, out: &std::path::Path, env: &[(&str, &str)]) -> Output {
    let campaigns = repo().join("campaigns");
    let text =
        std::fs::read_to_string(campaigns.join("tensile4_three_rates_synthetic.json")).unwrap();
    let mut c: serde_json::Value = serde_json::from_str(&text).unwrap();
    c["search"]["polish"] = serde_json::json!({"enabled": false});
    for e in c["experiments"].as_array_mut().unwrap() {
        let file = campaigns.join(e["data"]["file"].as_str().unwrap());
        e["data"]["file"] = serde_json::json!(file.to_str().unwrap());
    }
    let path = out.with_extension("json");
    std::fs::write(&path, serde_json::to_string(&c).unwrap()).unwrap();
    let mut c = Command::new(env!("CARGO_BIN_EXE_rigfit"));
    c.arg("run")
        .arg(&path)
        .arg("--out")
        .arg(out)
        .args([
            "--backend",
            "cpu",
            "--generations",
            "1",
            "--population",
            "64",
        ])
        .env("TMPDIR", tmp)
        .env("RIGFIT_NATIVE", "always");
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().unwrap()
}

#[test]
fn a_job_builds_native_lanes_and_leaves_nothing_in_the_temporary_folder() {
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let o = job(&tmp, &dir.path().join("out"), &[("RUST_LOG", "warn")]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(!err.contains("native lane code"), "the build failed: {err}");
    let left: Vec<_> = std::fs::read_dir(&tmp).unwrap().collect();
    assert!(left.is_empty(), "left in the temporary folder: {left:?}");
}

#[test]
fn without_a_c_compiler_the_job_interprets_and_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let out = dir.path().join("out");
    let o = job(&tmp, &out, &[("RIGFIT_CC", "/nonexistent/cc")]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(
        err.contains("the C compiler `/nonexistent/cc` could not be run")
            && err.contains("the lane ensemble interprets instead"),
        "{err}"
    );
    // Said once per drive program, not once per batch.
    assert_eq!(err.matches("could not be run").count(), 1, "{err}");
    assert!(out.join("result.json").exists());
    let left: Vec<_> = std::fs::read_dir(&tmp).unwrap().collect();
    assert!(left.is_empty(), "left in the temporary folder: {left:?}");
}
