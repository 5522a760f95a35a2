//! Whatever a bad campaign holds, its error is one short line: every value or
//! key quoted from the input (by rigfit or by the JSON library) is cut to 60
//! characters with its length, and control characters are escaped.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::{Value, json};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The shipped campaign with its record's absolute path, spoilt by `spoil`.
fn campaign(dir: &Path, spoil: impl FnOnce(&mut Value)) -> PathBuf {
    let text = std::fs::read_to_string(repo().join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    let record = repo().join("campaigns/aa2024_t3_v2_synthetic.csv");
    c["experiments"][0]["data"]["file"] = json!(record.to_str().unwrap());
    c["output"] = json!("out");
    spoil(&mut c);
    let path = dir.join("c.json");
    std::fs::write(&path, serde_json::to_string(&c).unwrap()).unwrap();
    path
}

#[test]
fn long_values_and_keys_are_cut_in_every_kind_of_error() {
    let long = "Z".repeat(5000);
    let l = || json!(long);
    type Spoil = fn(&mut Value, Value);
    let cases: [(&str, Spoil); 12] = [
        ("a string for a number", |c, l| c["params"]["m1"] = l),
        ("a string for an integer", |c, l| {
            c["search"]["population"] = l
        }),
        ("a string for an object", |c, l| {
            c["experiments"][0]["fit_window"] = l
        }),
        ("an unknown variant", |c, l| c["solver"]["backend"] = l),
        ("an unknown drive", |c, l| c["experiments"][0]["drive"] = l),
        ("an unknown scale", |c, l| c["params"]["k1"]["scale"] = l),
        ("an unknown top-level key", |c, l| {
            c[l.as_str().unwrap()] = json!(1)
        }),
        ("an unknown experiment key", |c, l| {
            c["experiments"][0][l.as_str().unwrap()] = json!(1)
        }),
        ("an unknown parameter", |c, l| {
            c["experiments"][0]["params"][l.as_str().unwrap()] = json!(1.0)
        }),
        ("the retired model key", |c, l| c["model"] = l),
        ("an unknown rig", |c, l| c["rig"] = l),
        ("a missing column", |c, l| {
            c["experiments"][0]["data"]["time_column"] = l
        }),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (what, spoil) in cases {
        let c = campaign(dir.path(), |c| spoil(c, l()));
        for json_flag in [false, true] {
            let mut cmd = Command::new(env!("CARGO_BIN_EXE_rigfit"));
            if json_flag {
                cmd.arg("--json");
            }
            let o = cmd.arg("check").arg(&c).output().unwrap();
            let err = String::from_utf8_lossy(&o.stderr);
            assert_eq!(o.status.code(), Some(2), "{what}: {err}");
            assert_eq!(err.lines().count(), 1, "{what}: {err}");
            assert!(err.len() < 600, "{what}: {} bytes: {err}", err.len());
            assert!(
                err.contains(" (5000 bytes)") || err.contains("(5001 bytes)"),
                "{what}: {err}"
            );
            assert!(!err.contains(&"Z".repeat(61)), "{what}: {err}");
            if json_flag {
                assert!(
                    o.stdout.len() < 1200,
                    "{what}: {}",
                    String::from_utf8_lossy(&o.stdout)
                );
            }
        }
    }
}

#[test]
fn control_characters_in_a_key_are_escaped_and_types_named_in_json_words() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), |c| {
        c["experiments"][0]["a\nb\u{0}c"] = json!(1);
    });
    let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .arg("check")
        .arg(&c)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains(r"a\nb\0c") || err.contains(r"a\nb\u{0}c"),
        "{err}"
    );
    assert!(!err.contains('\0'), "{err}");

    for (spoil, expected) in [
        (
            json!({"population": "x"}),
            "search.population: invalid type: string \"x\", expected a whole number ≥ 0",
        ),
        (
            json!({"population": 8, "generations": 1, "crossover": 3}),
            "search.crossover: invalid type: integer `3`, expected a JSON object {…}",
        ),
    ] {
        let c = campaign(dir.path(), |c| c["search"] = spoil);
        let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
            .arg("check")
            .arg(&c)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(expected), "expected {expected:?} in {err}");
    }
}

fn rigfit(args: &[&str]) -> (Option<i32>, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(args)
        .output()
        .unwrap();
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// Numbers in messages are brief: a time scale of 1e300 makes a record
/// 2.5e297 s long, said in a few characters, not three hundred digits.
#[test]
fn numbers_in_messages_are_brief() {
    let dir = tempfile::tempdir().unwrap();
    for (scale, shown) in [(1e300, "2.5e297 s"), (1e-300, "2.5e-303 s")] {
        let c = campaign(dir.path(), |c| {
            c["experiments"][0]["data"]["time_scale"] = json!(scale)
        });
        let (_, err) = rigfit(&["check", c.to_str().unwrap()]);
        assert!(err.contains(shown), "{err}");
        assert!(
            !err.contains("00000000000000000000"),
            "a number printed in full:\n{err}"
        );
    }
    let c = campaign(dir.path(), |c| {
        c["experiments"][0]["weight"] = json!(-1e300)
    });
    let (code, err) = rigfit(&["check", c.to_str().unwrap()]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("found -1e300"), "{err}");
}

/// A negative number given to an option that takes a number reaches the
/// command, which refuses it by the option's name; it is neither read as an
/// unknown flag nor blamed on the record the command reads.
#[test]
fn negative_option_values_are_refused_by_the_option() {
    let record = repo().join("campaigns/ringdown_synthetic.csv");
    let record = record.to_str().unwrap();
    for args in [
        vec!["ringdown", record, "--m1", "-7.9"],
        vec!["ringdown", record, "--m1=-7.9"],
    ] {
        let (code, err) = rigfit(&args);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        assert!(!err.contains("unexpected argument"), "{args:?}: {err}");
        assert!(
            err.contains("m1") && err.contains("-7.9"),
            "{args:?}: {err}"
        );
        assert!(!err.contains("ringdown_synthetic.csv"), "{args:?}: {err}");
    }
    // The restoring-force method's measured mass, on a record of its own.
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("rfs.csv");
    let rows: String = (0..400)
        .map(|k| {
            let t = k as f64 * 1e-3;
            format!(
                "{t},{},{}\n",
                1e-3 * (20.0 * t).sin(),
                -0.4 * (20.0 * t).sin()
            )
        })
        .collect();
    std::fs::write(&csv, format!("t,x,a\n{rows}")).unwrap();
    let (code, err) = rigfit(&["identify", "rfs", csv.to_str().unwrap(), "--mass", "-2"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(!err.contains("unexpected argument"), "{err}");
    assert!(err.contains("mass: -2 kg is not positive"), "{err}");
    assert!(!err.contains("rfs.csv"), "{err}");
    let (code, err) = rigfit(&["run", "x.json", "--population", "-3"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(!err.contains("unexpected argument"), "{err}");
    assert!(err.contains("--population"), "{err}");
}
