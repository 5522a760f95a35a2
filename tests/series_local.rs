//! `rigfit series` run on this machine: every test is the job `rigfit run`
//! runs on its campaign file, to the same bits; tests that cannot run are
//! kept with their error; a second run skips what is done; SIGUSR1 (Slurm's
//! warning before a time limit) stops the tests with their checkpoints, and
//! the same command resumes them to the bits of an uninterrupted run; bad
//! series files and folders are refused naming the file and the place.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn rigfit(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(args)
        .current_dir(dir)
        .env_remove("RIGFIT_ADAPTER")
        .output()
        .expect("rigfit runs")
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

fn json(path: &Path) -> serde_json::Value {
    let t = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&t).unwrap()
}

/// A series of the shipped tensile campaign in `dir`: `rows` after the
/// header `test,record,specimen,rate_mps,max.v2.k_lin`, the search made
/// small by `search`.
fn series(dir: &Path, rows: &[&str], search: &str) -> PathBuf {
    let campaign = repo().join("campaigns/aa2024_t3_synthetic.json");
    let mut table = String::from("test,record,specimen,rate_mps,max.v2.k_lin\n");
    for r in rows {
        table.push_str(r);
        table.push('\n');
    }
    std::fs::write(dir.join("tests.csv"), table).unwrap();
    let file = dir.join("s.series.json");
    std::fs::write(
        &file,
        format!(
            r#"{{"name": "repeats", "campaign": "{}", "tests": "tests.csv", "search": {search}}}"#,
            campaign.display()
        ),
    )
    .unwrap();
    file
}

fn record() -> String {
    repo()
        .join("campaigns/aa2024_t3_v2_synthetic.csv")
        .display()
        .to_string()
}

/// Runs test `id`'s campaign of the series in `root` with `rigfit run` and
/// checks that the series' job gave the same bits.
fn same_as_its_rigfit_run(d: &Path, root: &Path, id: &str) {
    let campaign = root.join(format!("campaigns/{id}.json"));
    let alone = d.join(format!("alone-{id}"));
    let o = rigfit(
        &[
            "-q",
            "run",
            campaign.to_str().unwrap(),
            "--backend",
            "cpu",
            "--out",
            alone.to_str().unwrap(),
        ],
        d,
    );
    assert!(o.status.success(), "{}", text(&o));
    let a = json(&alone.join("result.json"));
    let b = json(&root.join(format!("tests/{id}/result.json")));
    assert_eq!(
        a["params"], b["params"],
        "{id}: the series' job differs from its rigfit run"
    );
    assert_eq!(a["fitness"], b["fitness"]);
}

const SMALL: &str = r#"{"population": 24, "generations": 4, "profiles": false}"#;

#[test]
fn each_test_is_its_own_rigfit_run_and_failures_are_kept() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("broken.csv"), "t_s,force_N\n0,1\nabc,2\n").unwrap();
    let rec = record();
    let rows = [
        format!("a1,{rec},A1,2.0,"),
        format!("a2,{rec},A2,2.0,2e8"),
        "gone,missing.csv,A3,2.0,".to_string(),
        "bad,broken.csv,A4,2.0,".to_string(),
    ];
    let rows: Vec<&str> = rows.iter().map(String::as_str).collect();
    let file = series(d, &rows, SMALL);
    let out = rigfit(
        &[
            "series",
            file.to_str().unwrap(),
            "--out",
            "S",
            "--backend",
            "cpu",
        ],
        d,
    );
    assert_eq!(out.status.code(), Some(1), "{}", text(&out));
    let root = d.join("S");
    // Seeds: the campaign's (1) plus the row's index; the bound written in.
    let a2 = json(&root.join("campaigns/a2.json"));
    assert_eq!(a2["search"]["seed"], 2);
    assert_eq!(a2["experiments"][0]["params"]["k_lin"]["max"], 2e8);
    for id in ["a1", "a2"] {
        let status = json(&root.join(format!("status/{id}.json")));
        assert_eq!(status["state"], "done", "{id}: {status}");
        same_as_its_rigfit_run(d, &root, id);
    }
    let gone = json(&root.join("status/gone.json"));
    assert_eq!(gone["state"], "failed");
    assert!(
        gone["error"].as_str().unwrap().contains("missing.csv"),
        "{gone}"
    );
    let bad = json(&root.join("status/bad.json"));
    assert_eq!(bad["state"], "failed");
    let e = bad["error"].as_str().unwrap();
    assert!(e.contains("broken.csv:3") && e.contains("abc"), "{e}");

    // Again: the done tests are skipped, the failed ones tried again.
    let again = rigfit(
        &[
            "series",
            file.to_str().unwrap(),
            "--out",
            "S",
            "--backend",
            "cpu",
        ],
        d,
    );
    assert_eq!(again.status.code(), Some(1), "{}", text(&again));
    let t = text(&again);
    assert!(
        t.contains("a1: done before, skipped") && t.contains("a2: done before, skipped"),
        "{t}"
    );
    assert!(t.contains("bad: FAILED"), "{t}");
}

