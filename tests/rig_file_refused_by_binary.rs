//! A campaign whose rig file is bad: `rigfit check` and `rigfit run` exit 2 with
//! one line naming the rig file and the JSON path, and nothing is written.

use std::path::Path;
use std::process::Command;

fn rigfit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
}

fn setup(dir: &Path) {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut rig: serde_json::Value = serde_json::from_str(rigfit::rig::SHIPPED[0].1).unwrap();
    rig["elements"][0]["spring"]["law"] = serde_json::json!("hyperelastic");
    std::fs::write(
        dir.join("bad_rig.json"),
        serde_json::to_string_pretty(&rig).unwrap(),
    )
    .unwrap();
    let mut c: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(repo.join("campaigns/aa2024_t3_synthetic.json")).unwrap(),
    )
    .unwrap();
    let o = c.as_object_mut().unwrap();
    o.insert("rig".into(), "bad_rig.json".into());
    o.insert("output".into(), "out".into());
    std::fs::copy(
        repo.join("campaigns/aa2024_t3_v2_synthetic.csv"),
        dir.join("aa2024_t3_v2_synthetic.csv"),
    )
    .unwrap();
    std::fs::write(dir.join("c.json"), c.to_string()).unwrap();
}

#[test]
fn a_bad_rig_file_is_refused_with_exit_2_and_nothing_written() {
    let tmp = tempfile::tempdir().unwrap();
    setup(tmp.path());
    let before: Vec<_> = std::fs::read_dir(tmp.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    for cmd in [["check", "c.json"], ["run", "c.json"]] {
        let out = rigfit().args(cmd).current_dir(tmp.path()).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        println!("{cmd:?}: {err}");
        assert_eq!(out.status.code(), Some(2), "{cmd:?}: {err}");
        let line = err
            .lines()
            .find(|l| l.contains("bad_rig.json"))
            .expect("names the rig file");
        assert!(line.contains("elements[0].spring"), "{line}");
        assert!(line.contains("hyperelastic"), "{line}");
    }
    let after: Vec<_> = std::fs::read_dir(tmp.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(
        before.len(),
        after.len(),
        "something was written: {after:?}"
    );
}
