//! A hand-made series' folder: two done tests, a failed one, one never run,
//! one run with an earlier campaign, one whose result does not read, and
//! one that could not be prepared.

use std::path::{Path, PathBuf};

use serde_json::json;

use super::*;
use crate::series::manifest::GENERATOR;

const COVARIATES: [&str; 2] = ["strain_rate", "lot"];

/// Values whose shortest round-trip form is long: a cell that lost a bit
/// would read back differently.
const K_DONE: f64 = 0.1 + 0.2;
const K_DONE2: f64 = 87_791_966.899_360_69;

fn entry(id: &str, covariates: [&str; 2], error: Option<&str>) -> TestEntry {
    TestEntry {
        id: id.into(),
        campaign: PathBuf::from("campaigns").join(format!("{id}.json")),
        out: PathBuf::from("tests").join(id),
        seed: 1,
        covariates: covariates.map(String::from).to_vec(),
        source: format!("tests.csv line {id}"),
        error: error.map(String::from),
        work: 0.0,
    }
}

fn status(root: &Path, id: &str, state: TestState, error: Option<&str>) -> TestStatus {
    TestStatus {
        id: id.into(),
        state,
        error: error.map(String::from),
        campaign_sha256: file_sha256(&root.join(format!("campaigns/{id}.json"))).unwrap(),
        wall_time_s: 1.25,
        backend: Some("cpu".into()),
        device: Some("2 threads".into()),
        adapter: None,
        host: "node7".into(),
        task: Some(0),
        slurm_job: None,
        restarts: 2,
    }
}

fn write(path: &Path, text: &str) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

/// The series' folder: returns it.
fn series() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    let tests = vec![
        entry("t_done", ["10", "A"], None),
        entry("t_failed", ["100", "A"], None),
        entry("t_missing", ["200", "B"], None),
        entry("t_stale", ["300", "B"], None),
        entry("t_broken", ["400", "B"], None),
        entry(
            "t_unprepared",
            ["500", "C"],
            Some("record `r.csv` does not exist"),
        ),
        entry("t_done2", ["1000", "C"], None),
    ];
    for t in &tests {
        write(
            &root.join(&t.campaign),
            &format!("{{\"name\": \"{}\"}}\n", t.id),
        );
    }
    let manifest = Manifest {
        generator: GENERATOR.into(),
        name: "rates".into(),
        series_file: root.join("rates.json"),
        covariates: COVARIATES.map(String::from).to_vec(),
        tasks: (0..tests.len()).map(|i| vec![i]).collect(),
        tests,
    };
    manifest.write(root).unwrap();
    std::fs::create_dir_all(root.join(STATUS_DIR)).unwrap();
    for (id, state, error) in [
        ("t_done", TestState::Done, None),
        ("t_done2", TestState::Done, None),
        (
            "t_failed",
            TestState::Failed,
            Some("the rig blew up at every candidate"),
        ),
        ("t_stale", TestState::Done, None),
        ("t_broken", TestState::Done, None),
    ] {
        status(root, id, state, error).write(root).unwrap();
    }
    // The stale test's campaign changed after it ran.
    write(
        &root.join("campaigns/t_stale.json"),
        "{\"name\": \"changed\"}\n",
    );
    write(
        &root.join("tests/t_broken/result.json"),
        "{\"parameters\": [{\"name\": \"k_lin\", \"value\": \"x\"}]}",
    );
    let done = json!({
        "backend": "gpu", "device": "from the result",
        "fitness": 4.0e-5,
        "verdict": {"line": "at the noise floor", "cost_over_noise_floor": 1.0329987670287142, "flags": ["search still improving when it stopped"]},
        "experiments": [{"name": "v2", "r2": 0.9999571898743426, "cost_over_noise_floor": 1.03}],
        "parameters": [
            {"name": "m", "unit": "kg", "value": 7.9, "free": false},
            {"name": "k_lin", "unit": "N/m", "value": K_DONE, "free": true, "scale": "log", "bounds": [0.01, 10.0], "interval_95": [0.2, 0.4]},
            {"name": "c", "unit": "N·s/m", "value": 1.0 / 3.0, "free": true, "bounds": [0.0, 1.0], "interval_95": [0.25, 0.5]}
        ],
        "profiles": {"parameters": [{"name": "k_lin", "interval": [0.29, 0.31]}]},
        "warnings": ["the search was still improving", "the polish's starts ended at different costs"]
    });
    write(&root.join("tests/t_done/result.json"), &done.to_string());
    write(&root.join("tests/t_done/report.html"), "<!DOCTYPE html>");
    let done2 = json!({
        "fitness": 0.125,
        "experiments": [{"name": "a", "r2": 0.9}, {"name": "b", "r2": 0.85}],
        "parameters": [
            {"name": "k_lin", "unit": "N/m", "value": K_DONE2, "free": true, "scale": "log", "bounds": [0.01, 1.0e9], "interval_95": [8.0e7, 9.5e7]},
            {"name": "c", "unit": "N·s/m", "value": 0.5, "free": true, "interval_95": [null, 0.75]},
            {"name": "extra", "unit": "m", "value": 1.0e-7 / 3.0, "free": true}
        ]
    });
    write(&root.join("tests/t_done2/result.json"), &done2.to_string());
    dir
}

