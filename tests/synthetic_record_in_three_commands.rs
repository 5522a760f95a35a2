//! The README's "Your own rig in three commands", run as written: its rig, its
//! campaign and its true values taken from the README's own blocks, its
//! commands run in order in an empty folder (`simulate` with noise, `run`,
//! then the result read), and the fit holding each true value inside the 95 %
//! interval it reports, at the noise floor of the record it was made with.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The fenced blocks of the README's section `heading`, as (language, text).
fn blocks(heading: &str) -> Vec<(String, String)> {
    let readme = std::fs::read_to_string(repo().join("README.md")).unwrap();
    let start = readme
        .find(&format!("\n## {heading}\n"))
        .unwrap_or_else(|| panic!("README has no section '{heading}'"));
    let section = &readme[start + 1..];
    let end = section[3..].find("\n## ").map_or(section.len(), |e| e + 3);
    let mut out = Vec::new();
    let mut open: Option<(String, String)> = None;
    for line in section[..end].lines() {
        match (&mut open, line.strip_prefix("```")) {
            (None, Some(lang)) => open = Some((lang.trim().to_string(), String::new())),
            (Some(_), Some(_)) => out.push(open.take().unwrap()),
            (Some((_, text)), None) => {
                text.push_str(line);
                text.push('\n');
            }
            (None, None) => {}
        }
    }
    out
}

/// Runs one line of the README's shell block in `dir`; `cat FILE` is read
/// here. Returns what the line printed.
fn run_line(dir: &Path, line: &str) -> String {
    let words: Vec<&str> = line.split_whitespace().collect();
    match words[0] {
        "rigfit" => {
            let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
                .args(&words[1..])
                .current_dir(dir)
                .output()
                .unwrap();
            let text = String::from_utf8_lossy(&o.stdout).into_owned();
            println!("$ {line}\n{text}{}", String::from_utf8_lossy(&o.stderr));
            assert!(o.status.success(), "`{line}` failed");
            text
        }
        "cat" => std::fs::read_to_string(dir.join(words[1])).unwrap(),
        other => panic!("the README's block runs `{other}`, which this test does not know"),
    }
}

#[test]
fn the_readmes_synthetic_record_is_made_and_calibrated_in_three_commands() {
    let blocks = blocks("Your own rig in three commands");
    let json: Vec<&String> = blocks
        .iter()
        .filter(|(l, _)| l == "json")
        .map(|(_, t)| t)
        .collect();
    let sh: Vec<&String> = blocks
        .iter()
        .filter(|(l, _)| l == "sh")
        .map(|(_, t)| t)
        .collect();
    assert_eq!(
        (json.len(), sh.len()),
        (3, 1),
        "rig, campaign, truth; one command block"
    );
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in ["my_rig.json", "my_campaign.json", "truth.json"]
        .iter()
        .zip(&json)
    {
        serde_json::from_str::<Value>(text).unwrap_or_else(|e| panic!("{name}: {e}"));
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    let lines: Vec<&str> = sh[0].lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 3, "three commands: {lines:?}");
    assert!(lines[0].starts_with("rigfit simulate") && lines[0].contains("--noise"));
    assert!(lines[1].starts_with("rigfit run"));
    assert!(
        !dir.path().join("e1.csv").exists(),
        "the record is made, not given"
    );
    let printed: Vec<String> = lines.iter().map(|l| run_line(dir.path(), l)).collect();

    let result: Value = serde_json::from_str(&printed[2]).expect("the third shows result.json");
    let truth: Value = serde_json::from_str(json[2]).unwrap();
    let truth = truth.as_object().unwrap();
    let mut checked = 0;
    for p in result["parameters"].as_array().unwrap() {
        let name = p["name"].as_str().unwrap();
        let Some(want) = truth.get(name).and_then(Value::as_f64) else {
            continue;
        };
        assert_eq!(p["free"], true, "{name} is fitted");
        let value = p["value"].as_f64().unwrap();
        let lo = p["interval_95"][0].as_f64().unwrap();
        let hi = p["interval_95"][1].as_f64().unwrap();
        println!("{name}: true {want}, fitted {value} in [{lo}, {hi}]");
        assert!(
            lo <= want && want <= hi,
            "{name}: the true {want} is outside the reported 95 % interval [{lo}, {hi}] (fitted {value})"
        );
        assert!(
            hi - lo < 0.01 * want,
            "{name}: an interval that says something"
        );
        assert_eq!(p["determined"], true, "{name}");
        checked += 1;
    }
    assert_eq!(
        checked,
        truth.len(),
        "every true value is a fitted parameter"
    );
    // At the floor of the noise the record was made with, not above it.
    let e = &result["experiments"][0];
    let floor = e["cost_over_noise_floor"].as_f64().unwrap();
    assert!(
        (0.7..1.5).contains(&floor),
        "cost over the noise floor {floor}"
    );
    let sigma: f64 = lines[0]
        .split_whitespace()
        .skip_while(|w| *w != "--noise")
        .nth(1)
        .unwrap()
        .parse()
        .unwrap();
    let rms = e["residual_rms"].as_f64().unwrap();
    assert!(
        (rms / sigma - 1.0).abs() < 0.2,
        "residual RMS {rms} against the record's noise {sigma}"
    );
}
