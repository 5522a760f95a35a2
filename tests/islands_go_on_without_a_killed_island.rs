//! A killed island does not stop the others: they wait for its migrants at
//! most `wait_s` at each exchange, go on, and the gather polishes the best of
//! those that finished, listing the dead one as missing and the run as not
//! reproducible.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

/// The shipped one-record campaign with a small three-island search whose
/// islands wait one second for a neighbour.
fn campaign(dir: &Path) -> PathBuf {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(repo.join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    let data = repo.join("campaigns/aa2024_t3_v2_synthetic.csv");
    c["experiments"][0]["data"]["file"] = Value::from(data.to_str().unwrap());
    c["search"] = serde_json::json!({
        "population": 24, "generations": 12, "seed": 5,
        "polish": {"starts": 2, "max_iterations": 5},
        "islands": {"count": 3, "every": 3, "migrants": 2, "wait_s": 1}
    });
    c["solver"]["backend"] = Value::from("cpu");
    let path = dir.join("campaign.json");
    std::fs::write(&path, serde_json::to_string_pretty(&c).unwrap()).unwrap();
    path
}

fn rigfit(campaign: &Path, out: &Path, extra: &[&str]) -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_rigfit"));
    cmd.arg("--quiet")
        .arg("run")
        .arg(campaign)
        .arg("--out")
        .arg(out)
        .args(["--threads", "1"])
        .args(extra)
        .env("RIGFIT_CACHE_DIR", out.with_extension("cache"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    cmd
}

fn start(campaign: &Path, out: &Path, extra: &[&str]) -> Child {
    rigfit(campaign, out, extra).spawn().unwrap()
}

fn finish(child: Child) {
    let o = child.wait_with_output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn the_others_go_on_and_the_gather_polishes_the_best_of_them() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path());
    let out = dir.path().join("out");

    // Nothing to gather yet: refused, naming why.
    let o = rigfit(&c, &out, &["--gather"]).output().unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("none of the 3 islands has finished"), "{err}");

    // Island 1 sends its first migrants and is killed while it waits.
    let mut dead = start(&c, &out, &["--island", "1", "--overwrite"]);
    let sent = out.join("islands/migrants/1-2.json");
    let deadline = Instant::now() + Duration::from_secs(60);
    while !sent.exists() {
        assert!(dead.try_wait().unwrap().is_none(), "island 1 ended early");
        assert!(Instant::now() < deadline, "island 1 sent nothing");
        std::thread::sleep(Duration::from_millis(5));
    }
    dead.kill().unwrap();
    let _ = dead.wait();

    let began = Instant::now();
    let others = [
        start(&c, &out, &["--island", "0", "--overwrite"]),
        start(&c, &out, &["--island", "2", "--overwrite"]),
    ];
    others.into_iter().for_each(finish);
    // Island 2 waited a second at each of the two exchanges island 1 missed.
    assert!(began.elapsed() >= Duration::from_secs(2));
    finish(start(&c, &out, &["--gather", "--overwrite"]));

    let r: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    let islands = &r["islands"];
    assert_eq!(islands["reproducible"], false);
    let rows = islands["islands"].as_array().unwrap();
    assert_eq!(rows[1]["status"], "missing");
    // Island 0 hears from island 2, which runs late once it has waited: it
    // may miss one of its exchanges in turn, never wait past it.
    assert_eq!(rows[0]["status"], "finished");
    let heard = rows[0]["exchanges_made"].as_u64().unwrap();
    assert_eq!(heard + rows[0]["exchanges_missed"].as_u64().unwrap(), 3);
    // Island 2 took island 1's first migrants, then missed the other two.
    assert_eq!(rows[2]["exchanges_made"], 1);
    assert_eq!(rows[2]["exchanges_missed"], 2);
    let best = rows[0]["best_cost"]
        .as_f64()
        .unwrap()
        .min(rows[2]["best_cost"].as_f64().unwrap());
    let fitness = r["fitness"].as_f64().unwrap();
    assert!(fitness <= best * (1.0 + 1e-9), "{fitness} > {best}");
    let warnings = r["warnings"].to_string();
    assert!(warnings.contains("island 1 left no outcome"), "{warnings}");
    assert!(warnings.contains("not reproducible"), "{warnings}");
}