fn row<'a>(s: &'a Summary, id: &str) -> &'a SummaryRow {
    s.rows.iter().find(|r| r.id == id).unwrap()
}

#[test]
fn every_test_keeps_its_row_with_why_it_is_not_done() {
    let dir = series();
    let s = summarise(dir.path()).unwrap();
    let ids: Vec<&str> = s.rows.iter().map(|r| r.id.as_str()).collect();
    let manifest = Manifest::read(dir.path()).unwrap();
    let expected: Vec<&str> = manifest.tests.iter().map(|t| t.id.as_str()).collect();
    assert_eq!(ids, expected, "every test, in the manifest's order");
    let state = |id| row(&s, id).state;
    assert_eq!(state("t_done"), SummaryState::Done);
    assert_eq!(state("t_done2"), SummaryState::Done);
    assert_eq!(state("t_failed"), SummaryState::Failed);
    assert_eq!(state("t_missing"), SummaryState::Missing);
    assert_eq!(state("t_stale"), SummaryState::Missing);
    assert_eq!(state("t_broken"), SummaryState::Failed);
    assert_eq!(state("t_unprepared"), SummaryState::Failed);
    let error = |id| row(&s, id).error.clone().unwrap_or_default();
    assert!(
        error("t_failed").contains("blew up"),
        "{}",
        error("t_failed")
    );
    assert!(
        error("t_missing").contains("not run yet"),
        "{}",
        error("t_missing")
    );
    assert!(
        error("t_stale").starts_with("stale")
            && error("t_stale").contains("campaigns/t_stale.json"),
        "{}",
        error("t_stale")
    );
    assert!(
        error("t_broken").contains("result.json")
            && error("t_broken").contains("parameters[0].value"),
        "{}",
        error("t_broken")
    );
    assert!(
        error("t_unprepared").contains("r.csv"),
        "{}",
        error("t_unprepared")
    );
    assert!(row(&s, "t_done").error.is_none());
    // Parameters in the first done test's order, then what later ones add;
    // fixed parameters are not columns.
    let names: Vec<&str> = s.parameters.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["k_lin", "c", "extra"]);
    assert!(s.rows.iter().all(|r| r.parameters.len() == 3));
    // The runner's backend wins over the result's; R² of several
    // experiments is 1 − fitness.
    assert_eq!(row(&s, "t_done").backend.as_deref(), Some("cpu"));
    assert_eq!(row(&s, "t_done2").r2, Some(1.0 - 0.125));
    assert_eq!(row(&s, "t_done").r2, Some(0.9999571898743426));
    assert_eq!(
        row(&s, "t_done").noise_floor_ratio,
        Some(1.0329987670287142)
    );
    assert_eq!(
        row(&s, "t_done").report.as_deref(),
        Some("tests/t_done/report.html")
    );
    assert_eq!(row(&s, "t_done2").report, None);
    let text = s.to_string();
    assert_eq!(text.lines().count(), 1 + 7 + 1, "{text}");
    assert!(text.ends_with("2 done, 3 failed, 2 missing"), "{text}");
}

