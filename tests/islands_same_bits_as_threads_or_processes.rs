//! Islands give the same bits whether they run as threads of one process
//! (`rigfit run --islands K`) or as separate processes (`--island I`, then
//! `--gather`), one of them killed mid-exchange and requeued with `--resume`.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

/// The shipped one-record campaign with a small three-island search.
fn campaign(dir: &Path) -> PathBuf {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(repo.join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    let data = repo.join("campaigns/aa2024_t3_v2_synthetic.csv");
    c["experiments"][0]["data"]["file"] = Value::from(data.to_str().unwrap());
    c["search"] = serde_json::json!({
        "population": 24, "generations": 12, "seed": 11, "checkpoint_every": 1,
        "polish": {"starts": 2, "max_iterations": 5},
        "islands": {"count": 3, "every": 3, "migrants": 2, "wait_s": 30}
    });
    c["solver"]["backend"] = Value::from("cpu");
    let path = dir.join("campaign.json");
    std::fs::write(&path, serde_json::to_string_pretty(&c).unwrap()).unwrap();
    path
}

fn start(campaign: &Path, out: &Path, extra: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .arg("--quiet")
        .arg("run")
        .arg(campaign)
        .arg("--out")
        .arg(out)
        .args(["--threads", "1"])
        .args(extra)
        .env("RIGFIT_CACHE_DIR", out.with_extension("cache"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

fn finish(child: Child) {
    let o = child.wait_with_output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

fn json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Waits until `path` exists, the child still running.
fn wait_for(child: &mut Child, path: &Path) {
    let deadline = Instant::now() + Duration::from_secs(60);
    while !path.exists() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the island ended early"
        );
        assert!(
            Instant::now() < deadline,
            "{} never appeared",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(5));
    }
}

#[test]
fn threads_and_processes_with_a_requeued_island_give_the_same_bits() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path());
    let threads = dir.path().join("threads");
    finish(start(&c, &threads, &[]));

    // Island 1 alone: it sends its first migrants, then waits for island
    // 0's, which are not coming yet; killed there, it is requeued below.
    let procs = dir.path().join("procs");
    let mut first = start(&c, &procs, &["--island", "1"]);
    wait_for(&mut first, &procs.join("islands/migrants/1-2.json"));
    first.kill().unwrap();
    let _ = first.wait();
    assert!(!procs.join("islands/1/island.json").exists());
    let children = [
        start(&c, &procs, &["--island", "0"]),
        start(&c, &procs, &["--island", "2"]),
        start(&c, &procs, &["--island", "1", "--resume"]),
    ];
    children.into_iter().for_each(finish);
    finish(start(&c, &procs, &["--gather"]));

    for i in 0..3 {
        let island =
            |out: &Path| json(&out.join(format!("islands/{i}/island.json")))["outcome"].clone();
        let (a, b) = (island(&threads), island(&procs));
        assert_eq!(a["population"], b["population"], "island {i}");
        assert_eq!(a["costs"], b["costs"], "island {i}");
        assert_eq!(a["best_cost"], b["best_cost"], "island {i}");
    }
    let (a, b) = (
        json(&threads.join("result.json")),
        json(&procs.join("result.json")),
    );
    assert_eq!(a["params"], b["params"]);
    assert_eq!(a["fitness"], b["fitness"]);
    assert_eq!(a["islands"], b["islands"]);
    assert_eq!(a["islands"]["reproducible"], true);
    for row in a["islands"]["islands"].as_array().unwrap() {
        assert_eq!(row["exchanges_made"], 3, "{row}");
        assert_eq!(row["exchanges_missed"], 0, "{row}");
    }
    // The islands are distinct searches: their seeds and bests differ.
    let seeds: Vec<&Value> = a["islands"]["islands"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| &r["seed"])
        .collect();
    assert!(seeds[0] != seeds[1] && seeds[1] != seeds[2]);
}