#[cfg(unix)]
#[test]
fn sigusr1_keeps_checkpoints_and_the_same_command_resumes_to_the_same_bits() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let rec = record();
    let rows = [format!("long,{rec},A1,2.0,")];
    let rows: Vec<&str> = rows.iter().map(String::as_str).collect();
    let search = r#"{"population": 64, "generations": 400, "stall_generations": 100000, "checkpoint_every": 1, "profiles": false}"#;
    let file = series(d, &rows, search);
    let args = [
        "-q",
        "series",
        file.to_str().unwrap(),
        "--out",
        "S",
        "--backend",
        "cpu",
    ];
    let child = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(args)
        .current_dir(d)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let checkpoint = d.join("S/tests/long/checkpoint.json");
    let start = std::time::Instant::now();
    while !checkpoint.exists() {
        assert!(start.elapsed().as_secs() < 120, "no checkpoint appeared");
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    std::thread::sleep(std::time::Duration::from_millis(300));
    let pid = child.id().to_string();
    let killed = Command::new("kill").args(["-USR1", &pid]).status().unwrap();
    assert!(killed.success());
    let out = child.wait_with_output().unwrap();
    assert_eq!(
        out.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let status = json(&d.join("S/status/long.json"));
    assert_eq!(status["state"], "interrupted", "{status}");
    assert!(checkpoint.exists());
    let resumed = rigfit(&args, d);
    assert!(resumed.status.success(), "{}", text(&resumed));
    same_as_its_rigfit_run(d, &d.join("S"), "long");
}

#[test]
fn bad_series_files_and_folders_are_refused_with_the_place() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let rec = record();
    let rows = [format!("a1,{rec},A1,2.0,")];
    let rows: Vec<&str> = rows.iter().map(String::as_str).collect();
    let file = series(d, &rows, SMALL);
    let f = file.to_str().unwrap();

    // An unknown key, named with its path.
    std::fs::write(
        d.join("typo.series.json"),
        r#"{"name": "x", "campaigns": ["a.json"], "serach": {}}"#,
    )
    .unwrap();
    let o = rigfit(&["series", "typo.series.json"], d);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        text(&o).contains("typo.series.json") && text(&o).contains("serach"),
        "{}",
        text(&o)
    );

    // A bad cell, named with its line and column.
    std::fs::write(d.join("tests.csv"), "test,record,seed\nt1,x.csv,-4\n").unwrap();
    let o = rigfit(&["series", f], d);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("line 2, column \"seed\""), "{}", text(&o));

    // A folder that holds something else is never written into.
    let rows = [format!("a1,{rec},A1,2.0,")];
    let rows: Vec<&str> = rows.iter().map(String::as_str).collect();
    let file = series(d, &rows, SMALL);
    let f = file.to_str().unwrap();
    std::fs::create_dir(d.join("busy")).unwrap();
    std::fs::write(d.join("busy/notes.txt"), "mine").unwrap();
    let o = rigfit(&["series", f, "--out", "busy"], d);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("not a series' folder"), "{}", text(&o));
    assert_eq!(
        std::fs::read_to_string(d.join("busy/notes.txt")).unwrap(),
        "mine"
    );

    // A file planted in a series' campaigns folder is never replaced.
    let o = rigfit(&["series", f, "--out", "S", "--backend", "cpu"], d);
    assert!(o.status.success(), "{}", text(&o));
    std::fs::write(d.join("S/campaigns/a1.json"), "{\"mine\": true}").unwrap();
    let o = rigfit(&["series", f, "--out", "S", "--backend", "cpu"], d);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        text(&o).contains("not written by rigfit series"),
        "{}",
        text(&o)
    );
    assert_eq!(
        std::fs::read_to_string(d.join("S/campaigns/a1.json")).unwrap(),
        "{\"mine\": true}"
    );

    // A task that is not there names the tasks that are.
    let o = rigfit(&["series", "S", "--task", "7"], d);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("tasks 0 to 0"), "{}", text(&o));
}