fn read_csv(root: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(root.join(SUMMARY_CSV)).unwrap();
    assert!(text.starts_with(CSV_MARK), "{text}");
    let mut r = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    let header = r.headers().unwrap().iter().map(String::from).collect();
    let rows = r
        .records()
        .map(|rec| rec.unwrap().iter().map(String::from).collect())
        .collect();
    (header, rows)
}

#[test]
fn csv_cells_read_back_to_the_results_bits_and_nothing_is_dropped() {
    let dir = series();
    write_summary(dir.path()).unwrap();
    let (header, rows) = read_csv(dir.path());
    let h: Vec<&str> = header.iter().map(String::as_str).collect();
    assert_eq!(
        h,
        [
            "test",
            "strain_rate",
            "lot",
            "status",
            "error",
            "k_lin",
            "k_lin.lower",
            "k_lin.upper",
            "c",
            "c.lower",
            "c.upper",
            "extra",
            "extra.lower",
            "extra.upper",
            "interval",
            "r2",
            "noise_floor_ratio",
            "warnings",
            "wall_time_s",
            "backend",
            "device",
            "adapter",
            "host",
            "restarts"
        ]
    );
    assert_eq!(rows.len(), 7, "no test dropped");
    let get = |id: &str, col: &str| -> String {
        let r = rows.iter().find(|r| r[0] == id).unwrap();
        r[h.iter().position(|c| *c == col).unwrap()].clone()
    };
    let bits = |id: &str, col: &str| get(id, col).parse::<f64>().unwrap().to_bits();
    assert_eq!(bits("t_done", "k_lin"), K_DONE.to_bits());
    assert_eq!(bits("t_done", "c"), (1.0f64 / 3.0).to_bits());
    assert_eq!(bits("t_done2", "k_lin"), K_DONE2.to_bits());
    assert_eq!(bits("t_done2", "extra"), (1.0e-7f64 / 3.0).to_bits());
    // k_lin's profile interval wins over its covariance interval; c has none.
    assert_eq!(
        (get("t_done", "k_lin.lower"), get("t_done", "k_lin.upper")),
        ("0.29".into(), "0.31".into())
    );
    assert_eq!(
        (get("t_done", "c.lower"), get("t_done", "c.upper")),
        ("0.25".into(), "0.5".into())
    );
    assert_eq!(get("t_done", "interval"), "profile; covariance for c");
    assert_eq!(get("t_done2", "interval"), "covariance");
    assert_eq!(
        (get("t_done2", "c.lower"), get("t_done2", "c.upper")),
        (String::new(), "0.75".into())
    );
    assert_eq!(
        get("t_done", "extra"),
        "",
        "a parameter the test lacks is an empty cell"
    );
    assert_eq!(
        get("t_done", "warnings"),
        "the search was still improving | the polish's starts ended at different costs"
    );
    assert_eq!(
        get("t_done", "noise_floor_ratio").parse::<f64>().unwrap(),
        1.0329987670287142
    );
    assert_eq!(
        (
            get("t_done", "host"),
            get("t_done", "restarts"),
            get("t_done", "wall_time_s")
        ),
        ("node7".into(), "2".into(), "1.25".into())
    );
    for (id, status) in [
        ("t_failed", "failed"),
        ("t_missing", "missing"),
        ("t_stale", "missing"),
        ("t_broken", "failed"),
        ("t_unprepared", "failed"),
    ] {
        assert_eq!(get(id, "status"), status, "{id}");
        assert!(!get(id, "error").is_empty(), "{id} has its error");
        assert_eq!(get(id, "k_lin"), "", "{id}");
    }
    assert_eq!(
        (get("t_done2", "strain_rate"), get("t_done2", "lot")),
        ("1000".into(), "C".into())
    );
}

