//! The summary of a series holds each test's parameters exactly as the
//! test's `result.json` gives them: two real tiny jobs run by the binary in
//! a series' folder laid out by hand, then summarised.

use std::path::{Path, PathBuf};
use std::process::Command;

use rigfit::series::summary::{CSV_MARK, write_summary};
use rigfit::series::{Manifest, SUMMARY_CSV, SUMMARY_HTML, TestEntry, TestState, TestStatus};
use serde_json::{Value, json};
use sha2::Digest as _;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn sha256(path: &Path) -> String {
    let digest = sha2::Sha256::digest(std::fs::read(path).unwrap());
    digest.iter().map(|b| format!("{b:02x}")).collect()
}

/// The shipped campaign as a test's campaign: its record by absolute path,
/// a tiny search with seed `seed`, profiles on or off.
fn campaign(id: &str, seed: u64, profiles: bool) -> Value {
    let shipped = repo().join("campaigns/aa2024_t3_synthetic.json");
    let mut c: Value = serde_json::from_str(&std::fs::read_to_string(&shipped).unwrap()).unwrap();
    let record = repo()
        .join("campaigns")
        .join(c["experiments"][0]["data"]["file"].as_str().unwrap());
    c["experiments"][0]["data"]["file"] = json!(record);
    c["search"] = json!({"population": 32, "generations": 4, "seed": seed, "profiles": profiles});
    c["output"] = json!(format!("../tests/{id}"));
    c
}

#[test]
fn the_summary_holds_each_tests_parameters_to_the_bit() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    for sub in ["campaigns", "status"] {
        std::fs::create_dir_all(root.join(sub)).unwrap();
    }
    let plan = [("slow", "2.0", 3, true), ("fast", "2.5", 4, false)];
    let mut tests = Vec::new();
    for (id, velocity, seed, profiles) in plan {
        let file = root.join(format!("campaigns/{id}.json"));
        std::fs::write(
            &file,
            serde_json::to_string_pretty(&campaign(id, seed, profiles)).unwrap(),
        )
        .unwrap();
        let out = root.join("tests").join(id);
        let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
            .arg("run")
            .arg(&file)
            .arg("--out")
            .arg(&out)
            .args(["--backend", "cpu"])
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{id}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        tests.push(TestEntry {
            id: id.into(),
            campaign: PathBuf::from(format!("campaigns/{id}.json")),
            out: PathBuf::from(format!("tests/{id}")),
            seed,
            covariates: vec![velocity.into()],
            source: format!("by hand: {id}"),
            error: None,
            work: 0.0,
        });
        TestStatus {
            id: id.into(),
            state: TestState::Done,
            error: None,
            campaign_sha256: sha256(&file),
            wall_time_s: 0.5,
            backend: Some("cpu".into()),
            device: None,
            adapter: None,
            host: "here".into(),
            task: None,
            slurm_job: None,
            restarts: 0,
        }
        .write(root)
        .unwrap();
    }
    Manifest {
        generator: "rigfit series".into(),
        name: "velocities".into(),
        series_file: root.join("velocities.json"),
        covariates: vec!["velocity".into()],
        tasks: vec![vec![0], vec![1]],
        tests,
    }
    .write(root)
    .unwrap();

    let summary = write_summary(root).unwrap();
    assert!(
        summary.to_string().ends_with("2 done, 0 failed, 0 missing"),
        "{summary}"
    );
    let text = std::fs::read_to_string(root.join(SUMMARY_CSV)).unwrap();
    assert!(text.starts_with(CSV_MARK));
    let mut reader = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    let rows: Vec<Vec<String>> = reader
        .records()
        .map(|r| r.unwrap().iter().map(String::from).collect())
        .collect();
    assert_eq!(rows.len(), 2);
    let column = |name: &str| {
        header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
    };
    let bits = |cell: &str| {
        cell.parse::<f64>()
            .unwrap_or_else(|_| panic!("{cell:?} is no number"))
            .to_bits()
    };
    let mut free = 0;
    for (row, (id, _, _, profiles)) in rows.iter().zip(plan) {
        assert_eq!(row[0], id);
        assert_eq!(row[column("status")], "done");
        let result: Value = serde_json::from_str(
            &std::fs::read_to_string(root.join(format!("tests/{id}/result.json"))).unwrap(),
        )
        .unwrap();
        free = 0;
        for p in result["parameters"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|p| p["free"] == json!(true))
        {
            free += 1;
            let name = p["name"].as_str().unwrap();
            assert_eq!(
                bits(&row[column(name)]),
                p["value"].as_f64().unwrap().to_bits(),
                "{id} {name}"
            );
            let profile = result["profiles"]["parameters"]
                .as_array()
                .and_then(|ps| ps.iter().find(|q| q["name"] == json!(name)))
                .map(|q| q["interval"].clone());
            assert_eq!(profile.is_some(), profiles, "{id}: profiles as asked");
            let interval = profile.unwrap_or_else(|| p["interval_95"].clone());
            for (end, i) in [("lower", 0), ("upper", 1)] {
                let cell = &row[column(&format!("{name}.{end}"))];
                match interval[i].as_f64() {
                    Some(v) => assert_eq!(bits(cell), v.to_bits(), "{id} {name}.{end}"),
                    None => assert_eq!(cell, "", "{id} {name}.{end}: an open side is empty"),
                }
            }
        }
        assert_eq!(
            row[column("interval")],
            if profiles { "profile" } else { "covariance" }
        );
        assert_eq!(
            bits(&row[column("r2")]),
            result["experiments"][0]["r2"].as_f64().unwrap().to_bits()
        );
        assert_eq!(
            bits(&row[column("noise_floor_ratio")]),
            result["verdict"]["cost_over_noise_floor"]
                .as_f64()
                .unwrap()
                .to_bits()
        );
    }
    assert!(free > 0);
    let html = std::fs::read_to_string(root.join(SUMMARY_HTML)).unwrap();
    assert_eq!(
        html.matches("<svg class=\"scatter\"").count(),
        free,
        "one figure per free parameter against velocity"
    );
    for (id, ..) in plan {
        assert!(
            html.contains(&format!("<a href=\"tests/{id}/report.html\">{id}</a>")),
            "{id}"
        );
    }
}
