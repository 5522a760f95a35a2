//! `--adapter` and `RIGFIT_ADAPTER` pick the GPU adapter a job runs on (index,
//! PCI bus id or a piece of the name, as `rigfit devices` lists them): a
//! selector that names no adapter is refused before any work with exit 2 and
//! the list of adapters; one that names an adapter runs the job there and
//! result.json says which and how it was chosen.
mod oracle;
mod tensile_common;

mod gpu_common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use rigfit::gpu::{ADAPTER_ENV, list_adapters};
use serde_json::{Value, json};

/// The shipped example, a few generations of a small population on the GPU.
fn campaign(dir: &Path) -> PathBuf {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(repo.join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    let data = repo.join("campaigns/aa2024_t3_v2_synthetic.csv");
    c["experiments"][0]["data"]["file"] = json!(data.to_str().unwrap());
    c["search"] = json!({"population": 32, "generations": 3, "seed": 4});
    c["solver"]["backend"] = json!("auto");
    c["solver"]["precision"] = json!("f32");
    let path = dir.join("campaign.json");
    std::fs::write(&path, serde_json::to_string_pretty(&c).unwrap()).unwrap();
    path
}

fn run(c: &Path, out: &Path, flag: Option<&str>, env: Option<&str>) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_rigfit"));
    cmd.arg("--quiet").arg("run").arg(c).arg("--out").arg(out);
    if let Some(f) = flag {
        cmd.args(["--adapter", f]);
    }
    match env {
        Some(v) => cmd.env(ADAPTER_ENV, v),
        None => cmd.env_remove(ADAPTER_ENV),
    };
    cmd.output().unwrap()
}

fn refused(o: &Output, out: &Path, names: &str) -> String {
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains(names), "{err}");
    // The list of adapters, every one of them.
    for (i, a) in list_adapters().iter().enumerate() {
        assert!(err.contains(&format!("[{i}] {}", a.name)), "{err}");
    }
    assert!(!out.exists(), "a refused job wrote {}", out.display());
    err
}

#[test]
fn a_selector_that_names_no_adapter_is_refused_with_the_list() {
    if gpu_common::gpu().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path());
    let out = dir.path().join("out");
    let n = list_adapters().len();
    let o = run(&c, &out, Some("no such adapter"), None);
    refused(&o, &out, "--adapter no such adapter: no adapter");
    let o = run(&c, &out, None, Some(&n.to_string()));
    refused(
        &o,
        &out,
        &format!("{ADAPTER_ENV}={n}: there is no adapter [{n}]"),
    );
    // A long selector is echoed cut short, with its length.
    let long = "x".repeat(5000);
    let o = run(&c, &out, Some(&long), None);
    let err = refused(&o, &out, "(5000 bytes)");
    assert!(err.len() < 1000, "{} bytes of error", err.len());
    // The flag wins over the variable.
    let o = run(&c, &out, Some(&n.to_string()), Some("0"));
    refused(&o, &out, &format!("--adapter {n}"));
}

#[test]
fn an_adapter_chosen_by_name_or_index_runs_the_job_and_is_recorded() {
    if gpu_common::gpu().is_none() {
        return;
    }
    let adapters = list_adapters();
    // lavapipe's name where it is installed, else the first unique name.
    let lower: Vec<String> = adapters.iter().map(|a| a.name.to_lowercase()).collect();
    let unique = |i: usize| lower.iter().filter(|n| **n == lower[i]).count() == 1;
    let index = (0..adapters.len())
        .find(|&i| lower[i].contains("llvmpipe") && unique(i))
        .or_else(|| (0..adapters.len()).find(|&i| unique(i)))
        .expect("an adapter with a name of its own");
    let piece = if lower[index].contains("llvmpipe") {
        "LLVMpipe".to_string()
    } else {
        adapters[index].name.clone()
    };
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path());
    for (k, (flag, env, by)) in [
        (Some(piece.as_str()), None, format!("--adapter {piece}")),
        (
            None,
            Some(index.to_string()),
            format!("{ADAPTER_ENV}={index}"),
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let out = dir.path().join(format!("out{k}"));
        let o = run(&c, &out, flag, env.as_deref());
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(0), "{err}");
        let r: Value =
            serde_json::from_slice(&std::fs::read(out.join("result.json")).unwrap()).unwrap();
        assert_eq!(r["backend"], json!("gpu"));
        let device = r["device"].as_str().unwrap();
        assert!(device.starts_with(&adapters[index].name), "{device}");
        assert!(
            device.contains(&format!("adapter [{index}] chosen by {by}")),
            "{device}"
        );
    }
}