#[test]
fn the_page_plots_each_parameter_against_each_numeric_covariate() {
    let dir = series();
    write_summary(dir.path()).unwrap();
    let html = std::fs::read_to_string(dir.path().join(SUMMARY_HTML)).unwrap();
    assert!(crate::report::html::is_rigfit_report(
        &dir.path().join(SUMMARY_HTML)
    ));
    // strain_rate is a number in every test, lot is not: 1 × 3 figures.
    assert_eq!(html.matches("<svg class=\"scatter\"").count(), 3, "{html}");
    assert!(html.contains("<h3>Against strain_rate</h3>") && !html.contains("Against lot"));
    assert!(
        html.contains("aria-label=\"k_lin (N/m) against strain_rate: 2 of 7 tests"),
        "{html}"
    );
    // Each done test with an interval has its bar; the open side of c's
    // interval in t_done2 is dashed.
    let figures: Vec<&str> = html
        .split("<figure class=\"series-plot\">")
        .skip(1)
        .collect();
    let bars =
        |f: &str| f.matches("<line class=\"errbar").count() - f.matches("errbar cap").count();
    assert_eq!(
        figures.iter().map(|f| bars(f)).collect::<Vec<_>>(),
        [2, 2, 0]
    );
    assert_eq!(
        figures
            .iter()
            .map(|f| f.matches("<circle").count())
            .collect::<Vec<_>>(),
        [2, 2, 1]
    );
    assert!(figures[1].contains("errbar open"));
    // Every point lies inside its plot, also the one beyond the first
    // test's bounds.
    for f in &figures {
        let ys: Vec<f64> = f
            .split("<circle class=\"pt\" cx=\"")
            .skip(1)
            .map(|c| {
                c.split("cy=\"")
                    .nth(1)
                    .unwrap()
                    .split('"')
                    .next()
                    .unwrap()
                    .parse()
                    .unwrap()
            })
            .collect();
        assert!(ys.iter().all(|y| (12.0..=216.0).contains(y)), "{ys:?}");
    }
    assert!(html.contains("<a href=\"tests/t_done/report.html\">t_done</a>"));
    for id in [
        "t_failed",
        "t_missing",
        "t_stale",
        "t_broken",
        "t_unprepared",
    ] {
        assert!(
            html.contains(&format!("<th scope=\"row\">{id}</th>")),
            "{id}"
        );
    }
    assert!(html.contains("<tr class=\"failed\">") && html.contains("<tr class=\"missing\">"));
    assert!(html.contains("blew up at every candidate"));
}

#[test]
fn a_foreign_summary_is_refused_and_ours_is_replaced() {
    let dir = series();
    let root = dir.path();
    let csv = root.join(SUMMARY_CSV);
    write(&csv, "test,k\nmine,1\n");
    let e = write_summary(root).unwrap_err().to_string();
    assert!(
        e.contains("summary.csv") && e.contains("not written by rigfit"),
        "{e}"
    );
    assert_eq!(std::fs::read_to_string(&csv).unwrap(), "test,k\nmine,1\n");
    assert!(
        !root.join(SUMMARY_HTML).exists(),
        "nothing written when one is refused"
    );
    std::fs::remove_file(&csv).unwrap();
    write_summary(root).unwrap();
    // A second summary replaces the first (a test done since shows).
    status(root, "t_missing", TestState::Failed, Some("later"))
        .write(root)
        .unwrap();
    let s = write_summary(root).unwrap();
    assert_eq!(s.count(SummaryState::Missing), 1);
    let (_, rows) = read_csv(root);
    assert!(
        rows.iter()
            .any(|r| r[0] == "t_missing" && r.contains(&"later".to_string()))
    );
    let html = root.join(SUMMARY_HTML);
    write(&html, "<html>mine</html>");
    let e = write_summary(root).unwrap_err().to_string();
    assert!(e.contains("summary.html"), "{e}");
    assert_eq!(std::fs::read_to_string(&html).unwrap(), "<html>mine</html>");
    #[cfg(unix)]
    {
        std::fs::remove_file(&html).unwrap();
        std::fs::remove_file(&csv).unwrap();
        let elsewhere = root.join("elsewhere.csv");
        write(&elsewhere, &format!("{CSV_MARK} but not here\n"));
        std::os::unix::fs::symlink(&elsewhere, &csv).unwrap();
        assert!(write_summary(root).is_err(), "a link is never replaced");
        assert!(
            std::fs::symlink_metadata(&csv)
                .unwrap()
                .file_type()
                .is_symlink()
        );
    }
}
