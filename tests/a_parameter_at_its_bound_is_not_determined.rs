//! A fit whose range for a parameter stops short of the truth says so: the
//! shipped example with the load cell's stiffness bounded below its true value
//! (8.4e9 N/m, bound 6e9) leaves k1 at its upper bound, and the result marks it
//! `at_bound: "upper"`, not determined, with an interval open on the bound's
//! side, and warns naming the bound to widen. The genes inside their ranges
//! keep two-sided intervals.

use std::path::Path;

use rigfit::campaign::Campaign;
use rigfit::eval::CpuEvaluator;
use rigfit::job::{self, JobOptions};
use rigfit::search::AtBound;
use serde_json::{Value, json};

#[test]
fn a_parameter_bounded_below_its_truth_is_flagged_at_its_bound() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns");
    let mut v: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("aa2024_t3_synthetic.json")).unwrap(),
    )
    .unwrap();
    v["params"]["k1"] = json!({"min": 2e9, "max": 6e9, "scale": "log"});
    let csv = dir.join("aa2024_t3_v2_synthetic.csv");
    v["experiments"][0]["data"]["file"] = Value::String(csv.display().to_string());
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("c.json");
    std::fs::write(&path, v.to_string()).unwrap();
    let mut c = Campaign::load(&path).unwrap();
    c.search.population = 128;
    c.search.generations = 30;
    let out = tmp.path().join("out");
    let opts = JobOptions::quiet(&out);
    let s = job::run(&c, Box::new(CpuEvaluator::new(c.problem.clone(), 0)), &opts).unwrap();

    let k1 = s.parameters.iter().find(|p| p.name == "k1").unwrap();
    println!(
        "k1 = {:e}, interval {:?}, note {:?}",
        k1.value, k1.interval_95, k1.uncertainty_note
    );
    assert!(k1.value > 0.99 * 6e9, "k1 = {:e}", k1.value);
    assert_eq!(k1.at_bound, Some(AtBound::Upper));
    assert_eq!(k1.determined, Some(false));
    if let Some([lo, hi]) = k1.interval_95 {
        assert!(lo < k1.value && lo.is_finite(), "{lo}");
        assert_eq!(hi, f64::INFINITY, "open on the bound's side");
    }
    assert!(
        s.warnings
            .iter()
            .any(|w| w.starts_with("k1 = ") && w.contains("upper bound 6.000000e9")),
        "{:?}",
        s.warnings
    );
    // Inside their ranges: no flag, two-sided intervals.
    for p in s.parameters.iter().filter(|p| p.free && p.name != "k1") {
        if p.at_bound.is_none()
            && let Some([lo, hi]) = p.interval_95
        {
            assert!(lo.is_finite() && hi.is_finite(), "{}: {lo} {hi}", p.name);
        }
    }
    // result.json says the same, the open end as null.
    let r: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    let k1 = r["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "k1")
        .unwrap();
    assert_eq!(k1["at_bound"], "upper");
    assert_eq!(k1["determined"], false);
    if !k1["interval_95"].is_null() {
        assert!(k1["interval_95"][1].is_null(), "{k1}");
    }
}

/// The lower side as the upper: the load cell's stiffness bounded above its
/// true value (bound 1.2e10) leaves k1 at its lower bound, a log-scale gene,
/// and its interval is open below: `null` in result.json and `open` in the
/// printed summary, never 0 and `-100.000 %`.
#[test]
fn a_parameter_at_its_lower_bound_has_an_interval_open_below() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns");
    let mut v: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("aa2024_t3_synthetic.json")).unwrap(),
    )
    .unwrap();
    v["params"]["k1"] = json!({"min": 1.2e10, "max": 3e10, "scale": "log"});
    let csv = dir.join("aa2024_t3_v2_synthetic.csv");
    v["experiments"][0]["data"]["file"] = Value::String(csv.display().to_string());
    v["search"] = json!({"population": 128, "generations": 30, "seed": 1});
    v["solver"]["backend"] = json!("cpu");
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("c.json");
    std::fs::write(&path, v.to_string()).unwrap();
    let out = tmp.path().join("out");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .arg("run")
        .arg(&path)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    println!("{stdout}");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    let k1 = r["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "k1")
        .unwrap();
    assert_eq!(k1["at_bound"], "lower", "{k1}");
    assert_eq!(k1["determined"], false);
    let iv = &k1["interval_95"];
    assert!(iv[0].is_null(), "open below: {k1}");
    assert!(
        iv[1].as_f64().unwrap() > k1["value"].as_f64().unwrap(),
        "{k1}"
    );
    let row = stdout
        .lines()
        .find(|l| l.trim_start().starts_with("k1 "))
        .unwrap_or_else(|| panic!("no k1 row in {stdout}"));
    assert!(row.contains("open / +"), "{row}");
    assert!(!row.contains("-100.000 %"), "{row}");
    assert!(row.contains("at its lower bound"), "{row}");
}
