//! What `rigfit identify` and the record reader say about a bad record or
//! option: each message names the file and the flag and says what to do, and
//! a record's scale is printed as written, not with dozens of digits.

use std::path::Path;
use std::process::{Command, Output};

fn rigfit(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap()
}

/// Deterministic noise in [-1, 1).
fn noise(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6_364_136_223_846_793_005)
        .wrapping_add(1_442_695_040_888_963_407);
    ((*state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

#[test]
fn a_force_column_that_never_varies_names_the_file_and_the_flags() {
    let dir = tempfile::tempdir().unwrap();
    let mut csv = String::from("position_m,voltage_V\n");
    for i in 0..2000 {
        let t = f64::from(i) * 1e-3;
        csv += &format!("{},0\n", 1e-2 * (6.0 * t).sin());
    }
    std::fs::write(dir.path().join("data.csv"), csv).unwrap();
    let o = rigfit(
        dir.path(),
        &["identify", "idim", "data.csv", "--sample-rate", "1000"],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("data.csv"), "{err}");
    assert!(err.contains("invalid --force"), "{err}");
    assert!(err.contains("--gain"), "{err}");
    assert!(!err.contains("invalid option"), "{err}");
}

#[test]
fn a_band_without_coherent_lines_says_which_flags_to_change() {
    let dir = tempfile::tempdir().unwrap();
    let mut state = 7;
    let mut csv = String::from("t_s,force_N,x_m\n");
    for i in 0..4096 {
        let (f, x) = (noise(&mut state), noise(&mut state));
        csv += &format!("{},{f},{x}\n", f64::from(i) * 1e-3);
    }
    std::fs::write(dir.path().join("data.csv"), csv).unwrap();
    // Unrelated input and output: no line is coherent.
    let o = rigfit(
        dir.path(),
        &[
            "identify",
            "frf",
            "data.csv",
            "--f-min",
            "10",
            "--f-max",
            "100",
            "--min-coherence",
            "0.99",
        ],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("data.csv"), "{err}");
    assert!(err.contains("coherent lines in the band"), "{err}");
    for flag in ["--f-min", "--f-max", "--min-coherence"] {
        assert!(err.contains(flag), "{flag}: {err}");
    }
}

#[test]
fn a_record_scale_is_printed_as_a_short_number() {
    let dir = tempfile::tempdir().unwrap();
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(repo.join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let mut c: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut csv = String::from("t_s,force_N\n");
    for i in 0..100 {
        let force = if i == 50 { "1e300" } else { "1" };
        csv += &format!("{},{force}\n", f64::from(i) * 1e-6);
    }
    std::fs::write(dir.path().join("d.csv"), csv).unwrap();
    c["experiments"][0]["data"]["file"] = serde_json::json!("d.csv");
    c["experiments"][0]["data"]["force_scale"] = serde_json::json!(1e40);
    std::fs::write(dir.path().join("c.json"), c.to_string()).unwrap();
    let o = rigfit(dir.path(), &["check", "c.json"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("after scaling"), "{err}");
    assert!(err.contains("1e40"), "{err}");
    assert!(!err.contains("0000000000"), "{err}");
}
