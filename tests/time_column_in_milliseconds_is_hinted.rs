//! A record whose time column holds milliseconds read as seconds gets a
//! warning before the search, naming `time_scale`: by the column's name
//! (`t_ms`), or, whatever its name, by a sample interval far slower than the
//! rig moves. Scaled to seconds, neither warning is given; `rigfit run`
//! prints it before the search and keeps it in result.json.

use std::path::{Path, PathBuf};
use std::process::Command;

use rigfit::campaign::Campaign;
use serde_json::{Value, json};

/// The shipped friction_sdof campaign over `samples` samples of its record
/// at 0.2 ms (every other sample), written with the time column `column` in
/// milliseconds and read at `time_scale`.
fn campaign(dir: &Path, column: &str, time_scale: f64, samples: usize) -> PathBuf {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let shipped = repo.join("campaigns/friction_sdof_synthetic.json");
    let mut c: Value = serde_json::from_str(&std::fs::read_to_string(&shipped).unwrap()).unwrap();
    let text = std::fs::read_to_string(repo.join("campaigns/friction_sdof_synthetic.csv")).unwrap();
    let mut csv = format!("{column},force_N\n");
    for line in text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .step_by(2)
        .take(samples)
    {
        let (t, f) = line.split_once(',').unwrap();
        let ms = t.parse::<f64>().unwrap() * 1e3;
        csv.push_str(&format!("{ms:.6},{f}\n"));
    }
    std::fs::write(dir.join("record.csv"), csv).unwrap();
    c["experiments"][0]["data"] = json!({
        "file": "record.csv", "time_column": column, "force_column": "force_N",
        "time_scale": time_scale
    });
    c["search"] = json!({"population": 8, "generations": 1, "seed": 1,
                         "polish": {"enabled": false}});
    c["solver"]["backend"] = json!("cpu");
    let path = dir.join("c.json");
    std::fs::write(&path, c.to_string()).unwrap();
    path
}

fn hints(c: &Campaign) -> Vec<&String> {
    c.warnings
        .iter()
        .filter(|w| w.contains("\"time_scale\": 1e-3"))
        .collect()
}

#[test]
fn a_time_column_named_t_ms_read_as_seconds_is_hinted_before_the_search() {
    let dir = tempfile::tempdir().unwrap();
    let c = Campaign::load(&campaign(dir.path(), "t_ms", 1.0, 400)).unwrap();
    let h = hints(&c);
    // Both: the name, and a sample interval of 0.2 "s" that takes hundreds
    // of RK4 steps of the rig's contact.
    assert_eq!(h.len(), 2, "{:?}", c.warnings);
    assert!(
        h.iter()
            .any(|w| w.contains("'t_ms'") && w.contains("time_column"))
    );
    assert!(h.iter().any(|w| w.contains("RK4 steps")));
    // The same file read in milliseconds: no hint.
    let scaled = Campaign::load(&campaign(dir.path(), "t_ms", 1e-3, 400)).unwrap();
    assert!(hints(&scaled).is_empty(), "{:?}", scaled.warnings);
    assert!(
        !scaled
            .warnings
            .iter()
            .any(|w| w.contains("RK4 steps of the")),
        "{:?}",
        scaled.warnings
    );
}

#[test]
fn a_millisecond_column_under_another_name_is_hinted_by_its_interval() {
    let dir = tempfile::tempdir().unwrap();
    let c = Campaign::load(&campaign(dir.path(), "time", 1.0, 400)).unwrap();
    let h = hints(&c);
    assert_eq!(h.len(), 1, "{:?}", c.warnings);
    assert!(
        h[0].contains("experiments[0]") && h[0].contains("RK4 steps"),
        "{}",
        h[0]
    );
}

#[test]
fn run_prints_the_hint_before_the_search_and_keeps_it_in_the_result() {
    let dir = tempfile::tempdir().unwrap();
    let path = campaign(dir.path(), "t_ms", 1.0, 60);
    let out = dir.path().join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .current_dir(dir.path())
        .env("RIGFIT_CACHE_DIR", dir.path().join("cache"))
        .arg("run")
        .arg(&path)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    let lines: Vec<&str> = err.lines().collect();
    let hint = lines
        .iter()
        .position(|l| l.contains("warning") && l.contains("'t_ms'"))
        .unwrap_or_else(|| panic!("no hint:\n{err}"));
    let job = lines
        .iter()
        .position(|l| l.contains("steps per candidate"))
        .unwrap_or_else(|| panic!("no job line:\n{err}"));
    assert!(hint < job, "the hint came after the search began:\n{err}");
    let r: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    let kept = r["warnings"].as_array().unwrap();
    assert!(
        kept.iter().any(|w| w.as_str().unwrap().contains("'t_ms'")),
        "{kept:?}"
    );
}
