//! A record in the wrong unit is refused when the campaign is read, before
//! any search, with the key that fixes it: a time column in milliseconds
//! (3 of 2 501 samples in the fit window), a force in kN against a rig in N;
//! a record starting at t = 1000 s is warned of and read without the
//! step-doubling estimate integrating its 1000 s prologue. The shipped
//! example passes as it is.

use std::path::{Path, PathBuf};
use std::process::Command;

use rigfit::campaign::Campaign;
use serde_json::Value;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `campaigns/<csv>` with its time times `ft`, its second column times
/// `ff` and `shift` added to its time, written to `dir/<name>`.
fn record(dir: &Path, csv: &str, name: &str, ft: f64, ff: f64, shift: f64) {
    let text = std::fs::read_to_string(repo().join("campaigns").join(csv)).unwrap();
    let mut out = String::new();
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        let cells: Vec<&str> = line.split(',').collect();
        match (cells[0].parse::<f64>(), cells[1].parse::<f64>()) {
            (Ok(t), Ok(f)) => out.push_str(&format!("{:e},{:e}\n", t * ft + shift, f * ff)),
            _ => out.push_str(&format!("{line}\n")),
        }
    }
    std::fs::write(dir.join(name), out).unwrap();
}

/// The shipped campaign `campaign` reading `file` for its experiment 0, with
/// `data` keys added, written to `dir/c.json`.
fn campaign(dir: &Path, campaign: &str, file: &str, data: &[(&str, f64)]) -> PathBuf {
    let text = std::fs::read_to_string(repo().join("campaigns").join(campaign)).unwrap();
    let mut raw: Value = serde_json::from_str(&text).unwrap();
    let d = &mut raw["experiments"][0]["data"];
    d["file"] = file.into();
    for (k, v) in data {
        d[*k] = (*v).into();
    }
    for x in raw["experiments"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .skip(1)
    {
        let f = x["data"]["file"].as_str().unwrap().to_string();
        std::fs::copy(repo().join("campaigns").join(&f), dir.join(&f)).unwrap();
    }
    raw["output"] = "out".into();
    let path = dir.join("c.json");
    std::fs::write(&path, raw.to_string()).unwrap();
    path
}

const EXAMPLE: &str = "aa2024_t3_synthetic.json";
const EXAMPLE_CSV: &str = "aa2024_t3_v2_synthetic.csv";

#[test]
fn a_time_column_in_milliseconds_is_refused_with_its_time_scale() {
    let dir = tempfile::tempdir().unwrap();
    record(dir.path(), EXAMPLE_CSV, "ms.csv", 1e3, 1.0, 0.0);
    let path = campaign(dir.path(), EXAMPLE, "ms.csv", &[]);
    let err = Campaign::load(&path).unwrap_err().to_string();
    assert!(err.contains("experiments[0].fit_window"), "{err}");
    assert!(err.contains("3 of the record's 2501 samples"), "{err}");
    assert!(err.contains("\"time_scale\": 1e-3"), "{err}");
    // The same record read with its scale is the shipped one.
    let path = campaign(dir.path(), EXAMPLE, "ms.csv", &[("time_scale", 1e-3)]);
    let c = Campaign::load(&path).unwrap();
    assert_eq!(c.problem.experiments[0].window.len(), 2501);
    assert!(c.warnings.is_empty(), "{:?}", c.warnings);
}

#[test]
fn a_force_in_kilonewtons_is_refused_with_its_scale() {
    let dir = tempfile::tempdir().unwrap();
    record(dir.path(), EXAMPLE_CSV, "kn.csv", 1.0, 1e-3, 0.0);
    let path = campaign(dir.path(), EXAMPLE, "kn.csv", &[]);
    let err = Campaign::load(&path).unwrap_err().to_string();
    assert!(err.contains("experiments[0].data"), "{err}");
    assert!(err.contains("smaller than the rig produces"), "{err}");
    assert!(
        err.contains("in kN") && err.contains("\"scale\": 1e3"),
        "{err}"
    );
    let path = campaign(dir.path(), EXAMPLE, "kn.csv", &[("scale", 1e3)]);
    let c = Campaign::load(&path).unwrap();
    assert!(c.warnings.is_empty(), "{:?}", c.warnings);
    // A thousand times too large (a force in mN) is refused as well.
    record(dir.path(), EXAMPLE_CSV, "mn.csv", 1.0, 1e3, 0.0);
    let path = campaign(dir.path(), EXAMPLE, "mn.csv", &[]);
    let err = Campaign::load(&path).unwrap_err().to_string();
    assert!(
        err.contains("larger") && err.contains("\"scale\": 1e-3"),
        "{err}"
    );
}

#[test]
fn the_shipped_records_pass_without_a_word() {
    for name in [
        EXAMPLE,
        "bearing_2dof_synthetic.json",
        "bearing_2dof_channels_synthetic.json",
        "emps_open_loop.json",
        "emps_closed_loop.json",
        "quarter_car_channels_synthetic.json",
        "tensile4_three_rates_synthetic.json",
    ] {
        let c = Campaign::load(&repo().join("campaigns").join(name)).unwrap();
        assert!(c.warnings.is_empty(), "{name}: {:?}", c.warnings);
    }
}

#[test]
fn a_record_starting_at_1000_s_is_warned_of_and_read_without_its_prologue_estimated() {
    let dir = tempfile::tempdir().unwrap();
    let bearing = "bearing_2dof_synthetic.json";
    record(
        dir.path(),
        "bearing_2dof_x_synthetic.csv",
        "late.csv",
        1.0,
        1.0,
        1000.0,
    );
    let path = campaign(dir.path(), bearing, "late.csv", &[]);
    let c = Campaign::load(&path).unwrap();
    let w = c.warnings.join("\n");
    assert!(
        w.contains("starts at t = 1000 s") && w.contains("\"offset\": -1000"),
        "{w}"
    );
    // The step-doubling estimate would integrate 3.9e6 steps from rest for
    // each of its runs (54 s at 2e7 allowed per run): it is not taken.
    assert!(c.solver.estimated_error[0].is_none(), "{}", c.solver.note);
    assert!(
        c.solver.note.contains("not estimated for 'hx'"),
        "{}",
        c.solver.note
    );
    let shipped = Campaign::load(&repo().join("campaigns").join(bearing)).unwrap();
    assert!(shipped.solver.estimated_error[0].is_some());
}

#[test]
fn rigfit_check_refuses_a_time_column_in_milliseconds() {
    let dir = tempfile::tempdir().unwrap();
    record(dir.path(), EXAMPLE_CSV, "ms.csv", 1e3, 1.0, 0.0);
    let path = campaign(dir.path(), EXAMPLE, "ms.csv", &[]);
    let out = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(["check", "--no-measure"])
        .arg(&path)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{err}");
    assert!(
        err.contains("c.json") && err.contains("fit_window"),
        "{err}"
    );
    assert!(err.contains("\"time_scale\": 1e-3"), "{err}");
}
