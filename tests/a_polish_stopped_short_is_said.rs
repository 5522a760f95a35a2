//! A polish stopped by its iteration limit says so: the shipped example run
//! briefly (48 × 4) with a polish of 2 iterations ends with the polish short
//! of convergence, and the printed summary starts with a verdict that flags
//! it, the polish line says it, and result.json carries the verdict, the flag
//! and a warning that says what to raise.

use std::path::Path;
use std::process::Command;

use serde_json::{Value, json};

#[test]
fn a_polish_stopped_at_its_iteration_limit_is_flagged_in_the_summary_and_result() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns");
    let mut v: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("aa2024_t3_synthetic.json")).unwrap(),
    )
    .unwrap();
    let csv = dir.join("aa2024_t3_v2_synthetic.csv");
    v["experiments"][0]["data"]["file"] = Value::String(csv.display().to_string());
    v["search"] = json!({
        "population": 48, "generations": 4, "seed": 3,
        "polish": {"starts": 4, "max_iterations": 2}
    });
    v["solver"]["backend"] = json!("cpu");
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("c.json");
    std::fs::write(&path, v.to_string()).unwrap();
    let out = tmp.path().join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .arg("run")
        .arg(&path)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    println!("{stdout}\n{}", String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success());

    let r: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    assert_eq!(r["polish"]["stop"], "max_iterations", "{}", r["polish"]);
    let verdict = &r["verdict"];
    let flags: Vec<&str> = verdict["flags"]
        .as_array()
        .unwrap_or_else(|| panic!("no verdict in result.json: {verdict}"))
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    assert!(
        flags.contains(&"polish stopped at its iteration limit"),
        "{flags:?}"
    );
    let line = verdict["line"].as_str().unwrap();
    assert!(line.contains("parameters determined"), "{line}");
    assert!(
        line.contains("polish stopped at its iteration limit"),
        "{line}"
    );
    let free = r["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| p["free"] == true)
        .count();
    assert_eq!(verdict["free"], free);
    let warning = r["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(Value::as_str)
        .find(|w| w.starts_with("the polish stopped at its iteration limit (2)"))
        .unwrap_or_else(|| panic!("no warning in {}", r["warnings"]));
    assert!(warning.contains("\"max_iterations\": 60"), "{warning}");

    // The printed summary: the verdict first, the polish line says it.
    let verdict_line = stdout
        .lines()
        .find(|l| l.starts_with("verdict: "))
        .unwrap_or_else(|| panic!("no verdict line in {stdout}"));
    assert_eq!(verdict_line, format!("verdict: {line}"));
    let after: Vec<&str> = stdout
        .lines()
        .skip_while(|l| !l.starts_with("verdict: "))
        .collect();
    // At the top: the summary's heading (campaign — stop reason) follows it.
    assert!(after[1].starts_with("aa2024-t3-synthetic — "), "{stdout}");
    assert!(
        after
            .iter()
            .any(|l| l.contains("polish:") && l.contains("stopped at its iteration limit")),
        "{stdout}"
    );
    assert!(
        after
            .iter()
            .any(|l| l.contains("warning: the polish stopped at its iteration limit")),
        "{stdout}"
    );
}
